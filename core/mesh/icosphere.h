// The unit icosphere: the seamd sample's body and the test fixtures' closed genus-0 mesh.
#pragma once

#include "core/mesh/types.h"

namespace seam::core {

/// The icosahedron (12 vertices, 20 counter-clockwise faces seen from outside) subdivided
/// `levels` times (each triangle into four at its edges' midpoints), every vertex on the unit
/// sphere: 10 * 4^levels + 2 vertices, 20 * 4^levels faces. Deterministic vertex order: the
/// icosahedron's, then each level's midpoints in order of first use. O(faces log faces).
IndexedMesh icosphere(int levels);

}  // namespace seam::core
