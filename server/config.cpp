#include "server/config.h"

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <optional>
#include <sstream>
#include <string_view>
#include <thread>

#include "server/cgroup.h"

namespace seam::server {
namespace {

// One table drives parsing, the environment and --help, so the three cannot disagree.
struct OptionSpec {
  const char* flag;  // without the leading "--"
  const char* env;
  const char* meaning;
  // Applies a textual value; returns an error message (empty when accepted).
  std::function<std::string(ServerConfig&, std::string_view)> apply;
  std::function<std::string(const ServerConfig&)> show;
};

template <class T>
std::optional<T> parse_number(std::string_view text) {
  T value{};
  const auto* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (ec != std::errc() || ptr != end || text.empty()) return std::nullopt;
  return value;
}

// Integer option within [lo, hi]; the message states the range so a typo is fixable.
template <class T, class Setter>
std::function<std::string(ServerConfig&, std::string_view)> ranged(long long lo, long long hi, Setter set) {
  return [lo, hi, set](ServerConfig& c, std::string_view text) -> std::string {
    const auto v = parse_number<long long>(text);
    if (!v || *v < lo || *v > hi) {
      return "expects an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got '" +
             std::string(text) + "'";
    }
    set(c, static_cast<T>(*v));
    return {};
  };
}

const std::vector<OptionSpec>& option_table() {
  static const std::vector<OptionSpec> table = {
      {"bind", "SEAMD_BIND", "address to listen on",
       [](ServerConfig& c, std::string_view t) -> std::string {
         if (t.empty()) return "expects an address, e.g. 0.0.0.0 or 127.0.0.1";
         c.bind = std::string(t);
         return {};
       },
       [](const ServerConfig& c) { return c.bind; }},
      {"port", "SEAMD_PORT", "TCP port (0 = ephemeral)",
       ranged<int>(0, 65535, [](ServerConfig& c, int v) { c.port = v; }),
       [](const ServerConfig& c) { return std::to_string(c.port); }},
      {"health-port", "SEAMD_HEALTH_PORT", "second listener for /healthz and /readyz only (0 = none)",
       ranged<int>(0, 65535, [](ServerConfig& c, int v) { c.health_port = v; }),
       [](const ServerConfig& c) { return std::to_string(c.health_port); }},
      {"workers", "SEAMD_WORKERS", "compute worker threads (0 = CPUs available, cgroup quota included)",
       ranged<unsigned>(0, 1024, [](ServerConfig& c, unsigned v) { c.workers = v; }),
       [](const ServerConfig& c) { return std::to_string(c.workers); }},
      {"queue", "SEAMD_QUEUE", "jobs allowed to wait for a worker; beyond that 503 + Retry-After",
       ranged<std::size_t>(0, 100000, [](ServerConfig& c, std::size_t v) { c.queue = v; }),
       [](const ServerConfig& c) { return std::to_string(c.queue); }},
      {"http-threads", "SEAMD_HTTP_THREADS", "connection threads (0 = max(256, 2*(workers+queue)))",
       ranged<unsigned>(0, 4096, [](ServerConfig& c, unsigned v) { c.http_threads = v; }),
       [](const ServerConfig& c) { return std::to_string(c.http_threads); }},
      {"backlog", "SEAMD_BACKLOG", "listen backlog for connection bursts (clamped to net.core.somaxconn)",
       ranged<int>(1, 65535, [](ServerConfig& c, int v) { c.backlog = v; }),
       [](const ServerConfig& c) { return std::to_string(c.backlog); }},
      {"max-body-bytes", "SEAMD_MAX_BODY_BYTES", "request body limit in bytes; larger is 413",
       ranged<std::size_t>(1024, 1ll << 40, [](ServerConfig& c, std::size_t v) { c.max_body_bytes = v; }),
       [](const ServerConfig& c) { return std::to_string(c.max_body_bytes); }},
      {"time-budget-ms", "SEAMD_TIME_BUDGET_MS", "per-request budget incl. queueing; then 504",
       ranged<long long>(1, 24ll * 3600 * 1000,
                         [](ServerConfig& c, long long v) { c.time_budget = std::chrono::milliseconds(v); }),
       [](const ServerConfig& c) { return std::to_string(c.time_budget.count()); }},
      {"max-faces", "SEAMD_MAX_FACES", "largest primitive in faces; larger is 422",
       ranged<std::size_t>(1, 1ll << 32, [](ServerConfig& c, std::size_t v) { c.max_faces = v; }),
       [](const ServerConfig& c) { return std::to_string(c.max_faces); }},
      {"memory-limit-bytes", "SEAMD_MEMORY_LIMIT_BYTES",
       "memory for the jobs; lowers the face limit to fit (0 = cgroup limit)",
       ranged<std::uint64_t>(0, 1ll << 50, [](ServerConfig& c, std::uint64_t v) { c.memory_limit_bytes = v; }),
       [](const ServerConfig& c) { return std::to_string(c.memory_limit_bytes); }},
      {"max-extrema", "SEAMD_MAX_EXTREMA", "most extrema one request may name or detect; more is 422",
       ranged<std::size_t>(2, 100000, [](ServerConfig& c, std::size_t v) { c.max_extrema = v; }),
       [](const ServerConfig& c) { return std::to_string(c.max_extrema); }},
      {"max-primitives", "SEAMD_MAX_PRIMITIVES", "most triangle primitives one request may cut; more is 422",
       ranged<std::size_t>(1, 10'000'000, [](ServerConfig& c, std::size_t v) { c.max_primitives = v; }),
       [](const ServerConfig& c) { return std::to_string(c.max_primitives); }},
      {"threads-per-request", "SEAMD_THREADS_PER_REQUEST", "helper threads one request may use (0 = cores / workers)",
       ranged<unsigned>(0, 1024, [](ServerConfig& c, unsigned v) { c.threads_per_request = v; }),
       [](const ServerConfig& c) { return std::to_string(c.threads_per_request); }},
      {"max-inflight-bytes", "SEAMD_MAX_INFLIGHT_BYTES", "bytes held by requests in flight (4 x body each); then 503",
       ranged<std::uint64_t>(1 << 20, 1ll << 50, [](ServerConfig& c, std::uint64_t v) { c.max_inflight_bytes = v; }),
       [](const ServerConfig& c) { return std::to_string(c.max_inflight_bytes); }},
      {"request-timeout-s", "SEAMD_REQUEST_TIMEOUT_S", "the request head must arrive within this; then 408",
       ranged<int>(1, 3600, [](ServerConfig& c, int v) { c.request_timeout_s = v; }),
       [](const ServerConfig& c) { return std::to_string(c.request_timeout_s); }},
      {"min-body-rate", "SEAMD_MIN_BODY_RATE", "bytes/s a body must average after that; slower is 408",
       ranged<std::size_t>(1, 1ll << 34, [](ServerConfig& c, std::size_t v) { c.min_body_rate = v; }),
       [](const ServerConfig& c) { return std::to_string(c.min_body_rate); }},
      {"log-level", "SEAMD_LOG_LEVEL", "trace|debug|info|warn|error|critical|off",
       [](ServerConfig& c, std::string_view t) -> std::string {
         static const std::string_view kLevels[] = {"trace", "debug", "info", "warn",
                                                    "error", "critical", "off"};
         if (std::find(std::begin(kLevels), std::end(kLevels), t) == std::end(kLevels)) {
           return "expects one of trace|debug|info|warn|error|critical|off, got '" + std::string(t) + "'";
         }
         c.log_level = std::string(t);
         return {};
       },
       [](const ServerConfig& c) { return c.log_level; }},
      {"read-timeout-s", "SEAMD_READ_TIMEOUT_S", "one socket read without progress, in seconds; then 408",
       ranged<int>(1, 3600, [](ServerConfig& c, int v) { c.read_timeout_s = v; }),
       [](const ServerConfig& c) { return std::to_string(c.read_timeout_s); }},
      {"write-timeout-s", "SEAMD_WRITE_TIMEOUT_S", "socket write timeout in seconds",
       ranged<int>(1, 3600, [](ServerConfig& c, int v) { c.write_timeout_s = v; }),
       [](const ServerConfig& c) { return std::to_string(c.write_timeout_s); }},
      {"keep-alive-timeout-s", "SEAMD_KEEP_ALIVE_TIMEOUT_S", "idle keep-alive timeout in seconds",
       ranged<int>(1, 3600, [](ServerConfig& c, int v) { c.keep_alive_timeout_s = v; }),
       [](const ServerConfig& c) { return std::to_string(c.keep_alive_timeout_s); }},
      {"drain-timeout-s", "SEAMD_DRAIN_TIMEOUT_S",
       "on SIGTERM, cancel work still running after this (0 = budget + 5 s)",
       ranged<int>(0, 3600, [](ServerConfig& c, int v) { c.drain_timeout_s = v; }),
       [](const ServerConfig& c) { return std::to_string(c.drain_timeout_s); }},
      {"retry-after-s", "SEAMD_RETRY_AFTER_S", "Retry-After seconds of a 503",
       ranged<int>(0, 3600, [](ServerConfig& c, int v) { c.retry_after_s = v; }),
       [](const ServerConfig& c) { return std::to_string(c.retry_after_s); }},
  };
  return table;
}

api::ApiError bad(std::string message, const std::string& name) {
  return api::make_api_error(api::ApiErrorCode::kInvalidParameter, std::move(message),
                             {{"option", name}});
}

}  // namespace

api::ApiResult<ParsedConfig> parse_config(int argc, const char* const* argv, const EnvLookup& env) {
  ParsedConfig out;
  const EnvLookup lookup = env ? env : EnvLookup([](const char* name) { return std::getenv(name); });
  const auto& table = option_table();

  // Environment first, so flags override it.
  for (const auto& spec : table) {
    if (const char* value = lookup(spec.env); value != nullptr) {
      if (auto msg = spec.apply(out.config, value); !msg.empty()) {
        return bad(std::string(spec.env) + " " + msg, spec.env);
      }
    }
  }
  for (int i = 1; i < argc; ++i) {
    std::string_view arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      out.help = true;
      continue;
    }
    if (arg.substr(0, 2) != "--") return bad("unexpected argument '" + std::string(arg) + "'; see seamd --help", std::string(arg));
    arg.remove_prefix(2);
    std::string_view value;
    bool has_value = false;
    if (const auto eq = arg.find('='); eq != std::string_view::npos) {
      value = arg.substr(eq + 1);
      arg = arg.substr(0, eq);
      has_value = true;
    }
    const auto it = std::find_if(table.begin(), table.end(), [&](const OptionSpec& s) { return arg == s.flag; });
    if (it == table.end()) return bad("unknown flag --" + std::string(arg) + "; see seamd --help", std::string(arg));
    if (!has_value) {
      if (i + 1 >= argc) return bad("--" + std::string(arg) + " needs a value", std::string(arg));
      value = argv[++i];
    }
    if (auto msg = it->apply(out.config, value); !msg.empty()) {
      return bad("--" + std::string(arg) + " " + msg, std::string(arg));
    }
  }
  return out;
}

