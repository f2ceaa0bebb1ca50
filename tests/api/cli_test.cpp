// The command line: the sample starfish and a batch seam run on GLB and OFF input.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <map>
#include <sstream>

#include "api/cli.h"
#include "api/gltf_reader.h"
#include "api/sample_mesh.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/topology.h"
#include "gltf_test_util.h"
#include "test_data.h"

namespace {

int cli(std::vector<std::string> args, std::string& out, std::string& err) {
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  std::ostringstream o, e;
  const int code = seam::api::run_cli(static_cast<int>(argv.size()), argv.data(), o, e);
  out = o.str();
  err = e.str();
  return code;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

TEST_CASE("the sample is a closed genus-0 starfish whose five tips are the seam's leaves") {
  using namespace seam;
  const auto m = api::sample_mesh();
  auto mesh = core::build_halfedge_mesh(m.positions, m.triangles);
  REQUIRE(mesh.ok());
  const auto topo = core::compute_topology(*mesh);
  CHECK(topo.components.size() == 1);
  CHECK(topo.total_genus() == 0);
  CHECK(topo.boundary_loops.empty());
  CHECK(m.triangles.size() >= 2000);
  const auto tips = api::sample_tips();
  CHECK(std::set<std::uint32_t>(tips.begin(), tips.end()).size() == 5);

  std::string out, err;
  const std::string sample = test_gltf::temp_path("sample.glb");
  const std::string cut = test_gltf::temp_path("cut.glb");
  REQUIRE_MESSAGE(cli({"sample", "--out", sample}, out, err) == 0, err);
  std::string report;
  CHECK_MESSAGE(test_gltf::validator_errors(slurp(sample), report) == 0, report);

  std::string extrema;
  for (auto t : tips) extrema += (extrema.empty() ? "" : ",") + std::to_string(t);
  REQUIRE_MESSAGE(cli({"seam", "--mesh", sample, "--extrema", extrema, "--out", cut}, out, err) == 0, err);
  const auto body = nlohmann::json::parse(out);
  CHECK(!body.contains("asset"));
  CHECK(body["seam"]["extrema"].size() == 5);
  std::map<std::uint32_t, int> degree;
  for (const auto& e : body["seam"]["edges"]) {
    ++degree[e[0].get<std::uint32_t>()];
    ++degree[e[1].get<std::uint32_t>()];
  }
  for (auto t : tips) CHECK(degree[t] == 1);  // every extremum is a leaf (method skeleton)
  CHECK(body["cut"]["euler_characteristic"] == 1);
  CHECK_MESSAGE(test_gltf::validator_errors(slurp(cut), report) == 0, report);
  std::filesystem::remove(sample);
  std::filesystem::remove(cut);
}

TEST_CASE("seamd seam reads OFF, refuses bad usage with 2 and bad input with 1") {
  std::string out, err;
  const std::string off = seam::test_data::cgal_mesh_path("hand");
  const std::string cut = seam::test_gltf::temp_path("hand_cut.glb");
  REQUIRE_MESSAGE(cli({"seam", "--mesh", off, "--uv", "none", "--method", "mst", "--extrema", "0,100", "--out", cut},
                      out, err) == 0,
                  err);
  const auto body = nlohmann::json::parse(out);
  CHECK(body["seam"]["method"] == "mst");
  CHECK(body["uv"].is_null());
  auto doc = seam::api::parse_asset(slurp(cut), seam::api::AssetKind::kGlb);
  REQUIRE(doc.ok());
  std::filesystem::remove(cut);

  CHECK(cli({"seam"}, out, err) == 2);
  CHECK(nlohmann::json::parse(err)["error"]["code"] == "invalid_parameter");
  CHECK(cli({"seam", "--mesh", off, "--method", "best"}, out, err) == 2);
  CHECK(cli({"seam", "--mesh", "/nonexistent/x.glb"}, out, err) == 1);
  CHECK(nlohmann::json::parse(err)["error"]["code"] == "malformed_asset");
  CHECK(cli({"frobnicate"}, out, err) == 2);
}
