#include <doctest/doctest.h>

#include <algorithm>
#include <random>

#include "core/mesh/cut.h"
#include "core/mesh/cut_check.h"
#include "core/paths/geodesic.h"
#include "core/mesh/topology.h"
#include "fixture_mesh.h"
#include "test_data.h"

namespace seam_cut_test {

using namespace seam::core;
namespace fx = seam::fixtures;

namespace {

// Faces keep their ids and corner order; every cut vertex sits where its original does.
void check_correspondence(const HalfedgeMesh& mesh, const CutMesh& cut) {
  REQUIRE(check_invariants(cut.mesh).ok());
  REQUIRE(cut.mesh.num_faces() == mesh.num_faces());
  REQUIRE(cut.to_original.size() == cut.mesh.num_vertices());
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    const auto a = mesh.face_vertices(FaceId(f));
    const auto b = cut.mesh.face_vertices(FaceId(f));
    for (int i = 0; i < 3; ++i) CHECK(cut.to_original[b[i]] == a[i]);
  }
  for (std::size_t v = 0; v < cut.mesh.num_vertices(); ++v) {
    CHECK(cut.mesh.position(VertexId(v)) == mesh.position(cut.to_original[VertexId(v)]));
  }
}

// A path of `n` edges along a shortest path between two far vertices.
std::vector<EdgeId> path_edges(const HalfedgeMesh& mesh, VertexId a, VertexId b) {
  const EdgeGraph graph = build_edge_graph(mesh);
  const VertexId src[] = {a};
  auto tree = dijkstra(graph, src);
  REQUIRE(tree.ok());
  std::vector<EdgeId> edges;
  for (HalfedgeId h : trace_path(mesh, *tree, b)) edges.push_back(HalfedgeMesh::edge(h));
  return edges;
}

}  // namespace

TEST_CASE("cutting along nothing gives the same mesh") {
  const HalfedgeMesh mesh = fx::build_fixture(fx::icosphere(2));
  auto cut = cut_along_edges(mesh, {});
  REQUIRE(cut.ok());
  check_correspondence(mesh, *cut);
  CHECK(cut->mesh.num_vertices() == mesh.num_vertices());
  CHECK(cut->mesh.num_edges() == mesh.num_edges());
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) CHECK(cut->to_original[VertexId(v)] == VertexId(v));
  CHECK(check_is_disc(cut->mesh).error().code == ErrorCode::kTopologyViolation);
}

TEST_CASE("cutting a sphere along a path opens it into a disc with one copy per wedge") {
  const HalfedgeMesh mesh = fx::build_fixture(fx::icosphere(2));
  const auto edges = path_edges(mesh, VertexId(0u), VertexId(3u));  // antipodal-ish icosahedron vertices
  REQUIRE(edges.size() >= 2);
  auto cut = cut_along_edges(mesh, edges);
  REQUIRE(cut.ok());
  check_correspondence(mesh, *cut);
  // A path of n edges: its n - 1 inner vertices have two wedges, its ends one.
  CHECK(cut->mesh.num_vertices() == mesh.num_vertices() + edges.size() - 1);
  CHECK(cut->mesh.num_edges() == mesh.num_edges() + edges.size());
  CHECK(check_is_disc(cut->mesh).ok());
  const Topology topo = compute_topology(cut->mesh);
  REQUIRE(topo.boundary_loops.size() == 1);
  CHECK(topo.boundary_loops[0].size() == 2 * edges.size());
}

TEST_CASE("cutting a sphere along a closed loop gives two discs") {
  const HalfedgeMesh mesh = fx::build_fixture(fx::uv_sphere(16, 8, false));
  // The equator: ring 4 of the uv sphere (vertices 2 + 3*16 ... 2 + 3*16 + 15).
  std::vector<EdgeId> loop;
  for (int i = 0; i < 16; ++i) {
    const VertexId a(static_cast<std::uint32_t>(2 + 3 * 16 + i));
    const VertexId b(static_cast<std::uint32_t>(2 + 3 * 16 + (i + 1) % 16));
    const HalfedgeId h = mesh.find_halfedge(a, b);
    REQUIRE(h.valid());
    loop.push_back(HalfedgeMesh::edge(h));
  }
  auto cut = cut_along_edges(mesh, loop);
  REQUIRE(cut.ok());
  check_correspondence(mesh, *cut);
  CHECK(cut->mesh.num_vertices() == mesh.num_vertices() + 16);
  const Topology topo = compute_topology(cut->mesh);
  CHECK(topo.components.size() == 2);
  CHECK(check_is_disc(cut->mesh).ok());
}

