#include "core/mesh/topology.h"

#include <doctest/doctest.h>

#include <algorithm>

#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/icosphere.h"
#include "fixtures.h"
#include "test_data.h"

namespace seam_topology_test {

using namespace seam::core;
namespace fx = seam::fixtures;

namespace {
Topology topology_of(const fx::Soup& s) {
  auto mesh = build_halfedge_mesh(s.positions, s.triangles);
  REQUIRE(mesh.ok());
  REQUIRE(check_invariants(*mesh).ok());
  return compute_topology(*mesh);
}
}  // namespace

TEST_CASE("genus, Euler characteristic and boundary loops of the fixtures") {
  struct Case {
    const char* name;
    fx::Soup soup;
    int chi, genus;
    std::size_t loops;
  };
  const Case cases[] = {
      {"tetrahedron", fx::tetrahedron(), 2, 0, 0},  {"icosphere", fx::icosphere(2), 2, 0, 0},
      {"torus", fx::torus(), 0, 1, 0},              {"double torus", fx::holed_slab(2), -2, 2, 0},
      {"triple torus", fx::holed_slab(3), -4, 3, 0}, {"open cylinder", fx::open_cylinder(), 0, 0, 2},
      {"disc", fx::disc(), 1, 0, 1},
  };
  for (const auto& c : cases) {
    CAPTURE(c.name);
    const Topology t = topology_of(c.soup);
    REQUIRE(t.components.size() == 1);
    CHECK(t.components[0].euler_characteristic == c.chi);
    CHECK(t.components[0].genus == c.genus);
    CHECK(t.components[0].boundary_loops == c.loops);
    CHECK(t.boundary_loops.size() == c.loops);
  }
}

TEST_CASE("core::icosphere: 10 x 4^l + 2 vertices on the unit sphere, 20 x 4^l outward faces, a closed sphere") {
  for (int levels = 0; levels <= 3; ++levels) {
    CAPTURE(levels);
    const IndexedMesh m = icosphere(levels);
    const std::size_t four = std::size_t{1} << (2 * levels);
    CHECK(m.positions.size() == 10 * four + 2);
    CHECK(m.triangles.size() == 20 * four);
    for (const Vec3& p : m.positions) CHECK(p.norm() == doctest::Approx(1.0).epsilon(1e-12));
    // Counter-clockwise seen from outside: each face's normal points away from the centre.
    for (const Triangle& t : m.triangles) {
      const Vec3 n = (m.positions[t[1]] - m.positions[t[0]]).cross(m.positions[t[2]] - m.positions[t[0]]);
      CHECK(n.dot(m.positions[t[0]] + m.positions[t[1]] + m.positions[t[2]]) > 0);
    }
    const Topology t = topology_of({m.positions, m.triangles});
    REQUIRE(t.components.size() == 1);
    CHECK(t.components[0].genus == 0);
    CHECK(t.components[0].boundary_loops == 0);
  }
}

TEST_CASE("two components are counted separately") {
  const auto soup = fx::join(fx::torus(), fx::translated(fx::disc(), Vec3(10, 0, 0)));
  const Topology t = topology_of(soup);
  REQUIRE(t.components.size() == 2);
  CHECK(t.components[0].genus == 1);
  CHECK(t.components[1].boundary_loops == 1);
  CHECK(t.components[1].euler_characteristic == 1);
  CHECK(t.face_component[FaceId(0u)] == 0);
  CHECK(t.face_component[FaceId(soup.triangles.size() - 1)] == 1);
  CHECK(t.total_genus() == 1);
  CHECK(t.euler_characteristic() == 1);
}

TEST_CASE("boundary loops are ordered chains of boundary half-edges") {
  auto soup = fx::open_cylinder(12, 3);
  auto mesh = build_halfedge_mesh(soup.positions, soup.triangles);
  REQUIRE(mesh.ok());
  const Topology t = compute_topology(*mesh);
  REQUIRE(t.boundary_loops.size() == 2);
  for (const auto& loop : t.boundary_loops) {
    CHECK(loop.size() == 12);
    for (std::size_t i = 0; i < loop.size(); ++i) {
      CHECK(mesh->is_boundary(loop[i]));
      CHECK(mesh->head(loop[i]) == mesh->tail(loop[(i + 1) % loop.size()]));
    }
    // Every vertex of a loop lies on one rim (z = 0 or z = 2).
    const double z = mesh->position(mesh->tail(loop[0])).z();
    for (auto h : loop) CHECK(mesh->position(mesh->tail(h)).z() == doctest::Approx(z));
    // Each loop starts at its smallest half-edge; loops are sorted by it.
    CHECK(*std::min_element(loop.begin(), loop.end()) == loop[0]);
  }
  CHECK(t.boundary_loops[0][0] < t.boundary_loops[1][0]);
  CHECK(boundary_loops(*mesh) == t.boundary_loops);
}

TEST_CASE("real CGAL meshes have the topology they are known to have") {
  struct Case {
    const char* name;
    std::size_t components;
    int genus;
    std::size_t boundary_loops;
  };
  // Known facts about these models: the hand and camel are closed spheres, the elephant has
  // genus 3 (its trunk and tusks touch the body), knot1 is a trefoil tube (genus 1), the
  // mushroom and the lion head are open surfaces.
  const Case cases[] = {
      {"hand", 1, 0, 0}, {"elephant", 1, 3, 0}, {"knot1", 1, 1, 0}, {"mushroom", 1, 0, 1},
      {"lion-head", 1, 0, 1}, {"camel", 1, 0, 0},
  };
  for (const auto& c : cases) {
    CAPTURE(c.name);
    const auto mesh = seam::test_data::load_cgal_halfedge(c.name);
    CHECK(check_invariants(mesh).ok());
    const Topology t = compute_topology(mesh);
    CHECK(t.components.size() == c.components);
    CHECK(t.total_genus() == c.genus);
    CHECK(t.boundary_loops.size() == c.boundary_loops);
  }
}

}  // namespace seam_topology_test
