// The real-looking asset set (tests/assets/build_assets.mjs, built into .cache/assets by the
// test set-up): every asset cut whole with default parameters must give 200, one `primitives`
// entry per triangle primitive (an instanced mesh once), new UVs on every vertex of every
// triangle primitive with 0 flips, each component a disc, a validator-clean asset with no
// unused objects beyond the input's, every input attribute, morph target, skin and animation
// kept exactly, and repairs reported where defects were planted (issue 11 item 7).
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <draco/attributes/attribute_octahedron_transform.h>
#include <draco/attributes/attribute_quantization_transform.h>
#include <draco/compression/decode.h>
#include <nlohmann/json.hpp>

#include "api/gltf_reader.h"
#include "api/pipeline.h"
#include "gltf_test_util.h"

namespace seam_asset_set_test {

namespace {

using namespace seam;
using namespace seam::api;
using nlohmann::json;

std::filesystem::path assets_dir() { return std::filesystem::path(SEAM_TEST_DATA_DIR).parent_path() / "assets"; }

std::string read_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The builder's manifest entry for `file`; fails with the set-up command when it is missing.
json manifest_entry(const std::string& file) {
  const auto manifest = assets_dir() / "manifest.json";
  if (!std::filesystem::exists(manifest)) {
    FAIL("missing " << manifest.string() << ": run scripts/fetch-test-data.sh (it builds the asset set when "
                    << "`npm install --prefix tests` has installed glTF-Transform)");
  }
  const json m = json::parse(read_bytes(manifest));
  for (const auto& a : m["assets"]) {
    if (a["file"] == file) return a;
  }
  FAIL(file << " is not in " << manifest.string() << ": rebuild with scripts/fetch-test-data.sh");
  return {};
}

/// The validator's JSON report (tests/assets/validate_report.mjs) on each of `glbs`, in order.
std::vector<json> validate(const std::vector<std::string>& glbs, const std::string& name) {
  const std::string tests_dir = std::string(SEAM_SOURCE_DIR) + "/tests";
  std::string command = "node '" + tests_dir + "/assets/validate_report.mjs'";
  std::vector<std::string> paths;
  for (std::size_t i = 0; i < glbs.size(); ++i) {
    paths.push_back(test_gltf::temp_path(name + "_" + std::to_string(i) + ".glb"));
    test_gltf::write_file(paths.back(), glbs[i]);
    command += " '" + paths.back() + "'";
  }
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  REQUIRE(pipe != nullptr);
  std::string out;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe) != nullptr) out += buffer;
  const int status = ::pclose(pipe);
  for (const auto& p : paths) std::filesystem::remove(p);
  REQUIRE_MESSAGE(status == 0, "the validator did not run: " << out);
  std::vector<json> reports;
  std::istringstream lines(out);
  for (std::string line; std::getline(lines, line);) reports.push_back(json::parse(line));
  REQUIRE(reports.size() == glbs.size());
  return reports;
}

bool is_triangles(const json& primitive) {
  const int mode = primitive.value("mode", 4);
  return mode == 4 || mode == 5 || mode == 6;
}

/// An accessor's elements, tightly packed (no sparse accessors in the set's skins and
/// animations; the builder writes none).
std::vector<std::uint8_t> accessor_bytes(const GltfDocument& doc, std::size_t index) {
  const json& a = doc.json["accessors"][index];
  REQUIRE(!a.contains("sparse"));
  static const std::map<std::string, std::size_t> kComponents{{"SCALAR", 1}, {"VEC2", 2}, {"VEC3", 3}, {"VEC4", 4},
                                                               {"MAT2", 4},   {"MAT3", 9}, {"MAT4", 16}};
  const int type = a["componentType"].get<int>();
  const std::size_t csize = type == 5126 || type == 5125 ? 4 : type == 5122 || type == 5123 ? 2 : 1;
  const std::size_t element = csize * kComponents.at(a["type"].get<std::string>());
  const std::size_t count = a["count"].get<std::size_t>();
  const json& view = doc.json["bufferViews"][a["bufferView"].get<std::size_t>()];
  const std::size_t stride = view.value("byteStride", element);
  const std::size_t start = view.value("byteOffset", std::size_t{0}) + a.value("byteOffset", std::size_t{0});
  const auto& buffer = doc.buffers[view["buffer"].get<std::size_t>()];
  std::vector<std::uint8_t> out;
  for (std::size_t i = 0; i < count; ++i) {
    REQUIRE(start + i * stride + element <= buffer.size());
    out.insert(out.end(), buffer.begin() + static_cast<std::ptrdiff_t>(start + i * stride),
               buffer.begin() + static_cast<std::ptrdiff_t>(start + i * stride + element));
  }
  return out;
}

