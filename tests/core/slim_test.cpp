// SLIM (symmetric Dirichlet) refinement: isometries are fixed points, the energy only goes
// down, no fold is ever introduced, folded starts fall back to Tutte's embedding, both proxies
// reach the same optimum, and bad arguments and cancellation are typed errors.
#include "core/uv/slim.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/atlas/overlap.h"
#include "core/extrema/extrema.h"
#include "core/mesh/cut.h"
#include "core/mesh/topology.h"
#include "core/seam/seam.h"
#include "core/uv/bff.h"
#include "core/uv/collision.h"
#include "core/uv/distortion.h"
#include "core/uv/uv_patch.h"
#include "test_data.h"
#include "uv_fixture.h"

namespace seam_slim_test {

using namespace seam::core;
namespace fx = seam::fixtures;

namespace {

std::vector<Vec2> bff_start(const DiscPatch& patch) {
  auto uv = flatten_bff(patch, CancelToken::none());
  REQUIRE(uv.ok());
  return std::move(uv).value();
}

}  // namespace

TEST_CASE("an isometric start is a fixed point: a flat disc keeps energy 4") {
  const DiscPatch patch = fx::patch_of(fx::disc(8, 24));
  std::vector<Vec2> start(patch.num_vertices());
  for (std::size_t v = 0; v < start.size(); ++v) start[v] = patch.positions[v].head<2>();
  auto r = flatten_slim(patch, start, {}, CancelToken::none());
  REQUIRE(r.ok());
  CHECK(r->energy_start == doctest::Approx(4.0).epsilon(1e-9));
  CHECK(r->energy_end == doctest::Approx(4.0).epsilon(1e-9));
  CHECK_FALSE(r->tutte_start);
  for (std::size_t v = 0; v < start.size(); ++v) CHECK((r->uv[v] - start[v]).norm() < 1e-6);
}

TEST_CASE("on a curved cap the energy goes down, no triangle folds, and both proxies agree") {
  const DiscPatch patch = fx::patch_of(fx::dome(0.8));
  const std::vector<Vec2> start = bff_start(patch);
  REQUIRE(count_flipped(patch, start) == 0);
  double end_energy[2] = {};
  for (SlimProxy proxy : {SlimProxy::kIsotropic, SlimProxy::kAnisotropic}) {
    CAPTURE(static_cast<int>(proxy));
    auto r = flatten_slim(patch, start, {.iterations = 40, .tolerance = 1e-6, .proxy = proxy}, CancelToken::none());
    REQUIRE(r.ok());
    CHECK_FALSE(r->tutte_start);
    CHECK(r->iterations >= 1);
    CHECK(r->factorizations >= r->iterations);  // one per step, plus any retries
    CHECK(r->energy_end < r->energy_start);
    CHECK(r->energy_end > 4.0);  // a curved cap has no isometric flattening
    CHECK(count_flipped(patch, r->uv) == 0);
    end_energy[static_cast<int>(proxy)] = r->energy_end;
  }
  // Same energy, same optimum: the proxies only change the path there.
  CHECK(end_energy[0] == doctest::Approx(end_energy[1]).epsilon(2e-3));
}

TEST_CASE("more iterations never raise the energy") {
  const DiscPatch patch = fx::patch_of(fx::dome(1.2));
  const std::vector<Vec2> start = bff_start(patch);
  double previous = std::numeric_limits<double>::infinity();
  for (int iterations : {0, 1, 2, 4, 8}) {
    CAPTURE(iterations);
    auto r = flatten_slim(patch, start, {.iterations = iterations, .tolerance = 0}, CancelToken::none());
    REQUIRE(r.ok());
    CHECK(r->iterations <= iterations);
    CHECK(r->energy_end <= previous);
    previous = r->energy_end;
  }
}

TEST_CASE("a folded start falls back to Tutte's embedding and ends unfolded") {
  const DiscPatch patch = fx::patch_of(fx::dome(0.8));
  // Mirror half of a good map: the triangles across the mirror line fold.
  std::vector<Vec2> folded = bff_start(patch);
  for (Vec2& p : folded) {
    if (p.x() > 0) p.x() = -p.x();
  }
  REQUIRE(count_flipped(patch, folded) > 0);
  auto r = flatten_slim(patch, folded, {.iterations = 40, .tolerance = 1e-6}, CancelToken::none());
  REQUIRE(r.ok());
  CHECK(r->tutte_start);
  CHECK(std::isfinite(r->energy_start));
  CHECK(count_flipped(patch, r->uv) == 0);
  // From the Tutte start it still reaches the BFF start's optimum.
  auto from_bff = flatten_slim(patch, bff_start(patch), {.iterations = 40, .tolerance = 1e-6}, CancelToken::none());
  REQUIRE(from_bff.ok());
  CHECK(r->energy_end == doctest::Approx(from_bff->energy_end).epsilon(1e-2));
}

TEST_CASE("the injective step bound stops exactly where a triangle degenerates") {
  const DiscPatch patch = fx::patch_of(fx::disc(1, 3));  // a centre vertex and three rim vertices
  std::vector<Vec2> uv(patch.num_vertices());
  for (std::size_t v = 0; v < uv.size(); ++v) uv[v] = patch.positions[v].head<2>();
  // Move only the centre vertex straight at one rim vertex: the two triangles sharing that
  // rim vertex keep positive area until the centre arrives there (t = 1).
  std::vector<Vec2> direction(uv.size(), Vec2::Zero());
  std::size_t centre = 0;
  for (std::size_t v = 0; v < uv.size(); ++v) {
    if (patch.positions[v].head<2>().norm() < 1e-9) centre = v;
  }
  const std::size_t rim = centre == 0 ? 1 : 0;
  direction[centre] = uv[rim] - uv[centre];
  // The centre reaches the rim vertex at t = 1; two triangles degenerate there.
  CHECK(max_injective_step(patch, uv, direction) == doctest::Approx(1.0).epsilon(1e-9));
  // Moving everything rigidly never degenerates anything.
  std::vector<Vec2> shift(uv.size(), Vec2(3, -2));
  CHECK(max_injective_step(patch, uv, shift) == std::numeric_limits<double>::infinity());
}

TEST_CASE("a start squeezed by orders of magnitude is recovered on progressive references") {
  // A cup 40 radii deep: BFF's map of it folds, Tutte's squeezes its bottom to singular values
  // of 1e-8 and less, and SLIM's proxy alone finds no descent after a few steps (energy 2.6e14).
  // At 20 radii (BFF's start squeezed to 2e-9, unfolded) SLIM alone recovers, and no
  // progressive round runs.
  const DiscPatch patch = fx::patch_of(fx::cup(0.1, 4.0));
  const std::vector<Vec2> start = bff_start(patch);
  // The smallest singular value over the triangles (0 where one folds or degenerates).
  auto smallest = [&](const std::vector<Vec2>& uv) {
    double s = std::numeric_limits<double>::infinity();
    for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
      const auto& tri = patch.triangles[t];
      const auto j = triangle_jacobian(patch.positions[tri[0]], patch.positions[tri[1]], patch.positions[tri[2]],
                                       uv[tri[0]], uv[tri[1]], uv[tri[2]]);
      s = std::min(s, j.sign > 0 ? j.s2 : 0.0);
    }
    return s;
  };
  auto plain = flatten_slim(patch, start, {.progressive = false}, CancelToken::none());
  auto progressive = flatten_slim(patch, start, {}, CancelToken::none());
  REQUIRE(plain.ok());
  REQUIRE(progressive.ok());
  CHECK(plain->progressive_rounds == 0);
  CHECK(progressive->progressive_rounds > 0);
  CAPTURE(plain->energy_end);
  CAPTURE(progressive->energy_end);
  CHECK(smallest(plain->uv) < 1e-6);  // still squeezed: SLIM alone stalls
  CHECK(smallest(progressive->uv) > 1e-3);
  CHECK(progressive->energy_end < 1e-6 * plain->energy_end);
  CHECK(progressive->injective);
  // Where SLIM alone recovers (a cup 20 radii deep, its start squeezed to 2e-9), no round runs
  // and the map is the same either way.
  const DiscPatch shallow = fx::patch_of(fx::cup(0.1, 2.0));
  auto alone = flatten_slim(shallow, bff_start(shallow), {}, CancelToken::none());
  auto alone_plain = flatten_slim(shallow, bff_start(shallow), {.progressive = false}, CancelToken::none());
  REQUIRE(alone.ok());
  REQUIRE(alone_plain.ok());
  CHECK(alone->progressive_rounds == 0);
  CHECK(alone->uv == alone_plain->uv);
}

