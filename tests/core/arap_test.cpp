// ARAP local/global (Liu et al. 2008, §3) from a given start: the ARAP energy, computed here
// from each triangle's Jacobian and its closest rotation (an SVD), never rises from one
// iteration to the next and ends below the start; no triangle flips when the start had none; a
// flat disc started at a rigid copy of itself is a fixed point, and from a stretched copy it
// returns to an isometry; the result follows a rigid motion of the start; bad input and
// cancellation are typed errors.
#include "core/uv/arap.h"

#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <vector>

#include "core/uv/bff.h"
#include "uv_fixture.h"

namespace seam_arap_test {

using namespace seam::core;
namespace fx = seam::fixtures;

namespace {

// Sum over triangles of area * |J - R|_F^2: J the Jacobian of the map from the triangle's own
// plane to the UV plane, R the rotation closest to J (from J's SVD, with the sign fixed so R is
// a rotation even where J reflects).
double arap_energy(const DiscPatch& patch, const std::vector<Vec2>& uv) {
  double energy = 0;
  for (const Triangle& t : patch.triangles) {
    const Vec3 e1 = patch.positions[t[1]] - patch.positions[t[0]];
    const Vec3 e2 = patch.positions[t[2]] - patch.positions[t[0]];
    const Vec3 normal = e1.cross(e2);
    const Vec3 bx = e1.normalized();
    const Vec3 by = normal.cross(e1).normalized();
    Eigen::Matrix2d x;  // the edges in an orthonormal frame of the triangle's plane, as columns
    x << e1.dot(bx), e2.dot(bx), e1.dot(by), e2.dot(by);
    Eigen::Matrix2d u;
    u.col(0) = uv[t[1]] - uv[t[0]];
    u.col(1) = uv[t[2]] - uv[t[0]];
    const Eigen::Matrix2d j = u * x.inverse();
    const Eigen::JacobiSVD<Eigen::Matrix2d> svd(j, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix2d sign = Eigen::Matrix2d::Identity();
    if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0) sign(1, 1) = -1;
    const Eigen::Matrix2d r = svd.matrixU() * sign * svd.matrixV().transpose();
    energy += 0.5 * normal.norm() * (j - r).squaredNorm();
  }
  return energy;
}

double signed_area(const std::vector<Vec2>& uv, const Triangle& t) {
  const Vec2 a = uv[t[1]] - uv[t[0]];
  const Vec2 b = uv[t[2]] - uv[t[0]];
  return 0.5 * (a.x() * b.y() - a.y() * b.x());
}

std::size_t flipped(const DiscPatch& patch, const std::vector<Vec2>& uv) {
  std::size_t count = 0;
  for (const Triangle& t : patch.triangles) count += signed_area(uv, t) <= 0 ? 1 : 0;
  return count;
}

// The patch's (x, y) coordinates, each put through the affine map p -> a p + b.
std::vector<Vec2> planar_start(const DiscPatch& patch, const Eigen::Matrix2d& a, const Vec2& b) {
  std::vector<Vec2> uv;
  for (const Vec3& p : patch.positions) uv.push_back(a * p.head<2>() + b);
  return uv;
}

Eigen::Matrix2d rotation(double angle) {
  Eigen::Matrix2d r;
  r << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
  return r;
}

std::vector<Vec2> run(const DiscPatch& patch, const std::vector<Vec2>& start, int iterations) {
  auto uv = flatten_arap(patch, start, iterations, CancelToken::none());
  REQUIRE_MESSAGE(uv.ok(), (uv.ok() ? "" : uv.error().message));
  REQUIRE(uv->size() == patch.num_vertices());
  return std::move(uv).value();
}

// Runs 1, 2, ... `max_iterations` iterations from `start` and checks the energy after each is
// no higher than after the one before (local/global descent), and no triangle is flipped if
// the start had none. Returns the energy after the last.
double check_descent(const DiscPatch& patch, const std::vector<Vec2>& start, int max_iterations) {
  const bool start_unfolded = flipped(patch, start) == 0;
  double previous = arap_energy(patch, start);
  for (int k = 1; k <= max_iterations; k = k < 4 ? k + 1 : 2 * k) {
    CAPTURE(k);
    const std::vector<Vec2> uv = run(patch, start, k);
    const double energy = arap_energy(patch, uv);
    CHECK(energy <= previous * (1 + 1e-9) + 1e-14);
    if (start_unfolded) CHECK(flipped(patch, uv) == 0);
    previous = energy;
  }
  return previous;
}

}  // namespace

TEST_CASE("arap: a flat disc started at a rotated, shifted copy of itself is a fixed point") {
  const DiscPatch patch = fx::patch_of(fx::jittered_disc());
  const std::vector<Vec2> start = planar_start(patch, rotation(0.7), Vec2(3, -2));
  REQUIRE(arap_energy(patch, start) < 1e-20);
  const std::vector<Vec2> uv = run(patch, start, 10);
  double moved = 0;
  for (std::size_t v = 0; v < uv.size(); ++v) moved = std::max(moved, (uv[v] - start[v]).norm());
  CHECK(moved < 1e-9);
  CHECK(fx::max_edge_length_error(patch, uv) < 1e-9);
  CHECK(flipped(patch, uv) == 0);
}

TEST_CASE("arap: a flat disc started from a stretched copy descends back to an isometry") {
  // The planar disc has an energy-0 embedding (itself), which ARAP's descent must approach
  // from an anisotropic stretch; the result is then rigid up to rotation and translation.
  const DiscPatch patch = fx::patch_of(fx::jittered_disc(5, 16));
  Eigen::Matrix2d stretch;
  stretch << 1.5, 0.2, 0.0, 0.7;
  const std::vector<Vec2> start = planar_start(patch, stretch, Vec2(0.5, 0.5));
  const double start_energy = arap_energy(patch, start);
  REQUIRE(start_energy > 0.01);
  const double final_energy = check_descent(patch, start, 256);
  CHECK(final_energy < 1e-6 * start_energy);
  const std::vector<Vec2> uv = run(patch, start, 256);
  CHECK(fx::max_edge_length_error(patch, uv) < 1e-3);
}

TEST_CASE("arap: from BFF on a curved cap the energy never rises and ends lower, with no flips") {
  const DiscPatch patch = fx::patch_of(fx::dome(0.6, 10, 32));
  auto bff = flatten_bff(patch, CancelToken::none());
  REQUIRE(bff.ok());
  REQUIRE(flipped(patch, *bff) == 0);
  const double start_energy = arap_energy(patch, *bff);
  const double final_energy = check_descent(patch, *bff, 32);
  // BFF is conformal, not rigid, on a cap: ARAP has something to gain.
  CHECK(final_energy < start_energy);
}

TEST_CASE("arap: a strongly distorted but unfolded start never flips a triangle") {
  // A tall dome seen from above: near its rim the projection squashes triangles to a sliver
  // of their 3D width, far from the rotations ARAP pulls towards.
  {
    const DiscPatch patch = fx::patch_of(fx::dome(2.0, 8, 24));
    const std::vector<Vec2> start = planar_start(patch, Eigen::Matrix2d::Identity(), Vec2::Zero());
    REQUIRE(flipped(patch, start) == 0);
    CHECK(check_descent(patch, start, 64) < arap_energy(patch, start));
  }
  // A sharp cone (a coarse disc with its centre lifted 10 radii) started from its projection
  // stretched 100:1: an unrestricted global step folds triangles here, so this exercises the
  // step bound that keeps every triangle positive.
  {
    fx::Soup cone = fx::disc(3, 5);
    cone.positions[0].z() = 10.0;
    const DiscPatch patch = fx::patch_of(cone);
    Eigen::Matrix2d squash;
    squash << 10.0, 0.0, 0.0, 0.1;
    const std::vector<Vec2> start = planar_start(patch, squash, Vec2::Zero());
    REQUIRE(flipped(patch, start) == 0);
    CHECK(check_descent(patch, start, 64) < arap_energy(patch, start));
  }
}

TEST_CASE("arap: moving the start by a rigid motion moves the result by the same motion") {
  const DiscPatch patch = fx::patch_of(fx::dome(0.8, 8, 24));
  auto bff = flatten_bff(patch, CancelToken::none());
  REQUIRE(bff.ok());
  const Eigen::Matrix2d r = rotation(-1.1);
  const Vec2 shift(-4, 7.5);
  std::vector<Vec2> moved_start;
  for (const Vec2& p : *bff) moved_start.push_back(r * p + shift);
  const std::vector<Vec2> uv = run(patch, *bff, 8);
  const std::vector<Vec2> moved = run(patch, moved_start, 8);
  double worst = 0;
  for (std::size_t v = 0; v < uv.size(); ++v) worst = std::max(worst, (moved[v] - (r * uv[v] + shift)).norm());
  CHECK(worst < 1e-9);
  CHECK(arap_energy(patch, moved) == doctest::Approx(arap_energy(patch, uv)).epsilon(1e-9));
}

TEST_CASE("arap: zero iterations return the start unchanged") {
  const DiscPatch patch = fx::patch_of(fx::dome(0.6, 4, 12));
  const std::vector<Vec2> start = planar_start(patch, Eigen::Matrix2d::Identity() * 2.0, Vec2(1, 1));
  CHECK(run(patch, start, 0) == start);
}

TEST_CASE("arap: a start with another number of UVs than vertices is kInvalidArgument") {
  const DiscPatch patch = fx::patch_of(fx::dome(0.6, 4, 12));
  const std::vector<Vec2> good = planar_start(patch, Eigen::Matrix2d::Identity(), Vec2::Zero());
  std::vector<Vec2> short_by_one(good.begin(), good.end() - 1);
  std::vector<Vec2> long_by_one = good;
  long_by_one.push_back(Vec2::Zero());
  for (const std::vector<Vec2>* start : {&short_by_one, &long_by_one}) {
    for (int iterations : {0, 5}) {
      auto uv = flatten_arap(patch, *start, iterations, CancelToken::none());
      REQUIRE_FALSE(uv.ok());
      CHECK(uv.error().code == ErrorCode::kInvalidArgument);
    }
  }
  auto empty = flatten_arap(patch, {}, 5, CancelToken::none());
  REQUIRE_FALSE(empty.ok());
  CHECK(empty.error().code == ErrorCode::kInvalidArgument);
}

TEST_CASE("arap: a patch whose Laplacian is singular or a non-finite start is kSolverFailed") {
  // A vertex in no triangle has an empty row in the cotan Laplacian: not positive definite.
  DiscPatch patch = fx::patch_of(fx::dome(0.6, 4, 12));
  const std::vector<Vec2> start = planar_start(patch, Eigen::Matrix2d::Identity(), Vec2::Zero());
  {
    DiscPatch with_isolated = patch;
    with_isolated.positions.push_back(Vec3(5, 5, 5));
    with_isolated.to_mesh.push_back(VertexId::invalid());
    std::vector<Vec2> longer = start;
    longer.push_back(Vec2(5, 5));
    auto uv = flatten_arap(with_isolated, longer, 3, CancelToken::none());
    REQUIRE_FALSE(uv.ok());
    CHECK(uv.error().code == ErrorCode::kSolverFailed);
  }
  // A NaN in the start makes the global step non-finite.
  std::vector<Vec2> nan_start = start;
  nan_start[nan_start.size() / 2].x() = std::numeric_limits<double>::quiet_NaN();
  auto uv = flatten_arap(patch, nan_start, 3, CancelToken::none());
  REQUIRE_FALSE(uv.ok());
  CHECK(uv.error().code == ErrorCode::kSolverFailed);
}

TEST_CASE("arap: stops with kCancelled when cancelled") {
  fx::check_stops_when_cancelled([](const DiscPatch& patch, const CancelToken& token) {
    return flatten_arap(patch, planar_start(patch, Eigen::Matrix2d::Identity(), Vec2::Zero()), 10, token);
  });
}

}  // namespace seam_arap_test
