// Test-side discs for the flattening suites (bff, lscm, slim): fixture soups made into one
// DiscPatch, a curved cap, a planar disc with irregular triangles, and the corner angles of a
// UV triangle computed from scratch (the oracle for conformality).
#pragma once

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/extrema/extrema.h"
#include "core/mesh/cut.h"
#include "core/mesh/topology.h"
#include "core/seam/seam.h"
#include "core/uv/uv_patch.h"
#include "fixture_mesh.h"

namespace seam::fixtures {

/// The one disc of a fixture soup, failing the test if the soup is not exactly one disc.
inline core::DiscPatch patch_of(const Soup& soup) {
  const core::HalfedgeMesh mesh = build_fixture(soup);
  auto patches = core::extract_disc_patches(mesh, core::compute_topology(mesh));
  REQUIRE(patches.ok());
  REQUIRE(patches->size() == 1);
  return std::move(patches->front());
}

/// `mesh` cut open along its seam by `method` through its automatic extrema, failing the test
/// if a step fails.
inline core::HalfedgeMesh cut_along_seam(const core::HalfedgeMesh& mesh,
                                         core::SeamMethod method = core::SeamMethod::kSkeleton) {
  auto extrema = core::find_extrema(mesh);
  REQUIRE(extrema.ok());
  REQUIRE(extrema->size() >= 2);
  auto seam = core::compute_seam(mesh, *extrema, {.method = method});
  REQUIRE(seam.ok());
  auto cut = core::cut_along_edges(mesh, core::all_cut_edges(*seam));
  REQUIRE(cut.ok());
  return std::move(cut->mesh);
}

/// The unit disc fixture lifted onto the paraboloid z = height (1 - x^2 - y^2): a curved cap
/// that no map flattens isometrically.
inline Soup dome(double height, int rings = 10, int sectors = 32) {
  Soup s = disc(rings, sectors);
  for (core::Vec3& p : s.positions) p.z() = height * (1 - p.x() * p.x() - p.y() * p.y());
  return s;
}

/// The flat unit disc fixture with one interior edge AB split by a cap: a new vertex M at the
/// middle of AB, `gap` x |AB| off it towards the apex C of the triangle (C, A, B), which becomes
/// (C, A, M), (C, M, B) and the cap (A, B, M) (angle at M near pi, at A and B near 0). A, B
/// and M are interior vertices. Scanned and remeshed assets carry such caps (CGAL's
/// triceratops: angles of 179.9996 degrees).
inline Soup capped_disc(double gap, int rings = 6, int sectors = 16) {
  Soup s = disc(rings, sectors);
  // The band between rings 2 and 3 (of 6): C = (2, 0), A = (3, 0), B = (3, 1).
  const std::uint32_t c = 1 + sectors, a = 1 + 2 * sectors, b = a + 1;
  const std::array<std::uint32_t, 3> split = {c, a, b};
  const auto it = std::find(s.triangles.begin(), s.triangles.end(), split);
  REQUIRE(it != s.triangles.end());
  const Vec3 middle = 0.5 * (s.positions[a] + s.positions[b]);
  const Vec3 towards_c = (s.positions[c] - middle).normalized();
  const auto m = static_cast<std::uint32_t>(s.positions.size());
  s.positions.push_back(middle + gap * (s.positions[b] - s.positions[a]).norm() * towards_c);
  *it = {c, a, m};
  s.triangles.push_back({c, m, b});
  s.triangles.push_back({a, b, m});
  return s;
}

/// A cup: a tube of radius `radius` and length `length` along -z, open at z = 0 and closed by a
/// fan at the bottom. A disc whose conformal map (BFF's, with u = 0 on the rim) shrinks the
/// bottom by about exp(-length / radius): the start that SLIM alone cannot recover from.
inline Soup cup(double radius, double length, int around = 16, int along = 60) {
  Soup s;
  for (int i = 0; i <= along; ++i) {
    for (int k = 0; k < around; ++k) {
      const double a = 2 * std::numbers::pi * k / around;
      s.positions.emplace_back(radius * std::cos(a), radius * std::sin(a), -length * i / along);
    }
  }
  auto id = [&](int i, int k) { return static_cast<std::uint32_t>(i * around + (k + around) % around); };
  for (int i = 0; i < along; ++i) {
    for (int k = 0; k < around; ++k) {
      s.triangles.push_back({id(i, k), id(i + 1, k), id(i + 1, k + 1)});
      s.triangles.push_back({id(i, k), id(i + 1, k + 1), id(i, k + 1)});
    }
  }
  const auto bottom = static_cast<std::uint32_t>(s.positions.size());
  s.positions.emplace_back(0, 0, -length);
  for (int k = 0; k < around; ++k) s.triangles.push_back({id(along, k + 1), id(along, k), bottom});
  return s;
}

/// The flat unit disc fixture (z = 0) with every interior vertex moved by a fixed pseudo-random
/// offset of up to a fifth of the ring spacing: irregular triangles, still a valid embedding.
inline Soup jittered_disc(int rings = 8, int sectors = 24) {
  Soup s = disc(rings, sectors);
  const double amount = 0.2 / rings;
  for (std::size_t v = 1; v < s.positions.size(); ++v) {
    if (s.positions[v].head<2>().norm() > 1 - 1e-9) continue;  // the boundary ring stays round
    const double a = std::sin(12.9898 * static_cast<double>(v)) * 43758.5453;
    const double b = std::sin(78.233 * static_cast<double>(v)) * 12345.6789;
    s.positions[v].x() += amount * (a - std::floor(a) - 0.5);
    s.positions[v].y() += amount * (b - std::floor(b) - 0.5);
  }
  return s;
}

/// The three corner angles of a triangle given by its corner points (2D or 3D), from the law
/// of cosines.
template <class P>
std::array<double, 3> corner_angles_of(const P& a, const P& b, const P& c) {
  const std::array<P, 3> p = {a, b, c};
  std::array<double, 3> angles{};
  for (int k = 0; k < 3; ++k) {
    const P e1 = p[(k + 1) % 3] - p[k];
    const P e2 = p[(k + 2) % 3] - p[k];
    angles[k] = std::acos(std::clamp(e1.dot(e2) / (e1.norm() * e2.norm()), -1.0, 1.0));
  }
  return angles;
}

// Largest relative difference between an edge's UV length and its 3D length.
inline double max_edge_length_error(const core::DiscPatch& patch, const std::vector<core::Vec2>& uv) {
  double worst = 0;
  for (const core::Triangle& t : patch.triangles) {
    for (int k = 0; k < 3; ++k) {
      const double l3 = (patch.positions[t[(k + 1) % 3]] - patch.positions[t[k]]).norm();
      const double l2 = (uv[t[(k + 1) % 3]] - uv[t[k]]).norm();
      worst = std::max(worst, std::abs(l2 - l3) / l3);
    }
  }
  return worst;
}

/// Mean absolute difference (radians) between the corner angles of each UV triangle and of its
/// 3D triangle: 0 for a conformal map of a planar mesh, small for a conformal flattening.
inline double mean_angle_error(const core::DiscPatch& patch, const std::vector<core::Vec2>& uv) {
  double sum = 0;
  for (const core::Triangle& t : patch.triangles) {
    const auto a3 = corner_angles_of(patch.positions[t[0]], patch.positions[t[1]], patch.positions[t[2]]);
    const auto a2 = corner_angles_of(uv[t[0]], uv[t[1]], uv[t[2]]);
    for (int k = 0; k < 3; ++k) sum += std::abs(a3[k] - a2[k]);
  }
  return sum / (3.0 * static_cast<double>(patch.triangles.size()));
}

/// Checks that flatten(patch, token) on a curved cap with an already cancelled token returns
/// kCancelled (every flattening method polls its token).
template <class Flatten>
void check_stops_when_cancelled(Flatten&& flatten) {
  const core::DiscPatch patch = patch_of(dome(0.6));
  core::CancelToken token;
  token.cancel();
  auto uv = flatten(patch, token);
  REQUIRE_FALSE(uv.ok());
  CHECK(uv.error().code == core::ErrorCode::kCancelled);
}

}  // namespace seam::fixtures