TEST_CASE("a chart its own boundary squeezes is flattened without the collision bounds, for the pack step to cut") {
  // CGAL's cheese (genus 133) cut to one disc: the cut graph through its handles holds most of
  // the chart's vertices, BFF folds, Tutte's start squeezes triangles to 1e-21 of the chart,
  // and with the boundary held apart even the progressive rounds stall (energy 1.7e13 or more).
  const HalfedgeMesh mesh = seam::test_data::load_cgal_halfedge("cheese");
  auto extrema = find_extrema(mesh);  // one: the seam proper is a single edge, the cut graph all else
  REQUIRE(extrema.ok());
  auto seam = compute_seam(mesh, *extrema);
  REQUIRE(seam.ok());
  auto cut = cut_along_edges(mesh, all_cut_edges(*seam));
  REQUIRE(cut.ok());
  auto patches = extract_disc_patches(cut->mesh, compute_topology(cut->mesh));
  REQUIRE(patches.ok());
  REQUIRE(patches->size() == 1);
  const DiscPatch& patch = patches->front();
  const std::vector<Vec2> start = bff_start(patch);
  auto plain = flatten_slim(patch, start, {.progressive = false}, CancelToken::none());
  auto given_up = flatten_slim(patch, start, {}, CancelToken::none());
  REQUIRE(plain.ok());
  REQUIRE(given_up.ok());
  CHECK(plain->tutte_start);
  CHECK(plain->injective);
  CHECK(plain->energy_end > 1e12);
  // Fold-free and near isometric, but its boundary may now cross itself: not injective.
  CHECK(given_up->progressive_rounds > 0);
  CHECK(given_up->energy_end < 10);
  CHECK_FALSE(given_up->injective);
  for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
    const auto& tri = patch.triangles[t];
    const auto j = triangle_jacobian(patch.positions[tri[0]], patch.positions[tri[1]], patch.positions[tri[2]],
                                     given_up->uv[tri[0]], given_up->uv[tri[1]], given_up->uv[tri[2]]);
    CHECK(j.sign > 0);
  }
}

