#include <doctest/doctest.h>

#include <random>

#include "core/paths/geodesic.h"
#include "fixtures.h"

namespace seam_geodesic_test {

using namespace seam::core;
namespace fx = seam::fixtures;

namespace {

// Bellman-Ford over the undirected edge graph: the brute-force reference.
std::vector<double> bellman_ford(const HalfedgeMesh& mesh, const std::vector<VertexId>& sources) {
  std::vector<double> d(mesh.num_vertices(), ShortestPathTree::kUnreached);
  for (auto s : sources) d[s.index()] = 0;
  for (std::size_t round = 0; round < mesh.num_vertices(); ++round) {
    bool changed = false;
    for (std::size_t e = 0; e < mesh.num_edges(); ++e) {
      const HalfedgeId h = HalfedgeMesh::halfedge(EdgeId(e));
      const auto a = mesh.tail(h).index();
      const auto b = mesh.head(h).index();
      const double w = mesh.edge_length(EdgeId(e));
      if (d[a] + w < d[b]) d[b] = d[a] + w, changed = true;
      if (d[b] + w < d[a]) d[a] = d[b] + w, changed = true;
    }
    if (!changed) break;
  }
  return d;
}

// A jittered icosphere so that edge lengths differ and ties are rare.
fx::Soup jittered_sphere(unsigned seed) {
  auto s = fx::icosphere(2);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  for (auto& p : s.positions) p += Vec3(u(rng), u(rng), u(rng));
  return s;
}

}  // namespace

TEST_CASE("Dijkstra equals Bellman-Ford on random meshes, single and multi source") {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const auto soup = jittered_sphere(seed);
    auto mesh = build_halfedge_mesh(soup.positions, soup.triangles);
    REQUIRE(mesh.ok());
    const EdgeGraph graph = build_edge_graph(*mesh);
    std::mt19937 rng(seed);
    std::vector<VertexId> sources = {VertexId(static_cast<std::uint32_t>(rng() % mesh->num_vertices()))};
    if (seed % 2 == 0) sources.push_back(VertexId(static_cast<std::uint32_t>(rng() % mesh->num_vertices())));
    auto tree = dijkstra(graph, sources);
    REQUIRE(tree.ok());
    const auto reference = bellman_ford(*mesh, sources);
    for (std::size_t v = 0; v < mesh->num_vertices(); ++v) {
      CHECK(tree->distance[v] == doctest::Approx(reference[v]).epsilon(1e-12));
      // The traced path is a connected chain from a source whose length is the distance.
      const auto path = trace_path(*mesh, *tree, VertexId(v));
      CHECK(path_length(*mesh, path) == doctest::Approx(reference[v]).epsilon(1e-12));
      for (std::size_t i = 1; i < path.size(); ++i) CHECK(mesh->head(path[i - 1]) == mesh->tail(path[i]));
      if (!path.empty()) CHECK(mesh->tail(path.front()) == sources[tree->source[v]]);
    }
  }
}

TEST_CASE("Dijkstra stops early once its targets are settled, and is deterministic") {
  const auto soup = fx::torus(48, 24);
  auto mesh = build_halfedge_mesh(soup.positions, soup.triangles);
  REQUIRE(mesh.ok());
  const EdgeGraph graph = build_edge_graph(*mesh);
  const std::vector<VertexId> source = {VertexId(0u)};
  const std::vector<VertexId> target = {VertexId(5u)};
  auto full = dijkstra(graph, source);
  auto early = dijkstra(graph, source, {.targets = target});
  REQUIRE(full.ok());
  REQUIRE(early.ok());
  CHECK(early->distance[5] == full->distance[5]);
  std::size_t settled = 0;
  for (double d : early->distance) settled += d != ShortestPathTree::kUnreached;
  CHECK(settled < mesh->num_vertices() / 4);
  auto again = dijkstra(graph, source);
  REQUIRE(again.ok());
  CHECK(again->parent == full->parent);
}

TEST_CASE("blocked vertices end paths but are never passed through") {
  // On a cylinder, block a whole ring: nothing beyond it is reachable, the ring itself is.
  const auto soup = fx::open_cylinder(8, 4);
  auto mesh = build_halfedge_mesh(soup.positions, soup.triangles);
  REQUIRE(mesh.ok());
  const EdgeGraph graph = build_edge_graph(*mesh);
  std::vector<std::uint8_t> blocked(mesh->num_vertices(), 0);
  for (int i = 0; i < 8; ++i) blocked[2 * 8 + i] = 1;  // ring j = 2
  const std::vector<VertexId> source = {VertexId(0u)};
  auto tree = dijkstra(graph, source, {.blocked = blocked});
  REQUIRE(tree.ok());
  for (std::size_t v = 0; v < mesh->num_vertices(); ++v) CHECK(tree->reached(VertexId(v)) == (v < 3 * 8));
}

TEST_CASE("custom edge weights, max distance, errors and cancellation") {
  const auto soup = fx::icosphere(1);
  auto mesh = build_halfedge_mesh(soup.positions, soup.triangles);
  REQUIRE(mesh.ok());
  const std::vector<double> unit(mesh->num_edges(), 1.0);
  const EdgeGraph hops = build_edge_graph(*mesh, unit);
  const std::vector<VertexId> source = {VertexId(0u)};
  auto tree = dijkstra(hops, source, {.max_distance = 1.5});
  REQUIRE(tree.ok());
  for (std::size_t v = 0; v < mesh->num_vertices(); ++v) {
    const double d = tree->distance[v];
    CHECK((d == 0.0 || d == 1.0 || d == ShortestPathTree::kUnreached));
  }
  auto none = dijkstra(hops, {});
  REQUIRE_FALSE(none.ok());
  CHECK(none.error().code == ErrorCode::kInvalidArgument);
  const std::vector<VertexId> bad = {VertexId(9999u)};
  auto out = dijkstra(hops, bad);
  REQUIRE_FALSE(out.ok());
  CHECK(out.error().code == ErrorCode::kInvalidArgument);

  CancelToken token;
  token.cancel();
  auto cancelled = dijkstra(hops, source, {}, token);
  // Cancellation is polled every few thousand pops; on a small mesh it may finish first,
  // so use a deadline in the past on a larger mesh.
  const auto big = fx::torus(400, 200);
  auto big_mesh = build_halfedge_mesh(big.positions, big.triangles);
  REQUIRE(big_mesh.ok());
  const EdgeGraph big_graph = build_edge_graph(*big_mesh);
  const CancelToken expired(CancelToken::Clock::now());
  auto r = dijkstra(big_graph, source, {}, expired);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == ErrorCode::kCancelled);
  (void)cancelled;
}

}  // namespace seam_geodesic_test
