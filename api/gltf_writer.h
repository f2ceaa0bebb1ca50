// Writing the cut asset: the input glTF with the processed primitives replaced by their cut
// versions, as GLB (optionally Draco-compressed); and a plain GLB writer for tests and the sample.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <span>

#include <nlohmann/json.hpp>

#include "api/draco_io.h"
#include "api/error.h"
#include "api/gltf_compact.h"
#include "api/gltf_reader.h"
#include "core/mesh/types.h"

namespace seam::api {

/// The cut primitive in terms of the input primitive's vertices.
struct CutPrimitive {
  /// Output vertex -> input vertex whose attributes it copies. One entry per unique
  /// (input vertex, cut vertex) pair: a vertex is duplicated only where the seam passes.
  std::vector<std::uint32_t> source_vertex;
  std::vector<core::Triangle> triangles;      ///< over output vertices; the repaired winding
  std::vector<std::array<float, 2>> uv;       ///< empty, or one per output vertex (new TEXCOORD set)
  nlohmann::json seam_extras = nlohmann::json::object();  ///< goes to the primitive's extras.seam
};

/// One primitive to replace: where it is, what was read from it, and its cut.
struct ReplacedPrimitive {
  std::uint32_t mesh = 0;
  std::uint32_t primitive = 0;
  const PrimitiveData* data = nullptr;  ///< read_primitive(doc, mesh, primitive)
  const CutPrimitive* cut = nullptr;
  bool draco = false;                   ///< write it KHR_draco_mesh_compression-compressed
  DracoEncodeOptions draco_options;     ///< with draco: quantization (the input's, by default)
};

struct WrittenPrimitive {
  int uv_channel = -1;        ///< n of the TEXCOORD_n written, -1 if none
  std::size_t vertices = 0;   ///< output vertices of the cut primitive
  std::size_t draco_bytes = 0;
};

struct WrittenAsset {
  std::string glb;
  std::vector<WrittenPrimitive> primitives;  ///< one per ReplacedPrimitive, same order
  CompactResult compaction;                  ///< what the replaced primitives left and was dropped
};

/// Writes `doc` as one GLB with every primitive of `replaced` replaced by its cut. All
/// buffers are merged into the GLB BIN chunk; every other object (nodes, materials, images,
/// skins, animations, other primitives, extensions, extras) is kept as it was. Every
/// attribute and morph target of a replaced primitive is gathered per output vertex
/// bit-exactly in its own component type (quantized attributes stay quantized); POSITION
/// gets min/max; indices are u16 or u32; the new UV set is float32 TEXCOORD_n with the
/// smallest free n. The accessors and buffer views only the replaced primitives used are
/// dropped (compact_unused). extensionsUsed/Required list KHR_draco_mesh_compression exactly
/// when some primitive still uses it.
/// Preconditions: each entry's data was read from `doc` at (mesh, primitive), entries name
/// distinct primitives, source_vertex entries < the input vertex count, triangles index
/// source_vertex. Errors: kInternal (Draco refused).
/// Complexity: O(asset bytes + output vertices * attribute bytes).
ApiResult<WrittenAsset> write_cut_asset(const GltfDocument& doc, std::span<const ReplacedPrimitive> replaced);

/// Writes a one-mesh, one-node GLB from positions and triangles plus optional extra
/// attributes (each with mesh.positions.size() elements, e.g. NORMAL, COLOR_0, TEXCOORD_0).
/// Positions are stored as float32. With `draco`, the primitive is Draco-compressed.
/// Errors: kInternal (Draco refused; only with `draco`). O(vertices * attribute bytes + faces).
ApiResult<std::string> write_plain_glb(const core::IndexedMesh& mesh, const std::vector<AttributeArray>& extra = {},
                                       bool draco = false);

/// Packs a glTF JSON document and a binary chunk into GLB bytes (4-byte padded chunks).
std::string encode_glb(const nlohmann::json& json, const std::vector<std::uint8_t>& bin);

/// Helpers to build attribute arrays in tests and the sample.
AttributeArray make_float_attribute(const std::string& name, int components, const std::vector<float>& values);

}  // namespace seam::api