/// A glTF object with its accessor references replaced by the accessors' contents, so that
/// skins, animations and other primitives compare equal across a renumbering of accessors.
json with_accessor_data(const GltfDocument& doc, json object, const std::vector<std::string>& accessor_keys) {
  for (const auto& key : accessor_keys) {
    if (object.contains(key) && object[key].is_number_unsigned()) {
      const auto bytes = accessor_bytes(doc, object[key].get<std::size_t>());
      json a = doc.json["accessors"][object[key].get<std::size_t>()];
      a.erase("bufferView");
      a.erase("byteOffset");
      a["data"] = json::binary(bytes);
      object[key] = a;
    }
  }
  return object;
}

using Tuple = std::string;  // every input attribute's and morph target's bytes of one vertex
using PositionKey = std::array<double, 3>;

PositionKey position_key(const PrimitiveData& p, std::size_t v) {
  const auto& x = p.mesh.positions[v];
  return {x.x(), x.y(), x.z()};
}

/// Vertex `v`'s bytes of the attributes named in `names` and of every morph target.
Tuple tuple_of(const PrimitiveData& p, std::size_t v, const std::set<std::string>& names) {
  Tuple t;
  for (const auto& a : p.attributes) {
    if (names.count(a.name) == 0) continue;
    t += a.name;
    t.append(reinterpret_cast<const char*>(a.data.data() + v * a.element_size()), a.element_size());
  }
  for (const auto& target : p.targets) {
    for (const auto& a : target) {
      t += "target:" + a.name;
      t.append(reinterpret_cast<const char*>(a.data.data() + v * a.element_size()), a.element_size());
    }
  }
  return t;
}

/// How a Draco primitive stores each glTF attribute: "quantized N" or "octahedron N" bits, or
/// "lossless" (read with the attribute transforms skipped, so the bitstream's own parameters).
std::map<std::string, std::string> draco_storage(const GltfDocument& doc, std::size_t m, std::size_t p) {
  const json& ext = doc.json["meshes"][m]["primitives"][p]["extensions"]["KHR_draco_mesh_compression"];
  const json& view = doc.json["bufferViews"][ext["bufferView"].get<std::size_t>()];
  const auto& buffer = doc.buffers[view["buffer"].get<std::size_t>()];
  draco::DecoderBuffer bytes;
  bytes.Init(reinterpret_cast<const char*>(buffer.data()) + view.value("byteOffset", std::size_t{0}),
             view["byteLength"].get<std::size_t>());
  draco::Decoder decoder;
  for (auto type : {draco::GeometryAttribute::POSITION, draco::GeometryAttribute::NORMAL, draco::GeometryAttribute::COLOR,
                    draco::GeometryAttribute::TEX_COORD, draco::GeometryAttribute::GENERIC}) {
    decoder.SetSkipAttributeTransform(type);
  }
  auto decoded = decoder.DecodeMeshFromBuffer(&bytes);
  REQUIRE_MESSAGE(decoded.ok(), decoded.status().error_msg_string());
  const auto mesh = std::move(decoded).value();
  std::map<std::string, std::string> storage;
  for (const auto& [name, id] : ext["attributes"].items()) {
    const draco::PointAttribute* a = mesh->GetAttributeByUniqueId(id.get<std::uint32_t>());
    REQUIRE(a != nullptr);
    const draco::AttributeTransformData* transform = a->GetAttributeTransformData();
    std::string kind = "lossless";
    if (transform && transform->transform_type() == draco::ATTRIBUTE_QUANTIZATION_TRANSFORM) {
      draco::AttributeQuantizationTransform q;
      REQUIRE(q.InitFromAttribute(*a));
      kind = "quantized " + std::to_string(q.quantization_bits());
    } else if (transform && transform->transform_type() == draco::ATTRIBUTE_OCTAHEDRON_TRANSFORM) {
      draco::AttributeOctahedronTransform o;
      REQUIRE(o.InitFromAttribute(*a));
      kind = "octahedron " + std::to_string(o.quantization_bits());
    }
    storage[name] = kind;
  }
  return storage;
}

