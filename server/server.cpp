// Eigen (through api/pipeline.h) must be parsed before httplib.h: httplib includes <resolv.h>,
// whose `_res` macro breaks Eigen's templates (shared/notes/stack.md).
#include "server/server.h"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <future>
#include <mutex>
#include <optional>
#include <random>
#include <set>
#include <thread>
#include <unordered_map>

#include "server/request.h"
#include "server/worker_pool.h"

#include "api/sample_mesh.h"
#include "server/web_assets.h"

#include "server/http_front.h"
#include "server/http_request.h"
#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>

namespace seam::server {
namespace {

using Clock = std::chrono::steady_clock;
using api::ApiError;
using api::ApiErrorCode;
using api::make_api_error;

constexpr const char* kRequestIdHeader = "X-Request-Id";
constexpr const char* kJsonType = "application/json";
constexpr const char* kGlbType = "model/gltf-binary";
constexpr const char* kSvgType = "image/svg+xml";

// The viewer talks to this server only: scripts, styles, fetches and images from 'self'
// (blob: and data: for the GLBs it parses and the textures it makes), nothing from elsewhere.
// The Draco decoder is WebAssembly run in a worker made from a blob.
constexpr const char* kPagePolicy =
    "default-src 'none'; script-src 'self' 'wasm-unsafe-eval'; worker-src blob:; style-src 'self'; "
    "img-src 'self' data: blob:; connect-src 'self' data: blob:; base-uri 'none'; form-action 'none'; "
    "frame-ancestors 'none'";

// Fixed route labels keep metric cardinality bounded whatever paths clients probe.
std::string route_label(const std::string& path) {
  for (const char* r : {"/seam", "/healthz", "/readyz", "/metrics", "/version", "/", "/viewer.js", "/viewer.css",
                        "/openapi.json", "/sample.glb", "/draco/draco_wasm_wrapper.js", "/draco/draco_decoder.wasm"}) {
    if (path == r) return r;
  }
  return "other";
}

// An echoed id must be safe to log and to put back into a header.
bool acceptable_request_id(const std::string& id) {
  if (id.empty() || id.size() > 128) return false;
  for (const char c : id) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.' || c == ':')) return false;
  }
  return true;
}

double ms_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

FrontConfig front_config(const ServerConfig& c) {
  return FrontConfig{.head = {.max_body_bytes = c.max_body_bytes},
                     .request_timeout = std::chrono::seconds(c.request_timeout_s),
                     .min_body_rate = c.min_body_rate,
                     .idle_timeout = std::chrono::seconds(c.keep_alive_timeout_s),
                     .io_timeout = std::chrono::seconds(std::max(c.read_timeout_s, c.write_timeout_s)),
                     .backlog = c.backlog,
                     .max_inflight_bytes = effective_inflight_bytes(c)};
}

// How often a waiting handler looks at its client: a client that went away cancels its job
// within this (plus the core's cancellation poll interval).
constexpr auto kPeerPollInterval = std::chrono::milliseconds(100);

}  // namespace

SeamJob pipeline_job() {
  return [](const std::string& asset, api::AssetKind kind, const api::SeamParams& params,
            const api::PipelineLimits& limits, const core::CancelToken& cancel) {
    return api::run_seam_pipeline(asset, kind, params, limits, cancel);
  };
}

// One seam job shared by the connection thread (which may give up at the deadline) and the
// worker (which may still be running then): whoever finishes last frees it.
struct JobState {
  explicit JobState(Clock::time_point deadline) : token(deadline) {}
  core::CancelToken token;
  std::string asset;
  api::AssetKind kind = api::AssetKind::kAuto;
  api::SeamParams params;
  std::promise<api::ApiResult<api::PipelineOutput>> promise;
  Clock::time_point started{};
  Clock::time_point finished{};
  std::atomic<bool> drained{false};  ///< cancelled by the drain on SIGTERM, not the budget
};

