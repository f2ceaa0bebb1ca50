// glTF/GLB/Draco reading and writing: real-mesh round trips in three encodings, every
// accessor feature, the validator on our output, attribute preservation, hostile input.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>

#include "api/base64.h"
#include "api/draco_io.h"
#include "api/gltf_reader.h"
#include "api/gltf_writer.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/topology.h"
#include "core/mesh/weld.h"
#include "fixtures.h"
#include "gltf_test_util.h"
#include "test_data.h"

namespace seam_gltf_io_test {

namespace {

using namespace seam;
using namespace seam::api;
using seam::test_gltf::append;
using seam::test_gltf::json;
using seam::test_gltf::quad_asset;

using Tri3 = std::array<std::array<float, 3>, 3>;

// A triangle list in position space, each triangle rotated to start at its smallest corner
// (winding kept), sorted: equal for any vertex numbering, splitting or Draco reordering.
std::vector<Tri3> canonical(const core::IndexedMesh& m) {
  std::vector<Tri3> out;
  for (const auto& t : m.triangles) {
    Tri3 tri;
    for (int k = 0; k < 3; ++k) {
      const auto& p = m.positions[t[static_cast<std::size_t>(k)]];
      tri[static_cast<std::size_t>(k)] = {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())};
    }
    const auto first = std::min_element(tri.begin(), tri.end()) - tri.begin();
    std::rotate(tri.begin(), tri.begin() + first, tri.end());
    out.push_back(tri);
  }
  std::sort(out.begin(), out.end());
  return out;
}

struct Welded {
  std::size_t vertices = 0, edges = 0, faces = 0;
  int genus = 0;
  std::size_t boundary_loops = 0;
};

Welded welded_topology(const core::IndexedMesh& m) {
  auto weld = core::weld_vertices(m.positions, {});
  REQUIRE(weld.ok());
  const auto tris = core::remap_triangles(m.triangles, weld->input_to_welded);
  auto mesh = core::build_halfedge_mesh(weld->positions, tris);
  REQUIRE_MESSAGE(mesh.ok(), (mesh.ok() ? "" : mesh.error().message));
  REQUIRE(core::check_invariants(*mesh).ok());
  const auto topo = core::compute_topology(*mesh);
  return {mesh->num_vertices(), mesh->num_edges(), mesh->num_faces(), topo.total_genus(), topo.boundary_loops.size()};
}

PrimitiveData read_ok(const std::string& bytes, AssetKind kind = AssetKind::kAuto) {
  auto doc = parse_asset(bytes, kind);
  REQUIRE_MESSAGE(doc.ok(), (doc.ok() ? "" : doc.error().message));
  auto prim = read_primitive(*doc, 0, 0);
  REQUIRE_MESSAGE(prim.ok(), (prim.ok() ? "" : prim.error().message));
  return std::move(prim).value();
}

ApiErrorCode read_error(const std::string& bytes, AssetKind kind = AssetKind::kAuto) {
  auto doc = parse_asset(bytes, kind);
  if (!doc.ok()) return doc.error().code;
  auto prim = read_primitive(*doc, 0, 0);
  REQUIRE_MESSAGE(!prim.ok(), "expected an error");
  return prim.error().code;
}

// Exporters split vertices per face (flat normals) or per UV island; the split form here is
// the extreme case: every corner is its own vertex, with a per-face normal.
std::string split_glb(const core::IndexedMesh& m, bool draco = false) {
  core::IndexedMesh split;
  std::vector<float> normals;
  for (const auto& t : m.triangles) {
    const core::Vec3 n =
        (m.positions[t[1]] - m.positions[t[0]]).cross(m.positions[t[2]] - m.positions[t[0]]).normalized();
    core::Triangle nt;
    for (int k = 0; k < 3; ++k) {
      nt[static_cast<std::size_t>(k)] = static_cast<std::uint32_t>(split.positions.size());
      split.positions.push_back(m.positions[t[static_cast<std::size_t>(k)]]);
      normals.insert(normals.end(), {static_cast<float>(n.x()), static_cast<float>(n.y()), static_cast<float>(n.z())});
    }
    split.triangles.push_back(nt);
  }
  auto glb = write_plain_glb(split, {make_float_attribute("NORMAL", 3, normals)}, draco);
  REQUIRE(glb.ok());
  return *glb;
}

}  // namespace

