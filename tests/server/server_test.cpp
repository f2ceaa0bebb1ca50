// End-to-end tests of the HTTP layer with a scripted job in place of the seam pipeline, so
// backpressure, time budgets, failures and shutdown are deterministic. The real pipeline
// behind real HTTP is exercised in seam_http_test.cpp.
#include "api/base64.h"
#include "api/pipeline.h"
#include "server/request.h"

#include <atomic>
#include <future>
#include <vector>

#include "seamd_process.h"
#include "server_harness.h"

namespace seam_server_test {

namespace {

using namespace std::chrono_literals;
using seam::api::ApiErrorCode;
using seam::test_server::error_code_of;
using seam::test_server::RunningServer;
using seam::test_server::test_config;

// The scripted job reads its asset as a command:
//   "ok:TEXT"     answers at once, echoing TEXT, the asset kind and the output format
//   "sleep:MS"    works MS ms, polling the cancel token every millisecond (a well-behaved job)
//   "hang:MS"     works MS ms ignoring the token (a job that polls too rarely)
//   "throw"       throws (a bug in the job)
//   "reject"      returns a 422 (extremum_out_of_range)
struct ScriptedJob {
  std::shared_ptr<std::atomic<int>> started = std::make_shared<std::atomic<int>>(0);
  std::shared_ptr<std::atomic<int>> finished = std::make_shared<std::atomic<int>>(0);

