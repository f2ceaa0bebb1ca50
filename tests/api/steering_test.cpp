// Seeing and steering the seam (API.md v2, the paper's §6 and Fig. 10) through the pipeline:
// hide_from moves the seam out of a camera's sight, extrema stay leaves, optimal is the optimum
// of the weighted problem, _SEAM_COST steers by a painted attribute.
#include <doctest/doctest.h>

#include <map>
#include <set>

#include "api/gltf_reader.h"
#include "api/gltf_writer.h"
#include "api/pipeline.h"
#include "api/sample_mesh.h"
#include "test_data.h"

namespace seam_steering_test {

namespace {

using namespace seam;
using namespace seam::api;
using nlohmann::json;
using test_data::load_cgal;

json run_ok(const std::string& asset, const json& params) {
  auto p = params_from_json(params);
  REQUIRE_MESSAGE(p.ok(), (p.ok() ? "" : p.error().message));
  auto out = run_seam_pipeline(asset, AssetKind::kAuto, *p, {}, core::CancelToken::none());
  REQUIRE_MESSAGE(out.ok(), (out.ok() ? "" : out.error().message));
  return out->body;
}

// Every extremum is a leaf of the seam: exactly one seam edge at it.
void check_leaves(const json& seam) {
  std::map<std::uint32_t, int> degree;
  for (const auto& e : seam["edges"]) {
    ++degree[e[0].get<std::uint32_t>()];
    ++degree[e[1].get<std::uint32_t>()];
  }
  for (const auto& x : seam["extrema"]) CHECK(degree[x.get<std::uint32_t>()] == 1);
}

// The elephant painted expensive (20) on the half above its mean y, cheap (1) below, as
// written with and without the paint.
struct PaintedElephant {
  core::IndexedMesh mesh = load_cgal("elephant");
  std::vector<float> cost;
  std::string painted;
  std::string plain;

  PaintedElephant() {
    double mid = 0;
    for (const auto& p : mesh.positions) mid += p.y() / static_cast<double>(mesh.positions.size());
    for (const auto& p : mesh.positions) cost.push_back(p.y() > mid ? 20.0f : 1.0f);
    auto with_paint = write_plain_glb(mesh, {make_float_attribute("_SEAM_COST", 1, cost)});
    auto without = write_plain_glb(mesh);
    REQUIRE(with_paint.ok());
    REQUIRE(without.ok());
    painted = std::move(with_paint).value();
    plain = std::move(without).value();
  }

