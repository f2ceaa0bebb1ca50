#include "api/draco_io.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <optional>
#include <type_traits>

#include <draco/attributes/attribute_octahedron_transform.h>
#include <draco/attributes/attribute_quantization_transform.h>
#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/compression/expert_encode.h>
#include <draco/compression/mesh/mesh_edgebreaker_decoder.h>
#include <draco/compression/mesh/mesh_sequential_decoder.h>
#include <draco/core/varint_decoding.h>
#include <draco/mesh/mesh.h>

namespace seam::api {
namespace {

int gltf_component_type(draco::DataType type) {
  switch (type) {
    case draco::DT_INT8: return 5120;
    case draco::DT_UINT8: return 5121;
    case draco::DT_INT16: return 5122;
    case draco::DT_UINT16: return 5123;
    case draco::DT_UINT32: return 5125;
    case draco::DT_FLOAT32: return 5126;
    default: return 0;
  }
}

draco::DataType draco_data_type(int component_type) {
  switch (component_type) {
    case 5120: return draco::DT_INT8;
    case 5121: return draco::DT_UINT8;
    case 5122: return draco::DT_INT16;
    case 5123: return draco::DT_UINT16;
    case 5125: return draco::DT_UINT32;
    case 5126: return draco::DT_FLOAT32;
    default: return draco::DT_INVALID;
  }
}

std::string semantic_name(draco::GeometryAttribute::Type type) {
  switch (type) {
    case draco::GeometryAttribute::POSITION: return "POSITION";
    case draco::GeometryAttribute::NORMAL: return "NORMAL";
    case draco::GeometryAttribute::COLOR: return "COLOR";
    case draco::GeometryAttribute::TEX_COORD: return "TEX_COORD";
    default: return "GENERIC";
  }
}

draco::GeometryAttribute::Type draco_semantic(const std::string& gltf_name) {
  if (gltf_name == "POSITION") return draco::GeometryAttribute::POSITION;
  if (gltf_name == "NORMAL") return draco::GeometryAttribute::NORMAL;
  if (gltf_name.rfind("TEXCOORD_", 0) == 0) return draco::GeometryAttribute::TEX_COORD;
  if (gltf_name.rfind("COLOR_", 0) == 0) return draco::GeometryAttribute::COLOR;
  return draco::GeometryAttribute::GENERIC;
}

// --- Bounded decoding -------------------------------------------------------------------
//
// A Draco payload states its counts (faces, points, attribute components) and draco sizes its
// allocations by them: a 300 KB payload claiming 300k points of 255 float components made it
// allocate and zero 306 MB per copy (+568 MB, 1.1 s) before failing. draco has no hook
// between parsing a count and allocating by it, so we decode with draco's own mesh decoders
// subclassed at the two points where the claims are known and nothing sized by them exists:
//  1. DecodeConnectivity, entered right after the header and metadata: the connectivity
//     header's counts are peeked from a copy of the buffer and checked against the limits
//     before draco sizes its face list or corner table by them;
//  2. DecodeAllAttributes, entered after connectivity (the point count is then real) and after
//     the attribute headers (types and component counts, no values yet): the decoded
//     attribute bytes are checked before any attribute buffer is allocated.
// So memory stays O(faces) with faces <= max_faces, and attribute memory is at most
// 3 * faces * max_draco_bytes_per_point.

// Every mesh_too_large names its limit (details.limit) and the claimed amount (details.count).
ApiError too_large(std::string message, std::uint64_t count, std::uint64_t limit) {
  return make_api_error(ApiErrorCode::kMeshTooLarge, std::move(message), {{"count", count}, {"limit", limit}});
}

// A count as the bitstream version stores it: uint32 before `varint_from`, varint from it on.
std::optional<std::uint32_t> read_count(draco::DecoderBuffer& buffer, std::uint16_t varint_from) {
  std::uint32_t v = 0;
  const bool ok = buffer.bitstream_version() < varint_from ? buffer.Decode(&v) : draco::DecodeVarint(&v, &buffer);
  return ok ? std::optional<std::uint32_t>(v) : std::nullopt;
}

// The counts a connectivity header claims (layouts of draco 1.5's MeshSequentialDecoder and
// MeshEdgebreakerDecoderImpl::DecodeConnectivity, bitstreams 1.x to 2.2). Points of an
// edgebreaker stream: encoded vertices plus split symbols, what draco's corner table is sized by.
struct ClaimedCounts {
  std::uint32_t faces = 0;
  std::uint64_t points = 0;
};

std::optional<ClaimedCounts> sequential_counts(draco::DecoderBuffer buffer) {
  const auto faces = read_count(buffer, DRACO_BITSTREAM_VERSION(2, 2));
  const auto points = faces ? read_count(buffer, DRACO_BITSTREAM_VERSION(2, 2)) : std::nullopt;
  if (!points) return std::nullopt;
  return ClaimedCounts{*faces, *points};
}

std::optional<ClaimedCounts> edgebreaker_counts(draco::DecoderBuffer buffer) {
  const std::uint16_t v2_0 = DRACO_BITSTREAM_VERSION(2, 0);
  if (buffer.bitstream_version() < DRACO_BITSTREAM_VERSION(2, 2) && !read_count(buffer, v2_0)) return std::nullopt;
  const auto vertices = read_count(buffer, v2_0);
  const auto faces = vertices ? read_count(buffer, v2_0) : std::nullopt;
  std::uint8_t attribute_data = 0;
  if (!faces || !buffer.Decode(&attribute_data)) return std::nullopt;
  const auto symbols = read_count(buffer, v2_0);
  const auto splits = symbols ? read_count(buffer, v2_0) : std::nullopt;
  if (!splits) return std::nullopt;
  return ClaimedCounts{*faces, std::uint64_t{*vertices} + *splits};
}

// A mesh has at most 3 points per face that faces use; more are unused points whose memory
// the face limit would not bound.
std::optional<ApiError> check_counts(std::uint64_t faces, std::uint64_t points, const ReadLimits& limits) {
  if (faces > limits.max_faces) {
    return too_large("the Draco mesh declares " + std::to_string(faces) + " faces, more than the limit of " +
                         std::to_string(limits.max_faces),
                     faces, limits.max_faces);
  }
  if (points > limits.max_vertices || points > 3 * faces) {
    return too_large("the Draco mesh declares " + std::to_string(points) + " points for " + std::to_string(faces) +
                         " faces (at most 3 per face and " + std::to_string(limits.max_vertices) + " in all)",
                     points, std::min<std::uint64_t>(limits.max_vertices, 3 * faces));
  }
  return std::nullopt;
}

template <class Base>
class BoundedMeshDecoder : public Base {
 public:
  explicit BoundedMeshDecoder(const ReadLimits& limits) : limits_(limits) {}
  /// Why decoding stopped, when it was one of our checks rather than draco's.
  const std::optional<ApiError>& refusal() const { return refusal_; }

