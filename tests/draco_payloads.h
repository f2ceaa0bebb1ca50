// Hostile Draco payloads written byte by byte (bitstream 2.2), shared by the decoder's tests
// (tests/api/draco_io_test.cpp) and the end-to-end ones (tests/server/hostile_test.cpp).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <draco/attributes/geometry_attribute.h>
#include <draco/core/draco_types.h>

namespace seam::test_draco {

// Bitstream 2.2 bytes, written by hand after draco's MeshSequentialDecoder and
// MeshEdgebreakerDecoderImpl::DecodeConnectivity.
struct DracoBytes {
  std::vector<std::uint8_t> bytes;
  void u8(std::uint32_t v) { bytes.push_back(static_cast<std::uint8_t>(v)); }
  void varint(std::uint64_t v) {
    do {
      u8((v & 0x7F) | (v > 0x7F ? 0x80 : 0));
      v >>= 7;
    } while (v != 0);
  }
  void header(int method) {  // "DRACO", version 2.2, triangular mesh, no flags
    for (char c : std::string("DRACO")) u8(static_cast<std::uint8_t>(c));
    for (std::uint32_t v : {2u, 2u, 1u, static_cast<std::uint32_t>(method), 0u, 0u}) u8(v);
  }
};

struct Attribute {
  draco::GeometryAttribute::Type type = draco::GeometryAttribute::GENERIC;
  draco::DataType data_type = draco::DT_FLOAT32;
  std::uint32_t components = 3;
};

// A sequential mesh of `faces` faces (all 0,1,2) over `points`
// points, then the headers of `attributes` and no attribute values: the decoder must refuse
// it from the headers, or fail reading values that are not there.
inline std::vector<std::uint8_t> sequential_payload(std::uint32_t faces, std::uint32_t points,
                                             const std::vector<Attribute>& attributes) {
  DracoBytes d;
  d.header(0);
  d.varint(faces);
  d.varint(points);
  d.u8(1);  // uncompressed indices: uint8 below 256 points, uint16 below 2^16, then varints
  for (std::uint32_t f = 0; f < faces; ++f) {
    for (std::uint32_t i : {0u, 1u, 2u}) {
      d.u8(i);
      if (points >= 256 && points < (1u << 16)) d.u8(0);
    }
  }
  d.u8(1);  // one attributes decoder
  d.varint(attributes.size());
  for (std::size_t i = 0; i < attributes.size(); ++i) {
    d.u8(static_cast<std::uint32_t>(attributes[i].type));
    d.u8(static_cast<std::uint32_t>(attributes[i].data_type));
    d.u8(attributes[i].components);
    d.u8(0);          // not normalized
    d.varint(i);      // unique id
  }
  for (std::size_t i = 0; i < attributes.size(); ++i) d.u8(0);  // generic sequential decoders
  return d.bytes;
}

// An edgebreaker connectivity header claiming `faces` faces and `vertices` vertices.
inline std::vector<std::uint8_t> edgebreaker_header(std::uint32_t vertices, std::uint32_t faces) {
  DracoBytes d;
  d.header(1);
  d.u8(0);  // standard edgebreaker traversal
  d.varint(vertices);
  d.varint(faces);
  d.u8(0);                                   // attribute data
  d.varint(faces);                           // symbols
  d.varint(0);                               // split symbols
  d.bytes.resize(d.bytes.size() + 200, 0);   // and nothing that decodes
  return d.bytes;
}


}  // namespace seam::test_draco
