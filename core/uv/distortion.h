// Distortion of a map given as triangles with 3D and 2D corners (the engine behind
// measure_distortion, also used on single charts).
#pragma once

#include <span>

#include "core/uv/parameterize.h"
#include "core/mesh/types.h"

namespace seam::core {

/// Closed-form SVD of a 2x2 matrix: j = Rot(u_angle) diag(s1, s2) Rot(v_angle) with
/// s1 = |Q| + |R| >= |s2|, s2 = |Q| - |R| signed (negative iff det j < 0), where Q and R are
/// j's rotation and reflection parts. The closest rotation to j is Rot(u_angle + v_angle).
struct Svd2 {
  double s1 = 0;
  double s2 = 0;
  double u_angle = 0;
  double v_angle = 0;
};
Svd2 svd_2x2(const Eigen::Matrix2d& j);

/// Singular values s1 >= s2 >= 0 of the Jacobian of the affine map taking the 3D triangle
/// (p0, p1, p2) to the UV triangle (q0, q1, q2), and the sign of its determinant (+1, or -1
/// for a flipped or degenerate UV triangle). A zero-area 3D triangle gives s1 = s2 = 0.
struct TriangleJacobian {
  double s1 = 0;
  double s2 = 0;
  double sign = 1;
};
TriangleJacobian triangle_jacobian(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec2& q0, const Vec2& q1,
                                   const Vec2& q2);

/// The Distortion of `uv` over `triangles` (indices into positions and uv). O(F).
Distortion measure_distortion(std::span<const Vec3> positions, std::span<const Triangle> triangles,
                              std::span<const Vec2> uv);

}  // namespace seam::core
