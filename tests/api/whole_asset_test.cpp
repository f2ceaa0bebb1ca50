// Contract v2 at the pipeline: every primitive by default, the selection forms and their
// refusals, the atlas (pack groups, one texel density, overlap), charts "features", output svg.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <numeric>
#include <set>
#include <string>

#include "api/gltf_reader.h"
#include "api/gltf_writer.h"
#include "api/pipeline.h"
#include "core/uv/uv_patch.h"
#include "fixtures.h"
#include "gltf_test_util.h"
#include "test_data.h"

namespace seam_whole_asset_test {

namespace {

using namespace seam;
using namespace seam::api;
using seam::test_gltf::json;

// Three meshes: a sphere (mesh 0, "ball", material 0), a torus (mesh 1, "ring", material 1)
// drawn by two nodes, and mesh 2 ("both") with the sphere's and the torus's primitives again
// (sharing their accessors) plus a LINES primitive over the sphere's vertices.
std::string three_mesh_asset() {
  const auto ball = fixtures::icosphere(2);
  const auto ring = fixtures::translated(fixtures::torus(24, 12), core::Vec3(4, 0, 0));
  auto a = write_plain_glb(core::IndexedMesh{ball.positions, ball.triangles});
  auto b = write_plain_glb(core::IndexedMesh{ring.positions, ring.triangles});
  REQUIRE(a.ok());
  REQUIRE(b.ok());
  auto da = parse_asset(*a, AssetKind::kGlb);
  auto db = parse_asset(*b, AssetKind::kGlb);
  REQUIRE(da.ok());
  REQUIRE(db.ok());
  json j = da->json;
  std::vector<std::uint8_t> bin = da->buffers[0];
  while (bin.size() % 4) bin.push_back(0);
  const std::size_t offset = bin.size();
  bin.insert(bin.end(), db->buffers[0].begin(), db->buffers[0].end());
  const std::size_t views = j["bufferViews"].size(), accessors = j["accessors"].size();
  for (json view : db->json["bufferViews"]) {
    view["byteOffset"] = view.value("byteOffset", std::size_t{0}) + offset;
    j["bufferViews"].push_back(view);
  }
  for (json acc : db->json["accessors"]) {
    acc["bufferView"] = acc["bufferView"].get<std::size_t>() + views;
    j["accessors"].push_back(acc);
  }
  json ring_prim = db->json["meshes"][0]["primitives"][0];
  for (auto& [name, ref] : ring_prim["attributes"].items()) ref = ref.get<std::size_t>() + accessors;
  ring_prim["indices"] = ring_prim["indices"].get<std::size_t>() + accessors;
  ring_prim["material"] = 1;
  json ball_prim = j["meshes"][0]["primitives"][0];
  ball_prim["material"] = 0;
  json lines = {{"attributes", ball_prim["attributes"]}, {"mode", 1}};
  j["materials"] = {{{"name", "skin"}}, {{"name", "metal"}}};
  j["meshes"] = {{{"name", "ball"}, {"primitives", {ball_prim}}},
                 {{"name", "ring"}, {"primitives", {ring_prim}}},
                 {{"name", "both"}, {"primitives", {ball_prim, ring_prim, lines}}}};
  j["nodes"] = {{{"mesh", 0}}, {{"mesh", 1}}, {{"mesh", 1}, {"translation", {0, 3, 0}}}, {{"mesh", 2}}};
  j["scenes"] = {{{"nodes", {0, 1, 2, 3}}}};
  j["buffers"][0]["byteLength"] = bin.size();
  return encode_glb(j, bin);
}

ApiResult<PipelineOutput> run(const std::string& asset, const json& params) {
  auto p = params_from_json(params);
  REQUIRE_MESSAGE(p.ok(), (p.ok() ? "" : p.error().message));
  return run_seam_pipeline(asset, AssetKind::kAuto, *p, {}, core::CancelToken::none());
}

PipelineOutput run_ok(const std::string& asset, const json& params) {
  auto out = run(asset, params);
  REQUIRE_MESSAGE(out.ok(), (out.ok() ? "" : out.error().message));
  return std::move(out).value();
}

// The primitive's UVs of TEXCOORD_<channel> (float32 pairs), one per vertex.
std::vector<std::array<double, 2>> texcoords(const PrimitiveData& p, int channel) {
  const std::string name = "TEXCOORD_" + std::to_string(channel);
  const AttributeArray* uv = nullptr;
  for (const auto& a : p.attributes) {
    if (a.name == name) uv = &a;
  }
  REQUIRE(uv != nullptr);
  std::vector<std::array<double, 2>> out(uv->count);
  for (std::size_t v = 0; v < uv->count; ++v) {
    float x[2];
    std::memcpy(x, uv->data.data() + v * 8, 8);
    out[v] = {x[0], x[1]};
  }
  return out;
}

double uv_area(const PrimitiveData& p, int channel) {
  const std::vector<std::array<double, 2>> uv = texcoords(p, channel);
  auto at = [&](std::uint32_t v) { return uv.at(v); };
  double area = 0;
  for (const auto& t : p.mesh.triangles) {
    const auto a = at(t[0]), b = at(t[1]), c = at(t[2]);
    area += 0.5 * std::abs((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
    for (const auto& q : {a, b, c}) {
      CHECK(q[0] >= 0.0);
      CHECK(q[0] <= 1.0);
      CHECK(q[1] >= 0.0);
      CHECK(q[1] <= 1.0);
    }
  }
  return area;
}

double surface_area(const PrimitiveData& p) {
  double area = 0;
  for (const auto& t : p.mesh.triangles) {
    const auto& x = p.mesh.positions;
    area += 0.5 * (x[t[1]] - x[t[0]]).cross(x[t[2]] - x[t[0]]).norm();
  }
  return area;
}

}  // namespace

TEST_CASE("by default every triangle primitive is cut once, lines kept, the asset lean and valid") {
  const std::string asset = three_mesh_asset();
  const PipelineOutput out = run_ok(asset, json::object());
  const json& prims = out.body["primitives"];
  REQUIRE(prims.size() == 4);  // ball, ring (two nodes: once), both/0, both/1; not the lines
  const std::set<std::pair<int, int>> expected{{0, 0}, {1, 0}, {2, 0}, {2, 1}};
  std::set<std::pair<int, int>> got;
  for (const auto& p : prims) {
    got.emplace(p["mesh"].get<int>(), p["primitive"].get<int>());
    CHECK(p["uv"]["flipped"] == 0);
    CHECK(p["uv"]["overlap_area"] == 0.0);
    CHECK(p["uv"]["two_level_charts"] == 0);  // small charts: SLIM on the whole chart
    CHECK(p["cut"]["euler_characteristic"] == p["topology"]["components"]);
  }
  CHECK(got == expected);
  CHECK(prims[1]["name"] == "ring");
  CHECK(prims[1]["topology"]["genus"] == 1);
  CHECK(!out.body.contains("seam"));  // v1's top-level objects only with one primitive
  std::string report;
  CHECK_MESSAGE(test_gltf::validator_errors(out.glb, report, "whole_out.glb") == 0, report);
  CHECK_MESSAGE(report.find("UNUSED_OBJECT") == std::string::npos, report);
  auto doc = parse_asset(out.glb, AssetKind::kGlb);
  REQUIRE(doc.ok());
  // The lines primitive still reads the sphere's original vertices.
  CHECK(doc->json["meshes"][2]["primitives"][2]["mode"] == 1);
  const auto lines_positions = doc->json["meshes"][2]["primitives"][2]["attributes"]["POSITION"].get<std::size_t>();
  CHECK(doc->json["accessors"][lines_positions]["count"] == fixtures::icosphere(2).positions.size());
}

TEST_CASE("one texel density across an asset group, group_by primitive packs each alone") {
  const std::string asset = three_mesh_asset();
  for (const char* group : {"asset", "primitive", "material", "mesh"}) {
    CAPTURE(group);
    const PipelineOutput out = run_ok(asset, {{"pack", {{"group_by", group}, {"margin_px", 2}}}});
    auto doc = parse_asset(out.glb, AssetKind::kGlb);
    REQUIRE(doc.ok());
    std::vector<double> density;
    std::set<int> groups;
    for (const auto& e : out.body["primitives"]) {
      auto p = read_primitive(*doc, e["mesh"].get<std::uint32_t>(), e["primitive"].get<std::uint32_t>());
      REQUIRE(p.ok());
      density.push_back(uv_area(*p, e["uv"]["channel"].get<int>()) / surface_area(*p));
      groups.insert(e["uv"]["pack_group"].get<int>());
      CHECK(e["uv"]["overlap_area"] == 0.0);
      CHECK(e["uv"]["coverage"].get<double>() > 0.3);
    }
    const std::string g = group;
    CHECK(groups.size() == (g == "asset" ? 1u : g == "primitive" ? 4u : g == "material" ? 2u : 3u));
    if (g == "asset") {
      // UV area in proportion to surface area, the same ratio for every primitive.
      for (double d : density) CHECK(d == doctest::Approx(density[0]).epsilon(0.02));
    }
  }
  // pack: false keeps each primitive's own layout, still measured.
  const PipelineOutput own = run_ok(asset, {{"pack", false}});
  for (const auto& e : own.body["primitives"]) CHECK(e["uv"]["overlap_area"] == 0.0);
}

TEST_CASE("the selection: by list, by mesh name, v1's mesh/primitive, and its refusals") {
  const std::string asset = three_mesh_asset();
  auto named = run_ok(asset, {{"primitives", {{{"mesh", "both"}}}}});
  REQUIRE(named.body["primitives"].size() == 2);
  auto listed = run_ok(asset, {{"primitives", {{{"mesh", 1}, {"primitive", 0}, {"extrema", {0, 100}}},
                                               {{"mesh", 0}, {"extrema", "auto"}}}}});
  REQUIRE(listed.body["primitives"].size() == 2);
  CHECK(listed.body["primitives"][0]["mesh"] == 0);  // asset order
  CHECK(listed.body["primitives"][1]["seam"]["extrema"] == json::array({0, 100}));
  auto v1 = run_ok(asset, {{"mesh", 1}});
  CHECK(v1.body["primitives"].size() == 1);
  CHECK(v1.body.contains("seam"));
  CHECK(v1.body["mesh"]["genus"] == 1);

  auto refused = [&](const json& params, ApiErrorCode code, const std::string& words) {
    CAPTURE(params.dump());
    auto p = params_from_json(params);
    auto out = p.ok() ? run_seam_pipeline(asset, AssetKind::kAuto, *p, {}, core::CancelToken::none())
                      : ApiResult<PipelineOutput>(p.error());
    REQUIRE(!out.ok());
    CHECK(out.error().code == code);
    CHECK_MESSAGE(out.error().message.find(words) != std::string::npos, out.error().message);
  };
  refused({{"extrema", {1, 2}}}, ApiErrorCode::kInvalidParameter, "4 primitives are selected");
  refused({{"primitives", {{{"mesh", "nope"}}}}}, ApiErrorCode::kInvalidParameter, "no mesh is named");
  refused({{"primitives", {{{"mesh", 0}}, {{"mesh", "ball"}}}}}, ApiErrorCode::kInvalidParameter, "selected twice");
  refused({{"primitives", "all"}, {"mesh", 0}}, ApiErrorCode::kInvalidParameter, "cannot be combined");
  refused({{"primitives", {{{"mesh", 2}, {"primitive", 2}}}}}, ApiErrorCode::kUnsupportedPrimitiveMode, "LINES");
  refused({{"primitives", {{{"mesh", 1}, {"extrema", {99999}}}, {{"mesh", 0}}}}}, ApiErrorCode::kExtremumOutOfRange,
          "mesh 1 primitive 0: ");
  refused({{"pack", {{"texture_size", 8}}}}, ApiErrorCode::kInvalidParameter, "texture_size");
}

TEST_CASE("max_primitives: more selected triangle primitives than the limit is a 422 before any is read") {
  const std::string asset = three_mesh_asset();  // 4 triangle primitives and a LINES one
  auto params = params_from_json(json::object());
  REQUIRE(params.ok());
  PipelineLimits limits;
  limits.max_primitives = 3;
  auto refused = run_seam_pipeline(asset, AssetKind::kAuto, *params, limits, core::CancelToken::none());
  REQUIRE_FALSE(refused.ok());
  CHECK(refused.error().code == ApiErrorCode::kMeshTooLarge);
  CHECK(refused.error().details["primitives"] == 4);
  CHECK(refused.error().details["limit"] == 3);
  CHECK_MESSAGE(refused.error().message.find("--max-primitives") != std::string::npos, refused.error().message);
  limits.max_primitives = 4;  // the LINES primitive is not counted
  auto all = run_seam_pipeline(asset, AssetKind::kAuto, *params, limits, core::CancelToken::none());
  REQUIRE(all.ok());
  CHECK(all->body["primitives"].size() == 4);
  auto one = params_from_json({{"primitives", {{{"mesh", 1}}}}});
  REQUIRE(one.ok());
  limits.max_primitives = 1;
  CHECK(run_seam_pipeline(asset, AssetKind::kAuto, *one, limits, core::CancelToken::none()).ok());
}

TEST_CASE("charts features: a cube opens into its six sides, each flat (angle distortion 1)") {
  const auto cube = fixtures::voxel_surface({{0, 0, 0}});
  auto glb = write_plain_glb(core::IndexedMesh{cube.positions, cube.triangles});
  REQUIRE(glb.ok());
  const PipelineOutput seam = run_ok(*glb, json::object());
  const PipelineOutput sides = run_ok(*glb, {{"charts", "features"}});
  CHECK(sides.body["seam"]["feature_edges"] == 12);
  CHECK(sides.body["cut"]["euler_characteristic"] == 6);  // six discs
  CHECK(sides.body["uv"]["angle_distortion"].get<double>() == doctest::Approx(1.0).epsilon(1e-6));
  CHECK(seam.body["uv"]["angle_distortion"].get<double>() > 1.05);
  CHECK(sides.body["uv"]["flipped"] == 0);
  CHECK(sides.body["uv"]["overlap_area"] == 0.0);
}

TEST_CASE("faces without area that join two parts: one UV point each, both parts packed apart") {
  // Two spheres apart, a face with a repeated vertex joining them and three points of a line
  // from one to the other (its middle vertex in no other face): repair leaves both out of
  // the topology and the asset keeps them. Before, the repeated-vertex face lay in two charts
  // and the atlas step failed (a 500), and the line got a UV triangle over the charts.
  const auto sphere = fixtures::icosphere(1);
  core::IndexedMesh mesh{sphere.positions, sphere.triangles};
  const auto n = static_cast<std::uint32_t>(mesh.positions.size());
  const auto faces = mesh.triangles.size();
  for (std::uint32_t v = 0; v < n; ++v) mesh.positions.push_back(mesh.positions[v] + core::Vec3(4, 0, 0));
  for (std::size_t f = 0; f < faces; ++f) {
    const auto& t = mesh.triangles[f];
    mesh.triangles.push_back({t[0] + n, t[1] + n, t[2] + n});
  }
  std::uint32_t a = 0;  // the first sphere's vertex of largest x, and its copy on the second
  for (std::uint32_t v = 0; v < n; ++v) {
    if (mesh.positions[v].x() > mesh.positions[a].x()) a = v;
  }
  const std::uint32_t b = a + n;
  mesh.positions.push_back(0.5 * (mesh.positions[a] + mesh.positions[b]));  // exactly between
  const auto middle = static_cast<std::uint32_t>(mesh.positions.size() - 1);
  mesh.triangles.push_back({a, a, 2 * n - 1});
  mesh.triangles.push_back({a, middle, b});
  auto glb = write_plain_glb(mesh);
  REQUIRE(glb.ok());
  for (const json& params : {json::object(), json{{"pack", {{"split", true}}}}}) {
    CAPTURE(params.dump());
    const PipelineOutput out = run_ok(*glb, params);
    CHECK(out.body["repairs"]["degenerate_faces"] == 2);
    CHECK(out.body["uv"]["overlap_area"] == 0.0);
    CHECK(out.body["uv"]["flipped"] == 0);
    auto doc = parse_asset(out.glb, AssetKind::kGlb);
    REQUIRE(doc.ok());
    auto p = read_primitive(*doc, 0, 0);
    REQUIRE(p.ok());
    REQUIRE(p->mesh.triangles.size() == 2 * faces + 2);
    const int channel = out.body["uv"]["channel"].get<int>();
    const double both = uv_area(*p, channel);
    core::IndexedMesh last_two{p->mesh.positions, {p->mesh.triangles.end() - 2, p->mesh.triangles.end()}};
    PrimitiveData degenerate = *p;
    degenerate.mesh = last_two;
    CHECK(uv_area(degenerate, channel) == 0.0);
    CHECK(both > 0.2);
    std::string report;
    CHECK_MESSAGE(test_gltf::validator_errors(out.glb, report, "degenerate_joins.glb") == 0, report);
  }
}

TEST_CASE("output svg draws every new UV triangle, one group per primitive") {
  const std::string asset = three_mesh_asset();
  const PipelineOutput out = run_ok(asset, {{"output", "svg"}});
  REQUIRE(out.svg.rfind("<?xml", 0) == 0);
  std::size_t triangles = 0, polygons = 0, groups = 0;
  for (const auto& e : out.body["primitives"]) triangles += e["topology"]["faces"].get<std::size_t>();
  for (std::size_t at = out.svg.find("<polygon"); at != std::string::npos; at = out.svg.find("<polygon", at + 1)) ++polygons;
  for (std::size_t at = out.svg.find("class=\"primitive\""); at != std::string::npos;
       at = out.svg.find("class=\"primitive\"", at + 1)) {
    ++groups;
  }
  CHECK(polygons == triangles);
  CHECK(groups == 4);
  auto none = run(asset, {{"output", "svg"}, {"uv", "none"}});
  REQUIRE(!none.ok());
  CHECK(none.error().code == ApiErrorCode::kInvalidParameter);
}

namespace {

// Output edges used by one triangle: the UV set's chart boundaries (the seam and the cuts).
std::size_t boundary_edge_count(const std::vector<core::Triangle>& triangles) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
  for (const auto& t : triangles) {
    for (int k = 0; k < 3; ++k) ++uses[std::minmax(t[k], t[(k + 1) % 3])];
  }
  return static_cast<std::size_t>(std::count_if(uses.begin(), uses.end(), [](const auto& e) { return e.second == 1; }));
}

}  // namespace

TEST_CASE("pack split: a sprawling chart is cut into pieces that pack fuller, the surface and its attributes are kept") {
  const auto elephant = test_data::load_cgal("elephant");
  auto glb = write_plain_glb(elephant);
  REQUIRE(glb.ok());
  const PipelineOutput plain = run_ok(*glb, json::object());
  const PipelineOutput split = run_ok(*glb, {{"pack", {{"split", true}}}});
  const json& a = plain.body["uv"];
  const json& b = split.body["uv"];
  CHECK(a["charts"] == 1);
  CHECK(!a.contains("split"));
  CHECK(b["charts"].get<int>() > 1);
  CHECK(b["split"]["charts_split"] == 1);
  CHECK(b["split"]["cut_length"].get<double>() > 0);
  CHECK(b["coverage"].get<double>() > a["coverage"].get<double>() + 0.05);
  CHECK(b["overlap_area"] == 0.0);
  CHECK(b["flipped"] == 0);

  auto doc_a = parse_asset(plain.glb, AssetKind::kGlb);
  auto doc_b = parse_asset(split.glb, AssetKind::kGlb);
  REQUIRE(doc_a.ok());
  REQUIRE(doc_b.ok());
  auto pa = read_primitive(*doc_a, 0, 0);
  auto pb = read_primitive(*doc_b, 0, 0);
  REQUIRE(pa.ok());
  REQUIRE(pb.ok());
  // The same triangles in 3D (each output corner at its input position), more vertices (the
  // cuts duplicate theirs), more chart boundary, one texel density.
  REQUIRE(pb->mesh.triangles.size() == elephant.triangles.size());
  CHECK(pb->mesh.positions.size() == split.body["cut"]["asset_vertices"].get<std::size_t>());
  CHECK(pb->mesh.positions.size() > pa->mesh.positions.size());
  for (std::size_t f = 0; f < elephant.triangles.size(); f += 97) {
    for (int k = 0; k < 3; ++k) {
      CHECK(pb->mesh.positions[pb->mesh.triangles[f][k]] == pa->mesh.positions[pa->mesh.triangles[f][k]]);
    }
  }
  CHECK(boundary_edge_count(pb->mesh.triangles) > boundary_edge_count(pa->mesh.triangles));
  // Each piece keeps its chart's scale and shape: its UV area against the same faces' UV
  // area without the split is one factor for every piece (pieces found as the output's
  // connected components; faces keep their order).
  std::vector<std::uint32_t> root(pb->mesh.positions.size());
  std::iota(root.begin(), root.end(), 0u);
  auto find = [&](std::uint32_t v) {
    while (root[v] != v) v = root[v] = root[root[v]];
    return v;
  };
  for (const auto& t : pb->mesh.triangles) {
    root[find(t[1])] = find(t[0]);
    root[find(t[2])] = find(t[0]);
  }
  std::map<std::uint32_t, std::vector<std::size_t>> pieces;
  for (std::size_t f = 0; f < pb->mesh.triangles.size(); ++f) pieces[find(pb->mesh.triangles[f][0])].push_back(f);
  CHECK(pieces.size() == b["charts"].get<std::size_t>());
  auto piece_area = [](const PrimitiveData& p, int channel, const std::vector<std::size_t>& faces) {
    PrimitiveData piece = p;
    piece.mesh.triangles.clear();
    for (const std::size_t f : faces) piece.mesh.triangles.push_back(p.mesh.triangles[f]);
    return uv_area(piece, channel);
  };
  const double scale = uv_area(*pb, b["channel"].get<int>()) / uv_area(*pa, a["channel"].get<int>());
  for (const auto& [r, faces] : pieces) {
    CHECK(piece_area(*pb, b["channel"].get<int>(), faces) / piece_area(*pa, a["channel"].get<int>(), faces) ==
          doctest::Approx(scale).epsilon(1e-3));
  }
  std::string report;
  CHECK_MESSAGE(test_gltf::validator_errors(split.glb, report, "split_out.glb") == 0, report);
}

TEST_CASE("pack split: faces degenerate after welding, each there twice, stay in their chart's pieces (fuzz F14)") {
  // Such faces are kept in the asset at one UV point of their chart; two copies have the
  // same corners, so a piece's triangles are mapped back by place, not by corners. Before,
  // one copy kept the chart's numbering: a face across two placed pieces (a 200 with a UV
  // triangle spanning the atlas), or a 500 "chart 0 names UV 7 of 6" (mesh_fuzz).
  auto elephant = test_data::load_cgal("elephant");
  const std::size_t faces = elephant.triangles.size();
  for (std::size_t f = 0; f < faces; f += 3) {
    const auto t = elephant.triangles[f];
    elephant.triangles.push_back({t[0], t[0], t[1]});
    elephant.triangles.push_back({t[0], t[0], t[1]});
  }
  auto glb = write_plain_glb(elephant);
  REQUIRE(glb.ok());
  const PipelineOutput split = run_ok(*glb, {{"pack", {{"split", true}}}});
  const json& uv = split.body["uv"];
  CHECK(uv["split"]["charts_split"].get<int>() >= 1);
  CHECK(uv["overlap_area"] == 0.0);
  CHECK(uv["flipped"] == 0);
  auto doc = parse_asset(split.glb, AssetKind::kGlb);
  REQUIRE(doc.ok());
  auto out = read_primitive(*doc, 0, 0);
  REQUIRE(out.ok());
  REQUIRE(out->mesh.triangles.size() == elephant.triangles.size());
  for (std::size_t f = 0; f < elephant.triangles.size(); f += 13) {
    for (int k = 0; k < 3; ++k) {
      CHECK(out->mesh.positions[out->mesh.triangles[f][k]] ==
            elephant.positions[elephant.triangles[f][k]].cast<float>().cast<double>());
    }
  }
  // Every added face lies at one UV point of one chart (a copy left over the chart's vertex
  // numbering before the split reached across two placed pieces: 20 of them).
  const std::vector<std::array<double, 2>> corner_uv = texcoords(*out, uv["channel"].get<int>());
  auto uv_of = [&](std::uint32_t v) { return corner_uv.at(v); };
  std::size_t spread = 0;
  for (std::size_t f = faces; f < out->mesh.triangles.size(); ++f) {
    const auto& t = out->mesh.triangles[f];
    if (uv_of(t[0]) != uv_of(t[1]) || uv_of(t[0]) != uv_of(t[2])) ++spread;
  }
  CHECK(spread == 0);
  std::string report;
  CHECK_MESSAGE(test_gltf::validator_errors(split.glb, report, "split_degenerate_out.glb") == 0, report);
}

// A file of the real-looking asset set (.cache/assets, built by scripts/fetch-test-data.sh).
std::string asset_set_file(const std::string& name) {
  const auto path = std::filesystem::path(SEAM_TEST_DATA_DIR).parent_path() / "assets" / name;
  if (!std::filesystem::exists(path)) FAIL("missing " << path.string() << ": run scripts/fetch-test-data.sh");
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Twice the signed UV area of each triangle of TEXCOORD_<channel>.
std::vector<double> uv_orientations(const PrimitiveData& p, int channel) {
  const std::vector<std::array<double, 2>> uv = texcoords(p, channel);
  std::vector<double> out;
  for (const auto& t : p.mesh.triangles) {
    const auto a = uv.at(t[0]), b = uv.at(t[1]), c = uv.at(t[2]);
    out.push_back((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
  }
  return out;
}

TEST_CASE("a sliver the packing's rounding to float turned over is nudged back (skinned.glb, uv lscm)") {
  // One untangled lscm piece of skinned.glb holds a sliver that the placement's rotation and
  // rounding to float32 turned over: uv.flipped 1 and overlap 7e-15 of the atlas before the pack
  // step nudged such corners by one float step, as parameterize does for its own rounding.
  const PipelineOutput out = run_ok(asset_set_file("skinned.glb"), {{"uv", "lscm"}});
  std::size_t pieces = 0;
  for (const auto& e : out.body["primitives"]) {
    CHECK(e["uv"]["flipped"] == 0);
    CHECK(e["uv"]["overlap_area"] == 0.0);
    pieces += e["uv"]["untangle"]["pieces_added"].get<std::size_t>();
  }
  CHECK(pieces > 0);  // the case untangles: it is the one whose sliver turned
}

TEST_CASE("the stored map is the measured one: glTF's flipped v is exact on the UV grid (defects.glb, arap)") {
  // glTF stores 1 - v. On float32 values below 1/2 that subtraction rounds a second time,
  // after the flattening measured its map: the hand of defects.glb flattened by arap, measured
  // overlap-free, overlapped itself by 6e-10 of the atlas in its own layout (pack: false) and
  // 2.4e-10 packed. The UVs now lie on multiples of 2^-24, where 1 - v is exact.
  const std::string asset = asset_set_file("defects.glb");
  for (const json& pack : {json(false), json(true)}) {
    CAPTURE(pack);
    const PipelineOutput out = run_ok(asset, {{"uv", "arap"}, {"pack", pack}});
    auto doc = parse_asset(out.glb, AssetKind::kGlb);
    REQUIRE(doc.ok());
    for (const json& e : out.body["primitives"]) {
      // Unpacked, the elephant keeps its arap map's own overlap (5% of its layout; packing
      // untangles it); no primitive keeps a sliver of rounding.
      const double overlap = e["uv"]["overlap_area"].get<double>();
      CHECK((overlap == 0.0 || (pack == false && overlap > 1e-3)));
      if (pack == true) CHECK(e["uv"]["flipped"] == 0);
      auto p = read_primitive(*doc, e["mesh"].get<std::uint32_t>(), e["primitive"].get<std::uint32_t>());
      REQUIRE(p.ok());
      for (const auto& q : texcoords(*p, e["uv"]["channel"].get<int>())) {
        CHECK(seam::core::to_uv_grid(q[0]) == q[0]);
        CHECK(seam::core::to_uv_grid(q[1]) == q[1]);
      }
    }
    std::string report;
    CHECK_MESSAGE(test_gltf::validator_errors(out.glb, report, "defects_arap.glb") == 0, report);
  }
}

TEST_CASE("untangle: lscm, bff and arap charts that folded or overlapped themselves are packed as valid pieces") {
  const std::string props = asset_set_file("props.glb");
  // The default's charts are valid: nothing to untangle.
  const PipelineOutput by_default = run_ok(props, json::object());  // held: the loop reads into it
  for (const auto& e : by_default.body["primitives"]) CHECK(e["uv"]["untangle"]["charts"] == 0);
  std::size_t added = 0;
  for (const char* method : {"lscm", "bff", "arap"}) {
    CAPTURE(method);
    const PipelineOutput packed = run_ok(props, {{"uv", method}});
    const PipelineOutput own = run_ok(props, {{"uv", method}, {"pack", false}});  // as flattened
    auto doc = parse_asset(packed.glb, AssetKind::kGlb);
    auto own_doc = parse_asset(own.glb, AssetKind::kGlb);
    REQUIRE(doc.ok());
    REQUIRE(own_doc.ok());
    for (std::size_t i = 0; i < packed.body["primitives"].size(); ++i) {
      const json& e = packed.body["primitives"][i];
      CAPTURE(i);
      CHECK(e["uv"]["overlap_area"] == 0.0);
      CHECK(e["uv"]["flipped"] == 0);
      added += e["uv"]["untangle"]["pieces_added"].get<std::size_t>();
      const auto m = e["mesh"].get<std::uint32_t>(), p = e["primitive"].get<std::uint32_t>();
      auto out = read_primitive(*doc, m, p);
      auto before = read_primitive(*own_doc, m, p);
      REQUIRE(out.ok());
      REQUIRE(before.ok());
      REQUIRE(out->mesh.triangles.size() == before->mesh.triangles.size());
      CHECK(out->mesh.positions.size() == e["cut"]["asset_vertices"].get<std::size_t>());
      // Every triangle keeps its UV shape: one scale factor from the flattened map to the
      // packed one, and (pieces mirrored where they turned the wrong way) one orientation.
      const std::vector<double> now = uv_orientations(*out, e["uv"]["channel"].get<int>());
      const std::vector<double> then = uv_orientations(*before, own.body["primitives"][i]["uv"]["channel"].get<int>());
      const double scale = uv_area(*out, e["uv"]["channel"].get<int>()) /
                           uv_area(*before, own.body["primitives"][i]["uv"]["channel"].get<int>());
      const double total =
          std::accumulate(then.begin(), then.end(), 0.0, [](double s, double a) { return s + std::abs(a); });
      std::size_t turned[2] = {0, 0};
      for (std::size_t t = 0; t < now.size(); ++t) {
        if (now[t] != 0) ++turned[now[t] > 0 ? 1 : 0];
        if (std::abs(then[t]) < 1e-4 * total) continue;  // float32 blurs the smallest ones
        CHECK(std::abs(now[t]) / std::abs(then[t]) == doctest::Approx(scale).epsilon(1e-2));
      }
      CHECK(std::min(turned[0], turned[1]) == 0);
    }
    std::string report;
    CHECK_MESSAGE(test_gltf::validator_errors(packed.glb, report, std::string("untangled_") + method + ".glb") == 0,
                  report);
  }
  CHECK(added > 0);
}

}  // namespace seam_whole_asset_test