// What the log line and the metrics need to know about one request beyond req/res.
struct RequestRecord {
  Clock::time_point start{};
  double queue_ms = -1;
  double compute_ms = -1;
  std::string error_code;
};

struct Server::Impl {
  Impl(ServerConfig c, SeamJob j)
      : config(std::move(c)),
        job(j ? std::move(j) : pipeline_job()),
        pool(effective_workers(config), config.queue),
        http(front_config(config), front_hooks()),
        rng(std::random_device{}()) {
    configure_health();
    auto sink = std::make_shared<spdlog::sinks::stdout_sink_mt>();
    // Not registered globally: several servers (tests) can coexist with their own levels.
    log = std::make_shared<spdlog::logger>("seamd", std::move(sink));
    log->set_pattern("%v");
    log->set_level(spdlog::level::from_str(config.log_level));
    log->flush_on(spdlog::level::info);
    configure_http();
  }

  ServerConfig config;
  SeamJob job;
  WorkerPool pool;
  Metrics metrics;
  FrontServer http;
  // --health-port: /healthz and /readyz on a listener and threads of their own, so probes are
  // answered whatever the traffic port's clients do.
  std::unique_ptr<FrontServer> health;
  std::thread health_thread;
  int health_bound_port = -1;
  std::shared_ptr<spdlog::logger> log;
  int bound_port = -1;

  std::atomic<bool> draining{false};
  std::atomic<std::size_t> in_flight{0};
  std::atomic<std::int64_t> full_since_ns{0};  ///< steady clock; 0 = the pool was not full at the last probe
  const int drain_s = effective_drain_timeout_s(config);
  const std::size_t max_faces = effective_max_faces(config);

  std::mutex rng_mutex;
  std::mt19937_64 rng;

  std::once_flag sample_once;
  std::optional<api::ApiResult<std::string>> sample_glb;

  std::mutex records_mutex;
  std::unordered_map<const httplib::Request*, RequestRecord> records;

  // Live jobs, so a drain that runs out of time can cancel them.
  std::mutex jobs_mutex;
  std::condition_variable jobs_done;
  std::set<JobState*> live_jobs;
  std::thread drain_watchdog;
  std::mutex shutdown_mutex;

  // ---- request bookkeeping -------------------------------------------------------------

