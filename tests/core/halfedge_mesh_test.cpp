#include <doctest/doctest.h>

#include <algorithm>
#include <random>
#include <tuple>

#include "core/mesh/halfedge_mesh.h"
#include "fixtures.h"

namespace seam_halfedge_mesh_test {

using namespace seam::core;
namespace fx = seam::fixtures;

namespace {
Result<HalfedgeMesh> build(const fx::Soup& s) { return build_halfedge_mesh(s.positions, s.triangles); }
}  // namespace

TEST_CASE("closed fixtures build and satisfy every invariant") {
  for (const auto& soup : {fx::tetrahedron(), fx::icosphere(2), fx::torus(), fx::holed_slab(2),
                           fx::open_cylinder(), fx::disc(), fx::uv_sphere(), fx::uv_sphere(16, 8, false)}) {
    auto mesh = build(soup);
    REQUIRE(mesh.ok());
    CHECK(mesh->num_faces() == soup.triangles.size());
    CHECK(check_invariants(*mesh).ok());
    CHECK(mesh->triangles() == soup.triangles);
  }
}

TEST_CASE("tetrahedron connectivity") {
  auto mesh = build(fx::tetrahedron());
  REQUIRE(mesh.ok());
  CHECK(mesh->num_vertices() == 4);
  CHECK(mesh->num_edges() == 6);
  CHECK(mesh->num_halfedges() == 12);
  for (std::size_t v = 0; v < 4; ++v) {
    CHECK(mesh->valence(VertexId(v)) == 3);
    CHECK_FALSE(mesh->is_boundary(VertexId(v)));
  }
  const HalfedgeId h = mesh->find_halfedge(VertexId(0u), VertexId(1u));
  REQUIRE(h.valid());
  CHECK(mesh->tail(h) == VertexId(0u));
  CHECK(mesh->head(h) == VertexId(1u));
  CHECK(mesh->edge_length(HalfedgeMesh::edge(h)) == doctest::Approx(1.0));
  CHECK_FALSE(mesh->find_halfedge(VertexId(0u), VertexId(0u)).valid());
}

TEST_CASE("rotation around a vertex is counter-clockwise and complete") {
  auto mesh = build(fx::disc(2, 8));
  REQUIRE(mesh.ok());
  // Centre vertex 0 of a flat disc in z = 0: heads must appear with increasing angle.
  std::vector<double> angles;
  mesh->for_each_outgoing(VertexId(0u), [&](HalfedgeId h) {
    const Vec3 d = mesh->position(mesh->head(h));
    angles.push_back(std::atan2(d.y(), d.x()));
  });
  REQUIRE(angles.size() == 8);
  int increases = 0;
  for (std::size_t i = 0; i < angles.size(); ++i) {
    double step = angles[(i + 1) % angles.size()] - angles[i];
    if (step < 0) step += 2 * std::numbers::pi;
    increases += step > 0 && step < std::numbers::pi;
  }
  CHECK(increases == 8);
  // A boundary vertex starts its rotation at its outgoing boundary half-edge.
  const VertexId rim(9u);  // ring 2 of 2: on the rim
  CHECK(mesh->is_boundary(rim));
  CHECK(mesh->is_boundary(mesh->vertex_halfedge(rim)));
}

TEST_CASE("hostile input is reported with typed errors naming the offender") {
  SUBCASE("empty") {
    auto r = build_halfedge_mesh({}, {});
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == ErrorCode::kEmptyMesh);
  }
  SUBCASE("index out of range") {
    auto s = fx::tetrahedron();
    s.triangles[2][1] = 99;
    auto r = build(s);
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == ErrorCode::kIndexOutOfRange);
    CHECK(r.error().elements == std::vector<std::uint32_t>{2});
  }
  SUBCASE("NaN position") {
    auto s = fx::tetrahedron();
    s.positions[3].y() = std::nan("");
    auto r = build(s);
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == ErrorCode::kNonFinitePosition);
    CHECK(r.error().elements == std::vector<std::uint32_t>{3});
  }
  SUBCASE("infinite position") {
    auto s = fx::tetrahedron();
    s.positions[1].x() = std::numeric_limits<double>::infinity();
    auto r = build(s);
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == ErrorCode::kNonFinitePosition);
  }
  SUBCASE("repeated vertex") {
    auto s = fx::tetrahedron();
    s.triangles[1] = {0, 1, 1};
    auto r = build(s);
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == ErrorCode::kDegenerateFace);
    CHECK(r.error().elements == std::vector<std::uint32_t>{1});
    CHECK(r.error().message.find("repeats") != std::string::npos);
  }
  SUBCASE("zero area") {
    fx::Soup s{{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)}, {{0, 1, 2}}};
    auto r = build(s);
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == ErrorCode::kDegenerateFace);
    CHECK(r.error().message.find("zero area") != std::string::npos);
  }
  SUBCASE("fin edge") {
    auto r = build(fx::fin());
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == ErrorCode::kNonManifoldEdge);
    CHECK(r.error().elements == std::vector<std::uint32_t>{0, 1});
  }
  SUBCASE("flipped face") {
    auto r = build(fx::flipped_tetrahedron());
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == ErrorCode::kInconsistentOrientation);
  }
  SUBCASE("bowtie vertex with boundary") {
    auto r = build(fx::bowtie());
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == ErrorCode::kNonManifoldVertex);
    CHECK(r.error().elements == std::vector<std::uint32_t>{0});
  }
  SUBCASE("two closed surfaces pinched at one vertex") {
    // Two tetrahedra sharing vertex 0 only: no boundary, so only the fan count finds it.
    auto a = fx::tetrahedron();
    auto b = fx::translated(fx::tetrahedron(), Vec3(-1, -1, -1));
    auto s = fx::join(a, b);
    for (auto& t : s.triangles) {
      for (auto& v : t) {
        if (v == 4) v = 0;
      }
    }
    auto r = build(s);
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == ErrorCode::kNonManifoldVertex);
    CHECK(r.error().elements == std::vector<std::uint32_t>{0});
  }
}