TEST_CASE("real CGAL meshes as GLB, split-vertex GLB and Draco GLB give the same welded topology") {
  for (const char* name : {"elephant", "mushroom"}) {
    CAPTURE(name);
    const core::IndexedMesh soup = test_data::load_cgal(name);
    const auto plain = write_plain_glb(soup);
    const auto draco = write_plain_glb(soup, {}, true);
    REQUIRE(plain.ok());
    REQUIRE(draco.ok());
    const std::string split = split_glb(soup);
    const std::string split_draco = split_glb(soup, true);

    const auto a = read_ok(*plain), b = read_ok(split), c = read_ok(*draco), d = read_ok(split_draco);
    CHECK(!a.draco);
    CHECK(c.draco);
    CHECK(b.mesh.positions.size() == 3 * soup.triangles.size());
    CHECK(d.mesh.positions.size() == 3 * soup.triangles.size());
    const Welded wa = welded_topology(a.mesh);
    for (const auto* other : {&b, &c, &d}) {
      const Welded w = welded_topology(other->mesh);
      CHECK(w.vertices == wa.vertices);
      CHECK(w.edges == wa.edges);
      CHECK(w.faces == wa.faces);
      CHECK(w.genus == wa.genus);
      CHECK(w.boundary_loops == wa.boundary_loops);
      CHECK(canonical(other->mesh) == canonical(a.mesh));
    }
    // Positions come back exactly (float32 of the OFF's doubles), in input order.
    REQUIRE(a.mesh.positions.size() == soup.positions.size());
    for (std::size_t i = 0; i < soup.positions.size(); ++i) {
      CHECK(a.mesh.positions[i].x() == static_cast<float>(soup.positions[i].x()));
    }
    CHECK(a.mesh.triangles == soup.triangles);
    std::string report;
    CHECK_MESSAGE(test_gltf::validator_errors(*plain, report) == 0, report);
    CHECK_MESSAGE(test_gltf::validator_errors(split, report) == 0, report);
    CHECK_MESSAGE(test_gltf::validator_errors(*draco, report) == 0, report);
  }
}

