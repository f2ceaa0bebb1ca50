#include "core/seam/improve.h"

#include <doctest/doctest.h>

#include <functional>
#include <limits>
#include <map>
#include <queue>
#include <random>
#include <set>

#include "core/paths/steiner.h"
#include "core/seam/baselines.h"
#include "core/seam/skeleton.h"
#include "core/seam/straighten.h"
#include "fixtures.h"
#include "skeleton_fixtures.h"
#include "test_data.h"
#include "tree_oracle.h"

namespace seam_improve_test {

using namespace seam::core;
namespace fx = seam::fixtures;

using seam::test_oracle::full_component_length;

namespace {

HalfedgeMesh spiky_mesh(int spikes, std::vector<VertexId>& tips) {
  const auto s = fx::spiky_sphere(3, fx::spread_directions(spikes));
  for (auto t : s.tips) tips.push_back(VertexId(t));
  return build_halfedge_mesh(s.soup.positions, s.soup.triangles).value();
}

}  // namespace

TEST_CASE("improve_tree: the star tree gets shorter, stays a full component, never below the optimum") {
  std::vector<VertexId> tips;
  const HalfedgeMesh mesh = spiky_mesh(6, tips);
  const SearchSurface surface(mesh);
  auto star = star_tree(surface, tips);
  REQUIRE(star.ok());
  const double star_length = full_component_length(mesh, *star, tips);
  auto improved = improve_tree(surface, tips, *star);
  REQUIRE(improved.ok());
  const double length = full_component_length(mesh, improved->edges, tips);
  CHECK(length < star_length);  // the star through one centre is far from optimal on spikes
  CHECK(improved->stats.length_before == doctest::Approx(star_length));
  CHECK(improved->stats.length_after == doctest::Approx(length));
  CHECK(improved->stats.path_exchanges + improved->stats.vertex_eliminations > 0);
  auto optimal = optimal_seam(surface, tips, 10);
  REQUIRE(optimal.ok());
  CHECK(optimal->length <= length + 1e-9);
}

TEST_CASE("improve_tree: random terminal sets on a real mesh never lengthen the skeleton and are deterministic") {
  const HalfedgeMesh mesh = seam::test_data::load_cgal_halfedge("hand");
  const SearchSurface surface(mesh);
  std::mt19937 rng(7);
  for (int trial = 0; trial < 6; ++trial) {
    std::vector<VertexId> terminals;
    while (terminals.size() < static_cast<std::size_t>(3 + trial)) {
      const VertexId v(static_cast<std::uint32_t>(rng() % mesh.num_vertices()));
      if (std::find(terminals.begin(), terminals.end(), v) == terminals.end()) terminals.push_back(v);
    }
    CAPTURE(trial);
    auto paths = compute_terminal_paths(surface, terminals, 1);
    REQUIRE(paths.ok());
    auto skeleton = skeleton_seam(surface, *paths, {.refine = false, .improve = false});
    REQUIRE(skeleton.ok());
    const double before = full_component_length(mesh, skeleton->tree.edges, terminals);
    auto a = improve_tree(surface, terminals, skeleton->tree.edges);
    auto b = improve_tree(surface, terminals, skeleton->tree.edges);
    REQUIRE(a.ok());
    REQUIRE(b.ok());
    CHECK(a->edges == b->edges);
    const double after = full_component_length(mesh, a->edges, terminals);
    CHECK(after <= before + 1e-12);
    auto optimal = optimal_seam(surface, terminals, 10);
    REQUIRE(optimal.ok());
    CHECK(optimal->length <= after + 1e-9);
  }
}

TEST_CASE("improve_tree: weighted edges are what it shortens") {
  std::vector<VertexId> tips;
  const HalfedgeMesh mesh = spiky_mesh(4, tips);
  // Weights that make edges near +x expensive: the improved tree must not get heavier.
  std::vector<double> weights(mesh.num_edges());
  for (std::size_t e = 0; e < mesh.num_edges(); ++e) {
    const HalfedgeId h = HalfedgeMesh::halfedge(EdgeId(e));
    const double x = 0.5 * (mesh.position(mesh.tail(h)).x() + mesh.position(mesh.head(h)).x());
    weights[e] = mesh.edge_length(EdgeId(e)) * (x > 0.3 ? 5.0 : 1.0);
  }
  const SearchSurface surface(mesh, weights);
  auto star = star_tree(surface, tips);
  REQUIRE(star.ok());
  auto weighted_length = [&](const std::vector<EdgeId>& edges) {
    double sum = 0;
    for (EdgeId e : edges) sum += weights[e.index()];
    return sum;
  };
  auto improved = improve_tree(surface, tips, *star);
  REQUIRE(improved.ok());
  full_component_length(mesh, improved->edges, tips);
  CHECK(weighted_length(improved->edges) <= weighted_length(*star) + 1e-12);
  CHECK(improved->stats.length_after == doctest::Approx(weighted_length(improved->edges)));
}

TEST_CASE("improve_tree: input that is not a full-component tree is refused") {
  std::vector<VertexId> tips;
  const HalfedgeMesh mesh = spiky_mesh(4, tips);
  const SearchSurface surface(mesh);
  const std::vector<EdgeId> one = {EdgeId(0u)};
  auto bad = improve_tree(surface, tips, one);
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.error().code == ErrorCode::kInvalidArgument);
  auto star = star_tree(surface, tips);
  REQUIRE(star.ok());
  // One more edge makes a cycle, a non-terminal leaf or a second piece: never a full component.
  std::vector<EdgeId> extra = *star;
  EdgeId e(0u);
  while (std::find(star->begin(), star->end(), e) != star->end()) e = EdgeId(e.value() + 1);
  extra.push_back(e);
  auto refused = improve_tree(surface, tips, extra);
  REQUIRE_FALSE(refused.ok());
  CHECK(refused.error().code == ErrorCode::kInvalidArgument);
}

