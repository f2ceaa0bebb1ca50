// A second, independent glTF reader (tinygltf 2.7, with its Draco support) used to check that
// what we write is readable by common tools. Never used on untrusted input in the request
// path: our own reader (gltf_reader.h) handles that.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace seam::api {

struct TinygltfSummary {
  bool ok = false;
  std::string error;             ///< tinygltf's error and warning text when !ok
  std::size_t meshes = 0;
  std::size_t vertices = 0;      ///< POSITION count of mesh 0 primitive 0 (after tinygltf's Draco decode)
  std::size_t indices = 0;       ///< index count of mesh 0 primitive 0
  bool position_has_data = false;  ///< POSITION accessor resolved to a bufferView (Draco decoded)
};

/// Loads GLB bytes with tinygltf. File-system callbacks refuse every file and images are kept
/// as bytes, so even this path never reads outside the given bytes.
TinygltfSummary load_with_tinygltf(std::string_view glb);

}  // namespace seam::api
