// The distortion kernel (core/uv/distortion): the closed-form 2x2 SVD against Eigen's
// JacobiSVD (the independent oracle), across the whole range of magnitudes squeezed and
// stretched charts reach, and the per-triangle and per-map measures on maps whose distortion
// is known in closed form.
#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <vector>

#include <Eigen/SVD>

#include "core/uv/distortion.h"

namespace seam_distortion_test {

using namespace seam::core;

namespace {

// Checks svd against JacobiSVD and the factorisation it documents:
// j = Rot(u) diag(s1, s2) Rot(v) with (cos, sin)(u + v) = rotation, (cos, sin)(u - v) = reflection.
void check_svd(const Eigen::Matrix2d& j) {
  CAPTURE(j);
  const Svd2 svd = svd_2x2(j);
  const Eigen::JacobiSVD<Eigen::Matrix2d> oracle(j);
  const double scale = oracle.singularValues()(0);
  CHECK(svd.s1 == doctest::Approx(scale).epsilon(1e-12));
  CHECK(std::abs(svd.s2) == doctest::Approx(oracle.singularValues()(1)).epsilon(1e-12).scale(scale));
  CHECK(svd.s1 >= std::abs(svd.s2));
  const double det = (j / j.cwiseAbs().maxCoeff()).determinant();  // normalised: 1e300^2 overflows
  if (det != 0) CHECK((svd.s2 < 0) == (det < 0));
  CHECK(svd.rotation.norm() == doctest::Approx(1.0));
  CHECK(svd.reflection.norm() == doctest::Approx(1.0));
  // Rebuild j from the parts: Q = |Q| [cos -sin; sin cos](u+v), R = |R| [cos sin; sin -cos](u-v).
  const double q = 0.5 * (svd.s1 + svd.s2);
  const double r = 0.5 * (svd.s1 - svd.s2);
  Eigen::Matrix2d rebuilt;
  rebuilt << q * svd.rotation.x() + r * svd.reflection.x(), -q * svd.rotation.y() + r * svd.reflection.y(),
      q * svd.rotation.y() + r * svd.reflection.y(), q * svd.rotation.x() - r * svd.reflection.x();
  CHECK(((rebuilt - j) / scale).norm() <= 1e-12);  // scaled first: the squares of 1e300 overflow
}

}  // namespace

TEST_CASE("distortion: svd_2x2 matches JacobiSVD on random matrices of every scale") {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> entry(-1.0, 1.0);
  for (double scale : {1.0, 1e-3, 1e3, 1e-150, 1e-170, 1e-300, 1e150, 1e300}) {
    CAPTURE(scale);
    for (int i = 0; i < 200; ++i) {
      Eigen::Matrix2d j;
      j << entry(rng), entry(rng), entry(rng), entry(rng);
      check_svd(scale * j);
    }
  }
}

TEST_CASE("distortion: svd_2x2 on rotations, reflections, shears and zeros") {
  const double c = std::cos(0.7);
  const double s = std::sin(0.7);
  Eigen::Matrix2d rotation;
  rotation << c, -s, s, c;
  const Svd2 r = svd_2x2(3.0 * rotation);
  CHECK(r.s1 == doctest::Approx(3.0));
  CHECK(r.s2 == doctest::Approx(3.0));
  CHECK(r.rotation.x() == doctest::Approx(c));
  CHECK(r.rotation.y() == doctest::Approx(s));
  Eigen::Matrix2d mirror;
  mirror << 1, 0, 0, -1;
  const Svd2 m = svd_2x2(2.0 * mirror);
  CHECK(m.s1 == doctest::Approx(2.0));
  CHECK(m.s2 == doctest::Approx(-2.0));
  check_svd(mirror);
  Eigen::Matrix2d shear;
  shear << 1, 5, 0, 1;
  check_svd(shear);
  // Entries whose squares underflow or overflow alone, mixed with ordinary ones.
  Eigen::Matrix2d mixed;
  mixed << 1e-170, 1.0, -1e-200, 1e-170;
  check_svd(mixed);
  mixed << 1e200, 1e-200, 3e199, -1e200;
  check_svd(mixed);
  const Svd2 zero = svd_2x2(Eigen::Matrix2d::Zero());
  CHECK(zero.s1 == 0);
  CHECK(zero.s2 == 0);
  CHECK(zero.rotation == Vec2(1, 0));
  CHECK(zero.reflection == Vec2(1, 0));
}

TEST_CASE("distortion: triangle_jacobian of isometries, scalings and flips") {
  const Vec3 p0(0, 0, 0), p1(2, 0, 0), p2(0.5, 1.5, 0);
  // A tilted copy of the same triangle in 3D, laid flat: an isometry.
  const Eigen::Matrix3d tilt = Eigen::AngleAxisd(0.9, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const TriangleJacobian iso = triangle_jacobian(tilt * p0, tilt * p1, tilt * p2, Vec2(0, 0), Vec2(2, 0), Vec2(0.5, 1.5));
  CHECK(iso.s1 == doctest::Approx(1.0));
  CHECK(iso.s2 == doctest::Approx(1.0));
  CHECK(iso.sign == 1.0);
  // Stretched 3x along u only.
  const TriangleJacobian stretched = triangle_jacobian(p0, p1, p2, Vec2(0, 0), Vec2(6, 0), Vec2(1.5, 1.5));
  CHECK(stretched.s1 == doctest::Approx(3.0));
  CHECK(stretched.s2 == doctest::Approx(1.0));
  // Mirrored: flipped in the map.
  const TriangleJacobian flipped = triangle_jacobian(p0, p1, p2, Vec2(0, 0), Vec2(2, 0), Vec2(0.5, -1.5));
  CHECK(flipped.sign == -1.0);
  CHECK(flipped.s1 == doctest::Approx(1.0));
  // A degenerate 3D triangle has no Jacobian.
  const TriangleJacobian flat = triangle_jacobian(p0, p1, Vec3(4, 0, 0), Vec2(0, 0), Vec2(1, 0), Vec2(0, 1));
  CHECK(flat.s1 == 0);
  CHECK(flat.s2 == 0);
}

TEST_CASE("distortion: measure_distortion of an isometric, a scaled and a flipped map") {
  const std::vector<Vec3> positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  const std::vector<Triangle> triangles = {{0, 1, 2}, {0, 2, 3}};
  const std::vector<Vec2> same = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const Distortion iso = measure_distortion(positions, triangles, same);
  CHECK(iso.area == doctest::Approx(1.0));
  CHECK(iso.area_geometric == doctest::Approx(1.0));
  CHECK(iso.angle == doctest::Approx(1.0));
  CHECK(iso.flipped == 0);
  // Stretched 2x along u on one triangle only: measures are means over the 3D area.
  const std::vector<Vec2> sheared = {{0, 0}, {2, 0}, {2, 1}, {0, 1}};
  const Distortion d = measure_distortion(positions, triangles, sheared);
  CHECK(d.angle > 1.0);
  CHECK(d.flipped == 0);
  const std::vector<Vec2> mirrored = {{0, 0}, {1, 0}, {1, -1}, {0, 1}};
  CHECK(measure_distortion(positions, triangles, mirrored).flipped == 1);
}

}  // namespace seam_distortion_test
