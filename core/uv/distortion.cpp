#include "core/uv/distortion.h"

#include <algorithm>
#include <cmath>

namespace seam::core {

namespace {

// |(x, y)|. Squeezed charts reach entries of 1e-170, whose squares underflow, so the plain
// square root is taken only where the sum of squares is far from both ends of the range
// (then the smaller square, if it underflows, is below the larger one's rounding); hypot's
// rescaling, which costs several times as much, everywhere else.
double norm_2d(double x, double y) {
  const double s = x * x + y * y;
  if (s > 0x1p-960 && s < 0x1p960) return std::sqrt(s);
  return std::hypot(x, y);
}

}  // namespace

Svd2 svd_2x2(const Eigen::Matrix2d& j) {
  // j = [a b; c d] = Q + R with Q = [e -h; h e] (rotation-scale) and R = [f g; g -f]
  // (reflection-scale); |Q| and |R| give the singular values, their directions the rotations.
  const double e = 0.5 * (j(0, 0) + j(1, 1));
  const double f = 0.5 * (j(0, 0) - j(1, 1));
  const double g = 0.5 * (j(1, 0) + j(0, 1));
  const double h = 0.5 * (j(1, 0) - j(0, 1));
  const double q = norm_2d(e, h);
  const double r = norm_2d(f, g);
  return {.s1 = q + r,
          .s2 = q - r,
          .rotation = q > 0 ? Vec2(e / q, h / q) : Vec2(1, 0),
          .reflection = r > 0 ? Vec2(f / r, g / r) : Vec2(1, 0)};
}

TriangleJacobian triangle_jacobian(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec2& q0, const Vec2& q1,
                                   const Vec2& q2) {
  const Vec3 e1 = p1 - p0;
  const Vec3 e2 = p2 - p0;
  const double l1 = e1.norm();
  const Vec3 n = e1.cross(e2);
  const double twice_area = n.norm();
  TriangleJacobian out;
  if (l1 <= 0 || twice_area <= 0) return out;
  // 3D triangle in an isometric frame of its plane: (0,0), (l1,0), (x2,y2) with y2 > 0.
  const double x2 = e2.dot(e1) / l1;
  const double y2 = twice_area / l1;
  Eigen::Matrix2d source;
  source << l1, x2, 0, y2;
  Eigen::Matrix2d target;
  target.col(0) = q1 - q0;
  target.col(1) = q2 - q0;
  const Eigen::Matrix2d j = target * source.inverse();
  const Svd2 svd = svd_2x2(j);
  out.s1 = svd.s1;
  out.s2 = std::abs(svd.s2);
  out.sign = j.determinant() > 0 ? 1.0 : -1.0;
  return out;
}

Distortion measure_distortion(std::span<const Vec3> positions, std::span<const Triangle> triangles,
                              std::span<const Vec2> uv) {
  Distortion d;
  double area_3d = 0;
  double area_2d = 0;
  for (const Triangle& t : triangles) {
    area_3d += 0.5 * (positions[t[1]] - positions[t[0]]).cross(positions[t[2]] - positions[t[0]]).norm();
    const Vec2 a = uv[t[1]] - uv[t[0]];
    const Vec2 b = uv[t[2]] - uv[t[0]];
    const double signed_area = 0.5 * (a.x() * b.y() - a.y() * b.x());
    area_2d += std::abs(signed_area);
    if (!(signed_area > 0)) ++d.flipped;
  }
  if (!(area_3d > 0) || !(area_2d > 0)) {
    if (!(area_2d > 0)) {
      d.area = d.area_geometric = d.angle = d.stretch_l2 = d.stretch_linf = kDistortionCap;
    }
    return d;
  }
  // Uniform scale c so that the UV area equals the 3D area: singular values scale by c.
  const double scale = std::sqrt(area_3d / area_2d);
  double sum_area = 0;
  double sum_log = 0;
  double sum_angle = 0;
  double sum_l2 = 0;
  double linf = 0;
  for (const Triangle& t : triangles) {
    const Vec3& p0 = positions[t[0]];
    const double w = 0.5 * (positions[t[1]] - p0).cross(positions[t[2]] - p0).norm();
    if (!(w > 0)) continue;
    const TriangleJacobian jac = triangle_jacobian(p0, positions[t[1]], positions[t[2]], uv[t[0]], uv[t[1]], uv[t[2]]);
    const double s1 = scale * jac.s1;
    const double s2 = scale * jac.s2;
    const double det = s1 * s2;
    const double cap = kDistortionCap;
    const double area_term = det > 0 ? std::min(std::max(det, 1.0 / det), cap) : cap;
    const double log_term = det > 0 ? std::min(std::abs(std::log(det)), std::log(cap)) : std::log(cap);
    const double angle_term = s2 > 0 ? std::min(s1 / s2, cap) : cap;
    // Sander's stretch measures the texture->surface map, whose singular values are 1/s2 >= 1/s1.
    const double inv1 = s1 > 0 ? std::min(1.0 / s1, cap) : cap;
    const double inv2 = s2 > 0 ? std::min(1.0 / s2, cap) : cap;
    sum_area += w * area_term;
    sum_log += w * log_term;
    sum_angle += w * angle_term;
    sum_l2 += w * 0.5 * (inv1 * inv1 + inv2 * inv2);
    linf = std::max(linf, inv2);
  }
  d.area = sum_area / area_3d;
  d.area_geometric = std::exp(sum_log / area_3d);
  d.angle = sum_angle / area_3d;
  d.stretch_l2 = std::sqrt(sum_l2 / area_3d);
  d.stretch_linf = linf;
  return d;
}

Distortion measure_distortion(const HalfedgeMesh& mesh, const VertexData<Vec2>& uv) {
  SEAM_ASSERT(uv.size() == mesh.num_vertices());
  const std::vector<Triangle> triangles = mesh.triangles();
  return measure_distortion(mesh.positions(), triangles, uv.raw());
}

}  // namespace seam::core
