#include "core/paths/path_search.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <limits>
#include <numeric>
#include <random>
#include <set>
#include <type_traits>
#include <utility>
#include <vector>

#include "fixtures.h"

namespace seam_path_search_test {

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

TEST_CASE("PathSearch: a run's sources, distances and settled vertices end with it (reset is a new generation)") {
  const HalfedgeMesh mesh = torus_mesh();
  const EdgeGraph graph = build_edge_graph(mesh);
  PathSearch search(graph);
  const VertexId b(0u);
  VertexId a;
  mesh.for_each_outgoing(b, [&](HalfedgeId h) {
    if (!a.valid()) a = mesh.head(h);
  });
  std::vector<std::uint8_t> blocked(mesh.num_vertices(), 0), forbidden(mesh.num_vertices(), 0);
  blocked[b.index()] = 1;
  search.block(b);
  // Run 1: the blocked b is a source, so it is expanded.
  search.add_source(b);
  REQUIRE(search.run().ok());
  CHECK(search.reached(a));
  // Run 2 from b's neighbour a: b is blocked and no longer a source, so no path passes
  // through it (a source flag left over would let them).
  for (int run = 0; run < 3; ++run) {
    search.reset();
    CHECK_FALSE(search.reached(a));  // forgotten before the run
    CHECK_FALSE(search.parent(a).valid());
    search.add_source(a);
    REQUIRE(search.run().ok());
    const auto expected = bellman_ford(graph, {a}, blocked, forbidden);
    for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
      CAPTURE(v);
      REQUIRE(search.reached(VertexId(v)) == (expected[v] < std::numeric_limits<double>::infinity()));
      if (search.reached(VertexId(v)))
        CHECK(search.distance(VertexId(v)) == doctest::Approx(expected[v]).epsilon(1e-12));
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

namespace {

void push_entry(IndexedHeap& heap, std::uint32_t v, double) { heap.push_or_decrease(v); }
template <class Heap>
void push_entry(Heap& heap, std::uint32_t v, double key) {
  heap.push(key, v);
}

// A plain run_dijkstra visitor that records the settling order; stale entries are skipped.
template <class Heap>
struct OrderVisitor {
  std::vector<double>& dist;
  Heap& heap;
  std::vector<std::uint8_t> settled;
  std::vector<std::uint32_t> order;

  SettleAction settle(std::uint32_t v, double key) {
    if (settled[v] || key > dist[v]) return SettleAction::kSkip;
    settled[v] = 1;
    order.push_back(v);
    return SettleAction::kExpand;
  }
  double distance(std::uint32_t v) const { return dist[v]; }
  static std::uint32_t graph_vertex(std::uint32_t v) { return v; }
  void relax(std::uint32_t, std::uint32_t w, double nd, std::uint32_t) {
    if (nd < dist[w]) {
      dist[w] = nd;
      push_entry(heap, w, nd);
    }
  }
};

}  // namespace

TEST_CASE("run_dijkstra settles by (distance, vertex id) with every heap, from sources with offsets") {
  // Small integer weights make many exact ties. With positive weights every vertex at
  // distance d is in the heap before the first of them is popped, so the kernel must settle
  // in (distance, id) order; distances are checked against Bellman-Ford with start offsets.
  const HalfedgeMesh mesh = torus_mesh();
  std::mt19937 rng(5);
  std::vector<double> weights(mesh.num_edges());
  for (double& w : weights) w = static_cast<double>(1 + rng() % 3);
  const EdgeGraph g = build_edge_graph(mesh, weights);
  const std::size_t n = g.num_vertices();
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<std::pair<double, std::uint32_t>> seeds;
  for (std::uint32_t v : {3u, 40u, 41u, 77u, 100u}) seeds.emplace_back(static_cast<double>(rng() % 3), v);
  std::sort(seeds.begin(), seeds.end());

  std::vector<double> oracle(n, inf);
  for (const auto& [d, v] : seeds) oracle[v] = d;
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t v = 0; v < n; ++v) {
      for (std::uint32_t slot = g.offsets[v]; slot < g.offsets[v + 1]; ++slot) {
        if (oracle[v] + g.weight[slot] < oracle[g.head[slot].index()]) {
          oracle[g.head[slot].index()] = oracle[v] + g.weight[slot];
          changed = true;
        }
      }
    }
  }
  std::vector<std::uint32_t> expected(n);
  std::iota(expected.begin(), expected.end(), 0u);
  std::sort(expected.begin(), expected.end(),
            [&](std::uint32_t a, std::uint32_t b) { return std::pair(oracle[a], a) < std::pair(oracle[b], b); });

  auto check = [&](auto& heap, std::vector<double>& dist, const char* name) {
    CAPTURE(name);
    using Heap = std::remove_reference_t<decltype(heap)>;
    OrderVisitor<Heap> visitor{dist, heap, std::vector<std::uint8_t>(n, 0), {}};
    REQUIRE(run_dijkstra(g, heap, visitor, CancelToken::none(), "test").ok());
    CHECK(dist == oracle);
    CHECK(visitor.order == expected);
  };
  {
    std::vector<double> dist(n, inf);
    IndexedHeap heap(dist, n);
    for (const auto& [d, v] : seeds) dist[v] = d, heap.push_or_decrease(v);
    check(heap, dist, "IndexedHeap");
  }
  {
    std::vector<double> dist(n, inf);
    LazyHeap heap;
    for (const auto& [d, v] : seeds) dist[v] = d, heap.push(d, v);
    check(heap, dist, "LazyHeap");
  }
  {
    std::vector<double> dist(n, inf);
    LazyHeap improvements;
    SeededHeap heap(seeds, improvements);
    for (const auto& [d, v] : seeds) dist[v] = d;
    check(heap, dist, "SeededHeap");
  }
}

TEST_CASE("LazyHeap pops in (key, vertex) order under interleaved pushes, pops, ties and re-keying") {
  // The oracle is a sorted multiset of the same entries. Keys from a small range make many
  // ties, which the heap must break by vertex id; the same (key, vertex) may be pushed twice.
  std::mt19937 rng(11);
  LazyHeap heap;
  std::multiset<std::pair<double, std::uint32_t>> oracle;
  std::size_t popped = 0;
  for (int round = 0; round < 4000; ++round) {
    const unsigned action = rng() % 10;
    if (action < 6 || oracle.empty()) {
      const double key = static_cast<double>(rng() % 50) * 0.5;
      const auto v = static_cast<std::uint32_t>(rng() % 200);
      heap.push(key, v);
      oracle.emplace(key, v);
    } else if (action < 9) {
      REQUIRE(!heap.empty());
      CHECK(heap.top() == *oracle.begin());
      CHECK(heap.pop() == *oracle.begin());
      oracle.erase(oracle.begin());
      ++popped;
    } else {
      // A* re-keying: every key grows by a function of its vertex.
      auto delta = [](std::uint32_t v) { return static_cast<double>(v % 7) * 0.25; };
      heap.rekey(delta);
      std::multiset<std::pair<double, std::uint32_t>> rekeyed;
      for (const auto& [key, v] : oracle) rekeyed.emplace(key + delta(v), v);
      oracle.swap(rekeyed);
    }
    CHECK(heap.empty() == oracle.empty());
  }
  while (!oracle.empty()) {
    CHECK(heap.pop() == *oracle.begin());
    oracle.erase(oracle.begin());
  }
  CHECK(heap.empty());
  CHECK(popped > 1000);
}

TEST_CASE("run_astar reaches its target at the Bellman–Ford distance, and a nearest-terminal floor settles less") {
  const HalfedgeMesh mesh = torus_mesh();
  const EdgeGraph graph = build_edge_graph(mesh);
  const std::vector<std::uint8_t> none(mesh.num_vertices(), 0);
  PathSearch search(graph);
  std::mt19937 rng(11);
  std::size_t with_floor = 0, without = 0;
  for (int trial = 0; trial < 12; ++trial) {
    CAPTURE(trial);
    // A source, a target and four more "terminals": the floor is the distance to the nearest
    // of the target and those four (it holds the target, so it bounds the distance to it).
    std::vector<VertexId> picks;
    while (picks.size() < 6) {
      const VertexId v(static_cast<std::uint32_t>(rng() % mesh.num_vertices()));
      if (std::find(picks.begin(), picks.end(), v) == picks.end()) picks.push_back(v);
    }
    const VertexId source = picks[0], target = picks[1];
    const std::vector<VertexId> others(picks.begin() + 1, picks.end());
    const std::vector<double> floor = bellman_ford(graph, others, none, none);
    const double expected = bellman_ford(graph, {source}, none, none)[target.index()];
    std::size_t settled[2] = {0, 0};
    for (int use_floor = 0; use_floor < 2; ++use_floor) {
      search.reset();
      search.add_source(source);
      REQUIRE(search
                  .run_astar(target, mesh.positions(),
                             use_floor ? std::span<const double>(floor) : std::span<const double>())
                  .ok());
      REQUIRE(search.reached(target));
      CHECK(search.distance(target) == doctest::Approx(expected).epsilon(1e-12));
      CHECK(path_length(mesh, search.path_to(mesh, target)) == doctest::Approx(expected).epsilon(1e-12));
      // Every settled vertex has its exact distance (a consistent estimate).
      const auto exact = bellman_ford(graph, {source}, none, none);
      for (VertexId v : search.settled()) CHECK(search.distance(v) == doctest::Approx(exact[v.index()]).epsilon(1e-12));
      settled[use_floor] = search.settled().size();
    }
    CHECK(settled[1] <= settled[0]);
    without += settled[0];
    with_floor += settled[1];
  }
  CHECK(with_floor < without);
}

TEST_CASE("ordered_bits orders as the doubles do (negative keys and both zeros included), and LazyHeap pops them in order") {
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u(-1e6, 1e6);
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> keys = {0.0,
                              -0.0,
                              inf,
                              -inf,
                              1e-300,
                              -1e-300,
                              std::numeric_limits<double>::denorm_min(),
                              -std::numeric_limits<double>::denorm_min(),
                              1.0,
                              -1.0};
  for (int i = 0; i < 200; ++i) keys.push_back(u(rng));
  for (double a : keys) {
    for (double b : keys) {
      CAPTURE(a);
      CAPTURE(b);
      CHECK((ordered_bits(a) < ordered_bits(b)) == (a < b));
      CHECK((ordered_bits(a) == ordered_bits(b)) == (a == b));
    }
  }
  LazyHeap heap;
  std::vector<LazyHeap::Entry> oracle;
  for (std::uint32_t i = 0; i < keys.size(); ++i) {
    heap.push(keys[i], i % 7);
    oracle.emplace_back(keys[i] + 0.0, i % 7);
  }
  std::sort(oracle.begin(), oracle.end());
  for (const auto& expected : oracle) {
    REQUIRE_FALSE(heap.empty());
    const auto [key, v] = heap.pop();
    CHECK(key == expected.first);
    CHECK(v == expected.second);
  }
  CHECK(heap.empty());
}

}  // namespace seam_path_search_test