TEST_CASE("SLIM refuses bad arguments and stops when cancelled") {
  const DiscPatch patch = fx::patch_of(fx::dome(0.8));
  const std::vector<Vec2> start = bff_start(patch);
  CHECK(flatten_slim(patch, {Vec2(0, 0)}, {}, CancelToken::none()).error().code == ErrorCode::kInvalidArgument);
  CHECK(flatten_slim(patch, start, {.iterations = -1}, CancelToken::none()).error().code ==
        ErrorCode::kInvalidArgument);
  CHECK(flatten_slim(patch, start, {.iterations = 1001}, CancelToken::none()).error().code ==
        ErrorCode::kInvalidArgument);
  CHECK(flatten_slim(patch, start, {.tolerance = 2}, CancelToken::none()).error().code ==
        ErrorCode::kInvalidArgument);
  CHECK(flatten_slim(patch, start, {.tolerance = std::nan("")}, CancelToken::none()).error().code ==
        ErrorCode::kInvalidArgument);
  const std::vector<int> short_order(patch.num_vertices() - 1, 0);
  CHECK(flatten_slim(patch, start, {.vertex_order = short_order}, CancelToken::none()).error().code ==
        ErrorCode::kInvalidArgument);
  CancelToken token;
  token.cancel();
  CHECK(flatten_slim(patch, start, {}, token).error().code == ErrorCode::kCancelled);
}