  seam::server::SeamJob job() const {
    auto s = started;
    auto f = finished;
    return [s, f](const std::string& asset, seam::api::AssetKind kind, const seam::api::SeamParams& params,
                  const seam::api::PipelineLimits&,
                  const seam::core::CancelToken& cancel) -> seam::api::ApiResult<seam::api::PipelineOutput> {
      ++*s;
      struct Done {
        std::atomic<int>& n;
        ~Done() { ++n; }
      } done{*f};
      const auto colon = asset.find(':');
      const std::string verb = asset.substr(0, colon);
      const std::string arg = colon == std::string::npos ? "" : asset.substr(colon + 1);
      if (verb == "throw") throw std::runtime_error("scripted failure");
      if (verb == "reject") {
        return seam::api::make_api_error(ApiErrorCode::kExtremumOutOfRange, "extremum 99 is out of range");
      }
      if (verb == "sleep" || verb == "hang") {
        const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(std::stoi(arg));
        while (std::chrono::steady_clock::now() < until) {
          if (verb == "sleep" && cancel.is_cancelled()) {
            return seam::api::make_api_error(ApiErrorCode::kTimeout, "cancelled");
          }
          std::this_thread::sleep_for(1ms);
        }
      }
      seam::api::PipelineOutput out;
      out.body = {{"echo", arg},
                  {"kind", static_cast<int>(kind)},
                  {"glb", params.output == seam::api::OutputFormat::kGlb},
                  {"method", static_cast<int>(params.method)}};
      out.glb = "glTF-scripted:" + arg;
      return out;
    };
  }
};

// A generated request id: 16 lower-case hex digits. (No std::regex: GCC 12 warns inside
// <regex> under -O1 with sanitizers, and warnings are errors in CI.)
bool is_hex16(const std::string& id) {
  return id.size() == 16 && id.find_first_not_of("0123456789abcdef") == std::string::npos;
}

nlohmann::json parse(const std::string& body) {
  auto j = nlohmann::json::parse(body, nullptr, false);
  REQUIRE_MESSAGE(!j.is_discarded(), body);
  return j;
}

}  // namespace

TEST_CASE("operations endpoints answer JSON and Prometheus text") {
  RunningServer srv(test_config(), ScriptedJob{}.job());
  auto cli = srv.client();

  auto health = cli->Get("/healthz");
  REQUIRE(health);
  CHECK(health->status == 200);
  CHECK(parse(health->body)["status"] == "ok");

  auto ready = cli->Get("/readyz");
  REQUIRE(ready);
  CHECK(ready->status == 200);
  CHECK(parse(ready->body)["status"] == "ready");

  auto version = cli->Get("/version");
  REQUIRE(version);
  CHECK(version->status == 200);
  const auto v = parse(version->body);
  CHECK(v["version"] == SEAM_VERSION);
  CHECK(v["libraries"]["cpp-httplib"] == CPPHTTPLIB_VERSION);

  auto seam = cli->Post("/seam", "ok:x", "model/gltf-binary");
  REQUIRE(seam);
  CHECK(seam->status == 200);

  auto metrics = cli->Get("/metrics");
  REQUIRE(metrics);
  CHECK(metrics->status == 200);
  CHECK(metrics->get_header_value("Content-Type").find("text/plain") == 0);
  const auto& m = metrics->body;
  CHECK(m.find("seamd_requests_total{route=\"/healthz\",status=\"200\"} 1") != std::string::npos);
  CHECK(m.find("seamd_requests_total{route=\"/seam\",status=\"200\"} 1") != std::string::npos);
  CHECK(m.find("seamd_request_duration_seconds_count{route=\"/seam\"} 1") != std::string::npos);
  CHECK(m.find("seamd_request_duration_seconds_bucket{route=\"/seam\",le=\"+Inf\"} 1") != std::string::npos);
  CHECK(m.find("seamd_workers 2") != std::string::npos);
  // The gauges are sampled live: the worker that answered may still be leaving its task for a
  // moment after the client has the response, so wait for them to settle (they must, quickly).
  bool idle = false;
  for (int i = 0; i < 100 && !idle; ++i) {
    auto again = cli->Get("/metrics");
    REQUIRE(again);
    idle = again->body.find("seamd_queue_depth 0\n") != std::string::npos &&
           again->body.find("seamd_busy_workers 0\n") != std::string::npos;
    if (!idle) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  CHECK(idle);
  // The /seam request carried 4 body bytes; earlier GETs none.
  CHECK(m.find("seamd_request_bytes_total 4") != std::string::npos);
  CHECK(m.find("seamd_response_bytes_total 0") == std::string::npos);

  // A response is counted before it reaches the client: a /metrics read that follows a request
  // on the same connection always sees it (it once raced the write and failed under load).
  for (int n = 2; n <= 30; ++n) {
    auto again = cli->Post("/seam", "ok:x", "model/gltf-binary");
    REQUIRE(again);
    auto after = cli->Get("/metrics");
    REQUIRE(after);
    const auto want = "seamd_requests_total{route=\"/seam\",status=\"200\"} " + std::to_string(n) + "\n";
    CHECK_MESSAGE(after->body.find(want) != std::string::npos, "request ", n);
  }
}

TEST_CASE("every response carries X-Request-Id, echoed or generated") {
  RunningServer srv(test_config(), ScriptedJob{}.job());
  auto cli = srv.client();

  auto echoed = cli->Get("/healthz", {{"X-Request-Id", "farm-job-42"}});
  REQUIRE(echoed);
  CHECK(echoed->get_header_value("X-Request-Id") == "farm-job-42");

  auto a = cli->Get("/healthz");
  auto b = cli->Get("/nope");
  REQUIRE(a);
  REQUIRE(b);
  CHECK(is_hex16(a->get_header_value("X-Request-Id")));
  CHECK(is_hex16(b->get_header_value("X-Request-Id")));
  CHECK(a->get_header_value("X-Request-Id") != b->get_header_value("X-Request-Id"));

  // An id that is unsafe to log or echo is replaced, not reflected.
  auto hostile = cli->Get("/healthz", {{"X-Request-Id", "a\"b{c}<script>"}});
  REQUIRE(hostile);
  CHECK(is_hex16(hostile->get_header_value("X-Request-Id")));

  auto err = cli->Post("/seam", "x", "text/plain");
  REQUIRE(err);
  CHECK(err->status == 415);
  CHECK(is_hex16(err->get_header_value("X-Request-Id")));
}

TEST_CASE("the three request forms and both output formats reach the job") {
  RunningServer srv(test_config(), ScriptedJob{}.job());
  auto cli = srv.client();
  using seam::api::AssetKind;

  SUBCASE("raw body with query parameters") {
    auto r = cli->Post("/seam?method=mst", "ok:raw", "model/gltf-binary");
    REQUIRE(r);
    REQUIRE(r->status == 200);
    CHECK(r->get_header_value("Content-Type") == "application/json");
    const auto j = parse(r->body);
    CHECK(j["echo"] == "raw");
    CHECK(j["kind"] == static_cast<int>(AssetKind::kGlb));
    CHECK(j["method"] == static_cast<int>(seam::core::SeamMethod::kMst));

    auto gltf = cli->Post("/seam", "ok:json", "model/gltf+json");
    REQUIRE(gltf);
    CHECK(parse(gltf->body)["kind"] == static_cast<int>(AssetKind::kGltfJson));
    auto drc = cli->Post("/seam", "ok:drc", "application/octet-stream");
    REQUIRE(drc);
    CHECK(parse(drc->body)["kind"] == static_cast<int>(AssetKind::kAuto));
  }
  SUBCASE("multipart with a params part") {
    httplib::MultipartFormDataItems items = {{"mesh", "ok:multi", "a.glb", "application/octet-stream"},
                                             {"params", R"({"method":"greedy"})", "", "application/json"}};
    auto r = cli->Post("/seam", items);
    REQUIRE(r);
    REQUIRE(r->status == 200);
    const auto j = parse(r->body);
    CHECK(j["echo"] == "multi");
    CHECK(j["method"] == static_cast<int>(seam::core::SeamMethod::kGreedy));
  }
  SUBCASE("multipart parts other than one mesh and one params are refused, naming the part") {
    // They were ignored: a misspelt params part ran with the defaults, a second params or
    // mesh part was dropped unseen.
    struct Refused {
      const char* name;
      httplib::MultipartFormDataItems items;
      const char* part;
    };
    const httplib::MultipartFormDataItems::value_type mesh{"mesh", "ok:m", "a.glb", "application/octet-stream"};
    const httplib::MultipartFormDataItems::value_type params{"params", R"({"method":"greedy"})", "",
                                                             "application/json"};
    for (const auto& c : {Refused{"misspelt params", {mesh, {"parms", R"({"method":"mst"})", "", ""}}, "parms"},
                          Refused{"two params", {mesh, params, {"params", R"({"method":"mst"})", "", ""}}, "params"},
                          Refused{"two meshes", {mesh, {"mesh", "ok:n", "b.glb", ""}, params}, "mesh"},
                          Refused{"a parameter as a part", {mesh, {"extrema", "1,2", "", ""}}, "extrema"}}) {
      CAPTURE(c.name);
      auto r = cli->Post("/seam", c.items);
      REQUIRE(r);
      CHECK(r->status == 400);
      const auto j = parse(r->body);
      CHECK(j["error"]["code"] == "malformed_request");
      CHECK(j["error"]["details"]["part"] == c.part);
    }
  }
  SUBCASE("JSON body with base64 GLB") {
    const nlohmann::json body = {{"mesh", {{"glb_base64", seam::api::encode_base64("ok:b64")}}},
                                 {"method", "mst"}};
    auto r = cli->Post("/seam", body.dump(), "application/json");
    REQUIRE(r);
    REQUIRE(r->status == 200);
    CHECK(parse(r->body)["echo"] == "b64");
    CHECK(parse(r->body)["method"] == static_cast<int>(seam::core::SeamMethod::kMst));
  }
  SUBCASE("JSON body with an embedded glTF object") {
    const nlohmann::json body = {{"mesh", {{"gltf", {{"asset", {{"version", "2.0"}}}}}}}};
    auto r = cli->Post("/seam", body.dump(), "application/json");
    REQUIRE(r);
    // The scripted job sees the re-serialized glTF JSON as its asset.
    CHECK(r->status == 200);
    CHECK(parse(r->body)["kind"] == static_cast<int>(AssetKind::kGltfJson));
  }
  SUBCASE("output glb by parameter and by Accept") {
    auto by_param = cli->Post("/seam?output=glb", "ok:p", "model/gltf-binary");
    REQUIRE(by_param);
    CHECK(by_param->status == 200);
    CHECK(by_param->get_header_value("Content-Type") == "model/gltf-binary");
    CHECK(by_param->body == "glTF-scripted:p");
    auto by_accept = cli->Post("/seam", {{"Accept", "model/gltf-binary"}}, "ok:a", "model/gltf-binary");
    REQUIRE(by_accept);
    CHECK(by_accept->get_header_value("Content-Type") == "model/gltf-binary");
    CHECK(by_accept->body == "glTF-scripted:a");
    auto refused = cli->Post("/seam", {{"Accept", "application/json, model/gltf-binary;q=0"}}, "ok:j", "model/gltf-binary");
    REQUIRE(refused);
    CHECK(refused->get_header_value("Content-Type") == "application/json");
  }
  SUBCASE("an explicit output parameter wins over Accept, which only chooses without one") {
    // Accept used to override ?output: JSON asked for by name came back as GLB, GLB as SVG.
    auto json_wins = cli->Post("/seam?output=json", {{"Accept", "model/gltf-binary"}}, "ok:j", "model/gltf-binary");
    REQUIRE(json_wins);
    CHECK(json_wins->status == 200);
    CHECK(json_wins->get_header_value("Content-Type") == "application/json");
    CHECK(parse(json_wins->body)["glb"] == false);
    auto glb_wins = cli->Post("/seam?output=glb", {{"Accept", "image/svg+xml"}}, "ok:g", "model/gltf-binary");
    REQUIRE(glb_wins);
    CHECK(glb_wins->get_header_value("Content-Type") == "model/gltf-binary");
    CHECK(glb_wins->body == "glTF-scripted:g");
    auto json_refused =
        cli->Post("/seam?output=json", {{"Accept", "application/json;q=0"}}, "ok:k", "model/gltf-binary");
    REQUIRE(json_refused);
    CHECK(json_refused->status == 200);
    CHECK(json_refused->get_header_value("Content-Type") == "application/json");
  }
  SUBCASE("Accept with application/json at q=0 and nothing else acceptable is a 406") {
    for (const char* accept : {"application/json;q=0", "application/json; q=0.000, model/gltf-binary;q=0",
                               "text/html, application/json;Q=0"}) {
      CAPTURE(accept);
      auto r = cli->Post("/seam", {{"Accept", accept}}, "ok:n", "model/gltf-binary");
      REQUIRE(r);
      CHECK(r->status == 406);
      CHECK(parse(r->body)["error"]["code"] == "not_acceptable");
    }
    auto glb = cli->Post("/seam", {{"Accept", "application/json;q=0, model/gltf-binary"}}, "ok:b", "model/gltf-binary");
    REQUIRE(glb);
    CHECK(glb->status == 200);
    CHECK(glb->get_header_value("Content-Type") == "model/gltf-binary");
  }
}

TEST_CASE("every client error status of the contract, as a JSON error body") {
  auto config = test_config();
  config.max_body_bytes = 64 * 1024;
  RunningServer srv(config, ScriptedJob{}.job());
  auto cli = srv.client();

  struct Case {
    const char* name;
    httplib::Result result;
    int status;
    const char* code;
  };
  std::vector<Case> cases;
  cases.push_back({"bad JSON", cli->Post("/seam", "{not json", "application/json"), 400, "malformed_request"});
  cases.push_back({"JSON without mesh", cli->Post("/seam", R"({"extrema":[1]})", "application/json"), 400,
                   "malformed_request"});
  cases.push_back({"bad base64", cli->Post("/seam", R"({"mesh":{"glb_base64":"@@@@"}})", "application/json"), 400,
                   "malformed_request"});
  cases.push_back({"unknown parameter", cli->Post("/seam?metod=mst", "ok:x", "model/gltf-binary"), 400,
                   "invalid_parameter"});
  cases.push_back({"multipart without mesh", cli->Post("/seam", httplib::MultipartFormDataItems{{"params", "{}", "", ""}}),
                   400, "malformed_request"});
  cases.push_back({"broken multipart", cli->Post("/seam", "garbage", "multipart/form-data; boundary=xyz"), 400,
                   "malformed_request"});
  cases.push_back({"empty body", cli->Post("/seam", "", "model/gltf-binary"), 400, "malformed_request"});
  cases.push_back({"unknown route", cli->Get("/seams"), 404, "not_found"});
  cases.push_back({"GET /seam", cli->Get("/seam"), 405, "method_not_allowed"});
  cases.push_back({"DELETE /healthz", cli->Delete("/healthz"), 405, "method_not_allowed"});
  cases.push_back({"too large", cli->Post("/seam", std::string(100 * 1024, 'x'), "model/gltf-binary"), 413,
                   "payload_too_large"});
  cases.push_back({"unsupported type", cli->Post("/seam", "ok:x", "text/plain"), 415, "unsupported_media_type"});
  cases.push_back({"job rejects", cli->Post("/seam", "reject", "model/gltf-binary"), 422, "extremum_out_of_range"});
  cases.push_back({"job throws", cli->Post("/seam", "throw", "model/gltf-binary"), 500, "internal"});

  for (auto& c : cases) {
    CAPTURE(c.name);
    REQUIRE(c.result);
    CHECK(c.result->status == c.status);
    CHECK(c.result->get_header_value("Content-Type").find("application/json") == 0);
    CHECK(error_code_of(c.result->body) == c.code);
    const auto body = parse(c.result->body);
    CHECK(body["error"]["message"].get<std::string>().size() > 10);
    CHECK(c.result->has_header("X-Request-Id"));
  }
  auto get_seam = cli->Get("/seam");
  REQUIRE(get_seam);
  CHECK(get_seam->get_header_value("Allow") == "POST, OPTIONS");  // as OPTIONS /seam says

  // After every failure, including the job's exception, the server still serves.
  auto after = srv.client()->Post("/seam", "ok:after", "model/gltf-binary");
  REQUIRE(after);
  CHECK(after->status == 200);
  CHECK(srv.server().metrics().count("/seam", 500) == 1);
  CHECK(srv.server().metrics().count("other", 404) == 1);
}

TEST_CASE("a full pool answers 503 with Retry-After at once, and nothing is lost") {
  auto config = test_config();
  config.workers = 1;
  config.queue = 1;
  ScriptedJob scripted;
  RunningServer srv(config, scripted.job());

  constexpr int kClients = 10;
  std::vector<std::future<std::pair<int, std::string>>> answers;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < kClients; ++i) {
    answers.push_back(std::async(std::launch::async, [&srv, i] {
      auto cli = srv.client(20);
      auto r = cli->Post("/seam", "sleep:300", "model/gltf-binary");
      if (!r) return std::make_pair(-static_cast<int>(r.error()), std::string());
      (void)i;
      return std::make_pair(r->status, r->get_header_value("Retry-After"));
    }));
  }
  int ok = 0;
  int busy = 0;
  for (auto& a : answers) {
    REQUIRE(a.wait_for(15s) == std::future_status::ready);  // none hangs
    const auto [status, retry_after] = a.get();
    CHECK((status == 200 || status == 503));
    if (status == 200) ++ok;
    if (status == 503) {
      ++busy;
      CHECK(retry_after == "1");
    }
  }
  const auto elapsed = std::chrono::steady_clock::now() - t0;
  CHECK(ok + busy == kClients);
  CHECK(ok >= 2);    // one running plus one queued at least
  CHECK(busy >= 1);  // 10 clients at once cannot all fit in 1 worker + 1 queue slot
  CHECK(*scripted.started == ok);  // refused requests never reached a worker
  // 503s are immediate; only admitted jobs take time (ok * 300 ms, serially).
  CHECK(elapsed < std::chrono::milliseconds(300 * ok + 3000));

  auto ready = srv.client()->Get("/readyz");
  REQUIRE(ready);
  CHECK(ready->status == 200);
}

TEST_CASE("/readyz stays 200 (busy) while the pool is full, and 503 once full for longer than the budget") {
  auto config = test_config();
  config.workers = 1;
  config.queue = 0;
  config.time_budget = std::chrono::milliseconds(600);
  config.health_port = 0;
  RunningServer srv(config, ScriptedJob{}.job());
  // The job ignores its token and runs past its budget: the pool stays full for > 600 ms.
  auto running = std::async(std::launch::async, [&srv] { return srv.client()->Post("/seam", "hang:1500", "model/gltf-binary"); });
  bool saw_busy = false, saw_overloaded = false;
  for (int i = 0; i < 300 && !saw_overloaded; ++i) {
    auto r = srv.client()->Get("/readyz");
    REQUIRE(r);
    const auto status = parse(r->body)["status"];
    if (status == "busy") {
      saw_busy = true;
      CHECK(r->status == 200);  // a busy pod stays in the Service: its 503 + Retry-After is the backpressure
    }
    if (status == "overloaded") {
      saw_overloaded = true;
      CHECK(r->status == 503);
    }
    std::this_thread::sleep_for(5ms);
  }
  CHECK(saw_busy);
  CHECK(saw_overloaded);
  running.get();
  // Free again: ready.
  for (int i = 0; i < 200; ++i) {
    auto r = srv.client()->Get("/readyz");
    if (r && r->status == 200 && parse(r->body)["status"] == "ready") break;
    std::this_thread::sleep_for(10ms);
  }
  auto r = srv.client()->Get("/readyz");
  REQUIRE(r);
  CHECK(r->status == 200);
}

TEST_CASE("--health-port answers /healthz and /readyz on its own listener") {
  auto config = test_config();
  config.health_port = 0;
  {
    RunningServer srv(config);
    CHECK(srv.server().health_port() == -1);
  }
  const int probe_port = seam::test_process::free_port();
  config.health_port = probe_port;
  RunningServer srv(config);
  CHECK(srv.server().health_port() == probe_port);
  httplib::Client probe("127.0.0.1", probe_port);
  auto h = probe.Get("/healthz");
  REQUIRE(h);
  CHECK(h->status == 200);
  auto r = probe.Get("/readyz");
  REQUIRE(r);
  CHECK(r->status == 200);
  auto seam = probe.Post("/seam", "x", "model/gltf-binary");
  REQUIRE(seam);
  CHECK(seam->status == 404);  // probes only
}

TEST_CASE("time budget: 504, and the worker is free for the next request") {
  auto config = test_config();
  config.workers = 1;
  config.queue = 0;
  config.time_budget = 300ms;
  ScriptedJob scripted;
  RunningServer srv(config, scripted.job());
  auto cli = srv.client();

  SUBCASE("a job that polls its token stops at the deadline") {
    const auto t0 = std::chrono::steady_clock::now();
    auto slow = cli->Post("/seam", "sleep:20000", "model/gltf-binary");
    const auto took = std::chrono::steady_clock::now() - t0;
    REQUIRE(slow);
    CHECK(slow->status == 504);
    CHECK(error_code_of(slow->body) == "timeout");
    CHECK(took < 3s);
    // workers = 1 and queue = 0: this is admitted only if the cancelled job released its worker.
    auto next = cli->Post("/seam", "ok:next", "model/gltf-binary");
    REQUIRE(next);
    CHECK(next->status == 200);
    CHECK(parse(next->body)["echo"] == "next");
  }
  SUBCASE("a job that ignores its token still gets its client a 504 on time") {
    const auto t0 = std::chrono::steady_clock::now();
    auto slow = cli->Post("/seam", "hang:1500", "model/gltf-binary");
    const auto took = std::chrono::steady_clock::now() - t0;
    REQUIRE(slow);
    CHECK(slow->status == 504);
    CHECK(took < 1200ms);
    // Its worker is released when the job returns; meanwhile the pool is honest about it.
    for (int i = 0; i < 300 && *scripted.finished < 1; ++i) std::this_thread::sleep_for(10ms);
    auto next = cli->Post("/seam", "ok:next", "model/gltf-binary");
    REQUIRE(next);
    CHECK(next->status == 200);
  }
}

TEST_CASE("shutdown: no new work, in-flight requests complete, run() returns") {
  auto config = test_config();
  config.workers = 2;
  ScriptedJob scripted;
  RunningServer srv(config, scripted.job());

  std::vector<std::future<httplib::Result>> in_flight;
  for (int i = 0; i < 2; ++i) {
    in_flight.push_back(std::async(std::launch::async, [&srv] {
      return srv.client()->Post("/seam", "sleep:700", "model/gltf-binary");
    }));
  }
  for (int i = 0; i < 500 && *scripted.started < 2; ++i) std::this_thread::sleep_for(2ms);
  REQUIRE(*scripted.started == 2);

  const auto t0 = std::chrono::steady_clock::now();
  srv.server().shutdown();  // what SIGTERM does in seamd
  // New connections are refused once the listener is closed.
  std::this_thread::sleep_for(50ms);
  auto late = srv.client()->Get("/healthz");
  CHECK(!late);
  srv.stop();  // joins run(): it returns only after in-flight work was answered
  CHECK(std::chrono::steady_clock::now() - t0 < 5s);
  for (auto& f : in_flight) {
    auto r = f.get();
    REQUIRE(r);
    CHECK(r->status == 200);
  }
  CHECK(*scripted.finished == 2);
}

TEST_CASE("shutdown: work still running after the drain timeout is cancelled with 504") {
  auto config = test_config();
  config.drain_timeout_s = 1;  // 0 would mean "the time budget + 5 s"
  ScriptedJob scripted;
  RunningServer srv(config, scripted.job());
  auto job = std::async(std::launch::async, [&srv] { return srv.client()->Post("/seam", "sleep:30000", "model/gltf-binary"); });
  for (int i = 0; i < 500 && *scripted.started < 1; ++i) std::this_thread::sleep_for(2ms);
  REQUIRE(*scripted.started == 1);
  const auto t0 = std::chrono::steady_clock::now();
  srv.stop();
  CHECK(std::chrono::steady_clock::now() - t0 < 5s);
  auto r = job.get();
  REQUIRE(r);
  CHECK(r->status == 504);
  CHECK(r->body.find("drain") != std::string::npos);  // the message names the drain, not the budget
}

}  // namespace seam_server_test
