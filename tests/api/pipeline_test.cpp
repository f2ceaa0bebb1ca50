// The whole job: the same seam from GLB, split-vertex GLB and Draco GLB; the cut asset is
// valid glTF, a disc, and keeps every attribute; errors keep their codes.
#include <doctest/doctest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <thread>

#include "api/base64.h"
#include "api/gltf_reader.h"
#include "api/gltf_writer.h"
#include "api/pipeline.h"
#include "api/tinygltf_check.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/topology.h"
#include "core/mesh/weld.h"
#include "extrema_fixtures.h"
#include "fixtures.h"
#include "gltf_test_util.h"
#include "test_data.h"

namespace seam_pipeline_test {

namespace {

using namespace seam;
using namespace seam::api;
using seam::test_gltf::json;

using P3 = std::array<float, 3>;

P3 key(const core::Vec3& p) { return {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())}; }

PipelineOutput run_ok(const std::string& asset, const SeamParams& params) {
  auto out = run_seam_pipeline(asset, AssetKind::kAuto, params, {}, core::CancelToken::none());
  REQUIRE_MESSAGE(out.ok(), (out.ok() ? "" : out.error().message));
  // Never one input vertex twice among the extrema or the terminals (issue 11 item 5).
  for (const char* list : {"extrema", "terminals"}) {
    const auto& ids = out->body["seam"][list];
    CHECK_MESSAGE(std::set<std::uint32_t>(ids.begin(), ids.end()).size() == ids.size(), list << ": " << ids.dump());
  }
  return std::move(out).value();
}

// The seam as a set of position pairs: independent of vertex numbering.
std::set<std::pair<P3, P3>> seam_positions(const PipelineOutput& out, const PrimitiveData& input) {
  std::set<std::pair<P3, P3>> s;
  for (const auto& e : out.body["seam"]["edges"]) {
    auto a = key(input.mesh.positions[e[0].get<std::size_t>()]);
    auto b = key(input.mesh.positions[e[1].get<std::size_t>()]);
    s.emplace(std::min(a, b), std::max(a, b));
  }
  return s;
}

PrimitiveData read(const std::string& bytes) {
  auto doc = parse_asset(bytes, AssetKind::kAuto);
  REQUIRE_MESSAGE(doc.ok(), (doc.ok() ? "" : doc.error().message));
  auto p = read_primitive(*doc, 0, 0);
  REQUIRE_MESSAGE(p.ok(), (p.ok() ? "" : p.error().message));
  return std::move(p).value();
}

// Topology of an indexed primitive as stored (no welding): the cut must be a disc.
core::Topology stored_topology(const PrimitiveData& p) {
  auto mesh = core::build_halfedge_mesh(p.mesh.positions, p.mesh.triangles);
  REQUIRE_MESSAGE(mesh.ok(), (mesh.ok() ? "" : mesh.error().message));
  REQUIRE(core::check_invariants(*mesh).ok());
  return core::compute_topology(*mesh);
}

std::string split_copy(const core::IndexedMesh& m, bool draco) {
  // Split every vertex per face, as flat-shaded exports do.
  core::IndexedMesh split;
  for (const auto& t : m.triangles) {
    core::Triangle nt;
    for (int k = 0; k < 3; ++k) {
      nt[static_cast<std::size_t>(k)] = static_cast<std::uint32_t>(split.positions.size());
      split.positions.push_back(m.positions[t[static_cast<std::size_t>(k)]]);
    }
    split.triangles.push_back(nt);
  }
  auto glb = write_plain_glb(split, {}, draco);
  REQUIRE(glb.ok());
  return *glb;
}

}  // namespace

TEST_CASE("the same seam from GLB, split-vertex GLB and Draco GLB of a real mesh, output is valid and a disc") {
  const core::IndexedMesh soup = test_data::load_cgal("elephant");
  const auto plain = write_plain_glb(soup);
  const auto draco = write_plain_glb(soup, {}, true);
  REQUIRE(plain.ok());
  REQUIRE(draco.ok());
  const std::string split = split_copy(soup, false);

  // Extrema chosen automatically on the plain GLB, then given as positions to all three.
  SeamParams params;
  params.uv = core::UvMethod::kBff;
  // The seam's cut alone: packing would cut BFF's self-overlapping elephant into pieces too
  // (untangle_charts), and the output would not be one disc.
  params.pack.enabled = false;
  const PipelineOutput base = run_ok(*plain, params);
  const PrimitiveData plain_in = read(*plain);
  SeamParams by_position = params;
  by_position.extrema.automatic = false;
  for (const auto& i : base.body["seam"]["extrema"]) {
    const auto& p = plain_in.mesh.positions[i.get<std::size_t>()];
    by_position.extrema.positions.push_back({p.x(), p.y(), p.z()});
  }
  REQUIRE(by_position.extrema.positions.size() >= 2);
  const auto reference = seam_positions(base, plain_in);
  CHECK(!reference.empty());

  for (const std::string* asset : {&*plain, &split, &*draco}) {
    const PrimitiveData in = read(*asset);
    const PipelineOutput out = run_ok(*asset, by_position);
    const json& body = out.body;
    CHECK(seam_positions(out, in) == reference);
    CHECK(body["mesh"]["welded_vertices"] == base.body["mesh"]["welded_vertices"]);
    CHECK(body["mesh"]["genus"] == base.body["mesh"]["genus"]);
    CHECK(body["cut"]["euler_characteristic"] == 1);
    CHECK(body["cut"]["boundary_loops"] == 1);
    CHECK(body["uv"]["flipped"] == 0);
    CHECK(body["uv"]["channel"] == 0);
    for (const char* k : {"parse", "weld", "seam", "cut", "uv", "encode", "total"}) CHECK(body["timings_ms"].contains(k));
    CHECK(body["draco"] == (asset == &*draco));
    // The JSON form carries the same GLB.
    const auto decoded = decode_base64(body["asset"]["glb_base64"].get<std::string>());
    REQUIRE(decoded.ok());
    CHECK(*decoded == out.glb);

    std::string report;
    CHECK_MESSAGE(test_gltf::validator_errors(out.glb, report) == 0, report);

    const PrimitiveData cut = read(out.glb);
    CHECK(cut.draco == (asset == &*draco));
    // A second reader (tinygltf, decoding Draco itself) sees the same vertex and index counts.
    const TinygltfSummary tiny = load_with_tinygltf(out.glb);
    CHECK_MESSAGE(tiny.ok, tiny.error);
    CHECK(tiny.vertices == cut.mesh.positions.size());
    CHECK(tiny.indices == 3 * cut.mesh.triangles.size());
    CHECK(tiny.position_has_data);
    CHECK(cut.mesh.triangles.size() == in.mesh.triangles.size());
    // Every output vertex is an input vertex: its position is one of the input positions.
    std::set<P3> input_positions;
    for (const auto& p : in.mesh.positions) input_positions.insert(key(p));
    for (const auto& p : cut.mesh.positions) CHECK(input_positions.count(key(p)) == 1);
    if (asset != &split) {
      // Without input splits the stored primitive is exactly the cut disc, and vertices are
      // duplicated only along the seam: one extra copy per extra wedge.
      const auto topo = stored_topology(cut);
      CHECK(topo.components.size() == 1);
      CHECK(topo.euler_characteristic() == 1);
      CHECK(topo.boundary_loops.size() == 1);
      CHECK(cut.mesh.positions.size() == body["cut"]["vertices"].get<std::size_t>());
      // Cutting K edges of a surface with Euler characteristic chi into one disc adds
      // exactly K + 1 - chi vertices (V' - (E + K) + F = 1): no needless duplicates.
      const int chi = 2 - 2 * body["mesh"]["genus"].get<int>() - body["mesh"]["boundary_loops"].get<int>();
      CHECK(static_cast<long>(cut.mesh.positions.size()) ==
            body["mesh"]["welded_vertices"].get<long>() + static_cast<long>(reference.size()) + 1 - chi);
      // The new UV set: float32 VEC2 in [0,1].
      const auto uv = std::find_if(cut.attributes.begin(), cut.attributes.end(),
                                   [](const AttributeArray& a) { return a.name == "TEXCOORD_0"; });
      REQUIRE(uv != cut.attributes.end());
      CHECK(uv->component_type == 5126);
      CHECK(uv->components == 2);
    } else {
      // Welding the output by position gives the input's topology back.
      CHECK(cut.mesh.positions.size() == in.mesh.positions.size());
    }
  }
}