/// One processed primitive's output against its input: same faces, every output vertex one
/// of the input vertices at its position with all its attributes and morph deltas bit-exact,
/// every input vertex kept, and the new UV set on every vertex.
void check_primitive(const PrimitiveData& in, const PrimitiveData& out, const json& entry) {
  CHECK(out.mesh.triangles.size() == in.mesh.triangles.size());
  CHECK(out.draco == in.draco);
  std::map<std::string, const AttributeArray*> in_attr, out_attr;
  for (const auto& a : in.attributes) in_attr[a.name] = &a;
  for (const auto& a : out.attributes) out_attr[a.name] = &a;

  // The new UV set: a TEXCOORD the input did not have, on every vertex, finite.
  REQUIRE(entry["uv"].contains("channel"));
  const std::string uv_name = "TEXCOORD_" + std::to_string(entry["uv"]["channel"].get<int>());
  CHECK(in_attr.count(uv_name) == 0);
  REQUIRE_MESSAGE(out_attr.count(uv_name) == 1, "no " << uv_name << " in the output primitive");
  const AttributeArray& uv = *out_attr[uv_name];
  CHECK(uv.components == 2);
  CHECK(uv.count == out.mesh.positions.size());
  if (uv.component_type == 5126) {
    std::size_t bad = 0;
    for (std::size_t i = 0; i < 2 * uv.count; ++i) {
      float f;
      std::memcpy(&f, uv.data.data() + 4 * i, 4);
      bad += !std::isfinite(f);
    }
    CHECK(bad == 0);
    // Flip-free, checked here and not only taken from uv.flipped: every triangle that is not
    // degenerate in 3D turns the same way in UV as the others.
    std::size_t positive = 0, negative = 0;
    auto at = [&](std::uint32_t v, int c) {
      float f;
      std::memcpy(&f, uv.data.data() + 8 * v + 4 * static_cast<std::size_t>(c), 4);
      return static_cast<double>(f);
    };
    for (const auto& t : out.mesh.triangles) {
      const auto& p = out.mesh.positions;
      if ((p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]).squaredNorm() == 0) continue;
      const double area = (at(t[1], 0) - at(t[0], 0)) * (at(t[2], 1) - at(t[0], 1)) -
                          (at(t[1], 1) - at(t[0], 1)) * (at(t[2], 0) - at(t[0], 0));
      positive += area > 0;
      negative += area < 0;
    }
    CHECK_MESSAGE(std::min(positive, negative) == 0, positive << " UV triangles turn one way, " << negative << " the other");
  }

  // The same attributes, in the same component types (quantized stays quantized).
  std::set<std::string> names;
  for (const auto& [name, a] : in_attr) {
    CAPTURE(name);
    names.insert(name);
    REQUIRE(out_attr.count(name) == 1);
    CHECK(out_attr[name]->component_type == a->component_type);
    CHECK(out_attr[name]->normalized == a->normalized);
    CHECK(out_attr[name]->components == a->components);
  }
  REQUIRE(out.targets.size() == in.targets.size());
  for (std::size_t t = 0; t < in.targets.size(); ++t) {
    REQUIRE(out.targets[t].size() == in.targets[t].size());
    for (std::size_t k = 0; k < in.targets[t].size(); ++k) {
      CHECK(out.targets[t][k].name == in.targets[t][k].name);
      CHECK(out.targets[t][k].component_type == in.targets[t][k].component_type);
    }
  }

  // Split input vertices share a position, so the match is by position, then by the whole
  // tuple of attribute and morph-target bytes.
  std::map<PositionKey, std::set<Tuple>> input_tuples;
  std::set<std::uint32_t> used;
  for (const auto& t : in.mesh.triangles) used.insert(t.begin(), t.end());
  for (const std::uint32_t v : used) input_tuples[position_key(in, v)].insert(tuple_of(in, v, names));
  std::size_t unknown_position = 0, changed = 0;
  std::set<std::pair<PositionKey, Tuple>> seen;
  for (std::size_t v = 0; v < out.mesh.positions.size(); ++v) {
    const auto it = input_tuples.find(position_key(out, v));
    if (it == input_tuples.end()) {
      ++unknown_position;
      continue;
    }
    const Tuple t = tuple_of(out, v, names);
    if (it->second.count(t) == 0) ++changed;
    seen.emplace(it->first, t);
  }
  CHECK_MESSAGE(unknown_position == 0, unknown_position << " output vertices at positions the input does not have");
  CHECK_MESSAGE(changed == 0, changed << " output vertices whose attributes or morph deltas differ from every input "
                                         "vertex at their position");
  std::size_t input_distinct = 0;
  for (const auto& [p, tuples] : input_tuples) input_distinct += tuples.size();
  CHECK_MESSAGE(seen.size() == input_distinct, "input vertices lost: " << input_distinct - seen.size());
}

