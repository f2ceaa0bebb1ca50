// The chart operators that no single flattening method owns: the vertex graph the solvers of a
// chart share (vertex_graph_lower), checked against the triangles' edges listed from scratch.
#include "core/uv/uv_patch.h"

#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>
#include <utility>

#include "uv_fixture.h"

namespace seam_uv_patch_test {

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

TEST_CASE("the cotan Laplacian equals its triplet assembly bit for bit: symmetric, rows summing to zero") {
  for (int rings : {3, 9}) {
    CAPTURE(rings);
    const DiscPatch patch = fx::patch_of(fx::jittered_disc(rings, 4 * rings));
    const auto n = static_cast<Eigen::Index>(patch.num_vertices());
    // The oracle: every triangle's corner cotangents as triplets, repeats summed by Eigen.
    std::vector<Eigen::Triplet<double>> entries;
    for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
      const auto& tri = patch.triangles[t];
      const auto cot = seam::core::corner_cotans(patch, t);
      for (int k = 0; k < 3; ++k) {
        const auto i = static_cast<Eigen::Index>(tri[(k + 1) % 3]);
        const auto j = static_cast<Eigen::Index>(tri[(k + 2) % 3]);
        entries.emplace_back(i, j, -0.5 * cot[k]);
        entries.emplace_back(j, i, -0.5 * cot[k]);
      }
    }
    Eigen::SparseMatrix<double> off(n, n);
    off.setFromTriplets(entries.begin(), entries.end());
    const Eigen::SparseMatrix<double> laplacian = seam::core::cotan_laplacian(patch);
    REQUIRE(laplacian.rows() == n);
    REQUIRE(laplacian.isCompressed());
    CHECK(laplacian.nonZeros() == off.nonZeros() + n);
    for (Eigen::Index col = 0; col < n; ++col) {
      double column_sum = 0.0;
      Eigen::Index previous = -1;
      for (Eigen::SparseMatrix<double>::InnerIterator it(laplacian, col); it; ++it) {
        CHECK(it.row() > previous);  // rows sorted, no repeats
        previous = it.row();
        if (it.row() != col) CHECK(it.value() == off.coeff(it.row(), col));
        CHECK(it.value() == laplacian.coeff(col, it.row()));
        column_sum += it.value();
      }
      CHECK(column_sum == doctest::Approx(0.0).epsilon(1e-12).scale(1.0));
      CHECK(laplacian.coeff(col, col) == doctest::Approx(-off.col(col).sum()).epsilon(1e-12));
    }
  }
}

TEST_CASE("a triangle's cotangent weights are kept, or made semi-definite where clamping broke them") {
  using seam::core::semi_definite_cotans;
  using seam::core::Vec3;
  // cot_0 cot_1 + cot_1 cot_2 + cot_2 cot_0: 1 for a real triangle, >= 0 for a semi-definite energy.
  auto form = [](const Vec3& c) { return c[0] * c[1] + c[1] * c[2] + c[2] * c[0]; };
  SUBCASE("a real triangle's cotangents come back unchanged, an obtuse one's too") {
    for (const double degrees : {60.0, 100.0, 150.0, 179.0}) {
      CAPTURE(degrees);
      // An isosceles triangle with apex angle `degrees` (corner 0), its base angles equal.
      const double apex = degrees * std::numbers::pi / 180;
      const double base = (std::numbers::pi - apex) / 2;
      const Vec3 cot(1 / std::tan(apex), 1 / std::tan(base), 1 / std::tan(base));
      CHECK(form(cot) == doctest::Approx(1.0));
      CHECK(semi_definite_cotans(cot) == cot);
    }
  }
  SUBCASE("a clamped cap's negative weight is raised to the bound") {
    // The cap of CGAL's triceratops, clamped: -1e10 before.
    const Vec3 cap(-1e5, 1e5, 1e5);
    CHECK(form(cap) < 0);
    const Vec3 fixed = semi_definite_cotans(cap);
    CHECK(fixed[0] == doctest::Approx(-5e4));
    CHECK(fixed[1] == 1e5);
    CHECK(fixed[2] == 1e5);
    CHECK(form(fixed) >= -1e-6 * 1e10);
    // The negative weight may sit at any corner.
    CHECK(semi_definite_cotans(Vec3(1e5, 1e5, -1e5))[2] == doctest::Approx(-5e4));
  }
  SUBCASE("two negative weights, or one with no positive partner, become 0") {
    CHECK(semi_definite_cotans(Vec3(-1, -2, 3)) == Vec3(0, 0, 3));
    CHECK(semi_definite_cotans(Vec3(-1, 0, 0)) == Vec3(0, 0, 0));
  }
}