TEST_CASE("a torus needs two loops: one gives an annulus, which is not a disc") {
  const int nu = 24, nv = 12;
  const HalfedgeMesh mesh = fx::build_fixture(fx::torus(nu, nv));
  auto id = [&](int i, int j) { return VertexId(static_cast<std::uint32_t>(((i + nu) % nu) * nv + (j + nv) % nv)); };
  std::vector<EdgeId> meridian, longitude;
  for (int j = 0; j < nv; ++j) meridian.push_back(HalfedgeMesh::edge(mesh.find_halfedge(id(0, j), id(0, j + 1))));
  for (int i = 0; i < nu; ++i) longitude.push_back(HalfedgeMesh::edge(mesh.find_halfedge(id(i, 0), id(i + 1, 0))));
  auto annulus = cut_along_edges(mesh, meridian);
  REQUIRE(annulus.ok());
  auto status = check_is_disc(annulus->mesh);
  REQUIRE(!status.ok());
  CHECK(status.error().code == ErrorCode::kTopologyViolation);
  CHECK(status.error().message.find("2 boundary loops") != std::string::npos);
  std::vector<EdgeId> both = meridian;
  both.insert(both.end(), longitude.begin(), longitude.end());
  auto square = cut_along_edges(mesh, both);
  REQUIRE(square.ok());
  check_correspondence(mesh, *square);
  CHECK(check_is_disc(square->mesh).ok());
  // The crossing vertex becomes the square's four corners.
  CHECK(std::count(square->to_original.begin(), square->to_original.end(), id(0, 0)) == 4);
}

TEST_CASE("boundary edges are already open, several components are checked one by one") {
  const HalfedgeMesh mesh = fx::build_fixture(fx::join(fx::disc(), fx::translated(fx::disc(), Vec3(3, 0, 0))));
  std::vector<EdgeId> boundary;
  for (std::size_t e = 0; e < mesh.num_edges(); ++e) {
    if (mesh.is_boundary(EdgeId(e))) boundary.push_back(EdgeId(e));
  }
  auto cut = cut_along_edges(mesh, boundary);
  REQUIRE(cut.ok());
  CHECK(cut->mesh.num_vertices() == mesh.num_vertices());
  CHECK(check_is_disc(cut->mesh).ok());
  const HalfedgeMesh mixed = fx::build_fixture(fx::join(fx::disc(), fx::translated(fx::icosphere(1), Vec3(3, 0, 0))));
  auto status = check_is_disc(mixed);
  REQUIRE(!status.ok());
  CHECK(status.error().message.find("component 1") != std::string::npos);
}

TEST_CASE("hostile cuts: out-of-range edge ids and an unrepresentable slit are typed errors") {
  const HalfedgeMesh mesh = fx::build_fixture(fx::icosphere(1));
  const EdgeId bad[] = {EdgeId(static_cast<std::uint32_t>(mesh.num_edges()))};
  auto r = cut_along_edges(mesh, bad);
  REQUIRE(!r.ok());
  CHECK(r.error().code == ErrorCode::kInvalidArgument);
  CHECK(r.error().elements == std::vector<std::uint32_t>{static_cast<std::uint32_t>(mesh.num_edges())});
  const EdgeId invalid[] = {EdgeId()};
  CHECK(cut_along_edges(mesh, invalid).error().code == ErrorCode::kInvalidArgument);
  // One interior edge alone: both ends keep one wedge, the slit cannot be a simplicial mesh.
  const EdgeId slit[] = {EdgeId(0u)};
  auto s = cut_along_edges(mesh, slit);
  REQUIRE(!s.ok());
  CHECK(s.error().code == ErrorCode::kTopologyViolation);
}

TEST_CASE("real mesh: cutting the CGAL hand along a long path keeps every face and opens a disc") {
  const HalfedgeMesh mesh = seam::test_data::load_cgal_halfedge("hand");
  const auto edges = path_edges(mesh, VertexId(0u), VertexId(static_cast<std::uint32_t>(mesh.num_vertices() / 2)));
  auto cut = cut_along_edges(mesh, edges);
  REQUIRE(cut.ok());
  check_correspondence(mesh, *cut);
  CHECK(cut->mesh.num_vertices() == mesh.num_vertices() + edges.size() - 1);
  CHECK(check_is_disc(cut->mesh).ok());
}

TEST_CASE("check_cut_is_disc agrees with cutting and checking, on random edge sets") {
  std::mt19937 rng(99);
  const fx::Soup soups[] = {fx::icosphere(1), fx::torus(8, 6), fx::open_cylinder(8, 3), fx::disc(3, 8),
                            fx::join(fx::icosphere(0), fx::translated(fx::disc(2, 6), Vec3(4, 0, 0)))};
  int agreed = 0;
  for (const auto& soup : soups) {
    const HalfedgeMesh mesh = fx::build_fixture(soup);
    const EdgeGraph graph = build_edge_graph(mesh);
    for (int trial = 0; trial < 80; ++trial) {
      // Unions of 1-4 shortest paths between random vertices: trees, cycles, slits, forests.
      std::uniform_int_distribution<std::uint32_t> pick(0, static_cast<std::uint32_t>(mesh.num_vertices() - 1));
      std::vector<EdgeId> edges;
      const int paths = 1 + trial % 4;
      for (int p = 0; p < paths; ++p) {
        const VertexId src[] = {VertexId(pick(rng))};
        auto tree = dijkstra(graph, src);
        REQUIRE(tree.ok());
        for (HalfedgeId h : trace_path(mesh, *tree, VertexId(pick(rng)))) edges.push_back(HalfedgeMesh::edge(h));
      }
      const Status fast = check_cut_is_disc(mesh, edges);
      auto cut = cut_along_edges(mesh, edges);
      const bool slow = cut.ok() && check_is_disc(cut->mesh).ok();
      CAPTURE(trial);
      CHECK(fast.ok() == slow);
      if (!cut.ok()) CHECK(!fast.ok());
      agreed += fast.ok() == slow;
    }
  }
  CHECK(agreed == 400);
}

}  // namespace seam_cut_test
