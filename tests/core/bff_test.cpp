// Boundary First Flattening with u = 0 on the boundary: a planar disc comes back congruent,
// a curved cap is flattened conformally (corner angles kept, the error halving with the mesh
// size) with its boundary lengths kept, counter-clockwise and without folds; cancellation is a typed error.
#include <doctest/doctest.h>

#include <cmath>

#include "core/uv/bff.h"
#include "uv_fixture.h"

namespace seam_bff_test {

using namespace seam::core;
namespace fx = seam::fixtures;

namespace {

double signed_area(const DiscPatch& patch, const std::vector<Vec2>& uv, std::size_t t) {
  const Triangle& tri = patch.triangles[t];
  const Vec2 a = uv[tri[1]] - uv[tri[0]];
  const Vec2 b = uv[tri[2]] - uv[tri[0]];
  return 0.5 * (a.x() * b.y() - a.y() * b.x());
}

}  // namespace

TEST_CASE("BFF returns a planar disc congruent to itself") {
  // Flat: no interior curvature, so u = 0 everywhere and the boundary keeps its turning
  // angles and lengths; the harmonic extension reproduces linear functions exactly.
  const DiscPatch patch = fx::patch_of(fx::jittered_disc());
  auto uv = flatten_bff(patch, CancelToken::none());
  REQUIRE(uv.ok());
  REQUIRE(uv->size() == patch.num_vertices());
  CHECK(fx::max_edge_length_error(patch, *uv) < 1e-9);
  for (std::size_t t = 0; t < patch.triangles.size(); ++t) CHECK(signed_area(patch, *uv, t) > 0);
}

TEST_CASE("BFF flattens a curved cap conformally, better on a finer mesh") {
  double previous_error = 1.0;
  for (int rings : {6, 12, 24}) {
    CAPTURE(rings);
    const DiscPatch patch = fx::patch_of(fx::dome(0.6, rings, 4 * rings));
    auto uv = flatten_bff(patch, CancelToken::none());
    REQUIRE(uv.ok());
    for (std::size_t t = 0; t < patch.triangles.size(); ++t) REQUIRE(signed_area(patch, *uv, t) > 0);
    // Conformal: the corner angles of the 3D triangles survive (up to discretization), while
    // the lengths do not (the cap does not unroll isometrically).
    const double angle_error = fx::mean_angle_error(patch, *uv);
    CHECK(angle_error < 0.05);
    CHECK(angle_error < 0.6 * previous_error);  // first order: halves as the mesh is halved
    previous_error = angle_error;
    CHECK(fx::max_edge_length_error(patch, *uv) > 0.05);
    // u = 0 on the boundary: boundary edges keep their 3D lengths, but for the change that
    // closes the integrated curve, which the cap's rotational symmetry makes zero.
    double relative = 0;
    const std::size_t nb = patch.boundary.size();
    for (std::size_t k = 0; k < nb; ++k) {
      const std::uint32_t a = patch.boundary[k];
      const std::uint32_t b = patch.boundary[(k + 1) % nb];
      relative += std::abs((uv->at(b) - uv->at(a)).norm() / (patch.positions[b] - patch.positions[a]).norm() - 1);
    }
    CHECK(relative / static_cast<double>(nb) < 1e-9);
  }
}

TEST_CASE("BFF in a given vertex order (shared with SLIM) maps as in its own, and refuses an order of another size") {
  const DiscPatch patch = fx::patch_of(fx::dome(0.6, 12, 48));
  auto own = flatten_bff(patch, CancelToken::none());
  REQUIRE(own.ok());
  // Any permutation of the vertices is a valid order; a reversed one changes the factor, not the map.
  std::vector<int> reversed(patch.num_vertices());
  for (std::size_t v = 0; v < reversed.size(); ++v) reversed[v] = static_cast<int>(reversed.size() - 1 - v);
  auto ordered = flatten_bff(patch, CancelToken::none(), reversed);
  REQUIRE(ordered.ok());
  REQUIRE(ordered->size() == own->size());
  double worst = 0;
  for (std::size_t v = 0; v < own->size(); ++v) worst = std::max(worst, ((*ordered)[v] - (*own)[v]).norm());
  CHECK(worst < 1e-9);
  reversed.pop_back();
  CHECK(flatten_bff(patch, CancelToken::none(), reversed).error().code == ErrorCode::kInvalidArgument);
}

TEST_CASE("BFF stops with kCancelled when cancelled") {
  fx::check_stops_when_cancelled([](const DiscPatch& patch, const CancelToken& token) { return flatten_bff(patch, token); });
}

}  // namespace seam_bff_test