TEST_CASE("the cut asset keeps normals, colors, two texcoord sets, skin, morph targets, a second mesh, nodes, extras") {
  const auto sphere = fixtures::icosphere(2);
  const core::IndexedMesh m{sphere.positions, sphere.triangles};
  const std::size_t n = m.positions.size();
  std::vector<float> normals, uv0, uv1, weights, morph;
  std::vector<std::uint8_t> colors, joints;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& p = m.positions[i];
    normals.insert(normals.end(), {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())});
    uv0.insert(uv0.end(), {static_cast<float>(i % 7) / 7.f, static_cast<float>(i % 5) / 5.f});
    uv1.insert(uv1.end(), {0.5f, static_cast<float>(i % 3) / 3.f});
    weights.insert(weights.end(), {0.25f, 0.25f, 0.25f, 0.25f});
    morph.insert(morph.end(), {0.f, 0.f, static_cast<float>(i % 4) * 0.01f});
    colors.insert(colors.end(), {static_cast<std::uint8_t>(i * 7), static_cast<std::uint8_t>(i * 13), 200});
    joints.insert(joints.end(), {0, 1, 2, 3});
  }
  AttributeArray color;
  color.name = "COLOR_0";
  color.component_type = 5121;
  color.components = 3;
  color.type = "VEC3";
  color.normalized = true;
  color.count = n;
  color.data = colors;
  AttributeArray joint = color;
  joint.name = "JOINTS_0";
  joint.components = 4;
  joint.type = "VEC4";
  joint.normalized = false;
  joint.data = joints;
  const std::vector<AttributeArray> extra{make_float_attribute("NORMAL", 3, normals),
                                          make_float_attribute("TEXCOORD_0", 2, uv0),
                                          make_float_attribute("TEXCOORD_1", 2, uv1),
                                          color,
                                          joint,
                                          make_float_attribute("WEIGHTS_0", 4, weights),
                                          make_float_attribute("_MORPH", 3, morph)};
  auto plain = write_plain_glb(m, extra);
  REQUIRE(plain.ok());
  auto doc = parse_asset(*plain, AssetKind::kGlb);
  REQUIRE(doc.ok());
  json& j = doc->json;
  // Turn _MORPH into a morph target, add a second mesh sharing the data, a node hierarchy,
  // a skin and extras.
  json& prim = j["meshes"][0]["primitives"][0];
  const auto morph_accessor = prim["attributes"]["_MORPH"];
  prim["attributes"].erase("_MORPH");
  j["accessors"][morph_accessor.get<std::size_t>()]["min"] = {0, 0, 0};
  j["accessors"][morph_accessor.get<std::size_t>()]["max"] = {0, 0, 0.03f};
  prim["targets"] = {{{"POSITION", morph_accessor}}};
  prim["extras"] = {{"author", "test"}};
  j["meshes"][0]["weights"] = {0.5};
  j["meshes"].push_back({{"name", "second"}, {"primitives", {{{"attributes", {{"POSITION", prim["attributes"]["POSITION"]}}},
                                                              {"indices", prim["indices"]}}}}});
  j["nodes"] = {{{"name", "root"}, {"children", {1, 2, 3, 4, 5, 6}}},
                {{"name", "body"}, {"mesh", 0}, {"skin", 0}},
                {{"name", "other"}, {"mesh", 1}, {"translation", {3, 0, 0}}},
                {{"name", "j0"}}, {{"name", "j1"}}, {{"name", "j2"}}, {{"name", "j3"}}};
  j["skins"] = {{{"joints", {3, 4, 5, 6}}}};
  j["extras"] = {{"pipeline", "seam-test"}, {"nested", {{"a", 1}}}};
  j["scenes"][0]["nodes"] = {0};
  std::vector<std::uint8_t> bin = doc->buffers[0];
  const std::string input = encode_glb(j, bin);
  std::string report;
  REQUIRE_MESSAGE(test_gltf::validator_errors(input, report, "attrs_in.glb") == 0, report);
  const PrimitiveData in = read(input);

  for (bool draco : {false, true}) {
    CAPTURE(draco);
    SeamParams params;
    params.extrema.automatic = false;
    params.extrema.indices = {0, 3, 5, 9};
    params.draco = draco;
    params.mesh = 0;  // v1's selection: only this primitive; mesh 1 shares its accessors
    const PipelineOutput out = run_ok(input, params);
    CHECK_MESSAGE(test_gltf::validator_errors(out.glb, report, "attrs_out.glb") == 0, report);
    auto out_doc = parse_asset(out.glb, AssetKind::kGlb);
    REQUIRE(out_doc.ok());
    const json& o = out_doc->json;
    CHECK(o["nodes"] == j["nodes"]);
    CHECK(o["skins"] == j["skins"]);
    CHECK(o["extras"] == j["extras"]);
    // Mesh 1 is untouched; its accessor indices may be renumbered (mesh 0's unused ones dropped).
    CHECK(o["meshes"][1]["name"] == j["meshes"][1]["name"]);
    CHECK(o["meshes"][1]["primitives"][0].size() == j["meshes"][1]["primitives"][0].size());
    CHECK(o["meshes"][0]["weights"] == j["meshes"][0]["weights"]);
    const json& op = o["meshes"][0]["primitives"][0];
    CHECK(op["extras"]["author"] == "test");
    CHECK(op["extras"]["seam"]["edges"] == out.body["seam"]["edges"]);
    CHECK(op["extras"]["seam"]["uv_channel"] == 2);
    CHECK(op.contains("extensions") == draco);
    CHECK((o.contains("extensionsRequired") && o["extensionsRequired"] == json::array({"KHR_draco_mesh_compression"})) == draco);
    // The second mesh still reads as the original sphere.
    auto second = read_primitive(*out_doc, 1, 0);
    REQUIRE(second.ok());
    CHECK(second->mesh.triangles == in.mesh.triangles);

    auto cut = read_primitive(*out_doc, 0, 0);
    REQUIRE(cut.ok());
    CHECK(cut->draco == draco);
    CHECK(cut->mesh.positions.size() > n);  // the seam duplicated some vertices
    CHECK(cut->mesh.positions.size() == out.body["cut"]["vertices"].get<std::size_t>());
    // Every output vertex carries all attributes of the input vertex at its position, bit-exactly.
    std::map<P3, std::size_t> source;
    for (std::size_t i = 0; i < n; ++i) source[key(in.mesh.positions[i])] = i;
    std::map<std::string, const AttributeArray*> out_attr, in_attr;
    for (const auto& a : cut->attributes) out_attr[a.name] = &a;
    for (const auto& a : in.attributes) in_attr[a.name] = &a;
    for (const char* name : {"POSITION", "NORMAL", "TEXCOORD_0", "TEXCOORD_1", "COLOR_0", "JOINTS_0", "WEIGHTS_0"}) {
      CAPTURE(name);
      REQUIRE(out_attr.count(name) == 1);
      const AttributeArray& a = *out_attr[name];
      const AttributeArray& b = *in_attr[name];
      CHECK(a.component_type == b.component_type);
      CHECK(a.normalized == b.normalized);
      std::size_t mismatches = 0;
      for (std::size_t v = 0; v < cut->mesh.positions.size(); ++v) {
        const std::size_t s = source.at(key(cut->mesh.positions[v]));
        mismatches += std::memcmp(a.data.data() + v * a.element_size(), b.data.data() + s * b.element_size(),
                                  a.element_size()) != 0;
      }
      CHECK(mismatches == 0);
    }
    REQUIRE(out_attr.count("TEXCOORD_2") == 1);
    REQUIRE(cut->targets.size() == 1);
    REQUIRE(cut->targets[0].size() == 1);
    const AttributeArray& target = cut->targets[0][0];
    for (std::size_t v = 0; v < cut->mesh.positions.size(); ++v) {
      const std::size_t s = source.at(key(cut->mesh.positions[v]));
      CHECK(std::memcmp(target.data.data() + v * 12, in.targets[0][0].data.data() + s * 12, 12) == 0);
    }
  }
}