  std::string new_request_id() {
    std::lock_guard lock(rng_mutex);
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(rng()));
    return buf;
  }

  // Called before routing (and as a fallback from the error and post-routing handlers for
  // requests that failed before routing): echo a valid X-Request-Id or make one.
  void ensure_request_id(const httplib::Request& req, httplib::Response& res) {
    if (res.has_header(kRequestIdHeader)) return;
    const auto given = req.get_header_value(kRequestIdHeader);
    res.set_header(kRequestIdHeader, acceptable_request_id(given) ? given : new_request_id());
  }

  template <class F>
  void with_record(const httplib::Request& req, F&& f) {
    std::lock_guard lock(records_mutex);
    f(records[&req]);
  }

  void send_error(const httplib::Request& req, httplib::Response& res, const ApiError& error) {
    res.status = api::http_status(error.code);
    res.set_content(api::error_text(error), kJsonType);
    with_record(req, [&](RequestRecord& r) { r.error_code = std::string(api::code_name(error.code)); });
    if (res.status >= 500 && res.status != 503 && res.status != 504) {
      log->error(nlohmann::json{{"event", "internal_error"},
                                {"request_id", res.get_header_value(kRequestIdHeader)},
                                {"message", error.message}}
                     .dump());
    }
  }

  // ---- the connection front's hooks -----------------------------------------------------

  FrontServer::Hooks front_hooks() {
    return FrontServer::Hooks{
        .admit = [this](const RequestHead& head) { return admit(head); },
        .refused = [this](const RequestHead* head, Refusal& r, const std::string& remote) { log_refusal(head, r, remote); }};
  }

  // POST /seam takes four media types; anything else is refused before its body is read (a
  // form-urlencoded body would otherwise be parsed by the library).
  std::optional<Refusal> admit(const RequestHead& head) const {
    if (auto error = refuse_before_body(head)) return Refusal{std::move(*error), {}};
    return std::nullopt;
  }

  // A request the front answered itself: the same request id, access log line and metrics as
  // any other.
  void log_refusal(const RequestHead* head, Refusal& r, const std::string& remote) {
    const auto given = head ? std::string(head->field(kRequestIdHeader).value_or("")) : std::string();
    const auto id = acceptable_request_id(given) ? given : new_request_id();
    r.headers.emplace_back(kRequestIdHeader, id);
    if (r.error.code == ApiErrorCode::kMethodNotAllowed && r.error.details.contains("allow")) {
      r.headers.emplace_back("Allow", r.error.details["allow"].get<std::string>());
    }
    const int status = api::http_status(r.error.code);
    const auto route = head ? route_label(head->path) : std::string("other");
    metrics.record(route, status, 0.0, 0, 0);
    if (!log->should_log(spdlog::level::info)) return;
    nlohmann::ordered_json line{{"ts", std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count()},
                                {"level", "info"},
                                {"request_id", id},
                                {"method", head ? head->method : std::string()},
                                {"route", route},
                                {"status", status},
                                {"error_code", std::string(api::code_name(r.error.code))},
                                {"refused_by", "front"},
                                {"remote", remote}};
    log->info(line.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace));
  }

  // ---- POST /seam ----------------------------------------------------------------------

  void handle_seam(const httplib::Request& req, httplib::Response& res) {
    ++in_flight;
    struct Leave {
      std::atomic<std::size_t>& n;
      ~Leave() { --n; }
    } leave{in_flight};

    const auto deadline = Clock::now() + config.time_budget;
    auto decoded = decode_seam_request(req);
    if (!decoded.ok()) return send_error(req, res, decoded.error());
    SeamRequest& request = decoded.value();
    if (request.asset.empty()) {
      return send_error(req, res, make_api_error(ApiErrorCode::kMalformedRequest, "the request carries no asset bytes"));
    }
    auto format = choose_output(request.params, req.get_header_value("Accept"));
    if (!format.ok()) return send_error(req, res, format.error());
    request.params.output = *format;
    if (draining) {
      res.set_header("Retry-After", std::to_string(config.retry_after_s));
      return send_error(req, res, make_api_error(ApiErrorCode::kQueueFull, "the server is shutting down; retry on another replica"));
    }

    auto state = std::make_shared<JobState>(deadline);
    state->asset = std::move(request.asset);
    state->kind = request.kind;
    state->params = std::move(request.params);
    auto future = state->promise.get_future();
    const auto enqueued = Clock::now();
    if (!submit_job(state)) {
      res.set_header("Retry-After", std::to_string(config.retry_after_s));
      return send_error(req, res,
                        make_api_error(ApiErrorCode::kQueueFull,
                                       "all " + std::to_string(pool.workers()) + " workers are busy and the queue of " +
                                           std::to_string(pool.queue_capacity()) + " is full; retry later",
                                       {{"workers", pool.workers()}, {"queue", pool.queue_capacity()}}));
    }

    switch (wait_for_job(req, future, deadline)) {
      case JobWait::kReady: break;
      case JobWait::kClientGone:
        state->token.cancel();
        http.abandon(req);
        with_record(req, [&](RequestRecord& r) { r.queue_ms = ms_between(enqueued, Clock::now()); });
        return send_error(req, res, make_api_error(ApiErrorCode::kClientClosed,
                                                   "the client closed the connection; its job was cancelled"));
      case JobWait::kTimedOut:
        state->token.cancel();
        with_record(req, [&](RequestRecord& r) { r.queue_ms = ms_between(enqueued, Clock::now()); });
        return send_error(req, res, state->drained ? drain_error() : budget_error());
    }
    auto result = future.get();
    with_record(req, [&](RequestRecord& r) {
      r.queue_ms = ms_between(enqueued, state->started);
      r.compute_ms = ms_between(state->started, state->finished);
    });
    if (!result.ok()) {
      auto error = result.take_error();
      if (error.code == ApiErrorCode::kTimeout) error = state->drained ? drain_error() : budget_error();
      return send_error(req, res, error);
    }
    send_output(res, state->params.output, result.value());
  }

  // Registers the job and hands it to the pool; false (and unregistered) when the pool's
  // queue is full. The worker fulfils the job's promise whatever happens, exceptions included.
  bool submit_job(const std::shared_ptr<JobState>& state) {
    const api::PipelineLimits limits{.max_faces = max_faces,
                                     .max_extrema = config.max_extrema,
                                     .max_primitives = config.max_primitives,
                                     .threads = effective_threads_per_request(config)};
    {
      std::lock_guard lock(jobs_mutex);
      live_jobs.insert(state.get());
    }
    const bool admitted = pool.try_submit([this, state, limits] {
      state->started = Clock::now();
      // `finished` is written before the promise is fulfilled: the waiting thread reads it.
      auto fulfil = [&state](api::ApiResult<api::PipelineOutput> result) {
        state->finished = Clock::now();
        state->promise.set_value(std::move(result));
      };
      try {
        if (state->token.is_cancelled()) {
          fulfil(make_api_error(ApiErrorCode::kTimeout, "the time budget ran out while queued"));
        } else {
          fulfil(job(state->asset, state->kind, state->params, limits, state->token));
        }
      } catch (const std::bad_alloc&) {
        fulfil(make_api_error(ApiErrorCode::kInternal, "out of memory while computing the seam"));
      } catch (const std::exception& e) {
        fulfil(make_api_error(ApiErrorCode::kInternal, std::string("unexpected exception: ") + e.what()));
      }
      std::lock_guard lock(jobs_mutex);
      live_jobs.erase(state.get());
      jobs_done.notify_all();
    });
    if (!admitted) {
      std::lock_guard lock(jobs_mutex);
      live_jobs.erase(state.get());
    }
    return admitted;
  }

  // The job's answer in the format the request asked for (choose_output: params.output, or Accept).
  static void send_output(httplib::Response& res, api::OutputFormat format, api::PipelineOutput& output) {
    res.status = 200;
    if (format == api::OutputFormat::kSvg) {
      res.set_content(output.svg, kSvgType);
    } else if (format == api::OutputFormat::kGlb) {
      res.body = std::move(output.glb);
      res.set_header("Content-Type", kGlbType);
    } else {
      res.set_content(output.body.dump(), kJsonType);
    }
  }

  enum class JobWait { kReady, kClientGone, kTimedOut };

  // Waits for the job while watching the client: nobody is left to answer once it closed its
  // side, so its job is cancelled at once instead of holding a worker until the budget ends.
  // A job that polls its token returns kTimeout right at the deadline; the grace covers the
  // last poll interval. A job that does not poll is abandoned: the client still gets its 504
  // and the worker is released as soon as the job notices the cancelled token.
  JobWait wait_for_job(const httplib::Request& req, std::future<api::ApiResult<api::PipelineOutput>>& future,
                       Clock::time_point deadline) {
    const auto give_up = deadline + std::chrono::milliseconds(250);
    for (;;) {
      const auto until = std::min(give_up, Clock::now() + kPeerPollInterval);
      if (future.wait_until(until) == std::future_status::ready) return JobWait::kReady;
      if (http.peer_closed(req)) return JobWait::kClientGone;
      if (Clock::now() >= give_up) return JobWait::kTimedOut;
    }
  }

  ApiError drain_error() const {
    return make_api_error(ApiErrorCode::kTimeout,
                          "the server is shutting down and the job was still running when the drain of " +
                              std::to_string(drain_s) + " s ended (--drain-timeout-s); retry on another replica",
                          {{"drain_timeout_s", drain_s}});
  }

  ApiError budget_error() const {
    return make_api_error(ApiErrorCode::kTimeout,
                          "the seam computation exceeded the time budget of " +
                              std::to_string(config.time_budget.count()) +
                              " ms (queueing included); try fewer extrema, a smaller mesh or another method",
                          {{"time_budget_ms", config.time_budget.count()}});
  }

  // ---- operations ----------------------------------------------------------------------

  GaugeSnapshot gauges() const {
    return GaugeSnapshot{.queue_depth = pool.queue_depth(),
                         .busy_workers = pool.busy(),
                         .workers = pool.workers(),
                         .queue_capacity = pool.queue_capacity(),
                         .in_flight = in_flight.load(),
                         .inflight_bytes = http.budget().held(),
                         .inflight_bytes_limit = http.budget().capacity(),
                         .draining = draining.load()};
  }

  // Readiness is "can take work soon", not "a worker is idle": a full pool answers its own
  // 503 + Retry-After, which the front retries elsewhere, and a pod that left the Service
  // whenever its queue filled would flap (jobs take 30-500 ms, probes come every 5 s) and,
  // with every pod busy, leave clients with connection errors. So only a drain, or a pool
  // that stayed full across probes for longer than a whole time budget (wedged, or overloaded
  // far beyond its queue), takes the pod out.
  void handle_readyz(httplib::Response& res) {
    const auto g = gauges();
    const bool full = pool.full();
    const auto now = Clock::now();
    std::int64_t since = full_since_ns.load();
    if (!full) {
      full_since_ns = 0;
    } else if (since == 0) {
      since = now.time_since_epoch().count();
      full_since_ns = since;
    }
    const bool stuck = full && now - Clock::time_point(Clock::duration(since)) > config.time_budget;
    const char* status = draining ? "draining" : stuck ? "overloaded" : full ? "busy" : "ready";
    res.status = (draining || stuck) ? 503 : 200;
    res.set_content(nlohmann::json{{"status", status},
                                   {"queue_depth", g.queue_depth},
                                   {"busy_workers", g.busy_workers},
                                   {"workers", g.workers}}
                        .dump(),
                    kJsonType);
  }

  // ---- wiring --------------------------------------------------------------------------

  void method_not_allowed(const std::string& path, const std::string& allow) {
    // Allow lists every method the route takes, OPTIONS included, as OPTIONS itself answers.
    auto handler = [this, allow](const httplib::Request& req, httplib::Response& res) {
      res.set_header("Allow", allow + ", OPTIONS");
      send_error(req, res,
                 make_api_error(ApiErrorCode::kMethodNotAllowed,
                                req.method + " is not allowed on " + req.path + "; use " + allow,
                                {{"allow", allow}}));
    };
    if (allow.find("GET") == std::string::npos) http.Get(path, handler);
    if (allow.find("POST") == std::string::npos) http.Post(path, handler);
    http.Put(path, handler);
    http.Patch(path, handler);
    http.Delete(path, handler);
    // OPTIONS answers what the route takes (RFC 9110 §9.3.7), with no body.
    http.Options(path, [allow](const httplib::Request&, httplib::Response& res) {
      res.status = 204;
      res.set_header("Allow", allow + ", OPTIONS");
    });
  }

  void configure_http() {
    http.set_tcp_nodelay(true);
    http.set_payload_max_length(config.max_body_bytes);
    http.set_read_timeout(config.read_timeout_s, 0);
    http.set_write_timeout(config.write_timeout_s, 0);
    http.set_keep_alive_timeout(config.keep_alive_timeout_s);
    http.set_keep_alive_max_count(1000);  // httplib's default of 5 costs a reconnect every 5 requests
    const unsigned threads = effective_http_threads(config);
    http.new_task_queue = [threads] { return new httplib::ThreadPool(threads); };

    http.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
      ensure_request_id(req, res);
      with_record(req, [](RequestRecord& r) { r = RequestRecord{.start = Clock::now()}; });
      return httplib::Server::HandlerResponse::Unhandled;
    });
    // Statuses httplib sets itself (404, 400 for unparsable requests, 413) get the one JSON
    // error body too; bodies our handlers already wrote are left alone.
    http.set_error_handler(httplib::Server::HandlerWithResponse([this](const httplib::Request& req,
                                                                        httplib::Response& res) {
      ensure_request_id(req, res);
      if (!res.body.empty()) return httplib::Server::HandlerResponse::Unhandled;
      if (auto failure = http.body_failure(req); failure) {
        // The front stopped the body (over the limit, too slow, over the in-flight budget).
        for (const auto& [name, value] : failure->headers) res.set_header(name, value);
        res.set_header("Connection", "close");
        send_error(req, res, failure->error);
        return httplib::Server::HandlerResponse::Handled;
      }
      if (http.body_incomplete(req)) res.set_header("Connection", "close");
      const ApiError error = library_status_error(res.status, req.path, config.max_body_bytes);
      const int status = res.status;
      send_error(req, res, error);
      if (status != api::http_status(error.code)) res.status = status;  // keep e.g. 414, 416
      return httplib::Server::HandlerResponse::Handled;
    }));
    http.set_exception_handler([this](const httplib::Request& req, httplib::Response& res, std::exception_ptr ep) {
      std::string what = "unknown exception";
      try {
        if (ep) std::rethrow_exception(ep);
      } catch (const std::exception& e) {
        what = e.what();
      } catch (...) {
      }
      ensure_request_id(req, res);
      res.body.clear();
      send_error(req, res, make_api_error(ApiErrorCode::kInternal, "internal error: " + what));
    });
    // Metrics and the access log are written by the post-routing handler, which cpp-httplib runs
    // after the handler (and the error handler) and before the response goes on the wire. Its
    // logger hook runs only after the write, so a client could read /metrics before its own
    // previous request was counted. (One handler: a second call replaces the first.)
    http.set_post_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
      ensure_request_id(req, res);
      res.set_header("Date", http_date(std::chrono::system_clock::now()));
      // The front drops Range (server/http_head.h), so no answer is ever partial: say so, also
      // where the library has just offered byte ranges (it adds "bytes" to HEAD answers right
      // before this handler).
      if (req.method == "GET" || req.method == "HEAD") {
        res.headers.erase("Accept-Ranges");
        res.set_header("Accept-Ranges", "none");
      }
      log_request(req, res);
    });

    http.Post("/seam", [this](const httplib::Request& req, httplib::Response& res) { handle_seam(req, res); });
    method_not_allowed("/seam", "POST");
    add_probes(http);
    // OPTIONS * asks about the server as a whole (RFC 9110 §9.3.7): every method some route takes.
    http.Options(R"(\*)", [](const httplib::Request&, httplib::Response& res) {
      res.status = 204;
      res.set_header("Allow", "GET, HEAD, POST, OPTIONS");
    });
    http.Get("/metrics", [this](const httplib::Request&, httplib::Response& res) {
      res.set_content(metrics.render(gauges()), "text/plain; version=0.0.4; charset=utf-8");
    });
    http.Get("/version", [](const httplib::Request&, httplib::Response& res) {
      res.set_content(version_info().dump(), kJsonType);
    });
    for (const char* path : {"/healthz", "/readyz", "/metrics", "/version"}) method_not_allowed(path, "GET, HEAD");
    add_web_routes();
  }

  // GET /, its script and stylesheet, /openapi.json (embedded at build time) and the sample.
  void add_web_routes() {
    for (const WebAsset& asset : web_asset_table()) {
      // Route patterns are regular expressions: the dots are literal.
      std::string path;
      for (const char c : asset.path) path += c == '.' ? std::string("\\.") : std::string(1, c);
      http.Get(path, [&asset](const httplib::Request&, httplib::Response& res) {
        std::string type(asset.content_type);
        if (type.starts_with("text/")) type += "; charset=utf-8";
        res.set_content(asset.body.data(), asset.body.size(), type);
        res.set_header("X-Content-Type-Options", "nosniff");
        res.set_header("Cache-Control", "no-cache");
        if (asset.content_type == "text/html") res.set_header("Content-Security-Policy", kPagePolicy);
      });
      method_not_allowed(path, "GET, HEAD");
    }
    http.Get("/sample\\.glb", [this](const httplib::Request& req, httplib::Response& res) {
      const auto& glb = sample();
      if (!glb.ok()) return send_error(req, res, glb.error());
      res.set_content(glb.value(), kGlbType);
      res.set_header("Content-Disposition", "attachment; filename=\"sample.glb\"");
    });
    method_not_allowed("/sample\\.glb", "GET, HEAD");
  }

  // The bundled sample (api/sample_mesh.h), made once on first use: it is deterministic.
  const api::ApiResult<std::string>& sample() {
    std::call_once(sample_once, [this] { sample_glb.emplace(api::sample_glb()); });
    return *sample_glb;
  }

  void add_probes(FrontServer& server) {
    server.Get("/healthz", [](const httplib::Request&, httplib::Response& res) {
      res.set_content(R"({"status":"ok"})", kJsonType);
    });
    server.Get("/readyz", [this](const httplib::Request&, httplib::Response& res) { handle_readyz(res); });
  }

  void configure_health() {
    if (config.health_port == 0) return;
    FrontConfig fc = front_config(config);
    fc.request_timeout = std::chrono::seconds(5);
    fc.head.max_body_bytes = 1024;
    fc.backlog = 128;
    health = std::make_unique<FrontServer>(fc, FrontServer::Hooks{});
    health->set_tcp_nodelay(true);
    health->new_task_queue = [] { return new httplib::ThreadPool(4); };
    add_probes(*health);
  }

  void log_request(const httplib::Request& req, const httplib::Response& res) {
    RequestRecord record;
    {
      std::lock_guard lock(records_mutex);
      if (auto it = records.find(&req); it != records.end()) {
        record = std::move(it->second);
        records.erase(it);
      }
    }
    const auto now = Clock::now();
    const double ms = record.start == Clock::time_point{} ? 0.0 : ms_between(record.start, now);
    const auto route = route_label(req.path);
    std::size_t bytes_in = req.body.size();
    for (const auto& [name, file] : req.files) bytes_in += file.content.size();
    metrics.record(route, res.status, ms / 1000.0, bytes_in, res.body.size());
    if (!log->should_log(spdlog::level::info)) return;
    nlohmann::ordered_json line{{"ts", std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count()},
                        {"level", res.status >= 500 && res.status != 503 && res.status != 504 ? "error" : "info"},
                        {"request_id", res.get_header_value(kRequestIdHeader)},
                        {"method", req.method},
                        {"route", route},
                        {"status", res.status},
                        {"bytes_in", bytes_in},
                        {"bytes_out", res.body.size()},
                        {"duration_ms", ms},
                        {"remote", req.remote_addr}};
    if (route == "other") line["path"] = req.path.substr(0, 200);
    if (record.queue_ms >= 0) line["queue_ms"] = record.queue_ms;
    if (record.compute_ms >= 0) line["compute_ms"] = record.compute_ms;
    if (!record.error_code.empty()) line["error_code"] = record.error_code;
    // Lossy UTF-8 replacement: a hostile path must not make the log line throw.
    log->info(line.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace));
  }

  void start_drain_watchdog() {
    drain_watchdog = std::thread([this] {
      std::unique_lock lock(jobs_mutex);
      const auto limit = std::chrono::seconds(drain_s);
      if (!jobs_done.wait_for(lock, limit, [this] { return live_jobs.empty(); })) {
        log->warn(nlohmann::json{{"event", "drain_timeout"}, {"cancelled_jobs", live_jobs.size()}}.dump());
        for (auto* s : live_jobs) {
          s->drained = true;
          s->token.cancel();
        }
      }
    });
  }
};