  // The painted weighted length of a seam's edges but the cut graph's (which opens the
  // elephant's three handles and is not steered), computed here from the paint.
  double painted_cost(const json& seam) const {
    double c = 0;
    const std::set<json> cut_graph(seam["cut_graph_edges"].begin(), seam["cut_graph_edges"].end());
    for (const auto& e : seam["edges"]) {
      if (cut_graph.count(e)) continue;
      const auto a = e[0].get<std::size_t>(), b = e[1].get<std::size_t>();
      c += (mesh.positions[a] - mesh.positions[b]).norm() * 0.5 * (cost[a] + cost[b]);
    }
    return c;
  }
};

}  // namespace

TEST_CASE("hide_from: the view that sees most of the default seam sees much less of the hidden one") {
  const auto mesh = load_cgal("elephant");
  auto glb = write_plain_glb(mesh);
  REQUIRE(glb.ok());
  const json axes = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  // The default seam, as each axis view sees it.
  double worst_seen = -1;
  json worst_view;
  for (const auto& view : axes) {
    const json measured = run_ok(*glb, {{"hide_from", {view}}, {"hide_strength", 0}});
    const double seen = measured["seam"]["visible_length"].get<double>();
    if (seen > worst_seen) {
      worst_seen = seen;
      worst_view = view;
    }
  }
  const json plain = run_ok(*glb, json::object());
  const json hidden = run_ok(*glb, {{"hide_from", {worst_view}}});
  CAPTURE(worst_view.dump());
  const double seen = hidden["seam"]["visible_length"].get<double>();
  const double length = hidden["seam"]["length"].get<double>();
  MESSAGE("elephant, view " << worst_view.dump() << ": seen " << worst_seen << " -> " << seen << " at length "
                            << plain["seam"]["length"].get<double>() << " -> " << length);
  CHECK(seen < 0.5 * worst_seen);
  CHECK(length < 1.6 * plain["seam"]["length"].get<double>());
  CHECK(hidden["seam"]["extrema"] == plain["seam"]["extrema"]);
  check_leaves(hidden["seam"]);
  CHECK(hidden["seam"]["cost"].get<double>() >= length);
  CHECK(plain["seam"]["cost"].get<double>() == doctest::Approx(plain["seam"]["length"].get<double>()));
  CHECK(!plain["seam"].contains("visible_length"));
  // hide_strength 0 changes nothing.
  const json zero = run_ok(*glb, {{"hide_from", {worst_view}}, {"hide_strength", 0}});
  CHECK(zero["seam"]["edges"] == plain["seam"]["edges"]);
}

TEST_CASE("hide_from: a huge or tiny finite direction steers exactly like its unit direction") {
  // [[1e200, 1e200, 1e200]] used to overflow while normalising: nothing was seen, the seam
  // was not steered and cost == length; [[1e-200, ...]] underflowed and was refused.
  auto glb = sample_glb();
  REQUIRE(glb.ok());
  const json unit = run_ok(*glb, {{"hide_from", {{1, 1, 1}}}});
  CHECK(unit["seam"]["visible_length"].get<double>() > 0);
  CHECK(unit["seam"]["cost"].get<double>() > unit["seam"]["length"].get<double>());
  for (const double scale : {1e200, 1e-200, 1e308}) {
    CAPTURE(scale);
    const json scaled = run_ok(*glb, {{"hide_from", {{scale, scale, scale}}}});
    CHECK(scaled["seam"]["edges"] == unit["seam"]["edges"]);
    CHECK(scaled["seam"]["visible_length"] == unit["seam"]["visible_length"]);
    CHECK(scaled["seam"]["cost"] == unit["seam"]["cost"]);
  }
  for (const json& bad : {json{{0, 0, 0}}, json{{0.0, -0.0, 0}}}) {
    auto p = params_from_json({{"hide_from", {bad}}});
    REQUIRE(!p.ok());
    CHECK(p.error().code == ApiErrorCode::kInvalidParameter);
    CHECK(p.error().details["parameter"] == "hide_from");
  }
}

TEST_CASE("method optimal minimises the weighted length: no method costs less, extrema leaves") {
  const auto mesh = load_cgal("elephant");
  auto glb = write_plain_glb(mesh);
  REQUIRE(glb.ok());
  const json steer = {{"hide_from", {{0, 0, -1}}}, {"hide_occluded", true}, {"extrema", {{"auto", true}, {"max_count", 5}}}};
  json params = steer;
  params["method"] = "optimal";
  const json optimal = run_ok(*glb, params);
  CHECK(optimal["seam"]["optimal"] == true);
  check_leaves(optimal["seam"]);
  for (const char* method : {"skeleton", "mst", "greedy"}) {
    CAPTURE(method);
    params["method"] = method;
    const json other = run_ok(*glb, params);
    check_leaves(other["seam"]);
    CHECK(other["seam"]["extrema"] == optimal["seam"]["extrema"]);
    CHECK(other["seam"]["cost"].get<double>() >= optimal["seam"]["cost"].get<double>() * (1 - 1e-9));
  }
}

TEST_CASE("_SEAM_COST: a painted expensive half makes the seam cheaper under the paint, extrema kept") {
  PaintedElephant e;
  const json plain = run_ok(e.plain, json::object());
  const json steered = run_ok(e.painted, json::object());
  MESSAGE("painted cost of the seam: " << e.painted_cost(plain["seam"]) << " -> " << e.painted_cost(steered["seam"])
                                       << ", length " << plain["seam"]["length"].get<double>() << " -> "
                                       << steered["seam"]["length"].get<double>());
  CHECK(steered["seam"]["cost"].get<double>() == doctest::Approx(e.painted_cost(steered["seam"])));
  CHECK(e.painted_cost(steered["seam"]) < 0.9 * e.painted_cost(plain["seam"]));
  CHECK(steered["seam"]["extrema"] == plain["seam"]["extrema"]);
  check_leaves(steered["seam"]);
  // Negative or non-finite costs are the asset's defect.
  e.cost[3] = -1.0f;
  auto bad = write_plain_glb(e.mesh, {make_float_attribute("_SEAM_COST", 1, e.cost)});
  REQUIRE(bad.ok());
  auto p = params_from_json(json::object());
  auto refused = run_seam_pipeline(*bad, AssetKind::kAuto, *p, {}, core::CancelToken::none());
  REQUIRE(!refused.ok());
  CHECK(refused.error().code == ApiErrorCode::kMalformedAsset);
  CHECK(refused.error().details["vertex"] == 3);
}

TEST_CASE("charts features: _SEAM_COST and hide_from steer the seam of every side too") {
  // The seam runs on the surface cut along its sharp edges, which has more edges than the
  // surface: each side's edge takes the cost of the edge it came from (before, a 400). The
  // feature edges are the same in both runs, so the painted costs differ by the seams'.
  PaintedElephant e;
  const json features = {{"charts", "features"}};  // 60 degrees: 18 sharp edges on the elephant
  const json plain = run_ok(e.plain, features);
  const json steered = run_ok(e.painted, features);
  REQUIRE(plain["seam"]["feature_edges"].get<int>() > 0);
  CHECK(steered["seam"]["feature_edges"] == plain["seam"]["feature_edges"]);
  CHECK(steered["seam"]["extrema"] == plain["seam"]["extrema"]);
  MESSAGE("features, painted cost " << e.painted_cost(plain["seam"]) << " -> " << e.painted_cost(steered["seam"]));
  CHECK(e.painted_cost(steered["seam"]) < 0.95 * e.painted_cost(plain["seam"]));  // 0.89 measured
  CHECK(steered["seam"]["cost"].get<double>() > steered["seam"]["length"].get<double>());
  CHECK(plain["seam"]["cost"].get<double>() == doctest::Approx(plain["seam"]["length"].get<double>()));

  // Hidden from the axis view that sees most of it.
  double worst_seen = -1;
  json worst_view;
  for (const json& view :
       {json{1, 0, 0}, json{-1, 0, 0}, json{0, 1, 0}, json{0, -1, 0}, json{0, 0, 1}, json{0, 0, -1}}) {
    json params = features;
    params["hide_from"] = {view};
    params["hide_strength"] = 0;
    const json measured = run_ok(e.plain, params);
    CHECK(measured["seam"]["edges"] == plain["seam"]["edges"]);
    if (measured["seam"]["visible_length"].get<double>() > worst_seen) {
      worst_seen = measured["seam"]["visible_length"].get<double>();
      worst_view = view;
    }
  }
  json params = features;
  params["hide_from"] = {worst_view};
  const json hidden = run_ok(e.plain, params);
  MESSAGE("features, seen from " << worst_view.dump() << ": " << worst_seen << " -> "
                                 << hidden["seam"]["visible_length"].get<double>());
  CHECK(hidden["seam"]["visible_length"].get<double>() < 0.8 * worst_seen);
}

}  // namespace seam_steering_test
