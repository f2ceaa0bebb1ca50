// The chart operators that no single flattening method owns: the vertex graph the solvers of a
// chart share (vertex_graph_lower), checked against the triangles' edges listed from scratch.
#include "core/uv/uv_patch.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <set>
#include <utility>

#include "uv_fixture.h"

namespace fx = seam::fixtures;
using seam::core::DiscPatch;

TEST_CASE("the vertex graph is the lower triangle of the mesh's edges and the diagonal, every value 1") {
  const DiscPatch patch = fx::patch_of(fx::jittered_disc(5, 12));
  const auto n = static_cast<Eigen::Index>(patch.num_vertices());
  // The oracle: each triangle's three sides, an interior edge listed by both its triangles.
  std::set<std::pair<Eigen::Index, Eigen::Index>> expected;
  for (Eigen::Index v = 0; v < n; ++v) expected.emplace(v, v);
  for (const auto& tri : patch.triangles) {
    for (int k = 0; k < 3; ++k) {
      const auto a = static_cast<Eigen::Index>(tri[k]);
      const auto b = static_cast<Eigen::Index>(tri[(k + 1) % 3]);
      expected.emplace(std::max(a, b), std::min(a, b));
    }
  }
  // A disc: V - E + F = 1.
  const auto edges = static_cast<Eigen::Index>(expected.size()) - n;
  CHECK(n - edges + static_cast<Eigen::Index>(patch.triangles.size()) == 1);

  const Eigen::SparseMatrix<double> lower = seam::core::vertex_graph_lower(patch);
  REQUIRE(lower.rows() == n);
  REQUIRE(lower.cols() == n);
  std::set<std::pair<Eigen::Index, Eigen::Index>> found;
  for (Eigen::Index col = 0; col < lower.outerSize(); ++col) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(lower, col); it; ++it) {
      CHECK(it.row() >= col);
      CHECK(it.value() == 1.0);
      found.emplace(it.row(), col);
    }
  }
  CHECK(found == expected);
  CHECK(lower.nonZeros() == static_cast<Eigen::Index>(expected.size()));
}
