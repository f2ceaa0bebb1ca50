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
  unsigned http_threads = 0;     ///< connection threads; 0 = max(64, 2 * (workers + queue))
  std::size_t max_body_bytes = 256u << 20;          ///< larger bodies are a 413
  std::chrono::milliseconds time_budget{60'000};    ///< per request, queueing included; then 504
  std::size_t max_faces = 5'000'000;                ///< larger primitives are a 422
  std::string log_level = "info";  ///< trace|debug|info|warn|error|critical|off
  int read_timeout_s = 30;         ///< socket read timeout (headers and body)
  int write_timeout_s = 30;        ///< socket write timeout
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

}  // namespace seam::server
