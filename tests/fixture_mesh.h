// Test-side helper over the fixtures (needs doctest; fixtures.h itself does not, so the
// benchmarks can use the fixtures too).
#pragma once

#include <doctest/doctest.h>

#include "fixtures.h"

namespace seam::fixtures {

/// Builds the half-edge mesh of a fixture, failing the test if the builder refuses it or the
/// mesh it builds breaks the half-edge invariants.
inline core::HalfedgeMesh build_fixture(const Soup& s) {
  auto mesh = core::build_halfedge_mesh(s.positions, s.triangles);
  REQUIRE_MESSAGE(mesh.ok(), (mesh.ok() ? "" : mesh.error().message));
  REQUIRE(core::check_invariants(*mesh).ok());
  return std::move(mesh).value();
}

}  // namespace seam::fixtures