TEST_CASE("the cotan Laplacian of a disc with a cap thinner than the clamp stays positive semi-definite") {
  // The cap's cotangents (about 5e8 at its thin corners) are clamped to 1e5; clamped alone they
  // gave an indefinite Laplacian, whose interior block BFF and LSCM could not factor.
  for (const double gap : {1e-9, 1e-12, 0.0}) {
    CAPTURE(gap);
    const DiscPatch patch = fx::patch_of(fx::capped_disc(gap));
    const Eigen::MatrixXd laplacian(seam::core::cotan_laplacian(patch));
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(laplacian);
    REQUIRE(eigen.info() == Eigen::Success);
    const double largest = eigen.eigenvalues().maxCoeff();
    CHECK(largest > 1e4);  // the clamp is reached
    CHECK(eigen.eigenvalues().minCoeff() >= -1e-9 * largest);
  }
}

TEST_CASE("untangle unfolds a star by moving its centre into the kernel, and moves nothing else") {
  using seam::core::Vec2;
  const DiscPatch patch = fx::patch_of(fx::jittered_disc(8, 24));
  std::vector<Vec2> flat;
  for (const auto& p : patch.positions) flat.push_back(p.head<2>());
  REQUIRE(seam::core::count_flipped(patch, flat) == 0);
  // Throw one interior vertex far outside its ring, and another a little way.
  std::vector<std::uint8_t> boundary(patch.num_vertices(), 0);
  for (std::uint32_t v : patch.boundary) boundary[v] = 1;
  std::vector<std::uint32_t> interior;
  for (std::uint32_t v = 0; v < patch.num_vertices(); ++v) {
    if (!boundary[v]) interior.push_back(v);
  }
  REQUIRE(interior.size() > 40);
  std::vector<Vec2> uv = flat;
  const std::uint32_t far = interior[3];
  const std::uint32_t near = interior[interior.size() / 2];
  uv[far] += Vec2(0.4, -0.3);
  uv[near] += Vec2(0.05, 0.04);
  const std::size_t folded = seam::core::count_flipped(patch, uv);
  REQUIRE(folded > 0);
  CHECK(seam::core::untangle(patch, uv) == 0);
  CHECK(seam::core::count_flipped(patch, uv) == 0);
  // Only vertices within two rings of the thrown ones moved (the corners of folded triangles,
  // then their neighbours); the boundary never does.
  std::set<std::uint32_t> allowed = {far, near};
  for (int ring = 0; ring < 2; ++ring) {
    const std::set<std::uint32_t> inner = allowed;
    for (const auto& t : patch.triangles) {
      for (std::uint32_t v : t) {
        if (inner.count(v)) allowed.insert(t.begin(), t.end());
      }
    }
  }
  for (std::uint32_t v = 0; v < patch.num_vertices(); ++v) {
    if (uv[v] == (v == far || v == near ? uv[v] : flat[v])) continue;
    CHECK(allowed.count(v) == 1);
    CHECK_FALSE(boundary[v]);
  }
  // A fold-free map is left exactly as it is.
  std::vector<Vec2> same = flat;
  CHECK(seam::core::untangle(patch, same) == 0);
  CHECK(same == flat);
}

TEST_CASE("untangle with an area floor fattens thin triangles without folding any") {
  using seam::core::Vec2;
  const DiscPatch patch = fx::patch_of(fx::disc(6, 16));
  std::vector<Vec2> uv;
  for (const auto& p : patch.positions) uv.push_back(p.head<2>());
  // Vertex 0 (the centre) nearly onto the first ring: its triangles towards there go thin.
  uv[0] = 0.999 * uv[1];
  auto thinnest = [&] {
    double least = 1e300;
    for (const auto& t : patch.triangles) {
      const Vec2 a = uv[t[1]] - uv[t[0]];
      const Vec2 b = uv[t[2]] - uv[t[0]];
      least = std::min(least, a.x() * b.y() - a.y() * b.x());
    }
    return least;
  };
  const double before = thinnest();
  REQUIRE(before > 0);
  const double floor = 1e-3;
  REQUIRE(before < floor);
  CHECK(seam::core::untangle(patch, uv, 20, floor) == 0);
  CHECK(thinnest() > floor);
  CHECK(seam::core::count_flipped(patch, uv) == 0);
  CHECK(uv[0].norm() < 0.1);  // back near the centre of its ring
}

