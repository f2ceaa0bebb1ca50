// The routes beside POST /seam that serve files: the viewer (GET /, its script and
// stylesheet), GET /openapi.json and GET /sample.glb, against a real server on 127.0.0.1.
#include "api/error.h"
#include "api/sample_mesh.h"
#include "server/web_assets.h"

#include <fstream>
#include <sstream>

#include "server_harness.h"

namespace seam_web_routes_test {

namespace {

using seam::test_server::RunningServer;
using seam::test_server::test_config;

std::string read_source_file(const std::string& relative) {
  std::ifstream in(std::string(SEAM_SOURCE_DIR) + "/" + relative, std::ios::binary);
  REQUIRE_MESSAGE(in.good(), relative);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

TEST_CASE("web: GET /openapi.json is api/openapi.json, byte for byte, and names every error code with its status") {
  RunningServer server(test_config());
  auto res = server.client()->Get("/openapi.json");
  REQUIRE(res);
  CHECK(res->status == 200);
  CHECK(res->get_header_value("Content-Type") == "application/json");
  CHECK(res->body == read_source_file("api/openapi.json"));
  const auto doc = nlohmann::json::parse(res->body);
  CHECK(doc["openapi"].get<std::string>().starts_with("3."));
  const auto& codes = doc["components"]["schemas"]["Error"]["properties"]["error"]["properties"]["code"]["enum"];
  const auto& statuses = doc["info"]["x-error-codes"];
  // Every enumerator, in declaration order from the first to kInternal, the last.
  for (int c = 0; c <= static_cast<int>(seam::api::ApiErrorCode::kInternal); ++c) {
    const auto code = static_cast<seam::api::ApiErrorCode>(c);
    const std::string name(seam::api::code_name(code));
    CAPTURE(name);
    CHECK(std::find(codes.begin(), codes.end(), name) != codes.end());
    REQUIRE(statuses.contains(name));
    CHECK(statuses[name].get<int>() == seam::api::http_status(code));
  }
  CHECK(codes.size() == static_cast<std::size_t>(seam::api::ApiErrorCode::kInternal) + 1);
}

TEST_CASE("web: the page, its script and stylesheet are served from memory with their types") {
  RunningServer server(test_config());
  auto client = server.client();
  auto page = client->Get("/");
  REQUIRE(page);
  CHECK(page->status == 200);
  CHECK(page->get_header_value("Content-Type") == "text/html; charset=utf-8");
  CHECK(page->get_header_value("X-Content-Type-Options") == "nosniff");
  const auto policy = page->get_header_value("Content-Security-Policy");
  CHECK(policy.find("default-src 'none'") != std::string::npos);
  CHECK(policy.find("script-src 'self'") != std::string::npos);
  CHECK_FALSE(page->get_header_value("X-Request-Id").empty());
  if (seam::server::viewer_built()) {
    CHECK(page->body.find("<script type=\"module\" src=\"/viewer.js\"") != std::string::npos);
    for (const auto& [path, type] : {std::pair{"/viewer.js", "text/javascript; charset=utf-8"},
                                     std::pair{"/viewer.css", "text/css; charset=utf-8"}}) {
      auto res = client->Get(path);
      REQUIRE(res);
      CHECK(res->status == 200);
      CHECK(res->get_header_value("Content-Type") == type);
      CHECK(res->body == std::string(seam::server::find_web_asset(path)->body));
    }
    // The bundle carries three.js: the page needs no other host.
    CHECK(client->Get("/viewer.js")->body.size() > 100'000);
  } else {
    CHECK(page->body.find("viewer was not built") != std::string::npos);
    CHECK(client->Get("/viewer.js")->status == 404);
  }
  CHECK(client->Head("/")->status == 200);
}

TEST_CASE("web: other methods on the file routes are 405 with Allow, near-miss paths 404") {
  RunningServer server(test_config());
  auto client = server.client();
  for (const char* path : {"/", "/openapi.json", "/sample.glb"}) {
    CAPTURE(path);
    auto res = client->Post(path, "{}", "application/json");
    REQUIRE(res);
    CHECK(res->status == 405);
    CHECK(res->get_header_value("Allow") == "GET, HEAD, OPTIONS");
    CHECK(seam::test_server::error_code_of(res->body) == "method_not_allowed");
  }
  // Route patterns are regular expressions; their dots must not match any character.
  auto res = client->Get("/openapiXjson");
  REQUIRE(res);
  CHECK(res->status == 404);
  CHECK(client->Get("/sampleXglb")->status == 404);
}

TEST_CASE("web: GET /sample.glb is the bundled sample") {
  RunningServer server(test_config());
  auto res = server.client()->Get("/sample.glb");
  REQUIRE(res);
  CHECK(res->status == 200);
  CHECK(res->get_header_value("Content-Type") == "model/gltf-binary");
  const auto expected = seam::api::sample_glb();
  REQUIRE(expected.ok());
  CHECK(res->body == expected.value());
  CHECK(res->body.substr(0, 4) == "glTF");
}

namespace {

// Whether the pipeline knows output "svg" yet (contract v2, wired by the pipeline's owner).
template <class Format = seam::api::OutputFormat>
constexpr bool pipeline_has_svg() {
  return requires { Format::kSvg; };
}

}  // namespace

TEST_CASE("web: Accept: image/svg+xml asks for the SVG UV layout") {
  RunningServer server(test_config());
  const auto sample = seam::api::sample_glb();
  REQUIRE(sample.ok());
  httplib::Headers headers{{"Accept", "image/svg+xml"}};
  auto res = server.client()->Post("/seam?extrema=auto&method=mst&uv=lscm", headers, sample.value(), "model/gltf-binary");
  REQUIRE(res);
  CHECK(res->status == 200);
  if constexpr (pipeline_has_svg()) {
    CHECK(res->get_header_value("Content-Type") == "image/svg+xml");
    CHECK(res->body.starts_with("<?xml"));
    // One polygon per face of the sample (5120), the seam marked.
    std::size_t polygons = 0;
    for (auto at = res->body.find("<polygon"); at != std::string::npos; at = res->body.find("<polygon", at + 1)) ++polygons;
    CHECK(polygons == 5120);
    CHECK(res->body.find("class=\"seam\"") != std::string::npos);
  } else {
    // Until the pipeline renders SVG the header changes nothing: the JSON answer.
    CHECK(res->get_header_value("Content-Type") == "application/json");
  }
  // q=0 is "not acceptable": JSON.
  headers = {{"Accept", "image/svg+xml;q=0"}};
  res = server.client()->Post("/seam?extrema=auto&method=mst&uv=lscm", headers, sample.value(), "model/gltf-binary");
  REQUIRE(res);
  CHECK(res->get_header_value("Content-Type") == "application/json");
}

}  // namespace seam_web_routes_test