/// Everything of the document but the processed primitives must survive: nodes, scenes,
/// materials, textures, skins (joints, inverse bind matrices), animations (channels and
/// keyframes), mesh names and weights, and the primitives that were not cut.
void check_document(const GltfDocument& in, const GltfDocument& out, const std::set<std::pair<int, int>>& processed) {
  for (const char* key : {"nodes", "scenes", "scene", "materials", "textures", "images", "samplers"}) {
    CAPTURE(key);
    CHECK(in.json.value(key, json()) == out.json.value(key, json()));
  }
  const json no_skins = json::array();
  const json& in_skins = in.json.value("skins", no_skins);
  REQUIRE(out.json.value("skins", no_skins).size() == in_skins.size());
  for (std::size_t s = 0; s < in_skins.size(); ++s) {
    CHECK(with_accessor_data(in, in_skins[s], {"inverseBindMatrices"}) ==
          with_accessor_data(out, out.json["skins"][s], {"inverseBindMatrices"}));
  }
  const json& in_anims = in.json.value("animations", no_skins);
  REQUIRE(out.json.value("animations", no_skins).size() == in_anims.size());
  for (std::size_t a = 0; a < in_anims.size(); ++a) {
    CHECK(in_anims[a]["channels"] == out.json["animations"][a]["channels"]);
    REQUIRE(out.json["animations"][a]["samplers"].size() == in_anims[a]["samplers"].size());
    for (std::size_t s = 0; s < in_anims[a]["samplers"].size(); ++s) {
      CHECK(with_accessor_data(in, in_anims[a]["samplers"][s], {"input", "output"}) ==
            with_accessor_data(out, out.json["animations"][a]["samplers"][s], {"input", "output"}));
    }
  }
  REQUIRE(out.json["meshes"].size() == in.json["meshes"].size());
  for (std::size_t m = 0; m < in.json["meshes"].size(); ++m) {
    const json& im = in.json["meshes"][m];
    const json& om = out.json["meshes"][m];
    CHECK(im.value("name", "") == om.value("name", ""));
    CHECK(im.value("weights", json()) == om.value("weights", json()));
    REQUIRE(om["primitives"].size() == im["primitives"].size());
    for (std::size_t p = 0; p < im["primitives"].size(); ++p) {
      const json& ip = im["primitives"][p];
      const json& op = om["primitives"][p];
      CHECK(ip.value("material", -1) == op.value("material", -1));
      if (processed.count({static_cast<int>(m), static_cast<int>(p)})) continue;
      // Not cut (lines): every accessor's contents as they were.
      json ia = ip["attributes"], oa = op["attributes"];
      std::vector<std::string> keys;
      for (auto it = ia.begin(); it != ia.end(); ++it) keys.push_back(it.key());
      CHECK(with_accessor_data(in, ia, keys) == with_accessor_data(out, oa, keys));
      CHECK(with_accessor_data(in, ip, {"indices"})["indices"] == with_accessor_data(out, op, {"indices"})["indices"]);
    }
  }
}