TEST_CASE("a pinched vertex is split per fan: CGAL's cow gives a valid seam, disc and asset") {
  const core::IndexedMesh soup = test_data::load_cgal("cow");
  const auto glb = write_plain_glb(soup);
  REQUIRE(glb.ok());
  const PipelineOutput out = run_ok(*glb, SeamParams{});
  const json& body = out.body;
  CHECK(body["mesh"]["pinched_vertices_split"] == 1);
  CHECK(body["uv"]["method"] == "slim");
  CHECK(body["uv"]["area_distortion_geometric"].get<double>() >= 1.0);
  CHECK(body["uv"]["area_distortion_geometric"].get<double>() <= body["uv"]["area_distortion"].get<double>());
  CHECK(body["uv"]["area_distortion_geometric"].get<double>() <= 1.7);
  CHECK(body["mesh"]["components"] == 1);
  CHECK(body["mesh"]["genus"] == 0);
  CHECK(body["cut"]["euler_characteristic"] == 1);
  CHECK(body["cut"]["boundary_loops"] == 1);
  CHECK(body["uv"]["flipped"] == 0);
  CHECK(body["seam"]["extrema"].size() >= 4);  // legs, head, tail
  // Seam ids are input vertex indices.
  for (const auto& e : body["seam"]["edges"]) CHECK(e[1].get<std::size_t>() < soup.positions.size());
  // The stored cut primitive is a disc and a valid glTF asset.
  const PrimitiveData cut = read(out.glb);
  const core::Topology topo = stored_topology(cut);
  CHECK(topo.components.size() == 1);
  CHECK(topo.boundary_loops.size() == 1);
  std::string report;
  CHECK_MESSAGE(test_gltf::validator_errors(out.glb, report, "cow.glb") == 0, report);
}

