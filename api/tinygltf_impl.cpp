// The one translation unit with tinygltf's implementation (it takes 6-11 s to compile; see
// shared/notes/stack.md). The macros it depends on are set for the whole target in CMake.
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>

#include "api/tinygltf_check.h"

namespace seam::api {
namespace {

// tinygltf's default callbacks would read any path named in the asset (../, %2F, absolute).
bool refuse_exists(const std::string&, void*) { return false; }
std::string no_expand(const std::string& path, void*) { return path; }
bool refuse_read(std::vector<unsigned char>*, std::string* err, const std::string& path, void*) {
  if (err != nullptr) *err = "refused to read " + path;
  return false;
}
bool refuse_write(std::string*, const std::string&, const std::vector<unsigned char>&, void*) { return false; }

// Images are kept as their encoded bytes; nothing is decoded.
bool keep_image_bytes(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                      const unsigned char* bytes, int size, void*) {
  image->image.assign(bytes, bytes + size);
  image->as_is = true;
  return true;
}

}  // namespace

TinygltfSummary load_with_tinygltf(std::string_view glb) {
  TinygltfSummary summary;
  tinygltf::TinyGLTF loader;
  tinygltf::FsCallbacks fs{};
  fs.FileExists = &refuse_exists;
  fs.ExpandFilePath = &no_expand;
  fs.ReadWholeFile = &refuse_read;
  fs.WriteWholeFile = &refuse_write;
  fs.user_data = nullptr;
  loader.SetFsCallbacks(fs);
  loader.SetImageLoader(&keep_image_bytes, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  const bool ok = loader.LoadBinaryFromMemory(&model, &err, &warn, reinterpret_cast<const unsigned char*>(glb.data()),
                                              static_cast<unsigned int>(glb.size()), "");
  summary.meshes = model.meshes.size();
  if (!ok || model.meshes.empty() || model.meshes[0].primitives.empty()) {
    summary.error = err + warn;
    return summary;
  }
  const auto& prim = model.meshes[0].primitives[0];
  const auto pos = prim.attributes.find("POSITION");
  if (pos == prim.attributes.end() || pos->second < 0 || static_cast<std::size_t>(pos->second) >= model.accessors.size() ||
      prim.indices < 0 || static_cast<std::size_t>(prim.indices) >= model.accessors.size()) {
    summary.error = "primitive 0 has no valid POSITION or indices";
    return summary;
  }
  const auto& accessor = model.accessors[static_cast<std::size_t>(pos->second)];
  summary.vertices = accessor.count;
  summary.position_has_data = accessor.bufferView >= 0;
  summary.indices = model.accessors[static_cast<std::size_t>(prim.indices)].count;
  summary.ok = true;
  return summary;
}

}  // namespace seam::api
