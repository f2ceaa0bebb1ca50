#include "core/paths/steiner.h"

#include <doctest/doctest.h>

#include "fixture_mesh.h"
#include "tree_oracle.h"

namespace seam_steiner_test {

using namespace seam::core;
namespace fx = seam::fixtures;

namespace {
HalfedgeMesh sphere() {
  return fx::build_fixture(fx::icosphere(3));
}
}  // namespace

TEST_CASE("terminal paths: symmetric, consistent with Dijkstra, independent of the thread count") {
  const HalfedgeMesh mesh = sphere();
  const SearchSurface surface(mesh);
  const std::vector<VertexId> terminals = {VertexId(0u), VertexId(7u), VertexId(100u), VertexId(321u), VertexId(555u)};
  auto one = compute_terminal_paths(surface, terminals, 1);
  auto two = compute_terminal_paths(surface, terminals, 2);
  REQUIRE(one.ok());
  REQUIRE(two.ok());
  const std::size_t k = terminals.size();
  for (std::size_t i = 0; i < k; ++i) {
    const VertexId src[] = {terminals[i]};
    auto tree = dijkstra(surface.graph(), src);
    REQUIRE(tree.ok());
    for (std::size_t j = 0; j < k; ++j) {
      CHECK(one->dist(i, j) == doctest::Approx(tree->distance[terminals[j].index()]).epsilon(1e-12));
      CHECK(one->dist(i, j) == one->dist(j, i));
      CHECK(one->path_between(i, j) == two->path_between(i, j));
      const auto& path = one->path_between(i, j);
      CHECK(path_length(mesh, path) == doctest::Approx(one->dist(i, j)).epsilon(1e-12));
      if (i == j) {
        CHECK(path.empty());
        continue;
      }
      REQUIRE_FALSE(path.empty());
      CHECK(mesh.tail(path.front()) == terminals[i]);
      CHECK(mesh.head(path.back()) == terminals[j]);
      // The reverse direction walks the same edges backwards.
      const auto& back = one->path_between(j, i);
      REQUIRE(back.size() == path.size());
      for (std::size_t s = 0; s < path.size(); ++s) {
        CHECK(back[s] == HalfedgeMesh::twin(path[path.size() - 1 - s]));
      }
    }
  }
}

TEST_CASE("terminal paths on demand: exact distances, shortest paths, an MST of the distance graph") {
  const HalfedgeMesh mesh = sphere();
  // Uneven weights, so ties are rare and Voronoi regions are not round.
  std::vector<double> weights(mesh.num_edges());
  for (std::size_t e = 0; e < weights.size(); ++e) weights[e] = mesh.edge_length(EdgeId(e)) * (1.0 + (e * 37 % 11) / 10.0);
  std::vector<double> lengths(mesh.num_edges());
  for (std::size_t e = 0; e < lengths.size(); ++e) lengths[e] = mesh.edge_length(EdgeId(e));
  // Euclidean (A* pair searches), the same lengths given as weights (plain Dijkstra), and
  // uneven weights.
  for (int variant : {0, 1, 2}) {
    CAPTURE(variant);
    const SearchSurface surface(mesh, variant == 0 ? std::vector<double>{} : variant == 1 ? lengths : weights);
    CHECK(surface.euclidean() == (variant == 0));
    const std::vector<VertexId> terminals = {VertexId(5u),   VertexId(70u),  VertexId(101u), VertexId(300u),
                                             VertexId(444u), VertexId(600u), VertexId(2u)};
    const std::size_t k = terminals.size();
    auto lazy = terminal_paths_on_demand(surface, terminals);
    auto full = compute_terminal_paths(surface, terminals, 1);
    REQUIRE(lazy.ok());
    REQUIRE(full.ok());
    REQUIRE(lazy->mst.size() == k - 1);
    double mst_weight = 0.0;
    for (const auto& [i, j] : lazy->mst) mst_weight += lazy->dist(i, j);
    CHECK(lazy->searches() == 0);  // the MST pairs come from the one multi-source search
    const double oracle = seam::test_oracle::prim_mst_weight(k, [&](std::size_t i, std::size_t j) { return full->dist(i, j); });
    CHECK(mst_weight == doctest::Approx(oracle).epsilon(1e-12));
    // lower_bound runs no search, never exceeds the distance, and is it once it is known.
    for (std::size_t i = 0; i < k; ++i) {
      for (std::size_t j = 0; j < k; ++j) CHECK(lazy->lower_bound(i, j) <= full->dist(i, j));
    }
    CHECK(lazy->searches() == 0);
    CHECK(lazy->lower_bound(0, 3) == lazy->dist(0, 3));
    for (std::size_t i = 0; i < k; ++i) {
      for (std::size_t j = 0; j < k; ++j) {
        CHECK(lazy->dist(i, j) == doctest::Approx(full->dist(i, j)).epsilon(1e-12));
        const auto& path = lazy->path_between(i, j);
        CHECK(path_length(mesh, path, surface.edge_weights()) == doctest::Approx(full->dist(i, j)).epsilon(1e-12));
        if (i == j) continue;
        REQUIRE_FALSE(path.empty());
        CHECK(mesh.tail(path.front()) == terminals[i]);
        CHECK(mesh.head(path.back()) == terminals[j]);
        for (std::size_t s = 1; s < path.size(); ++s) CHECK(mesh.tail(path[s]) == mesh.head(path[s - 1]));
      }
    }
    CHECK(lazy->searches() < k * (k - 1) / 2);  // a search records every terminal it settles
    CHECK(terminal_paths_on_demand(surface, std::span(terminals).first(1)).error().code == ErrorCode::kInvalidArgument);
  }
}

TEST_CASE("terminal paths reject bad terminal sets") {
  const HalfedgeMesh mesh = sphere();
  const SearchSurface surface(mesh);
  const std::vector<VertexId> single = {VertexId(0u)};
  const std::vector<VertexId> repeated = {VertexId(3u), VertexId(3u)};
  const std::vector<VertexId> outside = {VertexId(3u), VertexId(99999u)};
  for (const auto* set : {&single, &repeated, &outside}) {
    auto r = compute_terminal_paths(surface, *set);
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == ErrorCode::kInvalidArgument);
  }
}

