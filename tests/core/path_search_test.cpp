#include <doctest/doctest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <vector>

#include "core/paths/path_search.h"
#include "fixtures.h"

using namespace seam::core;
namespace fx = seam::fixtures;

namespace {

HalfedgeMesh torus_mesh() {
  const auto s = fx::torus(16, 8);
  auto mesh = build_halfedge_mesh(s.positions, s.triangles);
  REQUIRE(mesh.ok());
  return std::move(mesh).value();
}

// Bellman–Ford over the edge graph: the oracle, independent of any heap. Vertices in
// `blocked` are reached but never relaxed from (unless a source); `forbidden` never reached.
std::vector<double> bellman_ford(const EdgeGraph& g, const std::vector<VertexId>& sources,
                                 const std::vector<std::uint8_t>& blocked, const std::vector<std::uint8_t>& forbidden) {
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> d(g.num_vertices(), inf);
  std::vector<std::uint8_t> is_source(g.num_vertices(), 0);
  for (VertexId s : sources) d[s.index()] = 0, is_source[s.index()] = 1;
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t v = 0; v < g.num_vertices(); ++v) {
      if (d[v] == inf || (blocked[v] && !is_source[v])) continue;
      for (std::uint32_t slot = g.offsets[v]; slot < g.offsets[v + 1]; ++slot) {
        const std::size_t w = g.head[slot].index();
        if (forbidden[w]) continue;
        if (d[v] + g.weight[slot] < d[w] - 1e-15) {
          d[w] = d[v] + g.weight[slot];
          changed = true;
        }
      }
    }
  }
  return d;
}

}  // namespace

TEST_CASE("PathSearch equals Bellman–Ford with blocked and forbidden vertices, across reused runs") {
  const HalfedgeMesh mesh = torus_mesh();
  const EdgeGraph graph = build_edge_graph(mesh);
  PathSearch search(graph);
  std::mt19937 rng(5);
  for (int trial = 0; trial < 6; ++trial) {
    CAPTURE(trial);
    std::vector<std::uint8_t> blocked(mesh.num_vertices(), 0), forbidden(mesh.num_vertices(), 0);
    search.reset();
    search.clear_marks();
    for (int i = 0; i < 20; ++i) {
      const auto v = rng() % mesh.num_vertices();
      if (i % 2) {
        blocked[v] = 1, forbidden[v] = 0;
        search.block(VertexId(static_cast<std::uint32_t>(v)));
      } else {
        forbidden[v] = 1, blocked[v] = 0;
        search.forbid(VertexId(static_cast<std::uint32_t>(v)));
      }
    }
    std::vector<VertexId> sources;
    while (sources.size() < 2) {
      const VertexId v(static_cast<std::uint32_t>(rng() % mesh.num_vertices()));
      if (!forbidden[v.index()] && std::find(sources.begin(), sources.end(), v) == sources.end()) sources.push_back(v);
    }
    for (VertexId s : sources) search.add_source(s);
    REQUIRE(search.run().ok());
    const auto expected = bellman_ford(graph, sources, blocked, forbidden);
    for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
      CAPTURE(v);
      if (expected[v] == std::numeric_limits<double>::infinity()) {
        CHECK_FALSE(search.reached(VertexId(v)));
      } else {
        REQUIRE(search.reached(VertexId(v)));
        CHECK(search.distance(VertexId(v)) == doctest::Approx(expected[v]).epsilon(1e-12));
        // The traced path has that length and starts at a source.
        const auto path = search.path_to(mesh, VertexId(v));
        if (!path.empty()) {
          CHECK(path_length(mesh, path) == doctest::Approx(expected[v]).epsilon(1e-12));
          CHECK(std::find(sources.begin(), sources.end(), mesh.tail(path.front())) != sources.end());
        }
      }
    }
  }
}

TEST_CASE("PathSearch::run_to_nearest stops at the nearest target, within max_distance and max_settled") {
  const HalfedgeMesh mesh = torus_mesh();
  const EdgeGraph graph = build_edge_graph(mesh);
  PathSearch search(graph);
  const VertexId source(0u);
  search.add_source(source);
  REQUIRE(search.run().ok());
  std::vector<VertexId> by_distance(search.settled().begin(), search.settled().end());
  const VertexId near = by_distance[20], far = by_distance[100];
  const double near_d = search.distance(near);
  const std::vector<VertexId> targets = {far, near};

  search.reset();
  search.add_source(source);
  REQUIRE(search.run_to_nearest(targets).ok());
  CHECK(search.settled().back() == near);
  CHECK(search.distance(near) == doctest::Approx(near_d));
  CHECK_FALSE(search.reached(far));

  search.reset();
  search.add_source(source);
  REQUIRE(search.run_to_nearest(targets, CancelToken::none(), near_d * 0.5).ok());
  CHECK_FALSE(search.reached(near));

  search.reset();
  search.add_source(source);
  REQUIRE(search.run_to_nearest(targets, CancelToken::none(), PathSearch::kUnreached, 5).ok());
  CHECK(search.settled().size() == 5);
  CHECK_FALSE(search.reached(near));
  // The cap applies to that run only.
  search.reset();
  search.add_source(source);
  REQUIRE(search.run().ok());
  CHECK(search.settled().size() == mesh.num_vertices());
}
