// Checking that a cut opens every component into a disc without building the cut mesh.
#pragma once

#include <span>

#include "core/error.h"
#include "core/mesh/halfedge_mesh.h"

namespace seam::core {

/// Returns Ok when cutting `mesh` along `edges` (as cut_along_edges would) leaves every
/// connected component a topological disc, without building the cut mesh: components are
/// faces joined across uncut interior edges, vertices are wedges, a cut interior edge counts
/// twice, and a connected surface with Euler characteristic 1 is a disc (2 - 2g - b = 1 forces
/// g = 0, b = 1). Same answer as check_is_disc(cut_along_edges(mesh, edges)->mesh).
/// Errors: kInvalidArgument (edge out of range), kTopologyViolation (a component is not a disc,
/// or a cut edge cannot open: a slit). O(V + E + F) time, O(H) memory.
Status check_cut_is_disc(const HalfedgeMesh& mesh, std::span<const EdgeId> edges);

}  // namespace seam::core
