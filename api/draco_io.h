// Draco mesh decoding and encoding for KHR_draco_mesh_compression and raw .drc input.
// Every call checks draco's Status: a failed decode is an error, never silent success.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "api/error.h"
#include "api/gltf_reader.h"
#include "core/mesh/types.h"

namespace draco {
class Mesh;
}

namespace seam::api {

/// One attribute of a decoded Draco mesh, described in glTF terms.
struct DracoAttributeInfo {
  std::uint32_t unique_id = 0;
  std::string semantic;     ///< "POSITION", "NORMAL", "COLOR", "TEX_COORD" or "GENERIC"
  int components = 0;       ///< 1..4 (others are refused at decode)
  int component_type = 0;   ///< the glTF componentType of its data, 0 if glTF has none (int32, float64, ...)
  bool normalized = false;
};

/// A decoded Draco mesh: points (= glTF vertices), triangles over points, attributes.
struct DracoMesh {
  std::size_t num_points = 0;
  std::vector<core::Triangle> triangles;
  std::vector<DracoAttributeInfo> attributes;
  std::vector<DracoQuantization> quantization;  ///< quantized attributes (with read_quantization)
  std::shared_ptr<const draco::Mesh> mesh;  ///< owns the decoded data
};

/// Decodes a Draco mesh (sequential or edgebreaker, bitstreams 1.x-2.2), checking what the
/// payload claims before draco allocates by it: the connectivity header's face and point
/// counts before the connectivity is decoded, then the real point count and every
/// attribute's components and bytes before any attribute value is decoded. Memory is
/// O(bytes + faces) with faces <= limits.max_faces, attributes at most
/// limits.max_draco_bytes_per_point bytes per point and 3 points per face. Errors: kMalformedAsset (draco's status message; unknown encoding; not
/// a mesh; an attribute with other than 1-4 components; a face index >= num_points),
/// kNoTrianglePrimitive (a point cloud), kMeshTooLarge (more than limits.max_faces faces,
/// more than limits.max_vertices points or 3 per face, more attribute bytes per point than
/// limits.max_draco_bytes_per_point), kEmptyMesh (no faces). O(bytes + points + faces).
/// With read_quantization, the payload is decoded a second time without the attribute
/// transforms to read each quantized attribute's parameters (DracoMesh::quantization).
ApiResult<DracoMesh> decode_draco(std::span<const std::uint8_t> bytes, const ReadLimits& limits = {},
                                  bool read_quantization = false);

/// Reads attribute `unique_id` converted to `component_type` with `components` values per
/// point, one element per point in point order. Errors: kMalformedAsset (no such attribute,
/// component count mismatch, conversion refused). O(points).
ApiResult<AttributeArray> read_draco_attribute(const DracoMesh& mesh, std::uint32_t unique_id, int component_type,
                                               int components, bool normalized, const std::string& name);

struct DracoEncodeOptions {
  /// Quantization bits for POSITION, TEX_COORD, NORMAL and other float attributes.
  /// 0 = lossless (floats stored as they are): every output vertex keeps its exact input
  /// value, which the contract asks for. 11..16 trades exactness for size.
  int position_bits = 0;
  int texcoord_bits = 0;
  int normal_bits = 0;
  int generic_bits = 0;
  int speed = 5;  ///< draco encoding/decoding speed 0 (smallest) .. 10 (fastest)
  /// Per attribute (by glTF name), the input's quantization bits to keep; they override the bits
  /// above. Values decoded from a grid span it, so draco re-derives the same grid from them
  /// and they decode bit-exactly again (tests/api/asset_set_test.cpp checks it).
  std::vector<DracoQuantization> keep;
  /// Keep point i as decoded point i (sequential encoding, verified). Needed when data
  /// outside the Draco blob (morph targets) is indexed by vertex. Costs compression.
  bool preserve_point_order = false;
};

struct EncodedDraco {
  std::string bytes;
  std::vector<std::uint32_t> unique_ids;  ///< one per input attribute, same order
  bool sequential = false;  ///< fell back to sequential encoding to keep the point count
};

/// Encodes triangles over `attributes` (all with the same count; POSITION first or anywhere).
/// The result decodes to exactly attributes[0].count points and triangles.size() faces
/// (verified by decoding; edgebreaker falls back to sequential encoding if it would not);
/// with preserve_point_order, decoded point i also has the values of input element i.
/// Errors: kInternal (draco refused: a bug in our attribute description).
/// O(points + faces), plus one verification decode.
ApiResult<EncodedDraco> encode_draco(std::span<const AttributeArray> attributes, std::span<const core::Triangle> triangles,
                                     const DracoEncodeOptions& options = {});

}  // namespace seam::api
