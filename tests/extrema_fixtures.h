// Generated shapes with a known set of protrusion tips, for the extrema tests and benchmark.
// Shapes are implicit (signed distance to unions of capsules, spheres and ellipsoids) and
// triangulated by marching tetrahedra, so the grid step gives genuinely different meshes of
// the same shape ("remeshed"), and rotation, scaling and 1-to-4 subdivision are applied to
// the result. Header-only, like tests/fixtures.h.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <numbers>
#include <unordered_map>
#include <vector>

#include "fixtures.h"

namespace seam::fixtures {

/// A shape and the points where its protrusions end (the expected extrema).
struct ShapeWithTips {
  Soup soup;
  std::vector<Vec3> tips;
};

/// Signed distance to the capsule of radius r around segment [a, b] (negative inside).
inline double capsule_distance(const Vec3& p, const Vec3& a, const Vec3& b, double r) {
  const Vec3 ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (p - (a + t * ab)).norm() - r;
}

/// Approximate signed distance to an axis-aligned ellipsoid with semi-axes `radii` at c
/// (exact on the axes; the sign is exact everywhere, which is all marching needs).
inline double ellipsoid_distance(const Vec3& p, const Vec3& c, const Vec3& radii) {
  const Vec3 q = (p - c).cwiseQuotient(radii);
  const double k0 = q.norm();
  const double k1 = (p - c).cwiseQuotient(radii.cwiseProduct(radii)).norm();
  return k1 > 0 ? k0 * (k0 - 1.0) / k1 : -radii.minCoeff();
}

/// Polynomial smooth minimum (blend width k): fillets where parts join, as on real models.
inline double smooth_union(double a, double b, double k) {
  const double h = std::max(k - std::abs(a - b), 0.0) / k;
  return std::min(a, b) - h * h * k / 4.0;
}

/// Triangulates the zero level set of `sdf` (negative inside) on the grid of step `cell`
/// over [lo, hi] by marching tetrahedra on the Kuhn (Freudenthal) split of every cube into 6
/// tetrahedra, which is a consistent simplicial complex: one vertex per crossed grid edge,
/// shared by all tetrahedra on that edge, so the surface is a closed oriented 2-manifold
/// provided it stays inside the box. Triangles face outward (toward positive sdf).
inline Soup marching_tetrahedra(const std::function<double(const Vec3&)>& sdf, const Vec3& lo, const Vec3& hi,
                                double cell) {
  const int nx = static_cast<int>(std::ceil((hi.x() - lo.x()) / cell)) + 1;
  const int ny = static_cast<int>(std::ceil((hi.y() - lo.y()) / cell)) + 1;
  const int nz = static_cast<int>(std::ceil((hi.z() - lo.z()) / cell)) + 1;
  auto node = [&](int i, int j, int k) { return (static_cast<std::int64_t>(k) * ny + j) * nx + i; };
  auto point = [&](std::int64_t id) {
    const auto i = static_cast<double>(id % nx);
    const auto j = static_cast<double>((id / nx) % ny);
    const auto k = static_cast<double>(id / (static_cast<std::int64_t>(nx) * ny));
    return Vec3(lo.x() + i * cell, lo.y() + j * cell, lo.z() + k * cell);
  };
  std::vector<double> value(static_cast<std::size_t>(nx) * ny * nz);
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        double v = sdf(point(node(i, j, k)));
        if (v == 0.0) v = 1e-12;  // no vertex exactly on the surface: keeps the complex manifold
        value[static_cast<std::size_t>(node(i, j, k))] = v;
      }
    }
  }
  Soup s;
  std::unordered_map<std::int64_t, std::uint32_t> edge_vertex;
  const std::int64_t num_nodes = static_cast<std::int64_t>(value.size());
  auto crossing = [&](std::int64_t a, std::int64_t b) {
    if (a > b) std::swap(a, b);
    const auto [it, inserted] = edge_vertex.try_emplace(a * num_nodes + b, static_cast<std::uint32_t>(s.positions.size()));
    if (inserted) {
      const double fa = value[static_cast<std::size_t>(a)];
      const double fb = value[static_cast<std::size_t>(b)];
      // Clamped away from the grid nodes so that no triangle collapses to zero area.
      const double t = std::clamp(fa / (fa - fb), 1e-3, 1.0 - 1e-3);
      s.positions.push_back(point(a) + t * (point(b) - point(a)));
    }
    return it->second;
  };
  auto emit = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c, const Vec3& outward) {
    const Vec3 n = (s.positions[b] - s.positions[a]).cross(s.positions[c] - s.positions[a]);
    if (n.dot(outward) >= 0) {
      s.triangles.push_back({a, b, c});
    } else {
      s.triangles.push_back({a, c, b});
    }
  };
  static constexpr std::array<std::array<int, 3>, 6> kPermutations = {
      {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
  for (int k = 0; k + 1 < nz; ++k) {
    for (int j = 0; j + 1 < ny; ++j) {
      for (int i = 0; i + 1 < nx; ++i) {
        for (const auto& perm : kPermutations) {
          std::array<std::int64_t, 4> tet;
          int c[3] = {i, j, k};
          tet[0] = node(c[0], c[1], c[2]);
          for (int step = 0; step < 3; ++step) {
            ++c[perm[step]];
            tet[step + 1] = node(c[0], c[1], c[2]);
          }
          std::array<std::int64_t, 4> in{}, out{};
          int n_in = 0, n_out = 0;
          for (auto t : tet) (value[static_cast<std::size_t>(t)] < 0 ? in[n_in++] : out[n_out++]) = t;
          if (n_in == 0 || n_out == 0) continue;
          Vec3 outward = Vec3::Zero();
          for (int q = 0; q < n_out; ++q) outward += point(out[q]) / n_out;
          for (int q = 0; q < n_in; ++q) outward -= point(in[q]) / n_in;
          if (n_in == 1) {
            emit(crossing(in[0], out[0]), crossing(in[0], out[1]), crossing(in[0], out[2]), outward);
          } else if (n_out == 1) {
            emit(crossing(out[0], in[0]), crossing(out[0], in[1]), crossing(out[0], in[2]), outward);
          } else {  // a quad: in[0]-out[0], in[0]-out[1], in[1]-out[1], in[1]-out[0] in cyclic order
            const std::uint32_t q0 = crossing(in[0], out[0]), q1 = crossing(in[0], out[1]);
            const std::uint32_t q2 = crossing(in[1], out[1]), q3 = crossing(in[1], out[0]);
            emit(q0, q1, q2, outward);
            emit(q0, q2, q3, outward);
          }
        }
      }
    }
  }
  return s;
}

/// A unit sphere with thin spikes (capsules of radius 0.12) along `directions` with the
/// given lengths beyond the surface, blended in with a small fillet. `cell` is the grid step.
inline ShapeWithTips spiky_ball(const std::vector<Vec3>& directions, const std::vector<double>& lengths,
                                double cell = 0.06) {
  constexpr double kRadius = 0.12;
  ShapeWithTips shape;
  double reach = 1.0;
  for (std::size_t i = 0; i < directions.size(); ++i) {
    shape.tips.push_back(directions[i].normalized() * (1.0 + lengths[i] + kRadius));
    reach = std::max(reach, 1.0 + lengths[i] + kRadius);
  }
  auto sdf = [&](const Vec3& p) {
    double d = p.norm() - 1.0;
    for (std::size_t i = 0; i < directions.size(); ++i) {
      const Vec3 u = directions[i].normalized();
      d = smooth_union(d, capsule_distance(p, 0.8 * u, (1.0 + lengths[i]) * u, kRadius), 0.15);
    }
    return d;
  };
  // The grid is offset by a fraction of a cell so no grid plane is a symmetry plane.
  const Vec3 pad = Vec3::Constant(reach + 3 * cell + 0.0137);
  shape.soup = marching_tetrahedra(sdf, -pad, pad, cell);
  return shape;
}

/// The spiky ball of the tests: six spikes of different lengths in irregular directions.
/// `with_bump` adds a seventh, 0.08 long, a wart that is not a protrusion.
inline ShapeWithTips six_spike_ball(double cell = 0.06, bool with_bump = false) {
  std::vector<Vec3> dirs = {Vec3(0, 0, 1),        Vec3(0.9, 0.1, -0.3), Vec3(-0.5, 0.8, 0.1),
                            Vec3(-0.6, -0.7, 0.3), Vec3(0.2, -0.3, -0.9), Vec3(-0.3, 0.1, -0.6)};
  std::vector<double> lengths = {1.2, 1.0, 0.9, 1.1, 0.8, 1.3};
  if (with_bump) {
    dirs.emplace_back(0.6, 0.6, 0.6);
    lengths.push_back(0.08);
  }
  auto shape = spiky_ball(dirs, lengths, cell);
  if (with_bump) shape.tips.pop_back();  // the wart is not an expected tip
  return shape;
}

/// A "hand" of cylinders on a palm: a flat ellipsoidal palm (2 x 2.2 x 0.7), four fingers and
/// a thumb (capsules of radius 0.16-0.18, lengths 1.0-1.5) and a wrist stub of radius 0.35.
/// Six tips: the fingertips, the thumb tip, and the end of the wrist.
inline ShapeWithTips capsule_hand(double cell = 0.05) {
  struct Part {
    Vec3 a, b;
    double r;
  };
  const double s20 = std::sin(std::numbers::pi / 9), c20 = std::cos(std::numbers::pi / 9);
  const std::vector<Part> parts = {
      {Vec3(-0.6, 0.7, 0), Vec3(-0.6, 2.0, 0), 0.16},  {Vec3(-0.2, 0.8, 0), Vec3(-0.2, 2.3, 0), 0.17},
      {Vec3(0.2, 0.8, 0), Vec3(0.2, 2.2, 0), 0.17},    {Vec3(0.6, 0.7, 0), Vec3(0.6, 1.8, 0), 0.16},
      {Vec3(0.7, -0.2, 0), Vec3(0.7 + 1.1 * c20, -0.2 + 1.1 * s20, 0), 0.18},
      {Vec3(0, -0.7, 0), Vec3(0, -2.1, 0), 0.35}};
  ShapeWithTips shape;
  for (const auto& part : parts) shape.tips.push_back(part.b + part.r * (part.b - part.a).normalized());
  auto sdf = [&](const Vec3& p) {
    double d = ellipsoid_distance(p, Vec3::Zero(), Vec3(1.0, 1.1, 0.35));
    for (const auto& part : parts) d = smooth_union(d, capsule_distance(p, part.a, part.b, part.r), 0.1);
    return d;
  };
  const Vec3 lo(-1.3, -2.7, -0.7), hi(2.2, 2.8, 0.7);
  const Vec3 offset = Vec3::Constant(0.0113);
  shape.soup = marching_tetrahedra(sdf, lo - offset, hi + offset, cell);
  return shape;
}

/// The rotation of `angle` radians about `axis`.
inline Eigen::Matrix3d rotation(const Vec3& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

/// The shape moved rigidly (p -> R p + t) and scaled uniformly about the origin first.
inline ShapeWithTips transformed(ShapeWithTips shape, const Eigen::Matrix3d& rot, double scale, const Vec3& t) {
  for (auto& p : shape.soup.positions) p = rot * (scale * p) + t;
  for (auto& p : shape.tips) p = rot * (scale * p) + t;
  return shape;
}

/// 1-to-4 midpoint subdivision (no smoothing): the same surface with four times the faces.
inline Soup subdivided(const Soup& in) {
  Soup s;
  s.positions = in.positions;
  s.triangles.reserve(4 * in.triangles.size());
  std::unordered_map<std::uint64_t, std::uint32_t> midpoint;
  midpoint.reserve(3 * in.triangles.size() / 2);
  auto mid = [&](std::uint32_t a, std::uint32_t b) {
    const std::uint64_t key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
    const auto [it, inserted] = midpoint.try_emplace(key, static_cast<std::uint32_t>(s.positions.size()));
    if (inserted) s.positions.push_back(0.5 * (in.positions[a] + in.positions[b]));
    return it->second;
  };
  for (const auto& t : in.triangles) {
    const std::uint32_t ab = mid(t[0], t[1]), bc = mid(t[1], t[2]), ca = mid(t[2], t[0]);
    s.triangles.push_back({t[0], ab, ca});
    s.triangles.push_back({t[1], bc, ab});
    s.triangles.push_back({t[2], ca, bc});
    s.triangles.push_back({ab, bc, ca});
  }
  return s;
}

}  // namespace seam::fixtures
