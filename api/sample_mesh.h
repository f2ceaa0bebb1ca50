// The bundled procedural sample: a starfish (a flattened body with five arms), so users can
// try the service without an asset of their own (`seamd sample --out sample.glb`).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "api/error.h"
#include "core/mesh/types.h"

namespace seam::api {

/// A closed, genus-0, manifold starfish: an icosphere subdivided 4 times (2562 vertices,
/// 5120 faces) displaced radially along five arms in the z = 0 plane and flattened in z.
/// Radial displacement of a sphere keeps it embedded. Deterministic. O(faces).
core::IndexedMesh sample_mesh();

/// The five arm tips of sample_mesh() (vertex indices, arm k at angle 2*pi*k/5).
std::vector<std::uint32_t> sample_tips();

/// sample_mesh() as GLB with smooth vertex normals (NORMAL) and the tips in the node's extras.
/// Errors: write_plain_glb's (kInternal); none are expected for this fixed mesh.
ApiResult<std::string> sample_glb();

}  // namespace seam::api
