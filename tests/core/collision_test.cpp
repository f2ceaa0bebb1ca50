// The collision step bound (Smith & Schaefer's vertex-edge contact times) and the boundary
// simplicity test: exact contacts, the gap and the cases fuzzing found (F16, F18), every
// colliding pair of a crowded chart against a brute-force scan, and boundary_is_simple against
// exact integer segment tests on small grids (touching, collinear and folded-back edges).
#include "core/uv/collision.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

#include "uv_fixture.h"

namespace seam_collision_test {

using namespace seam::core;
namespace fx = seam::fixtures;

TEST_CASE("the collision step bound stops a boundary vertex exactly at the edge it would cross") {
  // A flat square fan: boundary 0-1-2-3, centre 4. Move boundary vertex 2 straight down across
  // the opposite side through the square; the contact with edge (0, 1) on y = 0 is at t = 1.
  fx::Soup s;
  s.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0), Vec3(0.5, 0.5, 0)};
  s.triangles = {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
  const DiscPatch patch = fx::patch_of(s);
  std::vector<Vec2> uv(patch.num_vertices());
  std::vector<Vec2> dir(patch.num_vertices(), Vec2::Zero());
  std::uint32_t moving = 0;
  for (std::size_t v = 0; v < uv.size(); ++v) {
    uv[v] = patch.positions[v].head<2>();
    if (uv[v] == Vec2(1, 1)) moving = static_cast<std::uint32_t>(v);
  }
  CHECK(boundary_is_simple(patch, uv));
  dir[moving] = Vec2(-0.25, -1);  // reaches (0.75, 0) on edge (0,0)-(1,0) at t = 1
  const CollisionStep c = max_collision_free_step(patch, uv, dir, 5.0);
  CHECK(c.limited);
  CHECK(c.step == doctest::Approx(1.0));
  CHECK(std::find(c.colliding.begin(), c.colliding.end(), moving) != c.colliding.end());
  // Within a shorter horizon nothing collides.
  const CollisionStep short_step = max_collision_free_step(patch, uv, dir, 0.5);
  CHECK_FALSE(short_step.limited);
  CHECK(short_step.step == 0.5);
  // Moved past the contact, the boundary is no longer simple.
  uv[moving] += 1.5 * dir[moving];
  CHECK_FALSE(boundary_is_simple(patch, uv));
}

TEST_CASE("a boundary vertex within the gap that first moves away still may not cross a turning edge") {
  // F16 (mesh_fuzz): a spike's vertex sat within the gap of a boundary edge and moved away from
  // it at first order, while the edge turned towards it; the bound took such a pair for safe,
  // the vertex crossed the edge and the default map overlapped itself. Here edge a-b turns
  // about a (b moves by (-0.5, 1)) and vertex p, 0.001 above it (the gap is 0.01), rises by
  // 0.7: its signed distance 0.001 + 0.0995 t - 0.35 t^2 first grows, then crosses 0.
  DiscPatch patch;
  patch.positions.assign(5, Vec3::Zero());
  patch.boundary = {0, 1, 2, 3, 4};  // a, b, x, p, y: edge (a, b) faces p across the slot
  const std::vector<Vec2> uv = {Vec2(0, 0), Vec2(1, 0), Vec2(1.2, 0.5), Vec2(0.6, 0.001), Vec2(-0.2, 0.5)};
  std::vector<Vec2> dir(5, Vec2::Zero());
  dir[1] = Vec2(-0.5, 1);
  dir[3] = Vec2(0, 0.7);
  // The oracle: p's signed distance to line (a, b) along the step, by bisection on its sign.
  auto side = [&](double t) { return cross2(uv[0] + t * dir[0], uv[1] + t * dir[1], uv[3] + t * dir[3]); };
  REQUIRE(side(0) > 0);
  REQUIRE(side(0.05) > side(0));  // moving away first
  REQUIRE(side(1) < 0);
  double lo = 0.05, hi = 1;
  for (int i = 0; i < 60; ++i) (side(0.5 * (lo + hi)) > 0 ? lo : hi) = 0.5 * (lo + hi);
  const double crossing = lo;  // about 0.2940
  const CollisionStep c = max_collision_free_step(patch, uv, dir, 1.0, 0.01);
  const auto pair = std::find_if(c.contacts.begin(), c.contacts.end(),
                                 [](const auto& k) { return k.vertex == 3 && k.a == 0 && k.b == 1; });
  REQUIRE(pair != c.contacts.end());
  CHECK(pair->time < crossing);
  CHECK(side(pair->time) == doctest::Approx(0.5 * side(0)));  // no closer than half its distance
  CHECK(c.step <= pair->time);
  // Without the gap the pair is bounded at the crossing itself.
  const CollisionStep bare = max_collision_free_step(patch, uv, dir, 1.0, 0.0);
  const auto bare_pair = std::find_if(bare.contacts.begin(), bare.contacts.end(),
                                      [](const auto& k) { return k.vertex == 3 && k.a == 0 && k.b == 1; });
  REQUIRE(bare_pair != bare.contacts.end());
  CHECK(bare_pair->time == doctest::Approx(crossing).epsilon(1e-9));
}