std::string help_text() {
  std::ostringstream os;
  const ServerConfig defaults;
  os << "seamd " << SEAM_VERSION << ": the seam service\n\n"
     << "usage:\n"
     << "  seamd [serve flags]             serve POST /seam, /healthz, /readyz, /metrics, /version\n"
     << "  seamd seam IN [OUT] [flags]     cut one asset (seamd seam --help lists the flags)\n"
     << "  seamd batch IN... --out-dir DIR cut many assets in parallel (seamd batch --help)\n"
     << "  seamd sample [OUT]              write the bundled sample\n"
     << "  seamd --version | --help\n\n"
     << "serve flags (--flag VALUE or --flag=VALUE; each also read from its environment variable;\n"
     << "flags win over the environment):\n";
  for (const auto& spec : option_table()) {
    std::string flag = std::string("  --") + spec.flag;
    flag.resize(std::max<std::size_t>(flag.size() + 1, 26), ' ');
    std::string env = spec.env;
    env.resize(std::max<std::size_t>(env.size() + 1, 28), ' ');
    os << flag << env << spec.meaning << " (default " << spec.show(defaults) << ")\n";
  }
  os << "\nSIGTERM/SIGINT: stop accepting, finish in-flight work (up to --drain-timeout-s), exit 0.\n";
  return os.str();
}