TEST_CASE("reader: index types, non-indexed, byteStride, sparse, quantized positions, strips, fans, data URIs") {
  SUBCASE("u8 and u32 indices read the same triangles as u16") {
    for (int ct : {5121, 5125}) {
      auto [j, bin] = quad_asset();
      const std::size_t offset = bin.size();
      if (ct == 5121) append(bin, std::vector<std::uint8_t>{0, 1, 2, 0, 2, 3});
      else append(bin, std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3});
      j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", ct == 5121 ? 6 : 24}});
      j["accessors"][1] = {{"bufferView", 2}, {"componentType", ct}, {"count", 6}, {"type", "SCALAR"}};
      j["buffers"][0]["byteLength"] = bin.size();
      const auto p = read_ok(encode_glb(j, bin));
      CHECK(p.mesh.triangles == std::vector<core::Triangle>{{0, 1, 2}, {0, 2, 3}});
    }
  }
  SUBCASE("non-indexed triangles") {
    auto [j, bin] = quad_asset();
    j["meshes"][0]["primitives"][0].erase("indices");
    j["accessors"][0]["count"] = 3;
    const auto p = read_ok(encode_glb(j, bin));
    CHECK(p.mesh.triangles == std::vector<core::Triangle>{{0, 1, 2}});
  }
  SUBCASE("interleaved positions with byteStride") {
    std::vector<std::uint8_t> bin;
    // position (12 bytes) + 4 bytes of something else per vertex
    append(bin, std::vector<float>{0, 0, 0, 9, 1, 0, 0, 9, 1, 1, 0, 9});
    append(bin, std::vector<std::uint16_t>{0, 1, 2});
    auto [j, unused] = quad_asset();
    (void)unused;
    j["bufferViews"] = {{{"buffer", 0}, {"byteLength", 48}, {"byteStride", 16}},
                        {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 6}}};
    j["accessors"][0]["count"] = 3;
    j["accessors"][1]["count"] = 3;
    j["buffers"][0]["byteLength"] = bin.size();
    const auto p = read_ok(encode_glb(j, bin));
    REQUIRE(p.mesh.positions.size() == 3);
    CHECK(p.mesh.positions[2] == core::Vec3(1, 1, 0));
  }
  SUBCASE("sparse accessor overrides one vertex") {
    auto [j, bin] = quad_asset();
    const std::size_t off = bin.size();
    append(bin, std::vector<std::uint16_t>{2});
    const std::size_t voff = bin.size();
    append(bin, std::vector<float>{2, 2, 0});
    j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", off}, {"byteLength", 2}});
    j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", voff}, {"byteLength", 12}});
    j["accessors"][0]["sparse"] = {{"count", 1},
                                   {"indices", {{"bufferView", 2}, {"componentType", 5123}}},
                                   {"values", {{"bufferView", 3}}}};
    j["buffers"][0]["byteLength"] = bin.size();
    const auto p = read_ok(encode_glb(j, bin));
    CHECK(p.mesh.positions[2] == core::Vec3(2, 2, 0));
    CHECK(p.mesh.positions[1] == core::Vec3(1, 0, 0));
  }
  SUBCASE("KHR_mesh_quantization: normalized int16 positions") {
    auto [j, bin] = quad_asset();
    const std::size_t off = bin.size();
    append(bin, std::vector<std::int16_t>{0, 0, 0, 0, 32767, 0, 0, 0, 32767, 32767, 0, 0, -32767, 32767, 0, 0});
    j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", off}, {"byteLength", 32}, {"byteStride", 8}});
    j["accessors"][0] = {{"bufferView", 2}, {"componentType", 5122}, {"normalized", true}, {"count", 4}, {"type", "VEC3"}};
    j["extensionsUsed"] = {"KHR_mesh_quantization"};
    j["extensionsRequired"] = {"KHR_mesh_quantization"};
    j["buffers"][0]["byteLength"] = bin.size();
    const auto p = read_ok(encode_glb(j, bin));
    CHECK(p.mesh.positions[1] == core::Vec3(1, 0, 0));
    CHECK(p.mesh.positions[3] == core::Vec3(-1, 1, 0));
  }
  SUBCASE("triangle strip and fan are converted with consistent winding") {
    for (int mode : {5, 6}) {
      auto [j, bin] = quad_asset();
      const std::size_t off = bin.size();
      append(bin, mode == 5 ? std::vector<std::uint16_t>{1, 2, 0, 3} : std::vector<std::uint16_t>{0, 1, 2, 3});
      j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", off}, {"byteLength", 8}});
      j["accessors"][1] = {{"bufferView", 2}, {"componentType", 5123}, {"count", 4}, {"type", "SCALAR"}};
      j["meshes"][0]["primitives"][0]["mode"] = mode;
      j["buffers"][0]["byteLength"] = bin.size();
      const auto p = read_ok(encode_glb(j, bin));
      REQUIRE(p.mesh.triangles.size() == 2);
      // Both triangles face +z (the quad is counter-clockwise seen from +z).
      for (const auto& t : p.mesh.triangles) {
        const auto& q = p.mesh.positions;
        CHECK((q[t[1]] - q[t[0]]).cross(q[t[2]] - q[t[0]]).z() > 0);
      }
      CHECK(welded_topology(p.mesh).boundary_loops == 1);
    }
  }
  SUBCASE(".gltf JSON with a data-URI buffer") {
    auto [j, bin] = quad_asset();
    j["buffers"][0]["uri"] =
        "data:application/octet-stream;base64," + encode_base64(std::string(bin.begin(), bin.end()));
    const auto p = read_ok(j.dump());
    CHECK(p.mesh.triangles.size() == 2);
    CHECK(p.mesh.positions[2] == core::Vec3(1, 1, 0));
  }
  SUBCASE("raw Draco .drc") {
    const auto soup = fixtures::icosphere(2);
    core::IndexedMesh m{soup.positions, soup.triangles};
    auto glb = write_plain_glb(m, {}, true);
    REQUIRE(glb.ok());
    // Pull the Draco blob out of the GLB: it is bufferView 0 of our writer's output.
    auto doc = parse_asset(*glb, AssetKind::kGlb);
    REQUIRE(doc.ok());
    const auto& view = doc->json["bufferViews"][0];
    const std::string drc(reinterpret_cast<const char*>(doc->buffers[0].data()) + view.value("byteOffset", 0),
                          view["byteLength"].get<std::size_t>());
    CHECK(detect_asset_kind(drc) == AssetKind::kDraco);
    const auto p = read_ok(drc);
    CHECK(p.draco);
    CHECK(canonical(p.mesh) == canonical(read_ok(*glb).mesh));
  }
}

