// seamd's serving configuration: flags override environment variables override defaults.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "api/error.h"

namespace seam::server {

/// Everything `seamd` (serve mode) can be told. In-class defaults are the production
/// defaults; 0 for `workers` / `http_threads` means "derive from the core count".
struct ServerConfig {
  std::string bind = "0.0.0.0";  ///< address to listen on (127.0.0.1 for loopback only)
  int port = 8080;               ///< 0 = an ephemeral port (tests); see Server::port()
  int health_port = 0;           ///< a second listener for /healthz and /readyz only; 0 = none
  unsigned workers = 0;          ///< compute threads; 0 = the CPUs available (cgroup quota)
  std::size_t queue = 16;        ///< seam jobs waiting beyond the busy workers; then 503
  unsigned http_threads = 0;     ///< connection threads; 0 = max(256, 2 * (workers + queue))
  int backlog = 1024;            ///< listen backlog (connection bursts), clamped to somaxconn
  std::size_t max_body_bytes = 256u << 20;          ///< larger bodies are a 413
  std::chrono::milliseconds time_budget{60'000};    ///< per request, queueing included; then 504
  std::size_t max_faces = 5'000'000;                ///< larger primitives are a 422
  /// Memory the jobs may use; 0 = the cgroup's memory limit (none outside a container). The
  /// face limit is lowered so that `workers` jobs of that size fit (effective_max_faces).
  std::uint64_t memory_limit_bytes = 0;
  std::size_t max_extrema = 256;                    ///< longer extrema lists are a 422
  std::size_t max_primitives = 10'000;              ///< more selected primitives are a 422
  /// Helper threads one request may use (terminal paths, extrema); 0 = available CPUs /
  /// workers (the cgroup quota counts), so workers x threads never oversubscribes them.
  unsigned threads_per_request = 0;
  std::uint64_t max_inflight_bytes = 4ull << 30;    ///< bodies x 4 of all requests; then 503
  int request_timeout_s = 30;      ///< the head must arrive within this (then 408)
  std::size_t min_body_rate = 64u << 10;  ///< bytes/s a body must average beyond that
  std::string log_level = "info";  ///< trace|debug|info|warn|error|critical|off
  int read_timeout_s = 30;         ///< one socket read making no progress; then 408
  int write_timeout_s = 30;        ///< one socket write making no progress; then the connection closes
  int keep_alive_timeout_s = 5;    ///< idle keep-alive connections are closed after this
  int drain_timeout_s = 0;         ///< on SIGTERM, work still running after this is cancelled; 0 = budget + 5 s
  int retry_after_s = 1;           ///< the Retry-After of a 503
};

/// The result of reading the command line: a config, or a request for help text.
struct ParsedConfig {
  ServerConfig config;
  bool help = false;
};

/// A getenv-like lookup (injected so tests need not touch the process environment).
using EnvLookup = std::function<const char*(const char*)>;

/// Reads `seamd [flags]` (argv[0] is the program name; `--flag value` and `--flag=value`)
/// over the SEAMD_* environment variables over the defaults, then validates ranges.
/// Errors: kInvalidParameter naming the flag or variable and the accepted range.
/// Complexity: O(argc).
api::ApiResult<ParsedConfig> parse_config(int argc, const char* const* argv,
                                          const EnvLookup& env = nullptr);

/// The `seamd --help` text: every flag, its environment variable and its default.
std::string help_text();

/// The worker count after resolving 0 to the available CPUs (at least 1).
unsigned effective_workers(const ServerConfig& config);
/// The connection thread count after resolving 0.
unsigned effective_http_threads(const ServerConfig& config);
/// The helper threads per request after resolving 0: max(1, available CPUs / workers).
unsigned effective_threads_per_request(const ServerConfig& config);

/// Peak memory of one default job (automatic extrema, refined skeleton seam, SLIM, GLB out),
/// rounded up from scripts/memory-bench.py's fit on 2026-12-01 (camel, 19.5k-1.25M faces:
/// 22 MiB + 1,136 B per face; 1.25M faces peaked at 1,375 MiB): base + per face.
inline constexpr std::uint64_t kJobBaseBytes = 64ull << 20;
inline constexpr std::uint64_t kJobBytesPerFace = 1200;
/// Memory the server holds besides its jobs and request bodies (code, pools, buffers).
inline constexpr std::uint64_t kServerBaseBytes = 96ull << 20;

/// The memory limit in force: --memory-limit-bytes, else the cgroup's, else none (0).
std::uint64_t effective_memory_limit(const ServerConfig& config);
/// --max-inflight-bytes, capped at a quarter of the memory limit when there is one.
std::uint64_t effective_inflight_bytes(const ServerConfig& config);
/// max_faces, lowered so that `workers` jobs of that many faces fit the memory limit beside
/// the bodies in flight: (limit - server base - in-flight bytes - workers x job base) /
/// (workers x bytes per face). Unchanged without a limit; at least 1.
std::size_t effective_max_faces(const ServerConfig& config);
/// The drain after resolving 0: the time budget (rounded up to seconds) + 5 s, so that a
/// rollout lets every admitted job finish.
int effective_drain_timeout_s(const ServerConfig& config);

}  // namespace seam::server
