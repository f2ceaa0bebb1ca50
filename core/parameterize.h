// Flattening the cut disc(s) into the plane, and the distortion of the result.
#pragma once

#include <cstddef>

#include "core/cancel.h"
#include "core/error.h"
#include "core/halfedge_mesh.h"

namespace seam::core {

enum class UvMethod {
  kLscm,  ///< least-squares conformal maps, free boundary (Lévy et al. 2002)
  kBff,   ///< Boundary First Flattening, free boundary with u = 0 (Sawhney & Crane 2017)
  kArap,  ///< as-rigid-as-possible local/global iterations started from BFF (Liu et al. 2008)
};

struct UvOptions {
  UvMethod method = UvMethod::kBff;
  /// ARAP only: local/global iterations.
  int arap_iterations = 10;
};

/// Distortion of a 3D->2D map, per triangle from the singular values s1 >= s2 of its
/// Jacobian after one global scale normalisation (total 2D area = total 3D area).
struct Distortion {
  double area = 1;            ///< area-weighted mean of max(s1 s2, 1/(s1 s2))
  double area_geometric = 1;  ///< exp(area-weighted mean of |log(s1 s2)|)
  double angle = 1;           ///< area-weighted mean of s1/s2
  double stretch_l2 = 1;      ///< Sander et al.'s L2 stretch
  double stretch_linf = 1;    ///< Sander et al.'s L-infinity stretch (max s1)
  std::size_t flipped = 0;    ///< triangles with non-positive signed UV area
};

struct UvResult {
  VertexData<Vec2> uv;  ///< per vertex of the disc mesh, fitted into [0,1]^2 (aspect kept)
  Distortion distortion;
  double solve_ms = 0;
};

/// Flattens every component of `disc_mesh` (each must be a topological disc; several are
/// packed side by side without overlap) and measures the distortion.
/// Errors: kTopologyViolation (a component is not a disc), kSolverFailed, kCancelled.
Result<UvResult> parameterize(const HalfedgeMesh& disc_mesh, const UvOptions& options = {},
                              const CancelToken& cancel = CancelToken::none());

/// Measures the distortion of a given per-vertex UV map. O(F).
Distortion measure_distortion(const HalfedgeMesh& mesh, const VertexData<Vec2>& uv);

}  // namespace seam::core