Server::Server(ServerConfig config, SeamJob job) : impl_(std::make_unique<Impl>(std::move(config), std::move(job))) {}

Server::~Server() {
  shutdown();
  impl_->pool.shutdown();
  if (impl_->drain_watchdog.joinable()) impl_->drain_watchdog.join();
}

api::ApiResult<int> Server::bind() {
  auto& c = impl_->config;
  const int port = impl_->http.bind_with_backlog(c.bind, c.port);
  if (port < 0) {
    return make_api_error(ApiErrorCode::kInternal,
                          "cannot listen on " + c.bind + ":" + std::to_string(c.port) + " (address in use or invalid)");
  }
  impl_->bound_port = port;
  if (impl_->health) {
    impl_->health_bound_port = impl_->health->bind_with_backlog(c.bind, c.health_port);
    if (impl_->health_bound_port < 0) {
      return make_api_error(ApiErrorCode::kInternal,
                            "cannot listen on " + c.bind + ":" + std::to_string(c.health_port) +
                                " for --health-port (address in use or invalid)");
    }
  }
  return port;
}

// A working first request for whoever just started the server (README's first command).
std::string Server::try_line() const {
  const auto& bind = impl_->config.bind;
  const std::string host = (bind == "0.0.0.0" || bind == "::" || bind.empty()) ? "127.0.0.1" : bind;
  return "seamd sample --out sample.glb && curl -F mesh=@sample.glb http://" + host + ":" +
         std::to_string(impl_->bound_port) + "/seam";
}

