#include "core/paths/search_surface.h"

#include <doctest/doctest.h>

#include <utility>
#include <vector>

#include "fixture_mesh.h"

namespace seam_search_surface_test {

using namespace seam::core;
namespace fx = seam::fixtures;

namespace {

HalfedgeMesh sphere() {
  return fx::build_fixture(fx::icosphere(2));
}

// The graph's rows, compared slot by slot with a graph built directly.
void check_same_graph(const EdgeGraph& a, const EdgeGraph& b) {
  CHECK(a.offsets == b.offsets);
  CHECK(a.head == b.head);
  CHECK(a.halfedge == b.halfedge);
  CHECK(a.weight == b.weight);
}

}  // namespace

TEST_CASE("search surface: Euclidean by default, its graph the mesh's, lengths summed edge by edge") {
  const HalfedgeMesh mesh = sphere();
  const SearchSurface surface(mesh);
  CHECK(&surface.mesh() == &mesh);
  CHECK(surface.euclidean());
  CHECK(surface.edge_weights().empty());
  check_same_graph(surface.graph(), build_edge_graph(mesh));
  double total = 0.0;
  std::vector<EdgeId> edges;
  for (std::size_t e = 0; e < mesh.num_edges(); e += 7) {
    CHECK(surface.weight(EdgeId(e)) == mesh.edge_length(EdgeId(e)));
    edges.push_back(EdgeId(e));
    total += mesh.edge_length(EdgeId(e));
  }
  CHECK(surface.length(edges) == total);
  CHECK(surface.length(std::vector<EdgeId>{}) == 0.0);
}

TEST_CASE("search surface: given weights are the graph's, the lengths' and switch A* off") {
  const HalfedgeMesh mesh = sphere();
  std::vector<double> weights(mesh.num_edges());
  for (std::size_t e = 0; e < weights.size(); ++e) weights[e] = 1.0 + static_cast<double>(e % 5);
  const SearchSurface surface(mesh, weights);
  CHECK_FALSE(surface.euclidean());
  REQUIRE(surface.edge_weights().size() == mesh.num_edges());
  check_same_graph(surface.graph(), build_edge_graph(mesh, weights));
  // A path of three half-edges around a face, and the same edges as a set.
  const HalfedgeId h0 = mesh.face_halfedge(FaceId(3u));
  const std::vector<HalfedgeId> loop = {h0, mesh.next(h0), mesh.next(mesh.next(h0))};
  double expected = 0.0;
  std::vector<EdgeId> edges;
  for (HalfedgeId h : loop) {
    expected += weights[HalfedgeMesh::edge(h).index()];
    edges.push_back(HalfedgeMesh::edge(h));
    CHECK(surface.weight(HalfedgeMesh::edge(h)) == weights[HalfedgeMesh::edge(h).index()]);
  }
  CHECK(surface.path_length(loop) == expected);
  CHECK(surface.length(edges) == expected);
}

TEST_CASE("search surface: a move keeps the graph where searches found it") {
  const HalfedgeMesh mesh = sphere();
  SearchSurface first(mesh, std::vector<double>(mesh.num_edges(), 2.0));
  const EdgeGraph* graph = &first.graph();
  const SearchSurface moved(std::move(first));
  CHECK(&moved.graph() == graph);
  CHECK(&moved.mesh() == &mesh);
  CHECK(moved.weight(EdgeId(0u)) == 2.0);
}

}  // namespace seam_search_surface_test