// A sphere as a DCC tool may export it: a fin (a third face on one edge), a patch of reversed
// faces, and faces that collapse when welded (they repeat a position stored twice; one of them
// sits on a vertex that is in no other face). `patch` = the reversed faces.
core::IndexedMesh broken_sphere(std::size_t& patch) {
  fixtures::Soup s = fixtures::sphere_with_fin(3);
  const fixtures::Soup flipped = fixtures::sphere_with_flipped_patch(3, 0.7);
  patch = 0;
  for (std::size_t f = 0; f < flipped.triangles.size(); ++f) {
    patch += flipped.triangles[f] != s.triangles[f];
    s.triangles[f] = flipped.triangles[f];
  }
  auto copy_of = [&](std::uint32_t v) {
    s.positions.push_back(s.positions[v]);
    return static_cast<std::uint32_t>(s.positions.size() - 1);
  };
  const core::Triangle a = s.triangles[10], b = s.triangles[20];
  s.triangles.push_back({a[0], a[1], copy_of(a[1])});
  s.triangles.push_back({copy_of(b[2]), b[0], b[2]});
  s.positions.push_back(core::Vec3(0, 0, 3));  // a stray vertex, only in a collapsed face
  const auto stray = static_cast<std::uint32_t>(s.positions.size() - 1);
  s.triangles.push_back({stray, copy_of(stray), copy_of(stray)});
  return core::IndexedMesh{s.positions, s.triangles};
}

double area3(const core::IndexedMesh& m, const core::Triangle& t) {
  return (m.positions[t[1]] - m.positions[t[0]]).cross(m.positions[t[2]] - m.positions[t[0]]).norm();
}

TEST_CASE("repair by default: fin, flipped patch and collapsed faces give a disc cut, 0 flips, a valid asset") {
  std::size_t patch = 0;
  const core::IndexedMesh soup = broken_sphere(patch);
  REQUIRE(patch > 10);
  const auto glb = write_plain_glb(soup);
  REQUIRE(glb.ok());
  const auto t0 = std::chrono::steady_clock::now();
  const PipelineOutput out = run_ok(*glb, SeamParams{});
  MESSAGE("repaired sphere (" << soup.triangles.size() << " faces): "
                              << std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count()
                              << " ms, repairs " << out.body["repairs"].dump());
  const json& body = out.body;
  CHECK(body["repairs"]["non_manifold_edges"] == 1);
  CHECK(body["repairs"]["degenerate_faces"] == 3);
  CHECK(body["repairs"]["reoriented_faces"].get<std::size_t>() >= patch);
  CHECK(body["repairs"]["reoriented_faces"].get<std::size_t>() <= patch + 1);  // the fin may be reversed too
  CHECK(body["repairs"]["split_off_faces"] == 0);
  CHECK(body["mesh"]["components"] == 2);  // the sphere, closed again, and the fin
  CHECK(body["cut"]["euler_characteristic"] == 2);
  CHECK(body["cut"]["boundary_loops"] == 2);
  CHECK(body["cut"]["faces"] == soup.triangles.size() - 3);
  CHECK(body["uv"]["flipped"] == 0);

  // Every input face is in the asset; without the collapsed ones it is two discs, and every
  // new UV triangle turns the same way as its face.
  const PrimitiveData cut = read(out.glb);
  REQUIRE(cut.mesh.triangles.size() == soup.triangles.size());
  core::IndexedMesh solid{cut.mesh.positions, {}};
  for (const auto& t : cut.mesh.triangles) {
    if (area3(cut.mesh, t) > 0) solid.triangles.push_back(t);
  }
  CHECK(solid.triangles.size() == soup.triangles.size() - 3);
  const PrimitiveData solid_data{solid, {}, {}, false};
  const core::Topology topo = stored_topology(solid_data);
  CHECK(topo.components.size() == 2);
  CHECK(topo.boundary_loops.size() == 2);
  const std::string channel = "TEXCOORD_" + std::to_string(body["uv"]["channel"].get<int>());
  const auto uv_attr = std::find_if(cut.attributes.begin(), cut.attributes.end(),
                                    [&](const AttributeArray& a) { return a.name == channel; });
  REQUIRE(uv_attr != cut.attributes.end());
  REQUIRE(uv_attr->component_type == 5126);
  std::vector<float> uv(uv_attr->count * 2);
  std::memcpy(uv.data(), uv_attr->data.data(), uv.size() * sizeof(float));
  std::size_t positive = 0, negative = 0;
  for (const auto& t : solid.triangles) {
    const double ax = uv[2 * t[1]] - uv[2 * t[0]], ay = uv[2 * t[1] + 1] - uv[2 * t[0] + 1];
    const double bx = uv[2 * t[2]] - uv[2 * t[0]], by = uv[2 * t[2] + 1] - uv[2 * t[0] + 1];
    (ax * by - ay * bx > 0 ? positive : negative) += 1;
  }
  CHECK(std::min(positive, negative) == 0);
  std::string report;
  CHECK_MESSAGE(test_gltf::validator_errors(out.glb, report, "repaired.glb") == 0, report);

  // repair: false keeps v1's 422 (the builder checks collapsed faces first).
  SeamParams strict;
  strict.repair = false;
  auto refused = run_seam_pipeline(*glb, AssetKind::kAuto, strict, {}, core::CancelToken::none());
  REQUIRE(!refused.ok());
  CHECK(refused.error().code == ApiErrorCode::kDegenerateFace);
  CHECK(http_status(refused.error().code) == 422);
}