/// Cuts `file` whole with default parameters and checks everything the issue asks.
void check_asset(const std::string& file) {
  const json manifest = manifest_entry(file);
  const std::string input = read_bytes(assets_dir() / file);
  auto in_doc = parse_asset(input, AssetKind::kGlb);
  REQUIRE_MESSAGE(in_doc.ok(), (in_doc.ok() ? "" : in_doc.error().message));

  // The triangle primitives of every mesh, in asset order: what `primitives` must list.
  std::vector<std::pair<int, int>> expected;
  for (std::size_t m = 0; m < in_doc->json["meshes"].size(); ++m) {
    const json& prims = in_doc->json["meshes"][m]["primitives"];
    for (std::size_t p = 0; p < prims.size(); ++p) {
      if (is_triangles(prims[p])) expected.emplace_back(static_cast<int>(m), static_cast<int>(p));
    }
  }
  REQUIRE(!expected.empty());
  // The asset is what it claims to be: meshes instanced by that many nodes, Draco or
  // quantized primitives in those variants.
  const json instanced = manifest["expect"].value("instanced", json::object());
  for (const auto& [mesh, uses] : instanced.items()) {
    long nodes = 0;
    for (const auto& n : in_doc->json["nodes"]) nodes += n.value("mesh", -1) == std::stol(mesh);
    CHECK(nodes == uses.get<long>());
  }
  const std::string variant = manifest.value("variant", "plain");
  for (const auto& [m, p] : expected) {
    const json& prim = in_doc->json["meshes"][m]["primitives"][p];
    const int position_type = in_doc->json["accessors"][prim["attributes"]["POSITION"].get<std::size_t>()]["componentType"];
    // glTF-Transform compresses TRIANGLES only (a strip stays plain in the Draco variant).
    if (prim.value("mode", 4) == 4) CHECK(prim.contains("extensions") == (variant == "draco"));
    CHECK((position_type != 5126) == (variant == "quantize"));
  }

  auto params = params_from_json(json::object());
  REQUIRE(params.ok());
  PipelineLimits limits;
  limits.threads = 2;
  const auto t0 = std::chrono::steady_clock::now();
  auto result = run_seam_pipeline(input, AssetKind::kAuto, *params, limits, core::CancelToken::none());
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  REQUIRE_MESSAGE(result.ok(), (result.ok() ? std::string() : std::string(code_name(result.error().code)) + ": " + result.error().message));
  const json& body = result->body;
  // SEAM_ASSET_DUMP=DIR keeps the cut assets and responses for a look (seamd, a viewer).
  if (const char* dump = std::getenv("SEAM_ASSET_DUMP")) {
    test_gltf::write_file((std::filesystem::path(dump) / file).string(), result->glb);
    json summary = body;
    summary.erase("asset");
    test_gltf::write_file((std::filesystem::path(dump) / (file + ".json")).string(), summary.dump(1));
  }

  // One entry per triangle primitive, in asset order, an instanced mesh once.
  REQUIRE_MESSAGE(body.contains("primitives"), "no `primitives` in the response: keys " << [&] {
    std::string keys;
    for (auto it = body.begin(); it != body.end(); ++it) keys += it.key() + " ";
    return keys;
  }());
  const json& entries = body["primitives"];
  std::vector<std::pair<int, int>> listed;
  for (const auto& e : entries) listed.emplace_back(e["mesh"].get<int>(), e["primitive"].get<int>());
  CHECK(listed == expected);
  if (entries.size() == 1) {
    for (const char* key : {"seam", "mesh", "cut", "uv"}) CHECK(body.contains(key));
  }

  auto out_doc = parse_asset(result->glb, AssetKind::kGlb);
  REQUIRE_MESSAGE(out_doc.ok(), (out_doc.ok() ? "" : out_doc.error().message));
  std::set<std::pair<int, int>> processed(listed.begin(), listed.end());
  check_document(*in_doc, *out_doc, processed);

  const json& planted = manifest["expect"].value("defects", json::object());
  const json& components = manifest["expect"].value("components", json::object());
  std::size_t faces = 0;
  std::vector<std::string> new_uvs;
  for (const auto& e : entries) {
    const int m = e["mesh"].get<int>(), p = e["primitive"].get<int>();
    const std::string where = std::to_string(m) + "/" + std::to_string(p);
    CAPTURE(file);
    CAPTURE(where);
    for (const char* key : {"name", "seam", "topology", "repairs", "cut", "uv", "timings_ms"}) {
      CHECK_MESSAGE(e.contains(key), "entry " << where << " has no " << key);
    }
    CHECK(e["name"] == in_doc->json["meshes"][m].value("name", ""));
    CHECK(e["uv"]["flipped"] == 0);
    // Each component cut to a disc: Euler characteristic 1 and one boundary loop apiece.
    const int parts = e["topology"]["components"].get<int>();
    CHECK(e["cut"]["euler_characteristic"] == parts);
    CHECK(e["cut"]["boundary_loops"] == parts);
    if (components.contains(where)) CHECK(parts == components[where].get<int>());
    // Repairs where defects were planted; none where there were none (a pinched vertex of the
    // cow and what quantization collapses are real, so only non-manifold edges and
    // orientation are held at 0 there).
    const json& repairs = e["repairs"];
    if (planted.contains(where)) {
      for (const auto& [kind, count] : planted[where].items()) {
        CAPTURE(kind);
        CHECK(repairs[kind].get<long>() >= count.get<long>());
        // Reorienting the larger side instead of the patch would be a bug too.
        CHECK(repairs[kind].get<long>() <= count.get<long>() + 1);
      }
    } else {
      CHECK(repairs["non_manifold_edges"] == 0);
      CHECK(repairs["reoriented_faces"] == 0);
    }
    new_uvs.push_back("/meshes/" + std::to_string(m) + "/primitives/" + std::to_string(p) + "/attributes/TEXCOORD_" +
                      std::to_string(e["uv"]["channel"].get<int>()));

    auto in_prim = read_primitive(*in_doc, static_cast<std::uint32_t>(m), static_cast<std::uint32_t>(p));
    auto out_prim = read_primitive(*out_doc, static_cast<std::uint32_t>(m), static_cast<std::uint32_t>(p));
    REQUIRE(in_prim.ok());
    REQUIRE_MESSAGE(out_prim.ok(), (out_prim.ok() ? "" : out_prim.error().message));
    faces += in_prim->mesh.triangles.size();
    check_primitive(*in_prim, *out_prim, e);

  }
  CHECK(faces == manifest["faces"].get<std::size_t>());

  // Valid glTF, and no unused object beyond the input's: the new UV sets are not bound to a
  // material (the cut does not edit materials), so the validator lists them and they are
  // left out of the count.
  const auto reports = validate({input, result->glb}, file);
  CHECK(reports[0]["unused"].size() == manifest["validator"]["unused_objects"].get<std::size_t>());
  CHECK_MESSAGE(reports[1]["errors"] == 0, reports[1]["messages"].dump(1));
  std::vector<std::string> unused;
  for (const auto& pointer : reports[1]["unused"]) {
    if (std::find(new_uvs.begin(), new_uvs.end(), pointer.get<std::string>()) == new_uvs.end()) {
      unused.push_back(pointer.get<std::string>());
    }
  }
  CHECK_MESSAGE(unused.size() <= reports[0]["unused"].size(),
                "unused objects: input " << reports[0]["unused"].dump() << ", output " << json(unused).dump());
  MESSAGE(file << ": " << faces << " faces, " << entries.size() << " primitives, " << ms << " ms, "
               << input.size() << " -> " << result->glb.size() << " bytes, unused objects " << reports[0]["unused"].size()
               << " -> " << unused.size());
}

