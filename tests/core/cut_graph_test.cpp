#include <doctest/doctest.h>

#include <map>
#include <numbers>

#include "core/mesh/cut.h"
#include "core/seam/cut_graph.h"
#include "core/mesh/topology.h"
#include "fixture_mesh.h"
#include "test_data.h"

namespace seam_cut_graph_test {

using namespace seam::core;
namespace fx = seam::fixtures;

namespace {

double length_of(const HalfedgeMesh& mesh, const std::vector<EdgeId>& edges) {
  double total = 0;
  for (EdgeId e : edges) total += mesh.edge_length(e);
  return total;
}

// The cut graph opens every component into one disc, is sorted and unique, avoids the
// boundary, and has no dangling branch (a degree-1 vertex must lie on a boundary loop).
void check_cut_graph(const HalfedgeMesh& mesh, const std::vector<EdgeId>& edges) {
  CHECK(std::is_sorted(edges.begin(), edges.end()));
  CHECK(std::adjacent_find(edges.begin(), edges.end()) == edges.end());
  std::map<std::uint32_t, int> degree;
  for (EdgeId e : edges) {
    CHECK(!mesh.is_boundary(e));
    ++degree[mesh.tail(HalfedgeMesh::halfedge(e)).value()];
    ++degree[mesh.head(HalfedgeMesh::halfedge(e)).value()];
  }
  for (const auto& [v, d] : degree) {
    if (d == 1) CHECK(mesh.is_boundary(VertexId(v)));
  }
  auto cut = cut_along_edges(mesh, edges);
  REQUIRE(cut.ok());
  // Every component becomes a disc, except spheres, which need no cut graph.
  const Topology before = compute_topology(mesh);
  const Topology after = compute_topology(cut->mesh);
  REQUIRE(after.components.size() == before.components.size());
  for (std::size_t c = 0; c < after.components.size(); ++c) {
    CAPTURE(c);
    const bool sphere = before.components[c].genus == 0 && before.components[c].boundary_loops == 0;
    CHECK(after.components[c].euler_characteristic == (sphere ? 2 : 1));
    CHECK(after.components[c].boundary_loops == (sphere ? 0u : 1u));
  }
}

}  // namespace

TEST_CASE("discs and spheres need no cut graph") {
  for (const auto& soup : {fx::icosphere(2), fx::disc(), fx::tetrahedron()}) {
    const HalfedgeMesh mesh = fx::build_fixture(soup);
    auto cg = compute_cut_graph(mesh);
    REQUIRE(cg.ok());
    CHECK(cg->empty());
  }
}

TEST_CASE("cut graphs open tori, multi-holed slabs, cylinders and mixed components into discs") {
  struct Case {
    const char* name;
    fx::Soup soup;
  };
  const Case cases[] = {{"torus", fx::torus()},
                        {"double torus", fx::holed_slab(2)},
                        {"triple torus", fx::holed_slab(3)},
                        {"open cylinder", fx::open_cylinder()},
                        {"torus + cylinder + sphere",
                         fx::join(fx::join(fx::torus(), fx::translated(fx::open_cylinder(), Vec3(10, 0, 0))),
                                  fx::translated(fx::icosphere(1), Vec3(-10, 0, 0)))}};
  for (const auto& c : cases) {
    CAPTURE(std::string(c.name));
    const HalfedgeMesh mesh = fx::build_fixture(c.soup);
    auto cg = compute_cut_graph(mesh);
    REQUIRE(cg.ok());
    CHECK(!cg->empty());
    check_cut_graph(mesh, *cg);
  }
}

TEST_CASE("torus cut graph is short: the two loops, not a tree sweep") {
  // R = 2, r = 0.6, 24 x 12: the shortest meridian is a 12-gon of radius 0.6 and the shortest
  // longitude the inner 24-gon of radius 1.4. A shortest system of two loops through one
  // point is at most about their sum (plus a short connector on the tube).
  const HalfedgeMesh mesh = fx::build_fixture(fx::torus(24, 12, 2.0, 0.6));
  auto cg = compute_cut_graph(mesh);
  REQUIRE(cg.ok());
  const double meridian = 12 * 2 * 0.6 * std::sin(std::numbers::pi / 12);
  const double inner = 24 * 2 * 1.4 * std::sin(std::numbers::pi / 24);
  const double length = length_of(mesh, *cg);
  CHECK(length >= meridian + inner - 1e-9);
  CHECK(length <= 1.25 * (meridian + inner));
}

TEST_CASE("open cylinder: the cut graph is one shortest path between the two rims") {
  const HalfedgeMesh mesh = fx::build_fixture(fx::open_cylinder(16, 6, 2.0));
  auto cg = compute_cut_graph(mesh);
  REQUIRE(cg.ok());
  check_cut_graph(mesh, *cg);
  CHECK(length_of(mesh, *cg) == doctest::Approx(2.0));  // six vertical rungs of height 1/3
}

TEST_CASE("real meshes: elephant (genus 3 handles in the CGAL data), knot1, mushroom, lion-head") {
  for (const char* name : {"elephant", "knot1", "mushroom", "lion-head"}) {
    CAPTURE(std::string(name));
    const HalfedgeMesh mesh = seam::test_data::load_cgal_halfedge(name);
    const Topology topo = compute_topology(mesh);
    auto cg = compute_cut_graph(mesh);
    REQUIRE(cg.ok());
    bool needs = false;
    for (const auto& c : topo.components) needs = needs || c.genus > 0 || c.boundary_loops > 1;
    CHECK(cg->empty() == !needs);
    check_cut_graph(mesh, *cg);
  }
}

TEST_CASE("a holed part whose loops tie in distance still opens into one disc (mesh_fuzz F13)") {
  // What repair left of a triangle soup the fuzzer found: genus 0, five boundary loops, on a
  // lattice, with vertices split where the soup pinched (coincident positions). The spokes
  // of the coned loops weigh 0, so a loop's vertices tie with the loop's apex; the plain
  // shortest-path tree hung one loop's vertices from two others, and the cut graph closed a
  // cycle that cut a piece off (two components, a 400 "no path between terminals").
  const fx::Soup soup{
      {Vec3(-49, -49, -30), Vec3(-70, 0, -30),  Vec3(0, 0, -70),   Vec3(-5, -9, -16), Vec3(30, 0, -40),
       Vec3(-71, -71, 0),   Vec3(-49, -49, 30), Vec3(0, -100, -1), Vec3(-28, -28, 0), Vec3(-40, 0, 0),
       Vec3(8, 7, -8),      Vec3(-1, -1, -1),   Vec3(7, 7, 11),    Vec3(12, 11, 12),  Vec3(13, 8, 13),
       Vec3(10, 10, 14),    Vec3(14, 9, 14),    Vec3(15, 10, 15),  Vec3(60, -60, -1), Vec3(8, 12, 16),
       Vec3(13, 13, 17),    Vec3(14, 14, 18),   Vec3(17, 12, 17),  Vec3(18, 13, 18),  Vec3(19, 14, 19),
       Vec3(15, 15, 19),    Vec3(-1, 122, -1),  Vec3(0, 0, -70),   Vec3(30, 0, -40),  Vec3(0, -100, -1),
       Vec3(7, 7, 11),      Vec3(7, 7, 11),     Vec3(9, 9, 13),    Vec3(13, 8, 13),   Vec3(11, 11, 15),
       Vec3(19, 14, 19),    Vec3(16, 15, 30),   Vec3(0, 0, 60)},
      {{0, 1, 9},    {0, 4, 5},    {0, 5, 1},    {0, 9, 8},    {1, 5, 25},   {1, 21, 9},   {1, 24, 21},  {2, 10, 3},
       {27, 28, 8},  {27, 6, 11},  {27, 8, 6},   {27, 11, 26}, {27, 26, 28}, {3, 10, 15},  {3, 14, 12},  {3, 15, 17},
       {3, 17, 14},  {28, 7, 8},   {28, 26, 37}, {28, 37, 7},  {5, 6, 25},   {5, 29, 11},  {5, 11, 6},   {6, 8, 36},
       {6, 36, 25},  {29, 18, 11}, {8, 9, 36},   {9, 21, 23},  {9, 23, 36},  {10, 30, 16}, {10, 16, 15}, {30, 32, 16},
       {12, 14, 32}, {31, 22, 34}, {32, 13, 16}, {32, 14, 17}, {32, 34, 13}, {32, 17, 34}, {13, 33, 16}, {13, 34, 23},
       {13, 21, 19}, {13, 23, 21}, {15, 16, 19}, {15, 19, 22}, {15, 22, 17}, {34, 20, 23}, {34, 22, 20}, {19, 21, 24},
       {19, 24, 22}, {20, 22, 24}, {20, 35, 25}, {20, 25, 36}, {20, 36, 23}}};
  const HalfedgeMesh mesh = fx::build_fixture(soup);
  const Topology topo = compute_topology(mesh);
  REQUIRE(topo.components.size() == 1);
  REQUIRE(topo.boundary_loops.size() == 5);
  auto cg = compute_cut_graph(mesh);
  REQUIRE(cg.ok());
  check_cut_graph(mesh, *cg);
}

TEST_CASE("cut graph honours cancellation") {
  const HalfedgeMesh mesh = fx::build_fixture(fx::holed_slab(2));
  CancelToken token;
  token.cancel();
  auto cg = compute_cut_graph(mesh, token);
  REQUIRE(!cg.ok());
  CHECK(cg.error().code == ErrorCode::kCancelled);
}

}  // namespace seam_cut_graph_test
