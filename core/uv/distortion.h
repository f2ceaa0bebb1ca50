// Distortion of a map given as triangles with 3D and 2D corners (the engine behind
// measure_distortion, also used on single charts).
#pragma once

#include <span>

#include "core/uv/parameterize.h"
#include "core/mesh/types.h"

namespace seam::core {

/// Closed-form SVD of a 2x2 matrix: j = Rot(u) diag(s1, s2) Rot(v) with s1 = |Q| + |R| >= |s2|,
/// s2 = |Q| - |R| signed (negative iff det j < 0), where Q = [e -h; h e] and R = [f g; g -f]
/// are j's rotation-scale and reflection-scale parts. The angles come as unit vectors, no
/// trigonometry: `rotation` = (e, h) / |Q| = (cos, sin) of u + v (the closest rotation to j is
/// Rot(u + v)), `reflection` = (f, g) / |R| = (cos, sin) of u - v; (1, 0) where the part is 0.
struct Svd2 {
  double s1 = 0;
  double s2 = 0;
  Vec2 rotation = Vec2(1, 0);
  Vec2 reflection = Vec2(1, 0);
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