 protected:
  bool DecodeConnectivity() override {
    const auto claimed = std::is_base_of_v<draco::MeshEdgebreakerDecoder, Base> ? edgebreaker_counts(*this->buffer())
                                                                                : sequential_counts(*this->buffer());
    if (!claimed) return false;  // truncated: draco's own read fails the same way
    refusal_ = check_counts(claimed->faces, claimed->points, limits_);
    return !refusal_ && Base::DecodeConnectivity();
  }

  bool DecodeAllAttributes() override {
    const draco::PointCloud& pc = *this->point_cloud();
    refusal_ = check_counts(this->mesh()->num_faces(), pc.num_points(), limits_);
    if (refusal_) return false;
    std::size_t bytes_per_point = 0;
    for (int i = 0; i < pc.num_attributes(); ++i) {
      const draco::PointAttribute* a = pc.attribute(i);
      if (a == nullptr) continue;
      if (a->num_components() < 1 || a->num_components() > 4) {
        refusal_ = malformed_asset("Draco attribute " + std::to_string(a->unique_id()) + " has " +
                                   std::to_string(a->num_components()) + " components (glTF allows 1 to 4)");
        return false;
      }
      // glTF has no boolean component type, and draco converts a stored bool by loading it as
      // a C++ bool: a byte other than 0 or 1 is undefined behaviour (found by gltf_fuzz).
      if (a->data_type() == draco::DT_BOOL || a->data_type() == draco::DT_INVALID) {
        refusal_ = malformed_asset("Draco attribute " + std::to_string(a->unique_id()) +
                                   " is of a data type glTF has no component type for (bool or invalid)");
        return false;
      }
      bytes_per_point += static_cast<std::size_t>(a->num_components()) *
                         static_cast<std::size_t>(std::max(0, draco::DataTypeLength(a->data_type())));
    }
    if (bytes_per_point > limits_.max_draco_bytes_per_point) {
      refusal_ =
          too_large("the Draco attributes take " + std::to_string(bytes_per_point) +
                        " bytes per point, more than the limit of " + std::to_string(limits_.max_draco_bytes_per_point),
                    bytes_per_point, limits_.max_draco_bytes_per_point);
      return false;
    }
    return Base::DecodeAllAttributes();
  }