TEST_CASE("restore_turns gives a flattened triangle back its wanted turn, either way, by one grid step") {
  using seam::core::Triangle;
  using seam::core::Vec2;
  // c lies on the segment ab, so (a, b, c), wanted clockwise, has no area; (c, b, d) turns
  // counter-clockwise as wanted; (a, c, d) is free (want 0).
  std::vector<Vec2> uv = {{0.25, 0.5}, {0.75, 0.5}, {0.5, 0.5}, {0.5, 0.75}};
  const std::vector<Triangle> triangles = {{0, 1, 2}, {2, 1, 3}, {0, 2, 3}};
  const std::vector<double> want = {-1.0, 1.0, 0.0};
  auto area = [&](const Triangle& t) { return seam::core::cross2(uv[t[0]], uv[t[1]], uv[t[2]]); };
  const std::vector<Vec2> before = uv;
  const seam::core::Float32Rounding r = seam::core::restore_turns(triangles, want, uv);
  CHECK(r.degenerate == 1);
  CHECK(r.remaining == 0);
  CHECK(area(triangles[0]) < 0);
  CHECK(area(triangles[1]) > 0);
  // The first corner's first move that works, (-1, +1): one grid step left and up.
  CHECK(uv[0] == Vec2(0.25 - seam::core::kUvGrid, 0.5 + seam::core::kUvGrid));
  for (std::size_t v = 1; v < uv.size(); ++v) CHECK(uv[v] == before[v]);
  for (const Vec2& p : uv) {
    CHECK(seam::core::to_uv_grid(p.x()) == p.x());
    CHECK(seam::core::to_uv_grid(p.y()) == p.y());
  }
  // Turned the wanted way already: nothing moves.
  const std::vector<Vec2> settled = uv;
  CHECK(seam::core::restore_turns(triangles, want, uv).degenerate == 0);
  CHECK(uv == settled);
  // Wanted both ways at once over the same corners: no step restores it, and it is counted.
  const std::vector<Triangle> twice = {{0, 1, 2}, {0, 2, 1}};
  std::vector<Vec2> flat = before;
  const seam::core::Float32Rounding stuck = seam::core::restore_turns(twice, std::vector<double>{-1.0, -1.0}, flat);
  CHECK(stuck.degenerate == 2);
  CHECK(stuck.remaining == 2);
  CHECK(flat == before);
}

TEST_CASE("restore_turns reaches past the nearest grid points for a sliver no one-step move restores (F19)") {
  using seam::core::Triangle;
  using seam::core::Vec2;
  const double g = seam::core::kUvGrid;
  auto at = [&](double x, double y) { return Vec2(0.5 + x * g, 0.5 + y * g); };
  // (a, b, c) lies on a line, wanted counter-clockwise: c must go up. (c, q, b), wanted
  // counter-clockwise, needs 2 x - y > 2 of c's offset (x, y) in steps: no point one step away
  // gives both, (2, 1) does. a and b are pinned: each is in two triangles that want opposite
  // turns of the same corners, one of which is always wrong, so no move of theirs is taken.
  std::vector<Vec2> uv = {at(0, 0), at(2, 0), at(1, 0), at(3, 2), at(-5, 3), at(-5, -3), at(7, 3), at(7, -3)};
  const std::vector<Triangle> triangles = {{0, 1, 2}, {2, 3, 1}, {0, 4, 5}, {0, 5, 4}, {1, 6, 7}, {1, 7, 6}};
  const std::vector<double> want(triangles.size(), 1.0);
  const std::vector<Vec2> before = uv;
  const seam::core::Float32Rounding r = seam::core::restore_turns(triangles, want, uv);
  CHECK(r.degenerate == 4);  // the sliver, (c, q, b), and one of each pinned pair
  CHECK(r.remaining == 2);   // the pinned pairs
  CHECK(uv[2] == at(3, 1));  // c two steps right and one up
  for (std::size_t v = 0; v < uv.size(); ++v) {
    if (v != 2) CHECK(uv[v] == before[v]);
  }
  auto area = [&](const Triangle& t) { return seam::core::cross2(uv[t[0]], uv[t[1]], uv[t[2]]); };
  CHECK(area(triangles[0]) > 0);
  CHECK(area(triangles[1]) > 0);
}

TEST_CASE("the UV grid: multiples of 2^-24 in [0,1], floats whose 1 - v is a float too") {
  using seam::core::to_uv_grid;
  CHECK(to_uv_grid(-0.5) == 0.0);
  CHECK(to_uv_grid(1.5) == 1.0);
  CHECK(to_uv_grid(0.75) == 0.75);
  CHECK(to_uv_grid(0x1p-26) == 0.0);        // below half a step
  CHECK(to_uv_grid(0x1.8p-25) == 0x1p-24);  // half a step rounds away from zero
  // Float32 is finer below 1/2: 0.1f is no multiple of 2^-24, and 1 - 0.1f is no float.
  const double tenth = 0.1f;
  REQUIRE(static_cast<double>(static_cast<float>(1.0 - tenth)) != 1.0 - tenth);
  const double g = to_uv_grid(tenth);
  CHECK(std::abs(g - tenth) <= 0.5 * seam::core::kUvGrid);
  CHECK(static_cast<double>(static_cast<float>(g)) == g);
  CHECK(static_cast<double>(static_cast<float>(1.0 - g)) == 1.0 - g);
}

}  // namespace seam_uv_patch_test