TEST_CASE("a boundary vertex that passes around an edge's end and comes back across it is bounded") {
  // F18 (mesh_fuzz): SLIM's first step from a Tutte start on a 19-vertex strip (every vertex on
  // the boundary). Vertex p starts 3.25 from the line of edge (a, b) beyond a's end, crosses
  // that line off the segment at t = 0.058, and comes back across the segment itself from the
  // far side at t = 0.5823. Only the near side's gap line was solved, whose second root fell
  // 2e-4 after the step bound of 0.58237: the step was taken and the map overlapped itself.
  DiscPatch patch;
  patch.positions.assign(5, Vec3::Zero());
  patch.boundary = {0, 1, 2, 3, 4};  // a, b, x, p, y
  const std::vector<Vec2> uv = {Vec2(99.870545676252192, 18.130941133958594), Vec2(95.025721851380425, 35.678692614774),
                                Vec2(300, 300), Vec2(101.50298971003488, 0), Vec2(300, -300)};
  std::vector<Vec2> dir(5, Vec2::Zero());
  dir[0] = Vec2(-32.406708895038484, -87.25080727449226);
  dir[1] = Vec2(16.401902564265736, -104.65371105923592);
  dir[3] = Vec2(-26.921488415971542, -53.505669595132517);
  const double t_max = 0.58236792743333854;
  auto at = [&](std::size_t v, double t) { return Vec2(uv[v] + t * dir[v]); };
  auto side = [&](double t) { return cross2(at(0, t), at(1, t), at(3, t)); };
  auto along = [&](double t) {
    const Vec2 e = at(1, t) - at(0, t);
    return (at(3, t) - at(0, t)).dot(e) / e.squaredNorm();
  };
  REQUIRE(side(0) > 0);
  REQUIRE(side(0.3) < 0);  // across the line, but beyond a's end
  REQUIRE(along(0.3) < 0);
  REQUIRE(side(t_max) > 0);  // back across the line, on the segment this time
  REQUIRE(along(t_max) > 0);
  REQUIRE(along(t_max) < 1);
  double lo = 0.3, hi = t_max;
  for (int i = 0; i < 60; ++i) (side(0.5 * (lo + hi)) < 0 ? lo : hi) = 0.5 * (lo + hi);
  const double crossing = lo;  // about 0.58227
  for (const double gap : {0.0, 0.01}) {
    CAPTURE(gap);
    const CollisionStep c = max_collision_free_step(patch, uv, dir, t_max, gap);
    const auto pair = std::find_if(c.contacts.begin(), c.contacts.end(),
                                   [](const auto& k) { return k.vertex == 3 && k.a == 0 && k.b == 1; });
    REQUIRE(pair != c.contacts.end());
    CHECK(c.limited);
    CHECK(c.step <= pair->time);
    if (gap == 0) CHECK(pair->time == doctest::Approx(crossing).epsilon(1e-9));
    if (gap > 0) CHECK(pair->time < crossing);
  }
}