TEST_CASE("nearest_terminal_tree: a full component on random sets, shortened by improve_tree, never below optimal") {
  const HalfedgeMesh mesh = seam::test_data::load_cgal_halfedge("hand");
  const SearchSurface surface(mesh);
  std::mt19937 rng(11);
  for (int trial = 0; trial < 5; ++trial) {
    std::vector<VertexId> terminals;
    while (terminals.size() < static_cast<std::size_t>(3 + trial)) {
      const VertexId v(static_cast<std::uint32_t>(rng() % mesh.num_vertices()));
      if (std::find(terminals.begin(), terminals.end(), v) == terminals.end()) terminals.push_back(v);
    }
    CAPTURE(trial);
    auto greedy = nearest_terminal_tree(surface, terminals);
    REQUIRE(greedy.ok());
    const double length = full_component_length(mesh, *greedy, terminals);
    auto improved = improve_tree(surface, terminals, *greedy);
    REQUIRE(improved.ok());
    CHECK(full_component_length(mesh, improved->edges, terminals) <= length + 1e-12);
    auto optimal = optimal_seam(surface, terminals, 10);
    REQUIRE(optimal.ok());
    CHECK(optimal->length <= length + 1e-9);
  }
  const std::vector<VertexId> one = {VertexId(0u)};
  CHECK(nearest_terminal_tree(surface, one).error().code == ErrorCode::kInvalidArgument);
}

namespace {

// The shortest-path heuristic as its definition reads, one fresh search per join (the oracle
// for the growing search of nearest_terminal_tree): from terminals[0] first, then from every
// non-terminal vertex of the tree; no path passes through a terminal, and the nearest terminal
// not yet joined (smallest distance, then smallest id) is joined by its shortest path.
std::vector<EdgeId> fresh_search_nearest_terminal_tree(const HalfedgeMesh& mesh, const EdgeGraph& graph,
                                                       std::span<const VertexId> terminals) {
  const std::size_t n = mesh.num_vertices();
  std::vector<std::uint8_t> terminal(n, 0), in_tree(n, 0);
  for (VertexId t : terminals) terminal[t.index()] = 1;
  std::vector<VertexId> tree = {terminals[0]};
  in_tree[terminals[0].index()] = 1;
  std::vector<EdgeId> edges;
  for (std::size_t joined = 1; joined < terminals.size(); ++joined) {
    std::vector<double> dist(n, std::numeric_limits<double>::infinity());
    std::vector<HalfedgeId> parent(n);
    using Entry = std::pair<double, std::uint32_t>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
    for (VertexId v : tree) {
      if (joined > 1 && terminal[v.index()]) continue;
      dist[v.index()] = 0.0;
      queue.push({0.0, v.value()});
    }
    VertexId reached;
    while (!queue.empty() && !reached.valid()) {
      const auto [d, v] = queue.top();
      queue.pop();
      if (d > dist[v]) continue;
      if (terminal[v] && !(joined == 1 && v == terminals[0].value())) {
        if (!in_tree[v]) reached = VertexId(v);
        continue;
      }
      for (std::uint32_t slot = graph.offsets[v]; slot < graph.offsets[v + 1]; ++slot) {
        const std::uint32_t w = graph.head[slot].value();
        if (terminal[w] && in_tree[w]) continue;
        if (d + graph.weight[slot] < dist[w]) {
          dist[w] = d + graph.weight[slot];
          parent[w] = graph.halfedge[slot];
          queue.push({dist[w], w});
        }
      }
    }
    REQUIRE(reached.valid());
    for (HalfedgeId h = parent[reached.index()]; h.valid(); h = parent[mesh.tail(h).index()]) {
      edges.push_back(HalfedgeMesh::edge(h));
      for (VertexId w : {mesh.tail(h), mesh.head(h)}) {
        if (!in_tree[w.index()]) tree.push_back(w);
        in_tree[w.index()] = 1;
      }
    }
  }
  std::sort(edges.begin(), edges.end());
  return edges;
}

}  // namespace

TEST_CASE(
    "nearest_terminal_tree: the growing search joins what a fresh search per join joins, and gives up at its budget") {
  const HalfedgeMesh mesh = seam::test_data::load_cgal_halfedge("hand");
  const SearchSurface surface(mesh);
  std::mt19937 rng(23);
  for (std::size_t k : {2u, 3u, 5u, 8u, 13u, 21u}) {
    std::vector<VertexId> terminals;
    while (terminals.size() < k) {
      const VertexId v(static_cast<std::uint32_t>(rng() % mesh.num_vertices()));
      if (std::find(terminals.begin(), terminals.end(), v) == terminals.end()) terminals.push_back(v);
    }
    CAPTURE(k);
    auto grown = nearest_terminal_tree(surface, terminals);
    REQUIRE(grown.ok());
    CHECK(*grown == fresh_search_nearest_terminal_tree(mesh, surface.graph(), terminals));
    CHECK(check_full_component_tree(mesh, *grown, terminals).ok());
    // A budget below what the first join settles: no tree.
    auto starved = nearest_terminal_tree(surface, terminals, CancelToken::none(), 3);
    REQUIRE(starved.ok());
    CHECK(starved->empty());
  }
}

}  // namespace seam_improve_test
