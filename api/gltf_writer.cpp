#include "api/gltf_writer.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <set>

namespace seam::api {
namespace {

using nlohmann::json;

constexpr const char* kDracoExt = "KHR_draco_mesh_compression";

void align4(std::vector<std::uint8_t>& bin) {
  while (bin.size() % 4 != 0) bin.push_back(0);
}

// Appends buffer views and accessors to a document whose single buffer is `bin`.
class BinBuilder {
 public:
  BinBuilder(json& root, std::vector<std::uint8_t>& bin) : root_(root), bin_(bin) {
    if (!root_.contains("bufferViews")) root_["bufferViews"] = json::array();
    if (!root_.contains("accessors")) root_["accessors"] = json::array();
  }

  std::size_t add_view(const std::uint8_t* data, std::size_t length, std::size_t stride, int target) {
    align4(bin_);
    json view = {{"buffer", 0}, {"byteOffset", bin_.size()}, {"byteLength", length}};
    if (stride) view["byteStride"] = stride;
    if (target) view["target"] = target;
    bin_.insert(bin_.end(), data, data + length);
    root_["bufferViews"].push_back(std::move(view));
    return root_["bufferViews"].size() - 1;
  }

  // An accessor for `a`. Vertex attributes get 4-byte aligned elements (the spec asks it),
  // with a byteStride when the element is not a multiple of 4 bytes. `with_view` false makes
  // a Draco accessor (no bufferView).
  std::size_t add_accessor(const AttributeArray& a, bool vertex_attribute, bool with_view, bool min_max) {
    json acc = {{"componentType", a.component_type}, {"count", a.count}, {"type", a.type}};
    if (a.normalized) acc["normalized"] = true;
    if (min_max) add_min_max(a, acc);
    if (with_view) {
      const std::size_t elem = a.element_size();
      const std::size_t padded = vertex_attribute ? (elem + 3) / 4 * 4 : elem;
      if (padded == elem) {
        acc["bufferView"] = add_view(a.data.data(), a.data.size(), 0, vertex_attribute ? 34962 : 34963);
      } else {
        std::vector<std::uint8_t> strided(a.count * padded, 0);
        for (std::size_t i = 0; i < a.count; ++i) std::memcpy(strided.data() + i * padded, a.data.data() + i * elem, elem);
        acc["bufferView"] = add_view(strided.data(), strided.size(), padded, 34962);
      }
    }
    root_["accessors"].push_back(std::move(acc));
    return root_["accessors"].size() - 1;
  }

 private:
  static double component(const AttributeArray& a, std::size_t i) {
    const std::uint8_t* p = a.data.data() + i * a.component_size();
    switch (a.component_type) {
      case 5120: return static_cast<std::int8_t>(*p);
      case 5121: return *p;
      case 5122: {
        std::int16_t v;
        std::memcpy(&v, p, 2);
        return v;
      }
      case 5123: {
        std::uint16_t v;
        std::memcpy(&v, p, 2);
        return v;
      }
      case 5125: {
        std::uint32_t v;
        std::memcpy(&v, p, 4);
        return v;
      }
      default: {
        float v;
        std::memcpy(&v, p, 4);
        return v;
      }
    }
  }

  static void add_min_max(const AttributeArray& a, json& acc) {
    const auto k = static_cast<std::size_t>(a.components);
    std::vector<double> lo(k, std::numeric_limits<double>::infinity()), hi(k, -std::numeric_limits<double>::infinity());
    if (a.component_type == 5126 && k == 3) {
      // Float VEC3 (every POSITION we write): the same std::min/std::max on the same doubles,
      // read as a typed array instead of through component()'s switch per value.
      double l[3] = {lo[0], lo[1], lo[2]}, h[3] = {hi[0], hi[1], hi[2]};
      for (std::size_t i = 0; i < a.count; ++i) {
        float v[3];
        std::memcpy(v, a.data.data() + 12 * i, 12);
        for (std::size_t c = 0; c < 3; ++c) {
          l[c] = std::min(l[c], static_cast<double>(v[c]));
          h[c] = std::max(h[c], static_cast<double>(v[c]));
        }
      }
      lo.assign(l, l + 3);
      hi.assign(h, h + 3);
    } else {
      for (std::size_t i = 0; i < a.count; ++i) {
        for (std::size_t c = 0; c < k; ++c) {
          const double v = component(a, i * k + c);
          lo[c] = std::min(lo[c], v);
          hi[c] = std::max(hi[c], v);
        }
      }
    }
    json jlo = json::array(), jhi = json::array();
    for (std::size_t c = 0; c < k; ++c) {
      if (a.component_type == 5126) {
        jlo.push_back(lo[c]);
        jhi.push_back(hi[c]);
      } else {
        jlo.push_back(static_cast<std::int64_t>(lo[c]));
        jhi.push_back(static_cast<std::int64_t>(hi[c]));
      }
    }
    acc["min"] = std::move(jlo);
    acc["max"] = std::move(jhi);
  }