 private:
  ReadLimits limits_;
  std::optional<ApiError> refusal_;
};

template <class Decoder>
ApiResult<std::unique_ptr<draco::Mesh>> decode_bounded(draco::DecoderBuffer& buffer, const ReadLimits& limits,
                                                       bool skip_transforms) {
  Decoder decoder(limits);
  auto mesh = std::make_unique<draco::Mesh>();
  draco::DecoderOptions options;
  if (skip_transforms) {
    for (auto type : {draco::GeometryAttribute::POSITION, draco::GeometryAttribute::NORMAL, draco::GeometryAttribute::COLOR,
                      draco::GeometryAttribute::TEX_COORD, draco::GeometryAttribute::GENERIC}) {
      options.SetAttributeBool(type, "skip_attribute_transform", true);
    }
  }
  const draco::Status status = decoder.Decode(options, &buffer, mesh.get());
  if (decoder.refusal()) return *decoder.refusal();
  if (!status.ok()) return malformed_asset("Draco decode failed: " + status.error_msg_string());
  return mesh;
}

// draco::Decoder::DecodeMeshFromBuffer with our decoders in place of draco's.
ApiResult<std::unique_ptr<draco::Mesh>> decode_mesh(draco::DecoderBuffer& buffer, const ReadLimits& limits,
                                                    bool skip_transforms = false) {
  draco::DecoderBuffer header_buffer(buffer);
  draco::DracoHeader header;
  const draco::Status status = draco::PointCloudDecoder::DecodeHeader(&header_buffer, &header);
  if (!status.ok()) return malformed_asset("Draco: " + status.error_msg_string());
  switch (header.encoder_method) {
    case draco::MESH_SEQUENTIAL_ENCODING:
      return decode_bounded<BoundedMeshDecoder<draco::MeshSequentialDecoder>>(buffer, limits, skip_transforms);
    case draco::MESH_EDGEBREAKER_ENCODING:
      return decode_bounded<BoundedMeshDecoder<draco::MeshEdgebreakerDecoder>>(buffer, limits, skip_transforms);
    default:
      return malformed_asset("Draco: unknown mesh encoding method " + std::to_string(header.encoder_method));
  }
}

template <class T>
bool convert_all(const draco::PointAttribute& attribute, std::size_t num_points, int components,
                 std::vector<std::uint8_t>& out) {
  out.resize(num_points * sizeof(T) * static_cast<std::size_t>(components));
  T value[4];
  for (std::size_t p = 0; p < num_points; ++p) {
    const draco::AttributeValueIndex avi = attribute.mapped_index(draco::PointIndex(static_cast<std::uint32_t>(p)));
    if (avi.value() >= attribute.size()) return false;
    if (!attribute.ConvertValue<T>(avi, static_cast<std::int8_t>(components), value)) return false;
    std::memcpy(out.data() + p * sizeof(T) * components, value, sizeof(T) * components);
  }
  return true;
}

// The input's quantization where the attribute had one, else the options' bits per semantic
// (0 = lossless).
void set_quantization(draco::ExpertEncoder& encoder, int id, const AttributeArray& a, const DracoEncodeOptions& options) {
  if (a.component_type != 5126) return;  // integer data is stored as it is
  const auto kept = std::find_if(options.keep.begin(), options.keep.end(),
                                 [&](const DracoQuantization& q) { return q.name == a.name; });
  if (kept != options.keep.end() && kept->bits > 0) {
    // Bits only: draco then takes the grid's origin and extent from the values, which lie on
    // the input's grid, and stores them as floats. (An explicit origin and range would pass
    // through draco's option strings, printed with 6 decimals, and move the grid.)
    encoder.SetAttributeQuantization(id, kept->bits);
    return;
  }
  int bits = 0;
  switch (draco_semantic(a.name)) {
    case draco::GeometryAttribute::POSITION: bits = options.position_bits; break;
    case draco::GeometryAttribute::TEX_COORD: bits = options.texcoord_bits; break;
    case draco::GeometryAttribute::NORMAL: bits = options.normal_bits; break;
    case draco::GeometryAttribute::GENERIC: bits = options.generic_bits; break;
    default: break;
  }
  if (bits > 0) encoder.SetAttributeQuantization(id, bits);
}

core::Result<EncodedDraco, std::string> encode_once(std::span<const AttributeArray> attributes,
                                              std::span<const core::Triangle> triangles,
                                              const DracoEncodeOptions& options, bool sequential) {
  const std::size_t n = attributes.empty() ? 0 : attributes.front().count;
  draco::Mesh mesh;
  mesh.set_num_points(static_cast<std::uint32_t>(n));
  for (const auto& t : triangles) {
    mesh.AddFace({draco::PointIndex(t[0]), draco::PointIndex(t[1]), draco::PointIndex(t[2])});
  }
  EncodedDraco result;
  for (const auto& a : attributes) {
    draco::GeometryAttribute ga;
    const auto dt = draco_data_type(a.component_type);
    if (dt == draco::DT_INVALID || a.components < 1 || a.components > 4 || a.count != n) {
      return std::string("attribute ") + a.name + " cannot be Draco-encoded";
    }
    ga.Init(draco_semantic(a.name), nullptr, static_cast<std::uint8_t>(a.components), dt, a.normalized,
            static_cast<std::int64_t>(a.element_size()), 0);
    // identity_mapping: point p has value p. We never deduplicate values: each output vertex
    // must stay one glTF vertex.
    const int id = mesh.AddAttribute(ga, true, static_cast<std::uint32_t>(n));
    if (id < 0) return std::string("draco refused attribute ") + a.name;
    draco::PointAttribute* pa = mesh.attribute(id);
    for (std::size_t i = 0; i < n; ++i) {
      pa->SetAttributeValue(draco::AttributeValueIndex(static_cast<std::uint32_t>(i)),
                            a.data.data() + i * a.element_size());
    }
    result.unique_ids.push_back(pa->unique_id());
  }
  draco::ExpertEncoder encoder(mesh);
  encoder.SetSpeedOptions(options.speed, options.speed);
  for (std::size_t i = 0; i < attributes.size(); ++i) set_quantization(encoder, static_cast<int>(i), attributes[i], options);
  encoder.SetEncodingMethod(sequential ? draco::MESH_SEQUENTIAL_ENCODING : draco::MESH_EDGEBREAKER_ENCODING);
  draco::EncoderBuffer buffer;
  const draco::Status status = encoder.EncodeToBuffer(&buffer);
  if (!status.ok()) return std::string("draco encode failed: ") + status.error_msg_string();
  result.bytes.assign(buffer.data(), buffer.size());
  result.sequential = sequential;
  return result;
}

// The payload decoded once more without attribute transforms: each quantized attribute then
// carries its transform's parameters.
ApiResult<std::vector<DracoQuantization>> read_quantization(std::span<const std::uint8_t> bytes, const ReadLimits& limits) {
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  SEAM_TRY(const std::unique_ptr<draco::Mesh> raw, decode_mesh(buffer, limits, true));
  std::vector<DracoQuantization> out;
  for (int i = 0; i < raw->num_attributes(); ++i) {
    const draco::PointAttribute* a = raw->attribute(i);
    if (a == nullptr || a->GetAttributeTransformData() == nullptr) continue;
    DracoQuantization q;
    q.unique_id = a->unique_id();
    draco::AttributeQuantizationTransform grid;
    draco::AttributeOctahedronTransform octahedron;
    if (grid.InitFromAttribute(*a)) {
      q.bits = grid.quantization_bits();
    } else if (octahedron.InitFromAttribute(*a)) {
      q.bits = octahedron.quantization_bits();
      q.octahedral = true;
    } else {
      continue;
    }
    out.push_back(std::move(q));
  }
  return out;
}

}  // namespace

ApiResult<DracoMesh> decode_draco(std::span<const std::uint8_t> bytes, const ReadLimits& limits, bool quantization) {
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  auto type = draco::Decoder::GetEncodedGeometryType(&buffer);
  if (!type.ok()) return malformed_asset("Draco: " + type.status().error_msg_string());
  if (type.value() != draco::TRIANGULAR_MESH) {
    return make_api_error(ApiErrorCode::kNoTrianglePrimitive, "the Draco data is a point cloud, not a triangle mesh");
  }
  SEAM_TRY(std::unique_ptr<draco::Mesh> decoded, decode_mesh(buffer, limits));
  std::shared_ptr<const draco::Mesh> mesh(std::move(decoded));
  DracoMesh out;
  out.num_points = mesh->num_points();
  if (mesh->num_faces() > limits.max_faces) {
    return too_large("the Draco mesh has " + std::to_string(mesh->num_faces()) + " faces, more than the limit of " +
                         std::to_string(limits.max_faces),
                     mesh->num_faces(), limits.max_faces);
  }
  if (out.num_points > limits.max_vertices) {
    return too_large("the Draco mesh has " + std::to_string(out.num_points) + " points, more than the limit of " +
                         std::to_string(limits.max_vertices),
                     out.num_points, limits.max_vertices);
  }
  if (mesh->num_faces() == 0) return make_api_error(ApiErrorCode::kEmptyMesh, "the Draco mesh has no faces");
  out.triangles.reserve(mesh->num_faces());
  for (std::uint32_t f = 0; f < mesh->num_faces(); ++f) {
    const auto& face = mesh->face(draco::FaceIndex(f));
    core::Triangle t{face[0].value(), face[1].value(), face[2].value()};
    for (auto v : t) {
      if (v >= out.num_points)
        return malformed_asset("Draco face " + std::to_string(f) + " names a point out of range");
    }
    out.triangles.push_back(t);
  }
  for (int i = 0; i < mesh->num_attributes(); ++i) {
    const draco::PointAttribute* a = mesh->attribute(i);
    if (a == nullptr) continue;
    if (a->num_components() < 1 || a->num_components() > 4) {
      return malformed_asset("Draco attribute " + std::to_string(a->unique_id()) + " has " +
                             std::to_string(a->num_components()) + " components");
    }
    out.attributes.push_back(DracoAttributeInfo{a->unique_id(), semantic_name(a->attribute_type()),
                                                a->num_components(), gltf_component_type(a->data_type()),
                                                a->normalized()});
  }
  out.mesh = std::move(mesh);
  if (quantization) {
    SEAM_TRY(out.quantization, read_quantization(bytes, limits));
  }
  return out;
}

ApiResult<AttributeArray> read_draco_attribute(const DracoMesh& mesh, std::uint32_t unique_id, int component_type,
                                               int components, bool normalized, const std::string& name) {
  const draco::PointAttribute* a = mesh.mesh ? mesh.mesh->GetAttributeByUniqueId(unique_id) : nullptr;
  if (a == nullptr)
    return malformed_asset("Draco data has no attribute with id " + std::to_string(unique_id) + " for " + name);
  if (a->num_components() != components) {
    return malformed_asset("Draco attribute " + name + " has " + std::to_string(a->num_components()) +
                           " components but its accessor declares " + std::to_string(components));
  }
  AttributeArray out;
  out.name = name;
  out.component_type = component_type;
  out.components = components;
  out.normalized = normalized;
  out.count = mesh.num_points;
  static constexpr const char* kTypes[] = {"", "SCALAR", "VEC2", "VEC3", "VEC4"};
  out.type = kTypes[components];
  bool ok = false;
  switch (component_type) {
    case 5120: ok = convert_all<std::int8_t>(*a, mesh.num_points, components, out.data); break;
    case 5121: ok = convert_all<std::uint8_t>(*a, mesh.num_points, components, out.data); break;
    case 5122: ok = convert_all<std::int16_t>(*a, mesh.num_points, components, out.data); break;
    case 5123: ok = convert_all<std::uint16_t>(*a, mesh.num_points, components, out.data); break;
    case 5125: ok = convert_all<std::uint32_t>(*a, mesh.num_points, components, out.data); break;
    case 5126: ok = convert_all<float>(*a, mesh.num_points, components, out.data); break;
    default: break;
  }
  if (!ok)
    return malformed_asset("Draco attribute " + name + " cannot be read as componentType " +
                           std::to_string(component_type));
  return out;
}

ApiResult<EncodedDraco> encode_draco(std::span<const AttributeArray> attributes, std::span<const core::Triangle> triangles,
                                     const DracoEncodeOptions& options) {
  const std::size_t n = attributes.empty() ? 0 : attributes.front().count;
  // Edgebreaker may split vertices it sees as non-manifold, which would change the point
  // count the glTF accessors declare; verify by decoding and fall back to sequential.
  for (bool sequential : {false, true}) {
    if (options.preserve_point_order && !sequential) continue;
    auto encoded = encode_once(attributes, triangles, options, sequential);
    if (!encoded.ok()) return make_api_error(ApiErrorCode::kInternal, encoded.error());
    const auto& bytes = encoded->bytes;
    ReadLimits limits;
    limits.max_faces = triangles.size() + 1;
    limits.max_vertices = n + 1;
    // Our own output: as wide as the input's attributes (the limit is for hostile payloads).
    limits.max_draco_bytes_per_point = std::numeric_limits<std::size_t>::max();
    auto check = decode_draco(std::span(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()), limits);
    if (check.ok() && check->num_points == n && check->triangles.size() == triangles.size()) {
      if (!options.preserve_point_order) return std::move(encoded).value();
      // Lossless settings only: compare every attribute value point by point.
      bool same = check->triangles == std::vector<core::Triangle>(triangles.begin(), triangles.end());
      for (std::size_t i = 0; same && i < attributes.size(); ++i) {
        auto values = read_draco_attribute(*check, encoded->unique_ids[i], attributes[i].component_type,
                                           attributes[i].components, attributes[i].normalized, attributes[i].name);
        same = values.ok() && values->data == attributes[i].data;
      }
      if (same) return std::move(encoded).value();
    }
  }
  return make_api_error(ApiErrorCode::kInternal, "Draco encoding did not preserve the vertex count");
}

}  // namespace seam::api