/// Draco output keeps the input's quantization bits per attribute (issue 11 item 3): a Draco
/// character must not grow because the cut re-encodes it losslessly.
void check_draco_quantization(const std::string& file) {
  const std::string input = read_bytes(assets_dir() / file);
  auto in_doc = parse_asset(input, AssetKind::kGlb);
  REQUIRE(in_doc.ok());
  auto params = params_from_json(json::object());
  REQUIRE(params.ok());
  PipelineLimits limits;
  limits.threads = 2;
  auto result = run_seam_pipeline(input, AssetKind::kAuto, *params, limits, core::CancelToken::none());
  REQUIRE(result.ok());
  auto out_doc = parse_asset(result->glb, AssetKind::kGlb);
  REQUIRE(out_doc.ok());
  std::size_t in_bytes = 0, out_bytes = 0;
  for (const auto& e : result->body["primitives"]) {
    const auto m = e["mesh"].get<std::size_t>(), p = e["primitive"].get<std::size_t>();
    if (!in_doc->json["meshes"][m]["primitives"][p].contains("extensions")) continue;  // the plain strip
    const json& ext = out_doc->json["meshes"][m]["primitives"][p]["extensions"]["KHR_draco_mesh_compression"];
    REQUIRE(ext.is_object());
    CAPTURE(m);
    CAPTURE(p);
    const auto in_storage = draco_storage(*in_doc, m, p);
    auto out_storage = draco_storage(*out_doc, m, p);
    for (const auto& [name, kind] : in_storage) {
      CAPTURE(name);
      CHECK(out_storage[name] == kind);
    }
    auto view_bytes = [](const GltfDocument& d, std::size_t mi, std::size_t pi) {
      const json& x = d.json["meshes"][mi]["primitives"][pi]["extensions"]["KHR_draco_mesh_compression"];
      return d.json["bufferViews"][x["bufferView"].get<std::size_t>()]["byteLength"].get<std::size_t>();
    };
    for (const auto& [name, kind] : out_storage) {
      if (in_storage.count(name) == 0) MESSAGE("new " << name << " of " << m << "/" << p << ": " << kind);
    }
    in_bytes += view_bytes(*in_doc, m, p);
    out_bytes += view_bytes(*out_doc, m, p);
  }
  MESSAGE(file << ": Draco payloads " << in_bytes << " -> " << out_bytes << " bytes (with the new UV set)");
}

}  // namespace

