// Writing the cut asset: the input glTF with the selected primitive replaced by its cut
// version, as GLB (optionally Draco-compressed); and a plain GLB writer for tests and the sample.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/draco_io.h"
#include "api/error.h"
#include "api/gltf_reader.h"
#include "core/mesh/types.h"

namespace seam::api {

/// The cut primitive in terms of the input primitive's vertices.
struct CutPrimitive {
  /// Output vertex -> input vertex whose attributes it copies. One entry per unique
  /// (input vertex, cut vertex) pair: a vertex is duplicated only where the seam passes.
  std::vector<std::uint32_t> source_vertex;
  std::vector<core::Triangle> triangles;      ///< over output vertices, input winding kept
  std::vector<std::array<float, 2>> uv;       ///< empty, or one per output vertex (new TEXCOORD set)
  nlohmann::json seam_extras = nlohmann::json::object();  ///< goes to the primitive's extras.seam
};

struct WriteOptions {
  bool draco = false;  ///< compress the cut primitive with KHR_draco_mesh_compression
  DracoEncodeOptions draco_options;
};

struct WrittenAsset {
  std::string glb;
  int uv_channel = -1;        ///< n of the TEXCOORD_n written, -1 if none
  std::size_t vertices = 0;   ///< output vertices of the cut primitive
  std::size_t draco_bytes = 0;
};

/// Writes `doc` as one GLB with primitive (mesh, primitive) replaced by `cut`. All buffers
/// are merged into the GLB BIN chunk; every other object (nodes, materials, images, skins,
/// animations, other meshes, extensions, extras) is kept as it was. Every attribute and morph
/// target of the input primitive is gathered per output vertex bit-exactly in its own
/// component type; POSITION gets min/max; indices are u16 or u32; the new UV set is float32
/// TEXCOORD_n with the smallest free n. extensionsUsed/Required list
/// KHR_draco_mesh_compression exactly when some primitive still uses it.
/// Preconditions: `data` was read from `doc` at (mesh, primitive); source_vertex entries
/// < the input vertex count; triangles index source_vertex. Errors: kInternal (Draco refused).
/// Complexity: O(asset bytes + output vertices * attribute bytes).
ApiResult<WrittenAsset> write_cut_asset(const GltfDocument& doc, std::uint32_t mesh, std::uint32_t primitive,
                                        const PrimitiveData& data, const CutPrimitive& cut, const WriteOptions& options);

/// Writes a one-mesh, one-node GLB from positions and triangles plus optional extra
/// attributes (each with mesh.positions.size() elements, e.g. NORMAL, COLOR_0, TEXCOORD_0).
/// Positions are stored as float32. With `draco`, the primitive is Draco-compressed.
ApiResult<std::string> write_plain_glb(const core::IndexedMesh& mesh, const std::vector<AttributeArray>& extra = {},
                                       bool draco = false);

/// Packs a glTF JSON document and a binary chunk into GLB bytes (4-byte padded chunks).
std::string encode_glb(const nlohmann::json& json, const std::vector<std::uint8_t>& bin);

/// Helpers to build attribute arrays in tests and the sample.
AttributeArray make_float_attribute(const std::string& name, int components, const std::vector<float>& values);

}  // namespace seam::api