TEST_CASE("hostile inputs get their exact error code") {
  auto [j, bin] = quad_asset();
  const std::string good = encode_glb(j, bin);
  read_ok(good);
  auto with = [&](auto&& edit) {
    json jj = j;
    std::vector<std::uint8_t> bb = bin;
    edit(jj, bb);
    return encode_glb(jj, bb);
  };
  SUBCASE("truncated GLB") {
    for (std::size_t n : {0ul, 3ul, 12ul, 19ul, good.size() / 2, good.size() - 1}) {
      CAPTURE(n);
      CHECK(read_error(good.substr(0, n), AssetKind::kGlb) == ApiErrorCode::kMalformedAsset);
    }
  }
  SUBCASE("wrong chunk lengths") {
    std::string bad = good;
    const std::uint32_t huge = 0x7ffffff0;
    std::memcpy(bad.data() + 12, &huge, 4);  // JSON chunk length
    CHECK(read_error(bad) == ApiErrorCode::kMalformedAsset);
    bad = good;
    std::uint32_t json_len;
    std::memcpy(&json_len, good.data() + 12, 4);
    std::memcpy(bad.data() + 20 + json_len, &huge, 4);  // BIN chunk length
    CHECK(read_error(bad) == ApiErrorCode::kMalformedAsset);
    bad = good;
    const std::uint32_t total = static_cast<std::uint32_t>(good.size() + 100);
    std::memcpy(bad.data() + 8, &total, 4);
    CHECK(read_error(bad) == ApiErrorCode::kMalformedAsset);
  }
  SUBCASE("accessor past the buffer end") {
    CHECK(read_error(with([](json& x, auto&) { x["accessors"][0]["byteOffset"] = 40; })) == ApiErrorCode::kMalformedAsset);
    CHECK(read_error(with([](json& x, auto&) { x["bufferViews"][0]["byteLength"] = 4000; })) ==
          ApiErrorCode::kMalformedAsset);
    CHECK(read_error(with([](json& x, auto&) { x["buffers"][0]["byteLength"] = 1u << 30; })) ==
          ApiErrorCode::kMalformedAsset);
    CHECK(read_error(with([](json& x, auto&) { x["accessors"][0]["bufferView"] = 7; })) == ApiErrorCode::kMalformedAsset);
  }
  SUBCASE("huge declared counts are refused before allocation") {
    CHECK(read_error(with([](json& x, auto&) { x["accessors"][0]["count"] = 4000000000u; })) ==
          ApiErrorCode::kMalformedAsset);
    CHECK(read_error(with([](json& x, auto&) { x["accessors"][1]["count"] = std::uint64_t{1} << 62; })) ==
          ApiErrorCode::kMalformedAsset);
    // No bufferView: the count is bounded only by the limit.
    CHECK(read_error(with([](json& x, auto&) {
            x["accessors"][0].erase("bufferView");
            x["accessors"][0]["count"] = 4000000000u;
          })) == ApiErrorCode::kMeshTooLarge);
    auto unbacked = parse_asset(with([](json& x, auto&) {
                                  x["accessors"][0].erase("bufferView");
                                  x["accessors"][0]["count"] = 4000000000u;
                                }),
                                AssetKind::kAuto);
    REQUIRE(unbacked.ok());
    auto refused = read_primitive(*unbacked, 0, 0);
    REQUIRE(!refused.ok());
    CHECK(refused.error().details == json{{"count", 4000000000u}, {"limit", ReadLimits{}.max_vertices}});
    ReadLimits few;
    few.max_faces = 1;
    auto two_triangles = read_primitive(*parse_asset(good, AssetKind::kAuto), 0, 0, few);
    REQUIRE(!two_triangles.ok());
    CHECK(two_triangles.error().code == ApiErrorCode::kMeshTooLarge);
    CHECK(two_triangles.error().details["limit"] == 1);
  }
  SUBCASE("index out of range") {
    auto bad = bin;
    const std::uint16_t v = 9;
    std::memcpy(bad.data() + 48 + 4, &v, 2);
    CHECK(read_error(encode_glb(j, bad)) == ApiErrorCode::kIndexOutOfRange);
  }
  SUBCASE("external URIs are refused, never read") {
    for (const char* uri : {"../../etc/passwd", "/etc/passwd", "file:///etc/passwd", "http://example.com/a.bin",
                            "..%2F..%2Fetc%2Fpasswd"}) {
      CAPTURE(uri);
      json jj = j;
      jj["buffers"][0]["uri"] = uri;
      CHECK(read_error(jj.dump(), AssetKind::kGltfJson) == ApiErrorCode::kExternalUri);
      CHECK(read_error(with([&](json& x, auto&) { x["images"] = {{{"uri", uri}}}; })) == ApiErrorCode::kExternalUri);
    }
  }
  SUBCASE("a required extension the reader does not support is a 422 naming it") {
    // glTF 2.0 §3.12: a loader must fail on one. It used to be read and passed through.
    for (const std::string name : {"EXT_foo", "EXT_meshopt_compression"}) {
      CAPTURE(name);
      auto doc = parse_asset(with([&](json& x, auto&) {
                               x["extensionsUsed"] = {name};
                               x["extensionsRequired"] = {name};
                             }),
                             AssetKind::kAuto);
      REQUIRE(!doc.ok());
      CHECK(doc.error().code == ApiErrorCode::kUnsupportedExtension);
      CHECK(doc.error().details["extensions"] == json{name});
      CHECK(doc.error().message.find(name) != std::string::npos);
    }
    auto several = parse_asset(with([](json& x, auto&) {
                                 x["extensionsRequired"] = {"KHR_mesh_quantization", "EXT_a", "EXT_b"};
                               }),
                               AssetKind::kAuto);
    REQUIRE(!several.ok());
    CHECK(several.error().details["extensions"] == json{"EXT_a", "EXT_b"});
    // Supported (decoded) or passed through without touching geometry: accepted when required.
    for (const std::string name : {"KHR_mesh_quantization", "KHR_draco_mesh_compression", "KHR_materials_unlit",
                                   "KHR_materials_variants", "KHR_texture_transform", "KHR_texture_basisu",
                                   "EXT_texture_webp", "KHR_lights_punctual", "EXT_mesh_gpu_instancing"}) {
      CAPTURE(name);
      CHECK(parse_asset(with([&](json& x, auto&) { x["extensionsRequired"] = {name}; }), AssetKind::kAuto).ok());
    }
    // Only used, not required: read as before.
    CHECK(parse_asset(with([](json& x, auto&) { x["extensionsUsed"] = {"EXT_foo"}; }), AssetKind::kAuto).ok());
    CHECK(read_error(with([](json& x, auto&) { x["extensionsRequired"] = "EXT_foo"; })) ==
          ApiErrorCode::kMalformedAsset);
    CHECK(read_error(with([](json& x, auto&) { x["extensionsRequired"] = {1}; })) == ApiErrorCode::kMalformedAsset);
  }
  SUBCASE("NaN and infinite positions") {
    for (float bad_value : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
      auto bad = bin;
      std::memcpy(bad.data() + 16, &bad_value, 4);  // vertex 1, y
      auto doc = parse_asset(encode_glb(j, bad), AssetKind::kGlb);
      REQUIRE(doc.ok());
      auto prim = read_primitive(*doc, 0, 0);
      REQUIRE(!prim.ok());
      CHECK(prim.error().code == ApiErrorCode::kNonFinitePosition);
      CHECK(prim.error().details["vertices"] == json::array({1}));
    }
  }
  SUBCASE("points and lines are 422 unsupported_primitive_mode") {
    for (int mode : {0, 1, 2, 3}) {
      CHECK(read_error(with([&](json& x, auto&) { x["meshes"][0]["primitives"][0]["mode"] = mode; })) ==
            ApiErrorCode::kUnsupportedPrimitiveMode);
      CHECK(http_status(ApiErrorCode::kUnsupportedPrimitiveMode) == 422);
    }
    CHECK(read_error(with([&](json& x, auto&) { x["meshes"][0]["primitives"][0]["mode"] = 9; })) ==
          ApiErrorCode::kMalformedAsset);
  }
  SUBCASE("bad Draco bufferView and bad Draco bytes") {
    auto draco_ext = [](json& x, std::vector<std::uint8_t>&, int view) {
      x["meshes"][0]["primitives"][0]["extensions"] = {
          {"KHR_draco_mesh_compression", {{"bufferView", view}, {"attributes", {{"POSITION", 0}}}}}};
    };
    CHECK(read_error(with([&](json& x, auto& b) { draco_ext(x, b, 99); })) == ApiErrorCode::kMalformedAsset);
    // bufferView 0 holds floats, not Draco data: the decoder's failure is reported.
    CHECK(read_error(with([&](json& x, auto& b) { draco_ext(x, b, 0); })) == ApiErrorCode::kMalformedAsset);
    CHECK(read_error(std::string("DRACO\x02\x02\x01\x01\x00\x00", 11)) == ApiErrorCode::kMalformedAsset);
  }
  SUBCASE("missing primitive, bad JSON, deep nesting") {
    auto doc = parse_asset(good, AssetKind::kGlb);
    REQUIRE(doc.ok());
    CHECK(read_primitive(*doc, 1, 0).error().code == ApiErrorCode::kNoTrianglePrimitive);
    CHECK(read_primitive(*doc, 0, 5).error().code == ApiErrorCode::kNoTrianglePrimitive);
    CHECK(read_error("{\"asset\": ", AssetKind::kGltfJson) == ApiErrorCode::kMalformedAsset);
    CHECK(read_error(std::string(100000, '[') + std::string(100000, ']'), AssetKind::kGltfJson) ==
          ApiErrorCode::kMalformedAsset);
    CHECK(read_error("{\"asset\": {\"version\": \"1.0\"}}", AssetKind::kGltfJson) == ApiErrorCode::kMalformedAsset);
    CHECK(read_error(with([](json& x, auto&) { x["accessors"][0]["componentType"] = 5127; })) ==
          ApiErrorCode::kMalformedAsset);
    CHECK(read_error(with([](json& x, auto&) { x["accessors"][0]["count"] = -3; })) == ApiErrorCode::kMalformedAsset);
    CHECK(read_error(with([](json& x, auto&) { x["accessors"][0]["count"] = 2.5; })) == ApiErrorCode::kMalformedAsset);
    CHECK(read_error("garbage") == ApiErrorCode::kMalformedAsset);
  }
  if (const char* dir = std::getenv("SEAM_WRITE_FUZZ_CORPUS")) {
    // Seeds for tests/fuzz/corpus: run once with the variable set to that directory.
    test_gltf::write_file(std::string(dir) + "/quad.glb", good);
    test_gltf::write_file(std::string(dir) + "/quad.gltf", [&] {
      json jj = j;
      jj["buffers"][0]["uri"] = "data:application/octet-stream;base64," + encode_base64(std::string(bin.begin(), bin.end()));
      return jj.dump();
    }());
    const auto soup = fixtures::icosphere(1);
    auto draco = write_plain_glb(core::IndexedMesh{soup.positions, soup.triangles}, {}, true);
    REQUIRE(draco.ok());
    test_gltf::write_file(std::string(dir) + "/icosphere_draco.glb", *draco);
    test_gltf::write_file(std::string(dir) + "/sparse_strip.glb", with([](json& x, std::vector<std::uint8_t>& b) {
                            const std::size_t off = b.size();
                            append(b, std::vector<std::uint16_t>{2});
                            const std::size_t voff = b.size();
                            append(b, std::vector<float>{2, 2, 0});
                            x["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", off}, {"byteLength", 2}});
                            x["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", voff}, {"byteLength", 12}});
                            x["accessors"][0]["sparse"] = {{"count", 1},
                                                           {"indices", {{"bufferView", 2}, {"componentType", 5123}}},
                                                           {"values", {{"bufferView", 3}}}};
                            x["meshes"][0]["primitives"][0]["mode"] = 5;
                            x["buffers"][0]["byteLength"] = b.size();
                          }));
  }
}