TEST_CASE("SLIM's proxy in a given vertex order takes the same steps as in its own") {
  const DiscPatch patch = fx::patch_of(fx::dome(0.8));
  const std::vector<Vec2> start = bff_start(patch);
  std::vector<int> reversed(patch.num_vertices());
  for (std::size_t v = 0; v < reversed.size(); ++v) reversed[v] = static_cast<int>(reversed.size() - 1 - v);
  for (SlimProxy proxy : {SlimProxy::kIsotropic, SlimProxy::kAnisotropic}) {
    CAPTURE(static_cast<int>(proxy));
    auto own = flatten_slim(patch, start, {.iterations = 10, .tolerance = 0, .proxy = proxy}, CancelToken::none());
    auto ordered =
        flatten_slim(patch, start, {.iterations = 10, .tolerance = 0, .proxy = proxy, .vertex_order = reversed},
                     CancelToken::none());
    REQUIRE(own.ok());
    REQUIRE(ordered.ok());
    CHECK(ordered->iterations == own->iterations);
    CHECK(ordered->energy_end == doctest::Approx(own->energy_end).epsilon(1e-9));
    double worst = 0;
    for (std::size_t v = 0; v < own->uv.size(); ++v) worst = std::max(worst, (ordered->uv[v] - own->uv[v]).norm());
    CHECK(worst < 1e-7);
  }
}

namespace {

/// A flat strip of n x 2 quads (3D: [0, n/4] x [0, 1/2]) whose given UV start bends it around
/// the origin through `turn` radians: fold-free, but past 2 pi its boundary crosses itself.
struct BentStrip {
  DiscPatch patch;
  std::vector<Vec2> start;
};

BentStrip bent_strip(int n, double turn) {
  fx::Soup s;
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= 2; ++j) s.positions.emplace_back(0.25 * i, 0.25 * j, 0.0);
  }
  auto id = [](int i, int j) { return static_cast<std::uint32_t>(3 * i + j); };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < 2; ++j) {
      s.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      s.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  BentStrip b{fx::patch_of(s), {}};
  b.start.resize(b.patch.num_vertices());
  for (std::size_t v = 0; v < b.start.size(); ++v) {
    const Vec3& p = b.patch.positions[v];
    // Across the strip towards the centre (radius 1.5 down to 1), along it counter-clockwise:
    // positive orientation.
    const double a = turn * p.x() / (0.25 * n);
    const double r = 1.5 - p.y();
    b.start[v] = Vec2(r * std::cos(a), r * std::sin(a));
  }
  return b;
}

}  // namespace

TEST_CASE("an overlapping fold-free start is restarted from Tutte and the result is injective") {
  BentStrip b = bent_strip(40, 2.6 * std::numbers::pi);
  REQUIRE(count_flipped(b.patch, b.start) == 0);
  REQUIRE_FALSE(boundary_is_simple(b.patch, b.start));
  auto start_overlap = find_overlaps(b.start, b.patch.triangles);
  REQUIRE(start_overlap.ok());
  REQUIRE(start_overlap->overlaps);

  auto r = flatten_slim(b.patch, b.start, {}, CancelToken::none());
  REQUIRE(r.ok());
  CHECK(r->overlapping_start);
  CHECK(r->tutte_start);
  CHECK(r->injective);
  CHECK(count_flipped(b.patch, r->uv) == 0);
  auto end_overlap = find_overlaps(r->uv, b.patch.triangles);
  REQUIRE(end_overlap.ok());
  CHECK_FALSE(end_overlap->overlaps);
  // The strip is flat: SLIM unbends it towards the isometry.
  CHECK(r->energy_end < 4.2);

  // Without injectivity, the start is kept (it has no fold) and the result may overlap.
  auto loose = flatten_slim(b.patch, b.start, {.injective = false}, CancelToken::none());
  REQUIRE(loose.ok());
  CHECK_FALSE(loose->overlapping_start);
  CHECK_FALSE(loose->tutte_start);
}

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

