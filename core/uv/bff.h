// Boundary First Flattening, free boundary with u = 0 (Sawhney & Crane 2017).
#pragma once

#include <span>
#include <vector>

#include "core/cancel.h"
#include "core/error.h"
#include "core/uv/uv_patch.h"

namespace seam::core {

/// Flattens a disc with the conformal map whose scale factor u is 0 on the boundary, the
/// conformal map of least area distortion (Sawhney & Crane 2017, §4.1 and §5.2 "minimal
/// area distortion"):
/// 1. u_I solves the discrete Yamabe/Poisson problem A_II u_I = -K_I (A: cotan Laplacian,
///    K: interior angle defects), so the interior becomes flat;
/// 2. the target boundary curvature is k~ = k + (A u)_B (k: boundary geodesic curvature),
///    which sums to 2 pi; boundary lengths keep their 3D values (e^u = 1);
/// 3. the boundary polygon is integrated from k~ and closed by the paper's minimal change of
///    lengths (weights 1/l, §4.1.2);
/// 4. both coordinates are extended harmonically into the interior (§4.1.3, the variant that
///    keeps the boundary exactly).
/// Steps 1 and 4 reuse ONE Cholesky factorization of A_II.
/// Returns one UV per local vertex, counter-clockwise, at 3D scale (not yet fitted).
/// `vertex_order`, when not empty, is a fill-reducing order of the patch's vertices (e.g.
/// nested_dissection_order of its vertex graph, shared with SLIM's proxy): A_II is factored in
/// that order restricted to the interior instead of ordering it anew (by AMD). Precondition: empty or a
/// permutation of the patch's vertices.
/// Errors: kInvalidArgument (a vertex_order of another size), kSolverFailed, kCancelled. Complexity: one sparse
/// Cholesky of A_II plus 3 solves.
Result<std::vector<Vec2>> flatten_bff(const DiscPatch& patch, const CancelToken& cancel,
                                      std::span<const int> vertex_order = {});

}  // namespace seam::core
