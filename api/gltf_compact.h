// Dropping the accessors and buffer views that replacing primitives left unused, so a cut
// asset carries no dead data (API.md v2 "Whole assets": lean output).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace seam::api {

struct CompactResult {
  bool compacted = false;          ///< false: an extension outside the known set (see below)
  std::string skipped_because;     ///< which extension prevented it, when not compacted
  std::size_t dropped_accessors = 0;
  std::size_t dropped_buffer_views = 0;
  std::size_t dropped_bytes = 0;   ///< binary bytes no longer written
};

/// `root` is a glTF document whose single buffer is `bin`. Removes the `candidate_accessors`
/// that nothing references any more, then the buffer views that only they (or the
/// `candidate_views`, e.g. a replaced Draco blob) used, renumbers every reference and
/// rewrites `bin` with only the kept views' bytes (each view keeps its offset modulo 4, so
/// accessor alignment holds). Objects unused already in the input are not candidates and
/// stay. References are known exactly for core glTF and the extensions in
/// known_extension(); with any other extension in extensionsUsed nothing is changed
/// (compacted = false), since it could reference accessors or buffer bytes itself.
/// Complexity: O(JSON size + bin bytes).
CompactResult compact_unused(nlohmann::json& root, std::vector<std::uint8_t>& bin,
                             const std::vector<std::size_t>& candidate_accessors,
                             const std::vector<std::size_t>& candidate_views);

/// Extensions whose references to accessors and buffer views compact_unused knows (or that
/// have none): KHR_draco_mesh_compression, KHR_mesh_quantization, EXT_mesh_gpu_instancing,
/// KHR_texture_transform, KHR_texture_basisu, KHR_lights_punctual, KHR_materials_*,
/// EXT_texture_webp, EXT_texture_avif, KHR_xmp_json_ld, KHR_animation_pointer.
bool known_extension(const std::string& name);

}  // namespace seam::api
