// Least-squares conformal maps with a free boundary (Lévy, Petitjean, Ray, Maillot 2002).
#pragma once

#include <vector>

#include "core/cancel.h"
#include "core/error.h"
#include "core/uv/uv_patch.h"

namespace seam::core {

/// Flattens a disc by minimising the conformal energy E_D(u) + E_D(v) - Area(u, v)
/// (Desbrun et al.'s form of LSCM: cotan Dirichlet energy minus the signed area, which is a
/// boundary-only term), with two boundary vertices pinned: an approximately farthest pair
/// (two farthest-point sweeps over the boundary). Returns one UV per local vertex, not yet
/// fitted; the map is counter-clockwise like the faces.
/// Errors: kSolverFailed (the factorization failed), kCancelled.
/// Complexity: one sparse Cholesky (LL^T) of a 2n x 2n matrix (about O(n^1.5) on surface meshes).
Result<std::vector<Vec2>> flatten_lscm(const DiscPatch& patch, const CancelToken& cancel);

/// The two boundary vertices (local ids) that LSCM pins: farthest from boundary[0], then the
/// boundary vertex farthest from that one. O(boundary).
std::array<std::uint32_t, 2> boundary_far_pair(const DiscPatch& patch);

}  // namespace seam::core
