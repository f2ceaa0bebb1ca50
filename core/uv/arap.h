// As-rigid-as-possible parameterization: local/global iterations (Liu, Zhang, Xu, Gotsman,
// Gortler 2008, "A Local/Global Approach to Mesh Parameterization", §3 ARAP).
#pragma once

#include <vector>

#include "core/cancel.h"
#include "core/error.h"
#include "core/uv/uv_patch.h"

namespace seam::core {

/// Improves `initial` (one UV per local vertex, at 3D scale, e.g. BFF's map) by `iterations`
/// ARAP local/global steps: local = per triangle the rotation closest to its Jacobian (closed
/// form in 2D), global = one solve with the cotan Laplacian (free boundary, local vertex 0
/// pinned), factored once. Returns the final UVs.
/// Errors: kInvalidArgument (initial.size() != patch vertices), kSolverFailed, kCancelled.
/// Complexity: one sparse Cholesky plus `iterations` x (O(F) + 2 triangular solves).
Result<std::vector<Vec2>> flatten_arap(const DiscPatch& patch, std::vector<Vec2> initial, int iterations,
                                       const CancelToken& cancel);

}  // namespace seam::core