TEST_CASE("make_steiner_tree finds Steiner points, branches and the length of a Y-shaped tree") {
  const HalfedgeMesh mesh = sphere();
  const EdgeGraph graph = build_edge_graph(mesh);
  // Three paths from a common centre form a Y; the centre is a Steiner point of degree 3.
  const VertexId centre(0u);
  std::vector<VertexId> leaves;
  std::vector<EdgeId> edges;
  const VertexId src[] = {centre};
  auto tree = dijkstra(graph, src);
  REQUIRE(tree.ok());
  // Pick three leaves whose paths leave the centre by different first edges.
  std::vector<HalfedgeId> first_edges;
  for (std::size_t v = 1; v < mesh.num_vertices() && leaves.size() < 3; ++v) {
    const auto path = trace_path(mesh, *tree, VertexId(v));
    if (path.size() < 4) continue;
    if (std::find(first_edges.begin(), first_edges.end(), path.front()) != first_edges.end()) continue;
    first_edges.push_back(path.front());
    leaves.push_back(VertexId(v));
    for (auto h : path) edges.push_back(HalfedgeMesh::edge(h));
  }
  REQUIRE(leaves.size() == 3);
  const SteinerTree st = make_steiner_tree(mesh, edges, leaves);
  CHECK(st.steiner_points == std::vector<VertexId>{centre});
  CHECK(st.branches.size() == 3);
  double expected = 0;
  for (auto l : leaves) expected += tree->distance[l.index()];
  CHECK(st.length == doctest::Approx(expected));
  std::size_t branch_edges = 0;
  for (const auto& b : st.branches) {
    branch_edges += b.size();
    for (std::size_t i = 1; i < b.size(); ++i) CHECK(mesh.head(b[i - 1]) == mesh.tail(b[i]));
  }
  CHECK(branch_edges == st.edges.size());
  // Duplicate input edges are merged.
  std::vector<EdgeId> doubled = edges;
  doubled.insert(doubled.end(), edges.begin(), edges.end());
  CHECK(make_steiner_tree(mesh, doubled, leaves).edges == st.edges);
}

}  // namespace seam_steiner_test