namespace {

// A GLB whose JSON chunk is `text` verbatim (encode_glb would have to dump a json value,
// which is what a hostile depth must never reach).
std::string glb_with_json_text(std::string text) {
  while (text.size() % 4 != 0) text += ' ';
  std::string out("glTF", 4);
  auto put = [&](std::uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
  put(2);
  put(static_cast<std::uint32_t>(12 + 8 + text.size()));
  put(static_cast<std::uint32_t>(text.size()));
  put(0x4E4F534A);  // "JSON"
  return out + text;
}

std::string gltf_with_extras(const std::string& extras) {
  return R"({"asset":{"version":"2.0"},"extras":)" + extras + "}";
}

}  // namespace

TEST_CASE("glTF JSON nested 100,000 deep is a malformed asset in .gltf and GLB, depth 64 is read") {
  const std::string deep_arrays = std::string(100'000, '[') + std::string(100'000, ']');
  std::string deep_objects;
  for (int i = 0; i < 100'000; ++i) deep_objects += "{\"a\":";
  deep_objects += "1" + std::string(100'000, '}');
  for (const std::string& json_text : {deep_arrays, gltf_with_extras(deep_arrays), gltf_with_extras(deep_objects)}) {
    for (const auto& [bytes, kind] : {std::pair{json_text, AssetKind::kGltfJson},
                                      std::pair{glb_with_json_text(json_text), AssetKind::kGlb},
                                      std::pair{glb_with_json_text(json_text), AssetKind::kAuto}}) {
      auto doc = parse_asset(bytes, kind);
      REQUIRE(!doc.ok());
      CHECK(doc.error().code == ApiErrorCode::kMalformedAsset);
      CHECK(http_status(doc.error().code) == 400);
      CHECK(doc.error().message.find("JSON nested deeper than 64 levels at byte ") != std::string::npos);
    }
  }
  // The document object is level 1 and "extras" holds 63 more: depth 64, read (and safe to
  // dump, which the writer does).
  const std::string at_64 = gltf_with_extras(std::string(63, '[') + std::string(63, ']'));
  for (const auto& [bytes, kind] :
       {std::pair{at_64, AssetKind::kGltfJson}, std::pair{glb_with_json_text(at_64), AssetKind::kGlb}}) {
    auto doc = parse_asset(bytes, kind);
    REQUIRE_MESSAGE(doc.ok(), (doc.ok() ? "" : doc.error().message));
    CHECK(doc->json.dump().size() == at_64.size());
  }
  const std::string at_65 = gltf_with_extras(std::string(64, '[') + std::string(64, ']'));
  CHECK(parse_asset(at_65, AssetKind::kGltfJson).error().code == ApiErrorCode::kMalformedAsset);
}

TEST_CASE("gltf: a Draco primitive whose POSITION comes from its accessor must have the Draco point count (gltf_fuzz reproducer)") {
  // The extension names "[OSITION" instead of POSITION, so POSITION is read from its accessor
  // (no bufferView: 41 zeros) while the triangles index the Draco mesh's 42 points. The reader
  // returned triangles with index 41 for 41 vertices; the writer then wrote an asset that did
  // not read back.
  const std::string path = std::string(SEAM_SOURCE_DIR) + "/tests/fuzz/regressions/gltf/draco_position_from_accessor.glb";
  std::ifstream in(path, std::ios::binary);
  REQUIRE(in);
  const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  ReadLimits limits;
  auto doc = parse_asset(bytes, AssetKind::kAuto, limits);
  REQUIRE(doc.ok());
  auto prim = read_primitive(*doc, 0, 0, limits);
  REQUIRE_FALSE(prim.ok());
  CHECK(prim.error().code == ApiErrorCode::kMalformedAsset);
  CAPTURE(prim.error().message);
  CHECK(prim.error().message.find("41 vertices but the Draco data has 42") != std::string::npos);
}

}  // namespace seam_gltf_io_test
