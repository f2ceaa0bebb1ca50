// Least-squares conformal maps: a planar disc is reproduced up to a similarity (here an
// isometry, since the pinned pair keeps its 3D distance), the pinned pair is far apart on the
// boundary, a curved cap is flattened nearly conformally, and cancellation is a typed error.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>

#include "core/uv/lscm.h"
#include "uv_fixture.h"

namespace seam_lscm_test {

using namespace seam::core;
namespace fx = seam::fixtures;

TEST_CASE("LSCM reproduces a planar disc up to a similarity") {
  const DiscPatch patch = fx::patch_of(fx::jittered_disc());
  auto uv = flatten_lscm(patch, CancelToken::none());
  REQUIRE(uv.ok());
  REQUIRE(uv->size() == patch.num_vertices());
  // The best similarity z -> a z + b from the input plane (as complex numbers) to the UVs, by
  // least squares; its residual is round-off, and |a| = 1 since the pins keep their distance.
  const std::size_t n = patch.num_vertices();
  std::complex<double> mean_p = 0;
  std::complex<double> mean_q = 0;
  for (std::size_t v = 0; v < n; ++v) {
    mean_p += std::complex<double>(patch.positions[v].x(), patch.positions[v].y());
    mean_q += std::complex<double>(uv->at(v).x(), uv->at(v).y());
  }
  mean_p /= static_cast<double>(n);
  mean_q /= static_cast<double>(n);
  std::complex<double> num = 0;
  double den = 0;
  for (std::size_t v = 0; v < n; ++v) {
    const std::complex<double> p = std::complex<double>(patch.positions[v].x(), patch.positions[v].y()) - mean_p;
    const std::complex<double> q = std::complex<double>(uv->at(v).x(), uv->at(v).y()) - mean_q;
    num += std::conj(p) * q;
    den += std::norm(p);
  }
  const std::complex<double> a = num / den;
  CHECK(std::abs(a) == doctest::Approx(1.0).epsilon(1e-9));
  double residual = 0;
  for (std::size_t v = 0; v < n; ++v) {
    const std::complex<double> p = std::complex<double>(patch.positions[v].x(), patch.positions[v].y()) - mean_p;
    const std::complex<double> q = std::complex<double>(uv->at(v).x(), uv->at(v).y()) - mean_q;
    residual = std::max(residual, std::abs(a * p - q));
  }
  CHECK(residual < 1e-9);
  CHECK(fx::mean_angle_error(patch, *uv) < 1e-9);
}

TEST_CASE("LSCM pins a boundary pair at least half the boundary's diameter apart") {
  for (const fx::Soup& soup : {fx::jittered_disc(), fx::dome(0.8), fx::jittered_disc(3, 40)}) {
    const DiscPatch patch = fx::patch_of(soup);
    const auto [p0, p1] = boundary_far_pair(patch);
    CHECK(p0 != p1);
    CHECK(std::find(patch.boundary.begin(), patch.boundary.end(), p0) != patch.boundary.end());
    CHECK(std::find(patch.boundary.begin(), patch.boundary.end(), p1) != patch.boundary.end());
    double diameter = 0;  // brute force over boundary pairs
    for (std::uint32_t a : patch.boundary) {
      for (std::uint32_t b : patch.boundary) diameter = std::max(diameter, (patch.positions[a] - patch.positions[b]).norm());
    }
    // Two farthest-point sweeps: the second sweep's distance is at least half the diameter.
    CHECK((patch.positions[p0] - patch.positions[p1]).norm() >= 0.5 * diameter);
  }
}

TEST_CASE("LSCM flattens a curved cap nearly conformally and without folds") {
  const DiscPatch patch = fx::patch_of(fx::dome(0.6, 12, 48));
  auto uv = flatten_lscm(patch, CancelToken::none());
  REQUIRE(uv.ok());
  CHECK(count_flipped(patch, *uv) == 0);
  CHECK(fx::mean_angle_error(patch, *uv) < 0.05);
}

TEST_CASE("LSCM stops with kCancelled when cancelled") {
  fx::check_stops_when_cancelled([](const DiscPatch& patch, const CancelToken& token) { return flatten_lscm(patch, token); });
}

}  // namespace seam_lscm_test