TEST_CASE("40 small closed plates beside a rod in one primitive: tips only on the rod, each plate cut to a disc") {
  // The rod: an icosphere stretched 8:1 (vertices first, so its input indices come first).
  fixtures::Soup soup = fixtures::icosphere(3);
  for (auto& p : soup.positions) p = core::Vec3(p.x(), p.y(), 8 * p.z());
  const std::size_t rod_vertices = soup.positions.size();
  for (int i = 0; i < 40; ++i) {
    fixtures::Soup plate = fixtures::icosphere(2);
    for (auto& p : plate.positions) {
      p = p / p.cwiseAbs().maxCoeff();
      p = core::Vec3(p.x(), 0.5 * p.y(), 0.1 * p.z()) * 0.4 + core::Vec3(3 + (i % 8), 0, -4 + 2 * (i / 8));
    }
    soup = fixtures::join(soup, plate);
  }
  const auto glb = write_plain_glb(core::IndexedMesh{soup.positions, soup.triangles});
  REQUIRE(glb.ok());
  const auto t0 = std::chrono::steady_clock::now();
  const PipelineOutput out = run_ok(*glb, SeamParams{});
  MESSAGE("rod + 40 plates (" << soup.triangles.size() << " faces): "
                              << std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count()
                              << " ms, extrema " << out.body["seam"]["extrema"].dump());
  const json& body = out.body;
  CHECK(body["mesh"]["components"] == 41);
  REQUIRE(body["seam"]["extrema"].size() == 2);  // the rod's two ends
  for (const auto& v : body["seam"]["extrema"]) CHECK(v.get<std::size_t>() < rod_vertices);
  CHECK(body["cut"]["euler_characteristic"] == 41);
  CHECK(body["cut"]["boundary_loops"] == 41);
  CHECK(body["uv"]["flipped"] == 0);
  std::string report;
  CHECK_MESSAGE(test_gltf::validator_errors(out.glb, report, "plates.glb") == 0, report);
}