  json& root_;
  std::vector<std::uint8_t>& bin_;
};

// out[i] = in[source[i]] for elements of a compile-time size: the copy becomes one or two
// moves instead of a call to memcpy per element.
template <std::size_t kElem>
void gather_fixed(const std::uint8_t* in, const std::vector<std::uint32_t>& source, std::uint8_t* out) {
  for (std::size_t i = 0; i < source.size(); ++i) {
    std::memcpy(out + i * kElem, in + static_cast<std::size_t>(source[i]) * kElem, kElem);
  }
}

AttributeArray gather(const AttributeArray& a, const std::vector<std::uint32_t>& source) {
  AttributeArray out;  // a's description, not its data: copying the input array is wasted
  out.name = a.name;
  out.component_type = a.component_type;
  out.components = a.components;
  out.type = a.type;
  out.normalized = a.normalized;
  const std::size_t elem = a.element_size();
  out.count = source.size();
  out.data.resize(source.size() * elem);
  const std::uint8_t* in = a.data.data();
  std::uint8_t* dst = out.data.data();
  switch (elem) {
    case 4: gather_fixed<4>(in, source, dst); break;
    case 8: gather_fixed<8>(in, source, dst); break;
    case 12: gather_fixed<12>(in, source, dst); break;
    case 16: gather_fixed<16>(in, source, dst); break;
    default:
      for (std::size_t i = 0; i < source.size(); ++i) {
        std::memcpy(dst + i * elem, in + static_cast<std::size_t>(source[i]) * elem, elem);
      }
  }
  return out;
}

AttributeArray index_array(const std::vector<core::Triangle>& triangles, std::size_t vertices) {
  AttributeArray out;
  out.name = "indices";
  out.components = 1;
  out.type = "SCALAR";
  out.count = triangles.size() * 3;
  // 65535 is the primitive-restart value, which glTF forbids as an index.
  const bool small = vertices <= 65535;
  out.component_type = small ? 5123 : 5125;
  out.data.resize(out.count * (small ? 2 : 4));
  if (!small) {
    // std::array<uint32_t, 3> is three packed host-order uint32s, as GLB stores them (GLB is
    // little-endian, and so is every host this builds for).
    static_assert(sizeof(core::Triangle) == 12);
    if (!triangles.empty()) std::memcpy(out.data.data(), triangles.data(), out.data.size());
    return out;
  }
  std::uint8_t* dst = out.data.data();
  for (const auto& t : triangles) {
    const std::uint16_t narrow[3] = {static_cast<std::uint16_t>(t[0]), static_cast<std::uint16_t>(t[1]),
                                     static_cast<std::uint16_t>(t[2])};
    std::memcpy(dst, narrow, 6);
    dst += 6;
  }
  return out;
}

bool uses_draco(const json& root) {
  const auto meshes = root.find("meshes");
  if (meshes == root.end() || !meshes->is_array()) return false;
  for (const auto& m : *meshes) {
    if (!m.is_object() || !m.contains("primitives") || !m["primitives"].is_array()) continue;
    for (const auto& p : m["primitives"]) {
      if (p.is_object() && p.contains("extensions") && p["extensions"].is_object() && p["extensions"].contains(kDracoExt)) {
        return true;
      }
    }
  }
  return false;
}

void set_extension_listed(json& root, const char* key, const std::string& ext, bool listed) {
  json list = root.contains(key) && root[key].is_array() ? root[key] : json::array();
  json out = json::array();
  for (const auto& e : list) {
    if (!(e.is_string() && e.get<std::string>() == ext)) out.push_back(e);
  }
  if (listed) out.push_back(ext);
  if (out.empty()) root.erase(key);
  else root[key] = std::move(out);
}

// Adds a primitive's vertex data: plain accessors, or a Draco blob plus view-less accessors.
// Returns {"attributes", "indices", "extension" (with Draco), "draco_bytes"}.
ApiResult<json> add_primitive_data(BinBuilder& builder, const std::vector<AttributeArray>& attributes,
                                   const AttributeArray& indices, const std::vector<core::Triangle>& triangles,
                                   bool draco, const DracoEncodeOptions& draco_options) {
  json prim_attributes = json::object();
  json result = {{"draco_bytes", 0}};
  if (draco) {
    SEAM_TRY(const EncodedDraco encoded, encode_draco(attributes, triangles, draco_options));
    result["draco_bytes"] = encoded.bytes.size();
    const std::size_t view =
        builder.add_view(reinterpret_cast<const std::uint8_t*>(encoded.bytes.data()), encoded.bytes.size(), 0, 0);
    json ext_attributes = json::object();
    for (std::size_t i = 0; i < attributes.size(); ++i) {
      prim_attributes[attributes[i].name] = builder.add_accessor(attributes[i], true, false, attributes[i].name == "POSITION");
      ext_attributes[attributes[i].name] = encoded.unique_ids[i];
    }
    result["indices"] = builder.add_accessor(indices, false, false, false);
    result["extension"] = {{"bufferView", view}, {"attributes", ext_attributes}};
  } else {
    for (const auto& a : attributes) prim_attributes[a.name] = builder.add_accessor(a, true, true, a.name == "POSITION");
    result["indices"] = builder.add_accessor(indices, false, true, false);
  }
  result["attributes"] = std::move(prim_attributes);
  return result;
}

}  // namespace

std::string encode_glb(const json& document, const std::vector<std::uint8_t>& bin) {
  // Never throws: strings that came in as JSON are valid UTF-8; replace is a safety net.
  std::string text = document.dump(-1, ' ', false, json::error_handler_t::replace);
  while (text.size() % 4 != 0) text.push_back(' ');
  const std::size_t bin_padded = (bin.size() + 3) / 4 * 4;
  const bool has_bin = !bin.empty();
  const std::size_t total = 12 + 8 + text.size() + (has_bin ? 8 + bin_padded : 0);
  std::string out;
  out.reserve(total);
  auto put32 = [&out](std::uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
  put32(0x46546C67);
  put32(2);
  put32(static_cast<std::uint32_t>(total));
  put32(static_cast<std::uint32_t>(text.size()));
  put32(0x4E4F534A);
  out += text;
  if (has_bin) {
    put32(static_cast<std::uint32_t>(bin_padded));
    put32(0x004E4942);
    out.append(reinterpret_cast<const char*>(bin.data()), bin.size());
    out.append(bin_padded - bin.size(), '\0');
  }
  return out;
}

namespace {

// The input buffers concatenated into one (each 4-byte aligned), every view moved with them.
std::vector<std::uint8_t> merge_buffers(const GltfDocument& doc, json& root) {
  std::vector<std::uint8_t> bin;
  std::vector<std::size_t> base;
  for (const auto& b : doc.buffers) {
    align4(bin);
    base.push_back(bin.size());
    bin.insert(bin.end(), b.begin(), b.end());
  }
  if (root.contains("bufferViews")) {
    for (auto& view : root["bufferViews"]) {
      const std::size_t b = view["buffer"].get<std::size_t>();
      view["buffer"] = 0;
      view["byteOffset"] = base[b] + view.value("byteOffset", std::size_t{0});
    }
  }
  return bin;
}

// Every attribute of the input primitive gathered per output vertex, plus the new UV set as
// TEXCOORD_n with the smallest n the primitive does not use.
std::vector<AttributeArray> output_attributes(const PrimitiveData& data, const CutPrimitive& cut, int& uv_channel) {
  std::vector<AttributeArray> attributes;
  attributes.reserve(data.attributes.size() + 1);
  std::set<int> used_texcoords;
  for (const auto& a : data.attributes) {
    attributes.push_back(gather(a, cut.source_vertex));
    if (a.name.rfind("TEXCOORD_", 0) == 0) {
      try {
        used_texcoords.insert(std::stoi(a.name.substr(9)));
      } catch (...) {
        // A malformed TEXCOORD name only matters for choosing the next free set.
      }
    }
  }
  uv_channel = -1;
  if (!cut.uv.empty()) {
    int n = 0;
    while (used_texcoords.count(n)) ++n;
    uv_channel = n;
    std::vector<float> values;
    values.reserve(cut.uv.size() * 2);
    for (const auto& uv : cut.uv) values.insert(values.end(), {uv[0], uv[1]});
    attributes.push_back(make_float_attribute("TEXCOORD_" + std::to_string(n), 2, values));
  }
  return attributes;
}

// The accessors (and a Draco blob's view) a primitive references: dropped once replaced,
// unless something else still uses them.
void collect_references(const json& prim, std::vector<std::size_t>& accessors, std::vector<std::size_t>& views) {
  if (prim.contains("attributes")) {
    for (const auto& [name, ref] : prim["attributes"].items()) accessors.push_back(ref.get<std::size_t>());
  }
  if (prim.contains("indices")) accessors.push_back(prim["indices"].get<std::size_t>());
  if (prim.contains("targets")) {
    for (const auto& target : prim["targets"]) {
      for (const auto& [name, ref] : target.items()) accessors.push_back(ref.get<std::size_t>());
    }
  }
  if (prim.contains("extensions") && prim["extensions"].contains(kDracoExt)) {
    views.push_back(prim["extensions"][kDracoExt]["bufferView"].get<std::size_t>());
  }
}

// An upper bound of what replace_primitive appends to the BIN chunk without Draco (vertex
// attributes padded to 4 bytes, u32 indices, the new UVs, a 4-byte alignment per view), so the
// chunk grows in place: each reallocation of a vector of tens of MB copies it into fresh pages.
std::size_t appended_bytes(std::span<const ReplacedPrimitive> replaced) {
  std::size_t bytes = 0;
  for (const ReplacedPrimitive& r : replaced) {
    std::size_t per_vertex = 8;  // the new TEXCOORD
    std::size_t views = 2;
    for (const auto& a : r.data->attributes) per_vertex += (a.element_size() + 3) / 4 * 4, ++views;
    for (const auto& target : r.data->targets) {
      for (const auto& a : target) per_vertex += (a.element_size() + 3) / 4 * 4, ++views;
    }
    bytes += r.cut->source_vertex.size() * per_vertex + 12 * r.cut->triangles.size() + 4 * views;
  }
  return bytes;
}

// Replaces one primitive's JSON by the cut's accessors; extras.seam carries the seam.
ApiResult<WrittenPrimitive> replace_primitive(BinBuilder& builder, json& prim, const ReplacedPrimitive& r) {
  const PrimitiveData& data = *r.data;
  const CutPrimitive& cut = *r.cut;
  WrittenPrimitive written;
  written.vertices = cut.source_vertex.size();
  const std::vector<AttributeArray> attributes = output_attributes(data, cut, written.uv_channel);
  const AttributeArray indices = index_array(cut.triangles, cut.source_vertex.size());
  DracoEncodeOptions draco_options = r.draco_options;
  // Morph targets stay outside the Draco blob, indexed by vertex: Draco must not reorder.
  if (!data.targets.empty()) draco_options.preserve_point_order = true;
  SEAM_TRY(json added, add_primitive_data(builder, attributes, indices, cut.triangles, r.draco, draco_options));
  written.draco_bytes = added["draco_bytes"].get<std::size_t>();
  prim["attributes"] = added["attributes"];
  prim["indices"] = added["indices"];
  prim["mode"] = 4;
  if (!data.targets.empty()) {
    json targets = json::array();
    for (const auto& target : data.targets) {
      json t = json::object();
      for (const auto& a : target) {
        t[a.name] = builder.add_accessor(gather(a, cut.source_vertex), true, true, a.name == "POSITION");
      }
      targets.push_back(std::move(t));
    }
    prim["targets"] = std::move(targets);
  }
  if (prim.contains("extensions") && prim["extensions"].is_object()) {
    prim["extensions"].erase(kDracoExt);
    if (prim["extensions"].empty()) prim.erase("extensions");
  }
  if (r.draco) prim["extensions"][kDracoExt] = added["extension"];
  if (!prim.contains("extras") || !prim["extras"].is_object()) {
    json old = prim.contains("extras") ? prim["extras"] : json();
    prim["extras"] = json::object();
    if (!old.is_null()) prim["extras"]["original"] = std::move(old);
  }
  prim["extras"]["seam"] = cut.seam_extras;
  if (written.uv_channel >= 0) prim["extras"]["seam"]["uv_channel"] = written.uv_channel;
  return written;
}

}  // namespace

ApiResult<WrittenAsset> write_cut_asset(const GltfDocument& doc, std::span<const ReplacedPrimitive> replaced) {
  json root = doc.json;
  std::vector<std::uint8_t> bin = merge_buffers(doc, root);
  bin.reserve(bin.size() + appended_bytes(replaced));
  json merged = doc.buffers.empty() || !root["buffers"][0].is_object() ? json::object() : root["buffers"][0];
  merged.erase("uri");
  BinBuilder builder(root, bin);

  WrittenAsset written;
  std::vector<std::size_t> old_accessors, old_views;
  for (const ReplacedPrimitive& r : replaced) {
    json& prim = root["meshes"][r.mesh]["primitives"][r.primitive];
    collect_references(prim, old_accessors, old_views);
    SEAM_TRY(WrittenPrimitive w, replace_primitive(builder, prim, r));
    written.primitives.push_back(w);
  }
  const bool draco = uses_draco(root);
  set_extension_listed(root, "extensionsUsed", kDracoExt, draco);
  set_extension_listed(root, "extensionsRequired", kDracoExt, draco);
  written.compaction = compact_unused(root, bin, old_accessors, old_views);

  align4(bin);
  merged["byteLength"] = bin.size();
  root["buffers"] = json::array({merged});
  written.glb = encode_glb(root, bin);
  return written;
}

AttributeArray make_float_attribute(const std::string& name, int components, const std::vector<float>& values) {
  static constexpr const char* kTypes[] = {"", "SCALAR", "VEC2", "VEC3", "VEC4"};
  AttributeArray a;
  a.name = name;
  a.component_type = 5126;
  a.components = components;
  a.type = kTypes[components];
  a.count = values.size() / static_cast<std::size_t>(components);
  a.data.resize(values.size() * 4);
  std::memcpy(a.data.data(), values.data(), a.data.size());
  return a;
}

ApiResult<std::string> write_plain_glb(const core::IndexedMesh& mesh, const std::vector<AttributeArray>& extra, bool draco) {
  json root = {{"asset", {{"version", "2.0"}, {"generator", "seam service"}}},
               {"scene", 0},
               {"scenes", json::array({{{"nodes", {0}}}})},
               {"nodes", json::array({{{"mesh", 0}}})},
               {"meshes", json::array({{{"primitives", json::array({json::object()})}}})},
               {"buffers", json::array({json::object()})}};
  std::vector<std::uint8_t> bin;
  BinBuilder builder(root, bin);
  std::vector<float> positions;
  positions.reserve(mesh.positions.size() * 3);
  for (const auto& p : mesh.positions) {
    positions.insert(positions.end(), {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())});
  }
  std::vector<AttributeArray> attributes{make_float_attribute("POSITION", 3, positions)};
  for (const auto& a : extra) attributes.push_back(a);
  const AttributeArray indices = index_array(mesh.triangles, mesh.positions.size());
  SEAM_TRY(json added, add_primitive_data(builder, attributes, indices, mesh.triangles, draco, DracoEncodeOptions{}));
  json& prim = root["meshes"][0]["primitives"][0];
  prim["attributes"] = added["attributes"];
  prim["indices"] = added["indices"];
  prim["mode"] = 4;
  if (draco) {
    prim["extensions"][kDracoExt] = added["extension"];
    root["extensionsUsed"] = {kDracoExt};
    root["extensionsRequired"] = {kDracoExt};
  }
  align4(bin);
  root["buffers"][0]["byteLength"] = bin.size();
  return encode_glb(root, bin);
}

}  // namespace seam::api