TEST_CASE("asset set: props (multi-mesh, multi-primitive, instanced, split vertices, a strip, lines)") { check_asset("props.glb"); }
TEST_CASE("asset set: props_draco (KHR_draco_mesh_compression)") { check_asset("props_draco.glb"); }
TEST_CASE("asset set: props_quantized (KHR_mesh_quantization)") { check_asset("props_quantized.glb"); }
TEST_CASE("asset set: skinned (joints, weights, skin, animation)") { check_asset("skinned.glb"); }
TEST_CASE("asset set: skinned_draco") { check_asset("skinned_draco.glb"); }
TEST_CASE("asset set: morph (2 targets, weights, skin)") { check_asset("morph.glb"); }
TEST_CASE("asset set: morph_quantized") { check_asset("morph_quantized.glb"); }
TEST_CASE("asset set: defects (fin, flipped patch, collapsed faces, 40 small parts)") { check_asset("defects.glb"); }
TEST_CASE("asset set: bench6 (6 primitives, ~100k faces)") { check_asset("bench6.glb"); }
TEST_CASE("asset set: Draco output keeps the input's quantization bits per attribute") {
  check_draco_quantization("props_draco.glb");
  check_draco_quantization("skinned_draco.glb");
}

}  // namespace seam_asset_set_test