TEST_CASE("the collision step bound finds every colliding vertex-edge pair that a brute-force scan finds") {
  // A fan disc with a 240-gon boundary on a wobbly circle and every boundary vertex pushed
  // across the disc by a pseudo-random step: hundreds of crossings, many per grid cell. The
  // oracle samples each pair's signed distance along the step (independent of the quadratic)
  // and bisects the first sign change with the vertex over the edge.
  const std::size_t nb = 240;
  fx::Soup s;
  for (std::size_t i = 0; i < nb; ++i) {
    const double a = 2 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(nb);
    const double r = 1 + 0.2 * std::sin(7 * a);
    s.positions.emplace_back(r * std::cos(a), r * std::sin(a), 0);
  }
  s.positions.emplace_back(0, 0, 0);
  for (std::uint32_t i = 0; i < nb; ++i) {
    s.triangles.push_back({i, static_cast<std::uint32_t>((i + 1) % nb), static_cast<std::uint32_t>(nb)});
  }
  const DiscPatch patch = fx::patch_of(s);
  REQUIRE(patch.boundary.size() == nb);
  std::vector<Vec2> uv(patch.num_vertices());
  std::vector<Vec2> dir(patch.num_vertices(), Vec2::Zero());
  for (std::size_t v = 0; v < uv.size(); ++v) {
    uv[v] = patch.positions[v].head<2>();
    const double k = static_cast<double>(v);
    dir[v] = Vec2(std::sin(12.9898 * k) * 0.9, std::cos(78.233 * k) * 0.9);
  }
  const double t_max = 1.0;
  const CollisionStep c = max_collision_free_step(patch, uv, dir, t_max);
  // The oracle: per pair, the first t on a fine grid where cross(b - a, p - a) changes sign
  // with p between a and b, refined by bisection.
  // Plain doubles rather than Eigen: the scan evaluates this 2e8 times, and the sanitizer build
  // (-Og) ran Eigen's expressions 85x slower than Release (93 s).
  auto cross_at = [&](std::uint32_t p, std::uint32_t a, std::uint32_t b, double t) {
    const double ax = uv[a].x() + t * dir[a].x(), ay = uv[a].y() + t * dir[a].y();
    const double ex = uv[b].x() + t * dir[b].x() - ax, ey = uv[b].y() + t * dir[b].y() - ay;
    const double qx = uv[p].x() + t * dir[p].x() - ax, qy = uv[p].y() + t * dir[p].y() - ay;
    const double ee = ex * ex + ey * ey;
    return std::pair(ex * qy - ey * qx, ee > 0 ? (qx * ex + qy * ey) / ee : -1.0);
  };
  std::size_t expected_pairs = 0;
  double expected_step = t_max;
  std::vector<std::array<std::uint32_t, 3>> expected;
  const int samples = 4000;
  for (std::size_t i = 0; i < nb; ++i) {
    for (std::size_t e = 0; e < nb; ++e) {
      const std::size_t e1 = (e + 1) % nb;
      if (i == e || i == e1) continue;
      const std::uint32_t p = patch.boundary[i], a = patch.boundary[e], b = patch.boundary[e1];
      double previous = cross_at(p, a, b, 0).first;
      for (int k = 1; k <= samples; ++k) {
        const double t = t_max * k / samples;
        const double now = cross_at(p, a, b, t).first;
        if ((previous < 0) != (now < 0)) {
          double lo = t_max * (k - 1) / samples, hi = t;
          for (int it = 0; it < 60; ++it) {
            const double mid = 0.5 * (lo + hi);
            ((cross_at(p, a, b, mid).first < 0) == (previous < 0) ? lo : hi) = mid;
          }
          const double along = cross_at(p, a, b, hi).second;
          if (along >= 0 && along <= 1) {
            ++expected_pairs;
            expected_step = std::min(expected_step, hi);
            expected.push_back({p, a, b});
            break;
          }
        }
        previous = now;
      }
    }
  }
  REQUIRE(expected_pairs > 100);
  CHECK(c.limited);
  CHECK(c.step == doctest::Approx(expected_step).epsilon(1e-6));
  std::vector<std::array<std::uint32_t, 3>> found;
  for (const auto& k : c.contacts) found.push_back({k.vertex, k.a, k.b});
  std::sort(found.begin(), found.end());
  std::sort(expected.begin(), expected.end());
  CHECK(found == expected);
  CHECK(c.candidate_pairs >= found.size());
  CHECK(c.candidate_pairs < nb * (nb - 2));  // the grid tested a part of the pairs
}

