#include "api/gltf_compact.h"

#include <algorithm>
#include <array>
#include <functional>
#include <limits>

namespace seam::api {
namespace {

using nlohmann::json;
constexpr std::size_t kRemoved = std::numeric_limits<std::size_t>::max();

// Calls f on every JSON value that holds an accessor index.
void for_each_accessor_ref(json& root, const std::function<void(json&)>& f) {
  if (root.contains("meshes") && root["meshes"].is_array()) {
    for (auto& mesh : root["meshes"]) {
      if (!mesh.is_object() || !mesh.contains("primitives")) continue;
      for (auto& prim : mesh["primitives"]) {
        if (prim.contains("attributes")) {
          for (auto& [name, ref] : prim["attributes"].items()) f(ref);
        }
        if (prim.contains("indices")) f(prim["indices"]);
        if (prim.contains("targets")) {
          for (auto& target : prim["targets"]) {
            for (auto& [name, ref] : target.items()) f(ref);
          }
        }
      }
    }
  }
  if (root.contains("skins") && root["skins"].is_array()) {
    for (auto& skin : root["skins"]) {
      if (skin.contains("inverseBindMatrices")) f(skin["inverseBindMatrices"]);
    }
  }
  if (root.contains("animations") && root["animations"].is_array()) {
    for (auto& anim : root["animations"]) {
      if (!anim.contains("samplers")) continue;
      for (auto& s : anim["samplers"]) {
        if (s.contains("input")) f(s["input"]);
        if (s.contains("output")) f(s["output"]);
      }
    }
  }
  if (root.contains("nodes") && root["nodes"].is_array()) {
    for (auto& node : root["nodes"]) {
      if (!node.contains("extensions") || !node["extensions"].contains("EXT_mesh_gpu_instancing")) continue;
      auto& inst = node["extensions"]["EXT_mesh_gpu_instancing"];
      if (!inst.contains("attributes")) continue;
      for (auto& [name, ref] : inst["attributes"].items()) f(ref);
    }
  }
}

// Calls f on every JSON value that holds a buffer view index.
void for_each_view_ref(json& root, const std::function<void(json&)>& f) {
  if (root.contains("accessors")) {
    for (auto& acc : root["accessors"]) {
      if (acc.contains("bufferView")) f(acc["bufferView"]);
      if (!acc.contains("sparse")) continue;
      auto& sparse = acc["sparse"];
      if (sparse.contains("indices") && sparse["indices"].contains("bufferView")) f(sparse["indices"]["bufferView"]);
      if (sparse.contains("values") && sparse["values"].contains("bufferView")) f(sparse["values"]["bufferView"]);
    }
  }
  if (root.contains("images")) {
    for (auto& image : root["images"]) {
      if (image.contains("bufferView")) f(image["bufferView"]);
    }
  }
  if (root.contains("meshes")) {
    for (auto& mesh : root["meshes"]) {
      if (!mesh.is_object() || !mesh.contains("primitives")) continue;
      for (auto& prim : mesh["primitives"]) {
        if (prim.contains("extensions") && prim["extensions"].contains("KHR_draco_mesh_compression")) {
          auto& draco = prim["extensions"]["KHR_draco_mesh_compression"];
          if (draco.contains("bufferView")) f(draco["bufferView"]);
        }
      }
    }
  }
}

// Marks which of `count` objects the references reach; indices out of range are ignored
// (the reader validated the input; new references are ours).
std::vector<bool> referenced(json& root, std::size_t count,
                             void (*walk)(json&, const std::function<void(json&)>&)) {
  std::vector<bool> used(count, false);
  walk(root, [&](json& ref) {
    if (ref.is_number_unsigned() && ref.get<std::size_t>() < count) used[ref.get<std::size_t>()] = true;
  });
  return used;
}

// Removes the marked entries of root[key] and returns old index -> new index (kRemoved).
std::vector<std::size_t> remove_marked(json& root, const char* key, const std::vector<bool>& remove) {
  std::vector<std::size_t> map(remove.size(), kRemoved);
  json kept = json::array();
  for (std::size_t i = 0; i < remove.size(); ++i) {
    if (remove[i]) continue;
    map[i] = kept.size();
    kept.push_back(std::move(root[key][i]));
  }
  root[key] = std::move(kept);
  return map;
}

void renumber(json& root, const std::vector<std::size_t>& map, void (*walk)(json&, const std::function<void(json&)>&)) {
  walk(root, [&](json& ref) {
    if (ref.is_number_unsigned() && ref.get<std::size_t>() < map.size()) ref = map[ref.get<std::size_t>()];
  });
}

// Rewrites the single buffer with the kept views' bytes only, each at its old offset mod 4.
std::size_t rewrite_bin(json& root, std::vector<std::uint8_t>& bin) {
  std::vector<std::uint8_t> out;
  out.reserve(bin.size());
  for (auto& view : root["bufferViews"]) {
    const std::size_t offset = view.value("byteOffset", std::size_t{0});
    const std::size_t length = view["byteLength"].get<std::size_t>();
    while (out.size() % 4 != offset % 4) out.push_back(0);
    view["byteOffset"] = out.size();
    out.insert(out.end(), bin.begin() + static_cast<std::ptrdiff_t>(offset),
               bin.begin() + static_cast<std::ptrdiff_t>(offset + length));
  }
  while (out.size() % 4 != 0) out.push_back(0);
  const std::size_t dropped = bin.size() > out.size() ? bin.size() - out.size() : 0;
  bin = std::move(out);
  return dropped;
}

}  // namespace

bool known_extension(const std::string& name) {
  static const std::array<const char*, 10> kKnown = {
      "KHR_draco_mesh_compression", "KHR_mesh_quantization", "EXT_mesh_gpu_instancing", "KHR_texture_transform",
      "KHR_texture_basisu",         "KHR_lights_punctual",   "EXT_texture_webp",        "EXT_texture_avif",
      "KHR_xmp_json_ld",            "KHR_animation_pointer"};
  if (name.rfind("KHR_materials_", 0) == 0) return true;
  return std::find(kKnown.begin(), kKnown.end(), name) != kKnown.end();
}

CompactResult compact_unused(json& root, std::vector<std::uint8_t>& bin, const std::vector<std::size_t>& candidate_accessors,
                             const std::vector<std::size_t>& candidate_views) {
  CompactResult result;
  if (root.contains("extensionsUsed") && root["extensionsUsed"].is_array()) {
    for (const auto& e : root["extensionsUsed"]) {
      if (e.is_string() && !known_extension(e.get<std::string>())) {
        result.skipped_because = e.get<std::string>();
        return result;
      }
    }
  }
  result.compacted = true;
  if (!root.contains("accessors") || !root.contains("bufferViews")) return result;
  const std::size_t accessors = root["accessors"].size();
  const std::vector<bool> used_accessors = referenced(root, accessors, for_each_accessor_ref);
  std::vector<bool> drop_accessor(accessors, false);
  std::vector<std::size_t> view_candidates = candidate_views;
  for (auto a : candidate_accessors) {
    if (a >= accessors || used_accessors[a] || drop_accessor[a]) continue;
    drop_accessor[a] = true;
    ++result.dropped_accessors;
    const json& acc = root["accessors"][a];
    if (acc.contains("bufferView")) view_candidates.push_back(acc["bufferView"].get<std::size_t>());
    if (acc.contains("sparse")) {
      view_candidates.push_back(acc["sparse"]["indices"]["bufferView"].get<std::size_t>());
      view_candidates.push_back(acc["sparse"]["values"]["bufferView"].get<std::size_t>());
    }
  }
  renumber(root, remove_marked(root, "accessors", drop_accessor), for_each_accessor_ref);

  const std::size_t views = root["bufferViews"].size();
  const std::vector<bool> used_views = referenced(root, views, for_each_view_ref);
  std::vector<bool> drop_view(views, false);
  for (auto v : view_candidates) {
    if (v >= views || used_views[v] || drop_view[v]) continue;
    drop_view[v] = true;
    ++result.dropped_buffer_views;
  }
  renumber(root, remove_marked(root, "bufferViews", drop_view), for_each_view_ref);
  result.dropped_bytes = rewrite_bin(root, bin);
  return result;
}

}  // namespace seam::api
