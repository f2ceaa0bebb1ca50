// SLIM (symmetric Dirichlet) refinement: isometries are fixed points, the energy only goes
// down, no fold is ever introduced, folded starts fall back to Tutte's embedding, both proxies
// reach the same optimum, and bad arguments and cancellation are typed errors.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "core/uv/bff.h"
#include "core/uv/slim.h"
#include "core/mesh/topology.h"
#include "core/uv/uv_patch.h"
#include "fixture_mesh.h"

using namespace seam::core;
namespace fx = seam::fixtures;

namespace {

DiscPatch patch_of(const fx::Soup& soup) {
  const HalfedgeMesh mesh = fx::build_fixture(soup);
  auto patches = extract_disc_patches(mesh, compute_topology(mesh));
  REQUIRE(patches.ok());
  REQUIRE(patches->size() == 1);
  return std::move(patches->front());
}

/// The unit disc fixture lifted onto the paraboloid z = height (1 - x^2 - y^2): a curved cap
/// that no map flattens isometrically.
fx::Soup dome(double height) {
  fx::Soup s = fx::disc(10, 32);
  for (Vec3& p : s.positions) p.z() = height * (1 - p.x() * p.x() - p.y() * p.y());
  return s;
}

std::vector<Vec2> bff_start(const DiscPatch& patch) {
  auto uv = flatten_bff(patch, CancelToken::none());
  REQUIRE(uv.ok());
  return std::move(uv).value();
}

}  // namespace

TEST_CASE("an isometric start is a fixed point: a flat disc keeps energy 4") {
  const DiscPatch patch = patch_of(fx::disc(8, 24));
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
  const DiscPatch patch = patch_of(dome(0.8));
  const std::vector<Vec2> start = bff_start(patch);
  REQUIRE(count_flipped(patch, start) == 0);
  double end_energy[2] = {};
  for (SlimProxy proxy : {SlimProxy::kIsotropic, SlimProxy::kAnisotropic}) {
    CAPTURE(static_cast<int>(proxy));
    auto r = flatten_slim(patch, start, {.iterations = 40, .tolerance = 1e-6, .proxy = proxy}, CancelToken::none());
    REQUIRE(r.ok());
    CHECK_FALSE(r->tutte_start);
    CHECK(r->iterations >= 1);
    CHECK(r->energy_end < r->energy_start);
    CHECK(r->energy_end > 4.0);  // a curved cap has no isometric flattening
    CHECK(count_flipped(patch, r->uv) == 0);
    end_energy[static_cast<int>(proxy)] = r->energy_end;
  }
  // Same energy, same optimum: the proxies only change the path there.
  CHECK(end_energy[0] == doctest::Approx(end_energy[1]).epsilon(2e-3));
}

TEST_CASE("more iterations never raise the energy") {
  const DiscPatch patch = patch_of(dome(1.2));
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
  const DiscPatch patch = patch_of(dome(0.8));
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
  const DiscPatch patch = patch_of(fx::disc(1, 3));  // a centre vertex and three rim vertices
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

TEST_CASE("SLIM refuses bad arguments and stops when cancelled") {
  const DiscPatch patch = patch_of(dome(0.8));
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
  CancelToken token;
  token.cancel();
  CHECK(flatten_slim(patch, start, {}, token).error().code == ErrorCode::kCancelled);
}
