#include <doctest/doctest.h>

#include <algorithm>
#include <map>
#include <random>
#include <vector>

#include "core/paths/geodesic.h"
#include "core/seam/straighten.h"
#include "fixtures.h"

namespace seam_straighten_test {

using namespace seam::core;
namespace fx = seam::fixtures;

namespace {

HalfedgeMesh sphere() {
  const auto s = fx::icosphere(3);
  auto mesh = build_halfedge_mesh(s.positions, s.triangles);
  REQUIRE(mesh.ok());
  return std::move(mesh).value();
}

std::vector<EdgeId> path_edges(const HalfedgeMesh& mesh, const EdgeGraph& graph, VertexId a, VertexId b) {
  const VertexId sources[] = {a};
  auto tree = dijkstra(graph, sources);
  REQUIRE(tree.ok());
  std::vector<EdgeId> edges;
  for (HalfedgeId h : trace_path(mesh, *tree, b)) edges.push_back(HalfedgeMesh::edge(h));
  return edges;
}

std::map<std::uint32_t, int> degrees(const HalfedgeMesh& mesh, const std::vector<EdgeId>& edges) {
  std::map<std::uint32_t, int> degree;
  for (EdgeId e : edges) {
    ++degree[mesh.tail(HalfedgeMesh::halfedge(e)).value()];
    ++degree[mesh.head(HalfedgeMesh::halfedge(e)).value()];
  }
  return degree;
}

}  // namespace

TEST_CASE("check_full_component_tree: a path between two terminals passes, each violation is named") {
  const HalfedgeMesh mesh = sphere();
  const EdgeGraph graph = build_edge_graph(mesh);
  const VertexId a(0u), b(40u), c(100u);
  const std::vector<EdgeId> ab = path_edges(mesh, graph, a, b);
  REQUIRE(ab.size() >= 2);
  const std::vector<VertexId> two = {a, b};
  CHECK(check_full_component_tree(mesh, ab, two).ok());

  // A terminal in the middle of the path is not a leaf.
  const HalfedgeId mid_h = HalfedgeMesh::halfedge(ab[ab.size() / 2]);
  const std::vector<VertexId> inner = {a, b, mesh.tail(mid_h)};
  auto not_leaf = check_full_component_tree(mesh, ab, inner);
  REQUIRE_FALSE(not_leaf.ok());
  CHECK(not_leaf.error().code == ErrorCode::kTopologyViolation);

  // A terminal the edges miss.
  const std::vector<VertexId> missed = {a, b, c};
  auto missing = check_full_component_tree(mesh, ab, missed);
  REQUIRE_FALSE(missing.ok());
  CHECK(missing.error().code == ErrorCode::kTopologyViolation);

  // A dangling non-terminal end: drop the last edge.
  const std::vector<EdgeId> cut(ab.begin(), ab.end() - 1);
  auto dangling = check_full_component_tree(mesh, cut, two);
  REQUIRE_FALSE(dangling.ok());
  CHECK(dangling.error().code == ErrorCode::kTopologyViolation);

  // A cycle: the three edges of a face at an inner vertex of the path.
  std::vector<EdgeId> cyclic = ab;
  const HalfedgeId h = mesh.vertex_halfedge(mesh.tail(mid_h));
  for (HalfedgeId x : {h, mesh.next(h), mesh.next(mesh.next(h))}) cyclic.push_back(HalfedgeMesh::edge(x));
  std::sort(cyclic.begin(), cyclic.end());
  cyclic.erase(std::unique(cyclic.begin(), cyclic.end()), cyclic.end());
  auto cycle = check_full_component_tree(mesh, cyclic, two);
  REQUIRE_FALSE(cycle.ok());
  CHECK(cycle.error().code == ErrorCode::kTopologyViolation);

  // Each error names the first offender: the inner terminal, the missed one, the dangling
  // end, the edge that closes the cycle (in the edges' order; an edge out of range after it
  // comes second), and of a second piece its lowest vertex.
  CHECK(not_leaf.error().elements == std::vector<std::uint32_t>{mesh.tail(mid_h).value()});
  CHECK(missing.error().elements == std::vector<std::uint32_t>{c.value()});
  const std::map<std::uint32_t, int> cut_degree = degrees(mesh, cut);
  std::uint32_t dangling_end = 0;
  for (const auto& [v, d] : cut_degree) {
    if (d == 1 && v != a.value() && v != b.value()) {
      dangling_end = v;
      break;
    }
  }
  // (With both terminals, b's degree 0 is named first; with a alone, the dangling end.)
  CHECK(dangling.error().elements == std::vector<std::uint32_t>{b.value()});
  const std::vector<VertexId> one = {a};
  auto dangling_end_named = check_full_component_tree(mesh, cut, one);
  REQUIRE_FALSE(dangling_end_named.ok());
  CHECK(dangling_end_named.error().elements == std::vector<std::uint32_t>{dangling_end});
  std::vector<EdgeId> first_closing;  // the oracle: union-find over the mesh's vertices
  {
    std::vector<std::uint32_t> parent(mesh.num_vertices());
    for (std::uint32_t v = 0; v < parent.size(); ++v) parent[v] = v;
    auto find = [&](std::uint32_t x) {
      while (parent[x] != x) x = parent[x];
      return x;
    };
    for (EdgeId e : cyclic) {
      const std::uint32_t ra = find(mesh.tail(HalfedgeMesh::halfedge(e)).value());
      const std::uint32_t rb = find(mesh.head(HalfedgeMesh::halfedge(e)).value());
      if (ra == rb) {
        first_closing.push_back(e);
        break;
      }
      parent[ra] = rb;
    }
  }
  REQUIRE(first_closing.size() == 1);
  CHECK(cycle.error().elements == std::vector<std::uint32_t>{first_closing[0].value()});
  std::vector<EdgeId> cyclic_then_bad = cyclic;
  cyclic_then_bad.push_back(EdgeId(static_cast<std::uint32_t>(mesh.num_edges())));
  auto still_cycle = check_full_component_tree(mesh, cyclic_then_bad, two);
  REQUIRE_FALSE(still_cycle.ok());
  CHECK(still_cycle.error().elements == cycle.error().elements);
  std::vector<EdgeId> bad_first = {EdgeId(static_cast<std::uint32_t>(mesh.num_edges()))};
  bad_first.insert(bad_first.end(), cyclic.begin(), cyclic.end());
  auto out_of_range = check_full_component_tree(mesh, bad_first, two);
  REQUIRE_FALSE(out_of_range.ok());
  CHECK(out_of_range.error().elements == std::vector<std::uint32_t>{static_cast<std::uint32_t>(mesh.num_edges())});
  // Two pieces: the path and, apart from it, one edge far away (around c).
  std::vector<EdgeId> two_pieces = ab;
  const HalfedgeId far = mesh.vertex_halfedge(c);
  two_pieces.push_back(HalfedgeMesh::edge(far));
  const std::uint32_t lowest_apart = std::min(mesh.tail(far).value(), mesh.head(far).value());
  REQUIRE(degrees(mesh, ab).count(lowest_apart) == 0);
  auto apart = check_full_component_tree(mesh, two_pieces, two);
  REQUIRE_FALSE(apart.ok());
  CHECK(apart.error().elements == std::vector<std::uint32_t>{lowest_apart});
}

TEST_CASE("star_tree: every terminal a leaf of one tree on random sets, refused when a terminal is walled in") {
  const HalfedgeMesh mesh = sphere();
  const SearchSurface surface(mesh);
  std::mt19937 rng(3);
  for (int trial = 0; trial < 10; ++trial) {
    std::vector<VertexId> terminals;
    while (terminals.size() < static_cast<std::size_t>(3 + trial % 6)) {
      const VertexId v(static_cast<std::uint32_t>(rng() % mesh.num_vertices()));
      if (std::find(terminals.begin(), terminals.end(), v) == terminals.end()) terminals.push_back(v);
    }
    CAPTURE(trial);
    auto star = star_tree(surface, terminals);
    REQUIRE(star.ok());
    const auto degree = degrees(mesh, *star);
    CHECK(degree.size() == star->size() + 1);  // a tree (connected, as checked below)
    for (VertexId t : terminals) CHECK(degree.at(t.value()) == 1);
    CHECK(check_full_component_tree(mesh, *star, terminals).ok());
  }
  // Vertex 0 and all its neighbours are terminals: no tree can keep them all leaves.
  std::vector<VertexId> walled = {VertexId(0u)};
  const HalfedgeId h0 = mesh.vertex_halfedge(VertexId(0u));
  HalfedgeId h = h0;
  do {
    walled.push_back(mesh.head(h));
    h = mesh.next(HalfedgeMesh::twin(h));
  } while (h != h0);
  auto refused = star_tree(surface, walled);
  REQUIRE_FALSE(refused.ok());
  CHECK(refused.error().code == ErrorCode::kInvalidArgument);
}

}  // namespace seam_straighten_test
