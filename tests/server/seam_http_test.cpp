// End-to-end: the real pipeline behind the real server on 127.0.0.1, spoken to over HTTP.
// Inputs are a CGAL mesh turned into GLB here and the bundled sample (`seamd sample`).
// Eigen-heavy headers first: httplib.h (in the harness) must come after them.
#include "api/base64.h"
#include "api/cli.h"
#include "api/gltf_writer.h"
#include "api/pipeline.h"
#include "server/request.h"
#include "test_data.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <future>
#include <sstream>

#include "server_harness.h"

namespace seam_seam_http_test {

namespace {

using namespace std::chrono_literals;
using seam::test_server::error_code_of;
using seam::test_server::RunningServer;
using seam::test_server::test_config;
namespace fs = std::filesystem;

struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("seam_http_test_" + std::to_string(::getpid()) + "_" +
                                        std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()));
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_file(const fs::path& p, const std::string& bytes) {
  std::ofstream out(p, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::uint32_t le32(const std::string& s, std::size_t at) {
  return static_cast<std::uint32_t>(static_cast<unsigned char>(s[at])) |
         static_cast<std::uint32_t>(static_cast<unsigned char>(s[at + 1])) << 8 |
         static_cast<std::uint32_t>(static_cast<unsigned char>(s[at + 2])) << 16 |
         static_cast<std::uint32_t>(static_cast<unsigned char>(s[at + 3])) << 24;
}

// The same asset as .gltf JSON with its one buffer as a data URI (request forms 2b and 3b).
nlohmann::json glb_to_gltf(const std::string& glb) {
  REQUIRE(glb.size() >= 20);
  REQUIRE(glb.compare(0, 4, "glTF") == 0);
  const auto json_len = le32(glb, 12);
  auto json = nlohmann::json::parse(glb.substr(20, json_len));
  const auto bin_at = 20 + json_len;
  REQUIRE(glb.size() >= bin_at + 8);
  const auto bin_len = le32(glb, bin_at);
  const auto bin = glb.substr(bin_at + 8, bin_len);
  REQUIRE(json["buffers"].size() == 1);
  json["buffers"][0]["uri"] = "data:application/octet-stream;base64," + seam::api::encode_base64(bin);
  return json;
}

// Runs `seamd seam ...` in process, as the CLI would, and returns its JSON.
nlohmann::json run_cli_seam(const fs::path& mesh, const std::string& extrema) {
  std::vector<std::string> args = {"seam", "--mesh", mesh.string(), "--extrema", extrema, "--uv", "none"};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  std::ostringstream out;
  std::ostringstream err;
  const int rc = seam::api::run_cli(static_cast<int>(argv.size()), argv.data(), out, err);
  REQUIRE_MESSAGE(rc == 0, err.str());
  return nlohmann::json::parse(out.str());
}

int validator_errors(const fs::path& file) {
  const std::string script = std::string(SEAM_SOURCE_DIR) + "/tests/validate_gltf.js";
  const std::string cmd = "node " + script + " " + file.string() + " > " + file.string() + ".report 2>&1";
  const int rc = std::system(cmd.c_str());
  const int code = WIFEXITED(rc) ? WEXITSTATUS(rc) : 127;
  if (code == 101 || code == 127) {
    FAIL("glTF-Validator unavailable: run `npm install --prefix " << SEAM_SOURCE_DIR << "/tests`");
  }
  INFO(read_file(file.string() + ".report"));
  return code;
}

nlohmann::json parse(const std::string& body) {
  auto j = nlohmann::json::parse(body, nullptr, false);
  REQUIRE_MESSAGE(!j.is_discarded(), body.substr(0, 400));
  return j;
}

// Hand (CGAL, 1197 vertices, 2390 faces) with five extrema spread over its index range.
constexpr const char* kHandExtrema = "12,300,611,902,1180";

struct HandAsset {
  std::string glb;
  nlohmann::json gltf;
};

const HandAsset& hand() {
  static const HandAsset asset = [] {
    auto mesh = seam::test_data::load_cgal("hand");
    auto glb = seam::api::write_plain_glb(mesh);
    REQUIRE(glb.ok());
    HandAsset a{glb.value(), nlohmann::json()};
    a.gltf = glb_to_gltf(a.glb);
    return a;
  }();
  return asset;
}

}  // namespace

TEST_CASE("POST /seam: every request form on a real mesh gives the CLI's seam") {
  TempDir tmp;
  const auto& asset = hand();
  write_file(tmp.path / "hand.glb", asset.glb);
  const auto cli_result = run_cli_seam(tmp.path / "hand.glb", kHandExtrema);
  const auto& expected = cli_result["seam"];
  REQUIRE(!expected["edges"].empty());

  RunningServer srv(test_config());
  auto cli = srv.client();
  const nlohmann::json params = {{"extrema", {12, 300, 611, 902, 1180}}, {"uv", "none"}};

  std::vector<std::pair<std::string, httplib::Result>> answers;
  answers.emplace_back("raw GLB + query",
                       cli->Post((std::string("/seam?uv=none&extrema=") + kHandExtrema).c_str(), asset.glb,
                                 "model/gltf-binary"));
  answers.emplace_back("raw glTF JSON + query",
                       cli->Post((std::string("/seam?uv=none&extrema=") + kHandExtrema).c_str(), asset.gltf.dump(),
                                 "model/gltf+json"));
  answers.emplace_back("multipart",
                       cli->Post("/seam", httplib::MultipartFormDataItems{
                                              {"mesh", asset.glb, "hand.glb", "application/octet-stream"},
                                              {"params", params.dump(), "", "application/json"}}));
  auto b64 = params;
  b64["mesh"] = {{"glb_base64", seam::api::encode_base64(asset.glb)}};
  answers.emplace_back("JSON glb_base64", cli->Post("/seam", b64.dump(), "application/json"));
  auto gltf = params;
  gltf["mesh"] = {{"gltf", asset.gltf}};
  answers.emplace_back("JSON gltf", cli->Post("/seam", gltf.dump(), "application/json"));

  for (auto& [name, r] : answers) {
    CAPTURE(name);
    REQUIRE(r);
    REQUIRE_MESSAGE(r->status == 200, r->body.substr(0, 400));
    const auto body = parse(r->body);
    CHECK(body["seam"]["edges"] == expected["edges"]);
    CHECK(body["seam"]["terminals"] == expected["terminals"]);
    CHECK(body["seam"]["length"].get<double>() == doctest::Approx(expected["length"].get<double>()));
    CHECK(body["mesh"]["faces"] == 2390);
    CHECK(body["cut"]["euler_characteristic"] == 1);
    CHECK(body["cut"]["boundary_loops"] == 1);
    REQUIRE(body.contains("asset"));
    CHECK(body["asset"]["glb_base64"].get<std::string>().size() > 1000);
  }
}

TEST_CASE("POST /seam: GLB output on the bundled sample passes the glTF-Validator") {
  TempDir tmp;
  {
    std::string out_arg = (tmp.path / "sample.glb").string();
    std::vector<std::string> args = {"sample", "--out", out_arg};
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    std::ostringstream out;
    std::ostringstream err;
    REQUIRE_MESSAGE(seam::api::run_cli(static_cast<int>(argv.size()), argv.data(), out, err) == 0, err.str());
  }
  const auto sample = read_file(tmp.path / "sample.glb");
  REQUIRE(sample.size() > 100);

  RunningServer srv(test_config());
  auto cli = srv.client();
  // The sample ships with automatic extrema and the default UV method: the smoke test's call.
  auto json = cli->Post("/seam", sample, "model/gltf-binary");
  REQUIRE(json);
  REQUIRE_MESSAGE(json->status == 200, json->body.substr(0, 400));
  const auto body = parse(json->body);
  CHECK(body["seam"]["extrema"].size() >= 2);
  CHECK(body["cut"]["euler_characteristic"] == 1);

  auto glb = cli->Post("/seam", {{"Accept", "model/gltf-binary"}}, sample, "model/gltf-binary");
  REQUIRE(glb);
  REQUIRE(glb->status == 200);
  CHECK(glb->get_header_value("Content-Type") == "model/gltf-binary");
  REQUIRE(glb->body.compare(0, 4, "glTF") == 0);
  write_file(tmp.path / "cut.glb", glb->body);
  CHECK(validator_errors(tmp.path / "cut.glb") == 0);
  // The JSON form's asset is the same GLB.
  auto decoded = seam::api::decode_base64(body["asset"]["glb_base64"].get<std::string>());
  REQUIRE(decoded.ok());
  CHECK(decoded.value() == glb->body);
}

TEST_CASE("POST /seam: 422s from the pipeline through HTTP") {
  const auto& asset = hand();
  auto config = test_config();
  config.max_faces = 1000;
  RunningServer small(config);
  auto too_large = small.client()->Post("/seam?extrema=1,2", asset.glb, "model/gltf-binary");
  REQUIRE(too_large);
  CHECK(too_large->status == 422);
  CHECK(error_code_of(too_large->body) == "mesh_too_large");
  CHECK(too_large->body.find("1000") != std::string::npos);  // the limit is in the message

  RunningServer srv(test_config());
  auto cli = srv.client();
  auto out_of_range = cli->Post("/seam?extrema=1,5000", asset.glb, "model/gltf-binary");
  REQUIRE(out_of_range);
  CHECK(out_of_range->status == 422);
  CHECK(error_code_of(out_of_range->body) == "extremum_out_of_range");

  auto external = asset.gltf;
  external["buffers"][0]["uri"] = "../../../../etc/passwd";
  auto ext = cli->Post("/seam?extrema=1,2", external.dump(), "model/gltf+json");
  REQUIRE(ext);
  CHECK(ext->status == 422);
  CHECK(error_code_of(ext->body) == "external_uri");

  auto garbage = cli->Post("/seam?extrema=1,2", std::string("glTF\x02\0\0\0garbage", 15), "model/gltf-binary");
  REQUIRE(garbage);
  CHECK(garbage->status == 400);
  CHECK(error_code_of(garbage->body) == "malformed_asset");
}

TEST_CASE("POST /seam: many clients on a small queue: 200 or 503, results equal the serial one") {
  const auto& asset = hand();
  auto config = test_config();
  config.workers = 2;
  config.queue = 2;
  RunningServer srv(config);
  const std::string path = std::string("/seam?uv=none&extrema=") + kHandExtrema;
  auto serial = srv.client()->Post(path.c_str(), asset.glb, "model/gltf-binary");
  REQUIRE(serial);
  REQUIRE(serial->status == 200);
  const auto expected = parse(serial->body)["seam"];

  constexpr int kClients = 12;
  std::vector<std::future<httplib::Result>> answers;
  for (int i = 0; i < kClients; ++i) {
    answers.push_back(std::async(std::launch::async, [&] { return srv.client(60)->Post(path.c_str(), asset.glb, "model/gltf-binary"); }));
  }
  int ok = 0;
  int busy = 0;
  for (auto& a : answers) {
    REQUIRE(a.wait_for(120s) == std::future_status::ready);
    auto r = a.get();
    REQUIRE(r);  // every request answered: no dropped connection
    CHECK((r->status == 200 || r->status == 503));
    if (r->status == 200) {
      ++ok;
      CHECK(parse(r->body)["seam"] == expected);
    } else {
      ++busy;
      CHECK(r->has_header("Retry-After"));
    }
  }
  CHECK(ok + busy == kClients);
  CHECK(ok >= 2);
  auto health = srv.client()->Get("/healthz");
  REQUIRE(health);
  CHECK(health->status == 200);
}

TEST_CASE("POST /seam: a budget too small for the job is a 504, promptly") {
  const auto& asset = hand();
  auto config = test_config();
  config.time_budget = 2ms;
  config.workers = 1;
  RunningServer srv(config);
  const auto t0 = std::chrono::steady_clock::now();
  auto r = srv.client()->Post((std::string("/seam?extrema=") + kHandExtrema).c_str(), asset.glb, "model/gltf-binary");
  REQUIRE(r);
  CHECK(r->status == 504);
  CHECK(error_code_of(r->body) == "timeout");
  CHECK(std::chrono::steady_clock::now() - t0 < 5s);
}

}  // namespace seam_seam_http_test
