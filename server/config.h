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
  unsigned workers = 0;          ///< compute threads; 0 = std::thread::hardware_concurrency()
  std::size_t queue = 16;        ///< seam jobs waiting beyond the busy workers; then 503
  unsigned http_threads = 0;     ///< connection threads; 0 = max(256, 2 * (workers + queue))
  int backlog = 1024;            ///< listen backlog (connection bursts), clamped to somaxconn
  std::size_t max_body_bytes = 256u << 20;          ///< larger bodies are a 413
  std::chrono::milliseconds time_budget{60'000};    ///< per request, queueing included; then 504
  std::size_t max_faces = 5'000'000;                ///< larger primitives are a 422
  std::size_t max_extrema = 256;                    ///< longer extrema lists are a 422
  /// Helper threads one request may use (terminal paths, extrema); 0 = cores / workers, so
  /// that workers x threads never oversubscribes the cores.
  unsigned threads_per_request = 0;
  std::uint64_t max_inflight_bytes = 4ull << 30;    ///< bodies x 4 of all requests; then 503
  int request_timeout_s = 30;      ///< the head must arrive within this (then 408)
  std::size_t min_body_rate = 64u << 10;  ///< bytes/s a body must average beyond that
  std::string log_level = "info";  ///< trace|debug|info|warn|error|critical|off
  int read_timeout_s = 30;         ///< one socket read making no progress; then 408
  int write_timeout_s = 30;        ///< one socket write making no progress; then the connection closes
  int keep_alive_timeout_s = 5;    ///< idle keep-alive connections are closed after this
  int drain_timeout_s = 30;        ///< on SIGTERM, in-flight work older than this is cancelled
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

/// The worker count after resolving 0 to the core count (at least 1).
unsigned effective_workers(const ServerConfig& config);
/// The connection thread count after resolving 0.
unsigned effective_http_threads(const ServerConfig& config);
/// The helper threads per request after resolving 0: max(1, cores / workers).
unsigned effective_threads_per_request(const ServerConfig& config);

}  // namespace seam::server