void Server::run() {
  impl_->log->info(nlohmann::json{
      {"event", "listening"},
      {"bind", impl_->config.bind},
      {"port", impl_->bound_port},
      {"workers", impl_->pool.workers()},
      {"queue", impl_->pool.queue_capacity()},
      {"http_threads", effective_http_threads(impl_->config)},
      {"backlog", impl_->http.effective_backlog()},
      {"threads_per_request", effective_threads_per_request(impl_->config)},
      {"health_port", impl_->health_bound_port},
      {"max_faces", impl_->max_faces},
      {"max_primitives", impl_->config.max_primitives},
      {"memory_limit_bytes", effective_memory_limit(impl_->config)},
      {"drain_timeout_s", impl_->drain_s},
      {"version", SEAM_VERSION},
      {"try",
       try_line()}}.dump());
  if (impl_->health) impl_->health_thread = std::thread([this] { impl_->health->listen_after_bind(); });
  // Returns once stop() closed the listening socket and the connection threads finished
  // their requests (httplib joins its pool), so every in-flight client has its answer.
  impl_->http.listen_after_bind();
  impl_->pool.shutdown();
  {
    std::lock_guard lock(impl_->shutdown_mutex);
    if (impl_->drain_watchdog.joinable()) {
      {
        std::lock_guard jl(impl_->jobs_mutex);
        impl_->jobs_done.notify_all();
      }
      impl_->drain_watchdog.join();
    }
  }
  // Liveness is answered to the end: the probe listener stops last.
  if (impl_->health) {
    impl_->health->stop();
    if (impl_->health_thread.joinable()) impl_->health_thread.join();
  }
  impl_->log->info(nlohmann::json{{"event", "stopped"}}.dump());
  impl_->log->flush();
}

void Server::shutdown() {
  std::lock_guard lock(impl_->shutdown_mutex);
  if (impl_->draining.exchange(true)) return;
  impl_->log->info(nlohmann::json{{"event", "draining"}, {"in_flight", impl_->in_flight.load()}}.dump());
  impl_->start_drain_watchdog();
  impl_->http.begin_drain(Clock::now() + std::chrono::seconds(impl_->drain_s));
  impl_->http.stop();
}

bool Server::is_running() const { return impl_->http.is_running(); }
int Server::port() const { return impl_->bound_port; }
int Server::health_port() const { return impl_->health_bound_port; }
const ServerConfig& Server::config() const { return impl_->config; }
const Metrics& Server::metrics() const { return impl_->metrics; }

}  // namespace seam::server