TEST_CASE("isolated vertices are kept and skipped") {
  auto s = fx::tetrahedron();
  s.positions.emplace_back(5, 5, 5);
  auto mesh = build(s);
  REQUIRE(mesh.ok());
  CHECK(mesh->num_vertices() == 5);
  CHECK(mesh->is_isolated(VertexId(4u)));
  CHECK(check_invariants(*mesh).ok());
}

TEST_CASE("sorted_edge_uses is std::sort's (key, corner) order, fins, a pole and bad faces included") {
  fx::Soup s = fx::icosphere(3);
  const auto n = static_cast<std::uint32_t>(s.positions.size());
  // A pole of valence 40 (past the insertion sort's limit), a fin, a repeated triangle, and a
  // triangle out of range (left out); then the faces shuffled.
  s.positions.push_back(Vec3(0, 0, 5));
  for (std::uint32_t k = 0; k < 40; ++k) s.triangles.push_back({n, k, k + 1});
  s.triangles.push_back({s.triangles[0][0], s.triangles[0][1], 7});
  s.triangles.push_back(s.triangles[3]);
  s.triangles.push_back({0, 1, n + 5});
  std::mt19937 rng(9);
  std::shuffle(s.triangles.begin(), s.triangles.end(), rng);

  std::vector<EdgeCorner> expected;
  const std::size_t nv = s.positions.size();
  for (std::uint32_t t = 0; t < s.triangles.size(); ++t) {
    const Triangle& tri = s.triangles[t];
    if (tri[0] >= nv || tri[1] >= nv || tri[2] >= nv) continue;
    for (std::uint32_t k = 0; k < 3; ++k) {
      const std::uint64_t a = tri[k], b = tri[(k + 1) % 3];
      expected.push_back({(std::min(a, b) << 32) | std::max(a, b), 3 * t + k});
    }
  }
  std::sort(expected.begin(), expected.end(), [](const EdgeCorner& x, const EdgeCorner& y) {
    return std::tie(x.key, x.corner) < std::tie(y.key, y.corner);
  });
  const std::vector<EdgeCorner> uses = sorted_edge_uses(s.triangles, nv);
  REQUIRE(uses.size() == expected.size());
  for (std::size_t i = 0; i < uses.size(); ++i) {
    CHECK(uses[i].key == expected[i].key);
    CHECK(uses[i].corner == expected[i].corner);
  }
}

}  // namespace seam_halfedge_mesh_test