namespace {

// The oracle for boundary_is_simple, in exact integer arithmetic: a closed polygon on integer
// points is simple when no two non-adjacent edges share a point and no two adjacent edges run
// back over each other (collinear with their far ends on the same side of the shared vertex).
using P = std::array<std::int64_t, 2>;

int orientation(const P& a, const P& b, const P& c) {
  const std::int64_t d = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
  return (d > 0) - (d < 0);
}

bool within_box(const P& a, const P& b, const P& p) {
  return std::min(a[0], b[0]) <= p[0] && p[0] <= std::max(a[0], b[0]) && std::min(a[1], b[1]) <= p[1] &&
         p[1] <= std::max(a[1], b[1]);
}

bool closed_segments_meet(const P& a, const P& b, const P& c, const P& d) {
  const int o1 = orientation(a, b, c), o2 = orientation(a, b, d);
  const int o3 = orientation(c, d, a), o4 = orientation(c, d, b);
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;
  return (o1 == 0 && within_box(a, b, c)) || (o2 == 0 && within_box(a, b, d)) || (o3 == 0 && within_box(c, d, a)) ||
         (o4 == 0 && within_box(c, d, b));
}

bool simple_by_scan(const std::vector<P>& loop) {
  const std::size_t n = loop.size();
  for (std::size_t i = 0; i < n; ++i) {
    const P& a = loop[i];
    const P& shared = loop[(i + 1) % n];
    const P& c = loop[(i + 2) % n];
    const std::int64_t dot = (a[0] - shared[0]) * (c[0] - shared[0]) + (a[1] - shared[1]) * (c[1] - shared[1]);
    if (orientation(a, shared, c) == 0 && dot > 0) return false;  // folds back over its neighbour
    for (std::size_t j = i + 2; j < n; ++j) {
      if ((j + 1) % n == i) continue;  // adjacent through the loop's closing edge
      if (closed_segments_meet(a, shared, loop[j], loop[(j + 1) % n])) return false;
    }
  }
  return true;
}

}  // namespace

TEST_CASE("boundary_is_simple agrees with exact integer segment tests on small grids") {
  // Random closed polygons on a 9 x 9 grid: vertical and horizontal edges (boxes of zero
  // width, which the grid of boxes must still pair), edges that touch at a vertex or overlap
  // collinearly, polygons that pass through a vertex of their own, and flat triangles (with
  // three edges every pair is adjacent, so only the fold-back test sees them). No two
  // consecutive vertices coincide. The same polygons shifted and scaled by powers of two stay
  // exact.
  std::mt19937 rng(2026);
  std::uniform_int_distribution<std::int64_t> coord(-4, 4);
  std::uniform_int_distribution<std::size_t> size(3, 14);
  int simple = 0, not_simple = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    std::vector<P> loop;
    const std::size_t n = size(rng);
    while (loop.size() < n) {
      const P p{coord(rng), coord(rng)};
      if (!loop.empty() && p == loop.back()) continue;
      if (loop.size() + 1 == n && p == loop.front()) continue;
      loop.push_back(p);
    }
    // Half the trials: a star-shaped polygon (the points sorted by angle about the origin and
    // thinned to distinct angles), which is mostly simple, so both answers are well covered.
    if (trial % 2 == 1) {
      std::sort(loop.begin(), loop.end(), [](const P& a, const P& b) {
        return std::atan2(static_cast<double>(a[1]), static_cast<double>(a[0])) <
               std::atan2(static_cast<double>(b[1]), static_cast<double>(b[0]));
      });
      loop.erase(std::unique(loop.begin(), loop.end()), loop.end());
      if (loop.size() < 3 || loop.front() == loop.back()) continue;
    }
    const bool expected = simple_by_scan(loop);
    (expected ? simple : not_simple) += 1;
    DiscPatch patch;
    patch.positions.assign(loop.size(), Vec3::Zero());
    // The loop in a shuffled vertex numbering: boundary order, not vertex order, matters.
    std::vector<std::uint32_t> ids(loop.size());
    for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<std::uint32_t>(i);
    std::shuffle(ids.begin(), ids.end(), rng);
    patch.boundary = ids;
    for (const auto& [scale, shift] : {std::pair(1.0, 0.0), std::pair(0.0078125, 1024.0)}) {
      std::vector<Vec2> uv(loop.size());
      for (std::size_t i = 0; i < loop.size(); ++i) {
        uv[ids[i]] =
            Vec2(static_cast<double>(loop[i][0]) * scale + shift, static_cast<double>(loop[i][1]) * scale - shift);
      }
      CAPTURE(trial);
      CAPTURE(scale);
      CHECK(boundary_is_simple(patch, uv) == expected);
    }
  }
  CHECK(simple > 2000);
  CHECK(not_simple > 2000);
}

}  // namespace seam_collision_test