TEST_CASE("repair: false names the refused elements in input numbering, message and details agreeing") {
  std::size_t patch = 0;
  core::IndexedMesh soup = broken_sphere(patch);
  SeamParams strict;
  strict.repair = false;
  auto refuse = [&](const core::IndexedMesh& m) {
    const auto glb = write_plain_glb(m);
    REQUIRE(glb.ok());
    auto out = run_seam_pipeline(*glb, AssetKind::kAuto, strict, {}, core::CancelToken::none());
    REQUIRE(!out.ok());
    return out.take_error();
  };
  // The three collapsed faces are the last three input faces.
  const auto n = static_cast<std::uint32_t>(soup.triangles.size());
  ApiError e = refuse(soup);
  CHECK(e.code == ApiErrorCode::kDegenerateFace);
  CHECK(e.details["count"] == 3);
  CHECK(e.details["faces"] == json::array({n - 3, n - 2, n - 1}));
  const core::Triangle& first = soup.triangles[n - 3];
  CHECK_MESSAGE(e.message.find("3 faces are degenerate") != std::string::npos, e.message);
  CHECK_MESSAGE(e.message.find("face " + std::to_string(n - 3) + " (vertices " + std::to_string(first[0]) + ", ") !=
                    std::string::npos,
                e.message);
  CHECK(e.details["hint"].get<std::string>().find("repair: true") != std::string::npos);

  // Without them: the fin's edge, named by its input vertices (the first two of the fin face).
  soup.triangles.resize(n - 3);
  e = refuse(soup);
  const core::Triangle fin_face = soup.triangles.back();
  const auto a = std::min(fin_face[0], fin_face[1]), b = std::max(fin_face[0], fin_face[1]);
  CHECK(e.code == ApiErrorCode::kNonManifoldEdge);
  CHECK(e.details["count"] == 1);
  CHECK(e.details["edges"] == json::array({json::array({a, b})}));
  CHECK_MESSAGE(e.message.find("between vertices " + std::to_string(a) + " and " + std::to_string(b)) != std::string::npos,
                e.message);

  // Without the fin: every edge on the flipped patch's rim, counted and listed in input numbering.
  soup.triangles.pop_back();
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (const auto& t : soup.triangles) {
    for (std::size_t k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> rim;
  for (const auto& [edge, uses] : directed) {
    if (uses == 2) rim.emplace_back(std::min(edge.first, edge.second), std::max(edge.first, edge.second));
  }
  std::sort(rim.begin(), rim.end());
  e = refuse(soup);
  CHECK(e.code == ApiErrorCode::kInconsistentOrientation);
  CHECK(e.details["count"] == rim.size());
  REQUIRE(e.details["edges"].size() == rim.size());
  for (std::size_t i = 0; i < rim.size(); ++i) {
    CHECK(e.details["edges"][i] == json::array({rim[i].first, rim[i].second}));
  }
  CHECK_MESSAGE(e.message.find(std::to_string(rim.size()) + " edges are traversed") != std::string::npos, e.message);
}

TEST_CASE("pipeline errors keep their codes") {
  const auto sphere = fixtures::icosphere(1);
  auto glb = write_plain_glb(core::IndexedMesh{sphere.positions, sphere.triangles});
  REQUIRE(glb.ok());
  SeamParams params;
  params.extrema.automatic = false;
  params.extrema.indices = {0, 1000};
  auto out = run_seam_pipeline(*glb, AssetKind::kAuto, params, {}, core::CancelToken::none());
  REQUIRE(!out.ok());
  CHECK(out.error().code == ApiErrorCode::kExtremumOutOfRange);
  CHECK(http_status(out.error().code) == 422);

  // An extremum at a vertex no triangle uses: the same code, naming the client's index (the
  // core named its own vertex number under index_out_of_range before).
  core::IndexedMesh unused{sphere.positions, sphere.triangles};
  unused.positions.insert(unused.positions.begin(), core::Vec3(5, 5, 5));
  for (auto& t : unused.triangles) t = {t[0] + 1, t[1] + 1, t[2] + 1};
  auto unused_glb = write_plain_glb(unused);
  REQUIRE(unused_glb.ok());
  params.extrema.indices = {7, 0};
  out = run_seam_pipeline(*unused_glb, AssetKind::kAuto, params, {}, core::CancelToken::none());
  REQUIRE(!out.ok());
  CHECK(out.error().code == ApiErrorCode::kExtremumOutOfRange);
  CHECK(out.error().details["index"] == 0);
  CHECK_MESSAGE(out.error().message.find("extremum vertex 0 lies in no face") != std::string::npos,
                out.error().message);

  // Only triangles without area (a line, a repeated vertex): empty, and the message says why.
  core::IndexedMesh flat{{core::Vec3(0, 0, 0), core::Vec3(1, 0, 0), core::Vec3(2, 0, 0)}, {{0, 1, 2}, {0, 0, 2}}};
  auto flat_glb = write_plain_glb(flat);
  REQUIRE(flat_glb.ok());
  out = run_seam_pipeline(*flat_glb, AssetKind::kAuto, SeamParams{}, {}, core::CancelToken::none());
  REQUIRE(!out.ok());
  CHECK(out.error().code == ApiErrorCode::kEmptyMesh);
  CHECK(out.error().details["degenerate_faces"] == 2);
  CHECK_MESSAGE(out.error().message.find("no triangle with area: all 2") != std::string::npos, out.error().message);

  // Three triangles on one edge: non-manifold, reported in input vertex indices.
  core::IndexedMesh fin{{core::Vec3(0, 0, 0), core::Vec3(1, 0, 0), core::Vec3(0, 1, 0), core::Vec3(0, -1, 0),
                         core::Vec3(0, 0, 1)},
                        {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}}};
  auto fin_glb = write_plain_glb(fin);
  REQUIRE(fin_glb.ok());
  params.extrema.indices = {2};
  params.repair = false;
  out = run_seam_pipeline(*fin_glb, AssetKind::kAuto, params, {}, core::CancelToken::none());
  REQUIRE(!out.ok());
  CHECK((out.error().code == ApiErrorCode::kNonManifoldEdge || out.error().code == ApiErrorCode::kInconsistentOrientation));

  PipelineLimits small;
  small.max_faces = 10;
  out = run_seam_pipeline(*glb, AssetKind::kAuto, SeamParams{}, small, core::CancelToken::none());
  REQUIRE(!out.ok());
  CHECK(out.error().code == ApiErrorCode::kMeshTooLarge);
  CHECK(out.error().details["limit"] == 10);

  // too_many_terminals says how many and how many the method takes, in details too.
  SeamParams twelve;
  twelve.method = core::SeamMethod::kOptimal;
  twelve.extrema.automatic = false;
  for (std::uint32_t v = 0; v < 12; ++v) twelve.extrema.indices.push_back(v);
  out = run_seam_pipeline(*glb, AssetKind::kAuto, twelve, {}, core::CancelToken::none());
  REQUIRE(!out.ok());
  CHECK(out.error().code == ApiErrorCode::kTooManyTerminals);
  CHECK(out.error().details["count"] == 12);
  CHECK(out.error().details["limit"] == 10);

  core::CancelToken cancelled;
  cancelled.cancel();
  out = run_seam_pipeline(*glb, AssetKind::kAuto, SeamParams{}, {}, cancelled);
  REQUIRE(!out.ok());
  CHECK(out.error().code == ApiErrorCode::kTimeout);
}

TEST_CASE("parameters from JSON and from the query string agree") {
  auto a = params_from_json(json{{"extrema", {12, 345, 678}}, {"method", "mst"}, {"uv", "none"}, {"output", "glb"},
                                 {"draco", true}, {"weld_epsilon", 0.001}, {"mesh", 1}, {"primitive", 2},
                                 {"refine", false}, {"repair", false}});
  auto b = params_from_query({{"extrema", "12,345,678"}, {"method", "mst"}, {"uv", "none"}, {"output", "glb"},
                              {"draco", "true"}, {"weld_epsilon", "0.001"}, {"mesh", "1"}, {"primitive", "2"},
                              {"refine", "0"}, {"repair", "false"}});
  for (auto* p : {&a, &b}) {
    REQUIRE(p->ok());
    CHECK(!(*p)->extrema.automatic);
    CHECK((*p)->extrema.indices == std::vector<std::uint32_t>{12, 345, 678});
    CHECK((*p)->method == core::SeamMethod::kMst);
    CHECK(!(*p)->uv.has_value());
    CHECK((*p)->output == OutputFormat::kGlb);
    CHECK((*p)->draco == true);
    CHECK((*p)->weld_epsilon == doctest::Approx(0.001));
    CHECK((*p)->mesh == 1);
    CHECK((*p)->primitive == 2);
    CHECK((*p)->refine == false);
    CHECK((*p)->repair == false);
  }
  auto defaults = params_from_json(json::object());
  REQUIRE(defaults.ok());
  CHECK(defaults->extrema.automatic);
  CHECK(defaults->method == core::SeamMethod::kSkeleton);
  CHECK(defaults->refine == true);
  CHECK(defaults->repair == true);
  CHECK(defaults->uv == core::UvOptions{}.method);
  CHECK(defaults->uv == core::UvMethod::kSlim);
  // Every method by name, in both forms.
  for (const auto& [name, method] : {std::pair{"slim", core::UvMethod::kSlim}, std::pair{"arap", core::UvMethod::kArap},
                                     std::pair{"bff", core::UvMethod::kBff}, std::pair{"lscm", core::UvMethod::kLscm}}) {
    CAPTURE(name);
    auto from_json = params_from_json(json{{"uv", name}});
    auto from_query = params_from_query({{"uv", name}});
    REQUIRE(from_json.ok());
    REQUIRE(from_query.ok());
    CHECK(from_json->uv == method);
    CHECK(from_query->uv == method);
  }
  auto positions = params_from_json(json{{"extrema", {{{"position", {0.1, 0.2, 0.3}}}, 7}}});
  REQUIRE(positions.ok());
  CHECK(positions->extrema.positions.size() == 1);
  CHECK(positions->extrema.indices == std::vector<std::uint32_t>{7});
  auto with_exclude = params_from_json(json{{"extrema", {{"auto", true}, {"include", {4}}, {"exclude", {9}}}}});
  REQUIRE(with_exclude.ok());
  CHECK(with_exclude->extrema.automatic);
  CHECK(with_exclude->extrema.exclude == std::vector<std::uint32_t>{9});

  for (const json& bad : {json{{"extrema", {-1}}}, json{{"extrema", "some"}}, json{{"method", "best"}},
                          json{{"uv", 3}}, json{{"weld_epsilon", -1}}, json{{"draco", "yes"}}, json{{"typo", 1}}, json{{"refine", 1}}, json{{"repair", "no"}},
                          json{{"extrema", json::array()}}, json{{"extrema", {{{"position", {1, 2}}}}}}}) {
    CAPTURE(bad.dump());
    auto r = params_from_json(bad);
    REQUIRE(!r.ok());
    CHECK(r.error().code == ApiErrorCode::kInvalidParameter);
  }
  for (const auto& bad : std::vector<std::vector<std::pair<std::string, std::string>>>{
           {{"extrema", "1,,2"}}, {{"extrema", "x"}}, {{"mesh", "-1"}}, {{"weld_epsilon", "1e"}},
           {{"method", "mst"}, {"method", "greedy"}}, {{"nope", "1"}}, {{"refine", "maybe"}}, {{"repair", "off"}}}) {
    auto r = params_from_query(bad);
    REQUIRE(!r.ok());
    CHECK(r.error().code == ApiErrorCode::kInvalidParameter);
  }
}

TEST_CASE("the query form takes the v2 parameters as JSON, pack=false and decimal numbers only") {
  using Query = std::vector<std::pair<std::string, std::string>>;
  // Each pair: the query form and the JSON form it stands for give the same parameters.
  struct Same {
    Query query;
    json body;
  };
  const json groups = {{"group_by", "mesh"}, {"texture_size", 512}};
  for (const auto& c :
       {Same{{{"pack", "false"}}, {{"pack", false}}}, Same{{{"pack", "0"}}, {{"pack", false}}},
        Same{{{"pack", "true"}}, {{"pack", true}}}, Same{{{"pack", groups.dump()}}, {{"pack", groups}}},
        Same{{{"hide_from", "[[0,0,1]]"}}, {{"hide_from", {{0, 0, 1}}}}},
        Same{{{"primitives", R"([{"mesh":0}])"}}, {{"primitives", {{{"mesh", 0}}}}}},
        Same{{{"primitives", "all"}}, {{"primitives", "all"}}},
        Same{{{"extrema", R"({"auto":true,"exclude":[3],"max_count":4})"}},
             {{"extrema", {{"auto", true}, {"exclude", {3}}, {"max_count", 4}}}}},
        Same{{{"extrema", R"([{"position":[1,2,3]},7])"}}, {{"extrema", {{{"position", {1, 2, 3}}}, 7}}}},
        Same{{{"weld_epsilon", "1e-3"}}, {{"weld_epsilon", 0.001}}},
        Same{{{"hide_strength", "10"}}, {{"hide_strength", 10}}}}) {
    CAPTURE(c.body.dump());
    auto q = params_from_query(c.query);
    auto j = params_from_json(c.body);
    REQUIRE_MESSAGE(q.ok(), (q.ok() ? "" : q.error().message));
    REQUIRE(j.ok());
    CHECK(q->pack.enabled == j->pack.enabled);
    CHECK(q->pack.group_by == j->pack.group_by);
    CHECK(q->pack.texture_size == j->pack.texture_size);
    CHECK(q->hide_from == j->hide_from);
    CHECK(q->primitives.has_value() == j->primitives.has_value());
    if (q->primitives && j->primitives) CHECK(q->primitives->size() == j->primitives->size());
    CHECK(q->extrema.automatic == j->extrema.automatic);
    CHECK(q->extrema.indices == j->extrema.indices);
    CHECK(q->extrema.exclude == j->extrema.exclude);
    CHECK(q->extrema.positions == j->extrema.positions);
    CHECK(q->extrema.auto_options.max_count == j->extrema.auto_options.max_count);
    CHECK(q->weld_epsilon == j->weld_epsilon);
    CHECK(q->hide_strength == j->hide_strength);
  }
  CHECK(!params_from_query({{"pack", "false"}})->pack.enabled);
  // Numbers are decimal: 0x10 was read as 16. Broken JSON names its parameter.
  for (const auto& bad : std::vector<Query>{{{"weld_epsilon", "0x10"}},
                                            {{"weld_epsilon", "inf"}},
                                            {{"hide_strength", "NaN"}},
                                            {{"feature_angle_deg", "+5"}, {"charts", "features"}},
                                            {{"weld_epsilon", "1,5"}},
                                            {{"hide_from", "[[0,0,1]"}},
                                            {{"hide_from", "0,0,1"}},
                                            {{"pack", "{group_by:mesh}"}},
                                            {{"pack", "yes"}},
                                            {{"primitives", "some"}},
                                            {{"extrema", "[1,"}},
                                            {{"hide_from", std::string(100, '[') + std::string(100, ']')}}}) {
    CAPTURE(bad.front().first + "=" + bad.front().second.substr(0, 20));
    auto r = params_from_query(bad);
    REQUIRE(!r.ok());
    CHECK(r.error().code == ApiErrorCode::kInvalidParameter);
    CHECK(r.error().details["parameter"] == bad.front().first);
  }
}

TEST_CASE("extrema.max_count 0 and feature_angle_deg without charts features are refused, pack true is the default") {
  // max_count 0 used to be taken and ignored: detection returned its usual extrema.
  for (const json& bad : {json{{"extrema", {{"auto", true}, {"max_count", 0}}}},
                          json{{"primitives", {{{"mesh", 0}, {"extrema", {{"max_count", 0}}}}}}}}) {
    auto r = params_from_json(bad);
    REQUIRE(!r.ok());
    CHECK(r.error().code == ApiErrorCode::kInvalidParameter);
    CHECK(r.error().details["parameter"] == "extrema.max_count");
  }
  CHECK(params_from_json({{"extrema", {{"auto", true}, {"max_count", 1}}}}).ok());
  // The angle alone changed nothing, silently.
  for (const json& bad : {json{{"feature_angle_deg", 30}}, json{{"feature_angle_deg", 30}, {"charts", "seam"}}}) {
    auto r = params_from_json(bad);
    REQUIRE(!r.ok());
    CHECK(r.error().details["parameter"] == "feature_angle_deg");
    CHECK(r.error().message.find("charts") != std::string::npos);
  }
  auto features = params_from_json({{"feature_angle_deg", 30}, {"charts", "features"}});
  REQUIRE(features.ok());
  CHECK(features->feature_angle_deg == 30);
  auto packed = params_from_json({{"pack", true}});
  REQUIRE(packed.ok());
  const PackParams defaults;
  CHECK(packed->pack.enabled);
  CHECK(packed->pack.group_by == defaults.group_by);
  CHECK(packed->pack.texture_size == defaults.texture_size);
  CHECK(packed->pack.margin_px == defaults.margin_px);
  CHECK(packed->pack.rotate == defaults.rotate);
}

TEST_CASE("explicit extrema beyond max_extrema are a 422 before the asset is even parsed") {
  SeamParams params;
  params.extrema.automatic = false;
  for (std::uint32_t i = 0; i < 300; ++i) params.extrema.indices.push_back(i);
  // Not an asset at all: the cost cap answers first.
  auto out = run_seam_pipeline("not an asset", AssetKind::kAuto, params, {}, core::CancelToken::none());
  REQUIRE(!out.ok());
  CHECK(out.error().code == ApiErrorCode::kTooManyExtrema);
  CHECK(http_status(out.error().code) == 422);
  CHECK(code_name(out.error().code) == "too_many_extrema");
  CHECK(out.error().message == "extrema: 300 explicit extrema, more than the limit of 256 (the server's --max-extrema)");
  CHECK(out.error().details["count"] == 300);
  CHECK(out.error().details["limit"] == 256);

  // Indices and positions count together.
  params.extrema.indices.resize(200);
  params.extrema.positions.assign(57, {0.0, 0.0, 0.0});
  out = run_seam_pipeline("not an asset", AssetKind::kAuto, params, {}, core::CancelToken::none());
  REQUIRE(!out.ok());
  CHECK(out.error().code == ApiErrorCode::kTooManyExtrema);
  CHECK(out.error().details["count"] == 257);
  // 256 is within the limit: the asset is parsed next, and refused.
  params.extrema.positions.resize(56);
  out = run_seam_pipeline("not an asset", AssetKind::kAuto, params, {}, core::CancelToken::none());
  REQUIRE(!out.ok());
  CHECK(out.error().code == ApiErrorCode::kMalformedAsset);

  PipelineLimits two;
  two.max_extrema = 2;
  params.extrema.indices = {0, 1, 2};
  params.extrema.positions.clear();
  out = run_seam_pipeline("not an asset", AssetKind::kAuto, params, two, core::CancelToken::none());
  REQUIRE(!out.ok());
  CHECK(out.error().code == ApiErrorCode::kTooManyExtrema);
  CHECK(out.error().message.find("limit of 2 ") != std::string::npos);
}

TEST_CASE("automatic extrema are capped at max_extrema: the most prominent, explicit ones first") {
  const auto glb = write_plain_glb(test_data::load_cgal("elephant"));
  REQUIRE(glb.ok());
  SeamParams params;
  params.method = core::SeamMethod::kMst;
  params.uv = std::nullopt;
  auto run = [&](const SeamParams& p, std::size_t max_extrema) {
    PipelineLimits limits;
    limits.max_extrema = max_extrema;
    auto out = run_seam_pipeline(*glb, AssetKind::kAuto, p, limits, core::CancelToken::none());
    REQUIRE_MESSAGE(out.ok(), (out.ok() ? "" : out.error().message));
    std::vector<std::uint32_t> extrema;
    for (const auto& v : out->body["seam"]["extrema"]) extrema.push_back(v.get<std::uint32_t>());
    return extrema;
  };
  // The elephant is one component: the detector lists its tips most prominent first.
  const auto all = run(params, 256);
  REQUIRE(all.size() > 3);
  const auto three = run(params, 3);
  REQUIRE(three.size() == 3);
  CHECK(std::set<std::uint32_t>(three.begin(), three.end()) == std::set<std::uint32_t>(all.begin(), all.begin() + 3));

  // An included vertex takes one of the three places; the two most prominent tips fill the rest.
  SeamParams with_include = params;
  with_include.extrema.indices = {all.back()};
  const auto mixed = run(with_include, 3);
  CHECK(std::set<std::uint32_t>(mixed.begin(), mixed.end()) ==
        std::set<std::uint32_t>{all[0], all[1], all.back()});
}

namespace {

// Threads started while `work` runs (Linux /proc/self/task, sampled every millisecond): the
// most alive at once beyond those alive before, the sampler not counted.
template <class F>
std::size_t extra_threads_during(F&& work) {
  auto count = [] {
    std::size_t n = 0;
    for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator("/proc/self/task")) ++n;
    return n;
  };
  const std::size_t before = count();
  std::atomic<bool> done = false;
  std::atomic<std::size_t> peak = before + 1;
  std::thread sampler([&] {
    do {
      peak = std::max(peak.load(), count());
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    } while (!done);
  });
  work();
  done = true;
  sampler.join();
  return peak - before - 1;
}

}  // namespace

