// Splitting pinched vertices: one vertex per fan, nothing else touched, manifold input
// unchanged, and the real pinched mesh (CGAL's cow) builds afterwards.
#include <doctest/doctest.h>

#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/split_pinched.h"
#include "core/mesh/topology.h"
#include "core/mesh/weld.h"
#include "fixtures.h"
#include "test_data.h"

namespace seam_split_pinched_test {

using namespace seam::core;
namespace fx = seam::fixtures;

namespace {

// Two tetrahedra that touch only at one vertex: input vertex 0 of both.
fx::Soup touching_tetrahedra() {
  fx::Soup s = fx::tetrahedron();
  const fx::Soup b = fx::translated(fx::tetrahedron(), Vec3(-1, -1, -1));
  // b's vertex 0 sits at (-1,-1,-1); mirror b through the origin so it touches a at 0.
  const auto offset = static_cast<std::uint32_t>(s.positions.size()) - 1;
  for (std::size_t v = 1; v < b.positions.size(); ++v) s.positions.push_back(-(b.positions[v] - b.positions[0]));
  for (auto t : b.triangles) {
    Triangle u;
    for (int k = 0; k < 3; ++k) u[k] = t[k] == 0 ? 0 : t[k] + offset;
    s.triangles.push_back(u);
  }
  return s;
}

}  // namespace

TEST_CASE("a bowtie vertex becomes one vertex per fan") {
  const fx::Soup soup = fx::bowtie();
  REQUIRE(build_halfedge_mesh(soup.positions, soup.triangles).error().code == ErrorCode::kNonManifoldVertex);
  const PinchSplit split = split_pinched_vertices(soup.positions, soup.triangles);
  CHECK(split.pinched_vertices == 1);
  REQUIRE(split.positions.size() == soup.positions.size() + 1);
  CHECK(split.source.back() == 0);
  CHECK(split.positions.back() == soup.positions[0]);
  // The first fan (the lowest corner) keeps vertex 0; the second triangle gets the copy.
  CHECK(split.triangles[0] == soup.triangles[0]);
  CHECK(split.triangles[1] == Triangle{5, 3, 4});
  auto mesh = build_halfedge_mesh(split.positions, split.triangles);
  REQUIRE(mesh.ok());
  CHECK(check_invariants(*mesh).ok());
  CHECK(compute_topology(*mesh).components.size() == 2);
}

TEST_CASE("two closed surfaces touching at a vertex become two closed components") {
  const fx::Soup soup = touching_tetrahedra();
  REQUIRE(build_halfedge_mesh(soup.positions, soup.triangles).error().code == ErrorCode::kNonManifoldVertex);
  const PinchSplit split = split_pinched_vertices(soup.positions, soup.triangles);
  CHECK(split.pinched_vertices == 1);
  auto mesh = build_halfedge_mesh(split.positions, split.triangles);
  REQUIRE(mesh.ok());
  const Topology topo = compute_topology(*mesh);
  REQUIRE(topo.components.size() == 2);
  for (const auto& c : topo.components) {
    CHECK(c.boundary_loops == 0);
    CHECK(c.genus == 0);
  }
}

TEST_CASE("manifold input and input the builder must refuse pass through unchanged") {
  for (const fx::Soup& soup : {fx::icosphere(2), fx::disc(3, 8), fx::fin()}) {
    const PinchSplit split = split_pinched_vertices(soup.positions, soup.triangles);
    CHECK(split.pinched_vertices == 0);
    CHECK(split.positions.size() == soup.positions.size());
    CHECK(split.triangles == soup.triangles);
  }
  // Out-of-range and repeated indices are left for the builder to report.
  fx::Soup bad = fx::tetrahedron();
  bad.triangles.push_back({0, 1, 99});
  bad.triangles.push_back({2, 2, 3});
  const PinchSplit split = split_pinched_vertices(bad.positions, bad.triangles);
  CHECK(split.triangles == bad.triangles);
  CHECK(build_halfedge_mesh(split.positions, split.triangles).error().code == ErrorCode::kIndexOutOfRange);
}

TEST_CASE("CGAL's cow, refused for its pinched vertex once welded, builds after the split") {
  const auto soup = seam::test_data::load_cgal("cow");
  // Coincident vertices weld into a vertex where two fans touch.
  auto weld = weld_vertices(soup.positions, {});
  REQUIRE(weld.ok());
  const std::vector<Triangle> welded = remap_triangles(soup.triangles, weld->input_to_welded);
  REQUIRE(build_halfedge_mesh(weld->positions, welded).error().code == ErrorCode::kNonManifoldVertex);
  const PinchSplit split = split_pinched_vertices(weld->positions, welded);
  CHECK(split.pinched_vertices >= 1);
  CHECK(split.positions.size() == weld->positions.size() + split.pinched_vertices);  // one extra fan each
  auto mesh = build_halfedge_mesh(split.positions, split.triangles);
  REQUIRE(mesh.ok());
  CHECK(check_invariants(*mesh).ok());
}

}  // namespace seam_split_pinched_test
