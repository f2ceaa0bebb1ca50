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