unsigned effective_workers(const ServerConfig& config) {
  if (config.workers > 0) return config.workers;
  return available_cpus();
}

unsigned effective_http_threads(const ServerConfig& config) {
  if (config.http_threads > 0) return config.http_threads;
  // Each connection holds a thread while its request arrives and while it waits for its seam,
  // so the pool covers every admitted job plus slow or refused clients and the probes: 80
  // clients trickling a byte a second must leave /healthz answered (docs/http.md).
  const auto needed = 2 * (effective_workers(config) + static_cast<unsigned>(config.queue));
  return std::max(256u, needed);
}

unsigned effective_threads_per_request(const ServerConfig& config) {
  if (config.threads_per_request > 0) return config.threads_per_request;
  return std::max(1u, available_cpus() / effective_workers(config));
}

std::uint64_t effective_memory_limit(const ServerConfig& config) {
  if (config.memory_limit_bytes > 0) return config.memory_limit_bytes;
  return cgroup_memory_limit().value_or(0);
}

std::uint64_t effective_inflight_bytes(const ServerConfig& config) {
  const std::uint64_t limit = effective_memory_limit(config);
  return limit == 0 ? config.max_inflight_bytes : std::min(config.max_inflight_bytes, limit / 4);
}

std::size_t effective_max_faces(const ServerConfig& config) {
  const std::uint64_t limit = effective_memory_limit(config);
  if (limit == 0) return config.max_faces;
  const std::uint64_t workers = effective_workers(config);
  const std::uint64_t fixed = kServerBaseBytes + effective_inflight_bytes(config) + workers * kJobBaseBytes;
  const std::uint64_t per_job = limit > fixed ? (limit - fixed) / workers : 0;
  const std::uint64_t fit = per_job / kJobBytesPerFace;
  return static_cast<std::size_t>(std::max<std::uint64_t>(1, std::min<std::uint64_t>(config.max_faces, fit)));
}

int effective_drain_timeout_s(const ServerConfig& config) {
  if (config.drain_timeout_s > 0) return config.drain_timeout_s;
  return static_cast<int>((config.time_budget.count() + 999) / 1000) + 5;
}

}  // namespace seam::server