TEST_CASE("a chart whose boundary keeps touching itself stops within the step budget, injective") {
  // CGAL's elephant cut by Sheffer's MST seam: BFF's map overlaps itself (Tutte start), and on
  // the way to the optimum the trunk and legs run into each other, so most steps are
  // contact-limited. Each such step costs its one factorization (the contacts are solved with
  // it, not re-factored), the budget is the Tutte start's, not extended, and the window of
  // contact-limited gains ends the descent before it; the map stays injective and its energy
  // near the fold-free (overlapping) optimum's.
  const HalfedgeMesh cut = fx::cut_along_seam(seam::test_data::load_cgal_halfedge("elephant"), SeamMethod::kMst);
  auto patches = extract_disc_patches(cut, compute_topology(cut));
  REQUIRE(patches.ok());
  REQUIRE(patches->size() == 1);
  const DiscPatch& patch = patches->front();
  std::vector<Vec2> start = bff_start(patch);
  repair_flips(patch, start);
  const SlimOptions options;
  auto r = flatten_slim(patch, start, options, CancelToken::none());
  REQUIRE(r.ok());
  CHECK(r->collision_limited_steps > 0);
  CHECK(r->contact_solves > 0);
  const int budget = (r->tutte_start ? 3 : 1) * options.iterations;
  CHECK(r->iterations < budget);
  // The contacts are solved with each step's factor: no spring re-solve on this chart (at
  // most one retry with capped weights), and no step needs the springs-only fallback.
  CHECK(r->factorizations <= r->iterations + 1);
  CHECK(r->spring_fallbacks == 0);
  CHECK(r->injective);
  CHECK(count_flipped(patch, r->uv) == 0);
  CHECK(boundary_is_simple(patch, r->uv));
  auto overlap = find_overlaps(r->uv, patch.triangles);
  REQUIRE(overlap.ok());
  CHECK_FALSE(overlap->overlaps);
  auto loose = flatten_slim(patch, start, {.injective = false}, CancelToken::none());
  REQUIRE(loose.ok());
  auto loose_overlap = find_overlaps(loose->uv, patch.triangles);
  REQUIRE(loose_overlap.ok());
  CHECK(loose_overlap->overlaps);
  CHECK(r->energy_end <= 1.02 * loose->energy_end);
}

TEST_CASE("contacts beyond the solve budget are held by springs in every round, and the descent goes on") {
  // The elephant's MST chart of the test above, with the smallest contact budget: the vertices
  // of most colliding pairs are held by springs, and a step's later rounds meet new ones.
  // Zeroing those later vertices' motion without springs and a re-solve (as before) lets their
  // neighbours degenerate within the step; on camel x64's coarse chart the descent stopped at
  // energy 5.99 instead of 4.4 (slim.cpp, add_contacts). Now every such round adds springs and
  // solves again, and the descent ends near the default budget's energy.
  const HalfedgeMesh cut = fx::cut_along_seam(seam::test_data::load_cgal_halfedge("elephant"), SeamMethod::kMst);
  auto patches = extract_disc_patches(cut, compute_topology(cut));
  REQUIRE(patches.ok());
  const DiscPatch& patch = patches->front();
  std::vector<Vec2> start = bff_start(patch);
  repair_flips(patch, start);
  auto usual = flatten_slim(patch, start, {}, CancelToken::none());
  auto springs = flatten_slim(patch, start, {.contact_solves = 0}, CancelToken::none());
  REQUIRE(usual.ok());
  REQUIRE(springs.ok());
  CHECK(springs->collision_limited_steps > 0);
  // Some step held new vertices in more than one round (before, springs came once per step:
  // 17 spring rounds in 17 contact-limited steps, energy 4.2609; now 23 in 18, 4.2586).
  CHECK(springs->spring_rounds > springs->collision_limited_steps);
  CHECK(springs->energy_end <= 1.02 * usual->energy_end);
  CHECK(springs->injective);
  CHECK(count_flipped(patch, springs->uv) == 0);
  CHECK(boundary_is_simple(patch, springs->uv));
  CHECK_FALSE(flatten_slim(patch, start, {.contact_solves = -1}, CancelToken::none()).ok());
}

}  // namespace seam_slim_test