TEST_CASE("limits.threads bounds the job's threads, and one thread gives the same bytes as two") {
  // Six spikes: six extrema, so the terminal paths would use five Dijkstra threads, and over
  // 10k vertices, so extrema detection would use as many as there are cores.
  const auto ball = fixtures::six_spike_ball(0.045);
  REQUIRE(ball.soup.positions.size() > 10'000);
  const auto glb = write_plain_glb(core::IndexedMesh{ball.soup.positions, ball.soup.triangles});
  REQUIRE(glb.ok());
  SeamParams params;
  params.uv = std::nullopt;  // the solver's threads (OpenBLAS) are not the pipeline's
  auto run = [&](unsigned threads) {
    PipelineLimits limits;
    limits.threads = threads;
    std::optional<PipelineOutput> out;
    const std::size_t extra = extra_threads_during([&] {
      auto r = run_seam_pipeline(*glb, AssetKind::kAuto, params, limits, core::CancelToken::none());
      REQUIRE_MESSAGE(r.ok(), (r.ok() ? "" : r.error().message));
      out = std::move(r).value();
    });
    CAPTURE(threads);
    CHECK(extra <= threads - 1);  // the calling thread works too
    return std::move(*out);
  };
  const PipelineOutput one = run(1);
  const PipelineOutput two = run(2);
  CHECK(one.body["seam"]["extrema"].size() == 6);
  CHECK(one.body["seam"] == two.body["seam"]);
  CHECK(one.body["cut"] == two.body["cut"]);
  CHECK(one.glb == two.glb);
}

}  // namespace seam_pipeline_test
