// Reading untrusted glTF 2.0 assets (GLB, .gltf JSON with data-URI buffers,
// KHR_draco_mesh_compression primitives, raw Draco .drc meshes) into the core's indexed mesh
// plus every vertex attribute, so the writer can put the cut primitive back.
//
// Why not tinygltf for reading: tinygltf 2.7 reads files named in the asset, overflows the
// heap on an out-of-range Draco bufferView and reports failed Draco decodes as success
// (shared/notes/stack.md). We parse the JSON with nlohmann::json, keep it verbatim (so every
// extension, extra and unknown field survives the round trip), check every index, offset,
// length and count ourselves, and decode Draco with draco::Decoder, checking its status.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/error.h"
#include "core/mesh/types.h"


namespace seam::api {

/// What kind of bytes the asset is. kAuto sniffs: "glTF" magic = GLB, '{' = glTF JSON,
/// "DRACO" magic = raw Draco mesh.
enum class AssetKind { kAuto, kGlb, kGltfJson, kDraco };

/// Caps applied before any allocation sized by a number declared in the asset.
struct ReadLimits {
  std::size_t max_vertices = 20'000'000;  ///< per accessor count (vertices, sparse entries)
  std::size_t max_faces = 5'000'000;      ///< triangles of the selected primitive (kMeshTooLarge)
  std::size_t max_json_bytes = 64u << 20;
  /// Decoded Draco attribute bytes per point (all attributes): 32 float components, e.g.
  /// POSITION, NORMAL, TANGENT, two TEXCOORDs, COLOR, JOINTS and WEIGHTS (96) with room.
  std::size_t max_draco_bytes_per_point = 128;
};

/// A parsed asset: its JSON kept verbatim and its binary buffers resolved (GLB BIN chunk or
/// decoded data URIs). Invariant after parse_asset: buffers.size() == json["buffers"].size()
/// and buffers[i].size() >= buffers[i].byteLength.
struct GltfDocument {
  nlohmann::json json;
  std::vector<std::vector<std::uint8_t>> buffers;
  AssetKind kind = AssetKind::kGlb;  ///< what the input was (never kAuto)
};

/// One vertex attribute (or indices) read into a tightly packed array in the accessor's own
/// component type, so the writer can copy values bit-exactly.
struct AttributeArray {
  std::string name;           ///< "POSITION", "TEXCOORD_1", ...
  int component_type = 5126;  ///< glTF componentType (5120..5126)
  int components = 3;         ///< 1 (SCALAR) .. 4 (VEC4); 4/9/16 for MAT2/3/4
  std::string type = "VEC3";  ///< accessor type string
  bool normalized = false;
  std::size_t count = 0;
  std::vector<std::uint8_t> data;  ///< count * element_size() bytes

  std::size_t component_size() const;
  std::size_t element_size() const { return component_size() * static_cast<std::size_t>(components); }
};

/// How a Draco payload quantized one attribute, so a re-encode can keep it: positions,
/// texture coordinates and generic attributes on a uniform grid, normals on the octahedron.
struct DracoQuantization {
  std::uint32_t unique_id = 0;
  std::string name;  ///< the glTF attribute it feeds (read_primitive fills it)
  int bits = 0;
  bool octahedral = false;
};

/// The selected primitive: positions as doubles (dequantized), triangles in input vertex
/// indices (strips and fans converted), and every attribute and morph target.
struct PrimitiveData {
  core::IndexedMesh mesh;
  std::vector<AttributeArray> attributes;            ///< every attribute, POSITION included
  std::vector<std::vector<AttributeArray>> targets;  ///< morph targets, same vertex count
  bool draco = false;                                ///< the primitive was Draco-compressed
  std::vector<DracoQuantization> draco_quantization; ///< its quantized attributes, by name
  int mode = 4;                                      ///< the input primitive mode
};

/// Sniffs GLB ("glTF" magic), glTF JSON ('{' after whitespace) or Draco ("DRACO").
AssetKind detect_asset_kind(std::string_view bytes);

/// Parses and validates the container: GLB header and chunks, the JSON, buffers (only data
/// URIs or the GLB BIN chunk; any other URI is kExternalUri and is never read), image URIs,
/// every bufferView's range, and every accessor's, sparse block's and Draco extension's
/// references and byte ranges. A raw Draco mesh becomes a one-primitive document.
/// `extensionsRequired` may only name extensions supported_required_extension() accepts
/// (glTF 2.0 §3.12: a loader must refuse an asset that requires one it does not support).
/// Errors: kMalformedAsset (400, names the offending object; also an extensionsRequired that
/// is not an array of strings), kExternalUri (422), kUnsupportedExtension (422,
/// details.extensions: the unsupported names, at most 16 of 60 bytes each).
/// Complexity: O(bytes).
ApiResult<GltfDocument> parse_asset(std::string_view bytes, AssetKind kind, const ReadLimits& limits = {});

/// Whether an asset may list `name` in extensionsRequired. The reader decodes
/// KHR_draco_mesh_compression and KHR_mesh_quantization; the extensions that do not change a
/// primitive's geometry and that the service carries through untouched (materials and
/// textures: KHR_materials_*, KHR_texture_transform, KHR_texture_basisu, EXT_texture_webp,
/// EXT_texture_avif; scene-level: KHR_lights_punctual, EXT_mesh_gpu_instancing,
/// KHR_animation_pointer, KHR_xmp_json_ld) are honoured by the clients that read our output,
/// as they would be by readers of the input. Anything else (EXT_meshopt_compression, whose
/// buffer views we cannot read; unknown names) is refused. O(1).
bool supported_required_extension(std::string_view name);

/// Reads primitive `primitive` of mesh `mesh`. Node transforms are not applied.
/// Errors: kNoTrianglePrimitive (indices out of range), kUnsupportedPrimitiveMode (points or
/// lines), kMalformedAsset (bad accessor, failed Draco decode), kIndexOutOfRange (an index
/// >= the vertex count), kNonFinitePosition (NaN/Inf, details.vertices), kMeshTooLarge,
/// kEmptyMesh. Complexity: O(vertices + indices).
ApiResult<PrimitiveData> read_primitive(const GltfDocument& doc, std::uint32_t mesh, std::uint32_t primitive,
                                        const ReadLimits& limits = {});

}  // namespace seam::api
