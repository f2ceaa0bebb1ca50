#include <doctest/doctest.h>

#include <algorithm>
#include <limits>
#include <queue>
#include <random>
#include <vector>

#include "core/paths/dreyfus_wagner.h"
#include "fixtures.h"

namespace seam_dreyfus_wagner_test {

using namespace seam::core;
namespace fx = seam::fixtures;

namespace {

// A random group Steiner problem on `graph`: `ports` groups, each either one terminal (a
// leaf-only obstacle) or a vertex with its ring (a loose subtree: an obstacle that may be
// passed once held), and a few more terminals that are no port.
struct RandomProblem {
  std::size_t ports = 0;
  std::vector<std::uint32_t> port_mask;
  std::vector<std::uint8_t> obstacle, leaf_only;
  GroupSteinerProblem view(double bound, double target) const {
    return {.ports = ports, .port_mask = port_mask, .obstacle = obstacle, .leaf_only = leaf_only,
            .root = VertexId(), .bound = bound, .target = target};
  }
};

RandomProblem random_problem(const EdgeGraph& graph, std::size_t ports, std::mt19937& rng) {
  const std::size_t n = graph.num_vertices();
  RandomProblem out{ports, std::vector<std::uint32_t>(n, 0), std::vector<std::uint8_t>(n, 0),
                    std::vector<std::uint8_t>(n, 0)};
  auto free_vertex = [&] {
    for (;;) {
      const auto v = static_cast<std::uint32_t>(rng() % n);
      if (!out.obstacle[v]) return v;
    }
  };
  for (std::size_t q = 0; q < ports; ++q) {
    const std::uint32_t v = free_vertex();
    out.port_mask[v] = 1u << q;
    out.obstacle[v] = 1;
    if (rng() % 2) {
      out.leaf_only[v] = 1;  // a terminal port
      continue;
    }
    for (std::uint32_t slot = graph.offsets[v]; slot < graph.offsets[v + 1]; ++slot) {
      const std::uint32_t w = graph.head[slot].value();
      if (out.obstacle[w]) continue;
      out.port_mask[w] = 1u << q;
      out.obstacle[w] = 1;
    }
  }
  for (int extra = 0; extra < 3; ++extra) {
    const std::uint32_t v = free_vertex();
    out.obstacle[v] = out.leaf_only[v] = 1;
  }
  return out;
}

// The textbook Dreyfus-Wagner under the same rules, without bounds or pruning: every split
// merged at every meeting point, every row grown over the whole graph.
double reference_cost(const EdgeGraph& graph, const GroupSteinerProblem& problem) {
  const std::size_t n = graph.num_vertices();
  const std::uint32_t full = (1u << problem.ports) - 1;
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<std::vector<double>> table(full + 1, std::vector<double>(n, inf));
  auto singleton = [](std::uint32_t s) { return (s & (s - 1)) == 0; };
  for (std::uint32_t s = 1; s <= full; ++s) {
    std::vector<double>& row = table[s];
    for (std::uint32_t v = 0; v < n; ++v) {
      if (singleton(s) && (problem.port_mask[v] & s)) row[v] = 0.0;
      const bool meets = !problem.obstacle[v] || (!problem.leaf_only[v] && (problem.port_mask[v] & s));
      for (std::uint32_t a = (s - 1) & s; a > 0 && !singleton(s) && meets; a = (a - 1) & s) {
        row[v] = std::min(row[v], table[a][v] + table[s ^ a][v]);
      }
    }
    using Entry = std::pair<double, std::uint32_t>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> heap;
    for (std::uint32_t v = 0; v < n; ++v) {
      if (row[v] < inf) heap.emplace(row[v], v);
    }
    while (!heap.empty()) {
      const auto [d, v] = heap.top();
      heap.pop();
      if (d > row[v]) continue;
      const bool open = !problem.obstacle[v] || ((problem.port_mask[v] & s) && (!problem.leaf_only[v] || singleton(s)));
      for (std::uint32_t slot = graph.offsets[v]; open && slot < graph.offsets[v + 1]; ++slot) {
        const std::uint32_t w = graph.head[slot].value();
        if (d + graph.weight[slot] < row[w]) heap.emplace(row[w] = d + graph.weight[slot], w);
      }
    }
  }
  if (problem.root.valid()) return table[full][problem.root.index()];
  return *std::min_element(table[full].begin(), table[full].end());
}

}  // namespace

TEST_CASE("Dreyfus-Wagner: the pruned table (goal-oriented lower bounds, a bound lowered by the trees it holds, "
          "the full row ended at the root) finds the textbook optimum") {
  const auto sphere = fx::icosphere(3);
  const HalfedgeMesh mesh = build_halfedge_mesh(sphere.positions, sphere.triangles).value();
  const EdgeGraph graph = build_edge_graph(mesh);
  std::mt19937 rng(77);
  DreyfusWagner kernel;  // reused: each solve starts from the tables the last one left
  int solved = 0, rooted = 0;
  for (int trial = 0; trial < 40; ++trial) {
    CAPTURE(trial);
    RandomProblem problem = random_problem(graph, 2 + static_cast<std::size_t>(trial % 5), rng);
    GroupSteinerProblem view = problem.view(std::numeric_limits<double>::infinity(),
                                            std::numeric_limits<double>::infinity());
    if (trial % 2) {  // a root: a terminal that is no port (the last of random_problem's extras)
      for (std::uint32_t v = static_cast<std::uint32_t>(graph.num_vertices()); v-- > 0;) {
        if (problem.leaf_only[v] && !problem.port_mask[v]) {
          view.root = VertexId(v);
          break;
        }
      }
    }
    const double expected = reference_cost(graph, view);
    if (!(expected < std::numeric_limits<double>::infinity())) continue;  // ports walled in
    rooted += view.root.valid();
    ++solved;
    for (const double bound : {std::numeric_limits<double>::infinity(), expected * 1.05, expected * 1.0000001}) {
      view.bound = bound;
      auto r = kernel.solve(graph, view);
      REQUIRE(r.ok());
      CHECK(r->cost == doctest::Approx(expected).epsilon(1e-12));
      double length = 0.0;
      for (HalfedgeId h : r->halfedges) length += mesh.edge_length(HalfedgeMesh::edge(h));
      CHECK(length == doctest::Approx(expected).epsilon(1e-9));
    }
    view.bound = expected * 0.999;  // nothing below it
    auto none = kernel.solve(graph, view);
    REQUIRE(none.ok());
    CHECK(none->cost == std::numeric_limits<double>::infinity());
    CHECK(none->halfedges.empty());
  }
  CHECK(solved >= 20);
  CHECK(rooted >= 8);
}

TEST_CASE("Dreyfus-Wagner: with more ports than the tours are kept for, the 1-tree bound finds the optimum") {
  const auto sphere = fx::icosphere(2);
  const HalfedgeMesh mesh = build_halfedge_mesh(sphere.positions, sphere.triangles).value();
  const EdgeGraph graph = build_edge_graph(mesh);
  std::mt19937 rng(5);
  DreyfusWagner kernel;
  int solved = 0;
  for (int trial = 0; trial < 3; ++trial) {
    CAPTURE(trial);
    const RandomProblem problem = random_problem(graph, 10, rng);  // 11 lower rows with the bound's
    GroupSteinerProblem view = problem.view(std::numeric_limits<double>::infinity(),
                                            std::numeric_limits<double>::infinity());
    const double expected = reference_cost(graph, view);
    if (!(expected < std::numeric_limits<double>::infinity())) continue;
    ++solved;
    for (const double bound : {std::numeric_limits<double>::infinity(), expected * 1.0000001}) {
      view.bound = bound;
      auto r = kernel.solve(graph, view);
      REQUIRE(r.ok());
      CHECK(r->cost == doctest::Approx(expected).epsilon(1e-12));
    }
  }
  CHECK(solved >= 1);
}

TEST_CASE("Dreyfus-Wagner: the target's lower bound rules out only trees that cannot beat it, and changes nothing else") {
  const auto sphere = fx::icosphere(3);
  const HalfedgeMesh mesh = build_halfedge_mesh(sphere.positions, sphere.triangles).value();
  const EdgeGraph graph = build_edge_graph(mesh);
  std::mt19937 rng(2024);
  DreyfusWagner plain, targeted;
  int ruled_out = 0, kept = 0;
  for (int trial = 0; trial < 60; ++trial) {
    CAPTURE(trial);
    const RandomProblem problem = random_problem(graph, 2 + static_cast<std::size_t>(trial % 4), rng);
    auto optimum = plain.solve(graph, problem.view(std::numeric_limits<double>::infinity(),
                                                   std::numeric_limits<double>::infinity()));
    REQUIRE(optimum.ok());
    if (!(optimum->cost < std::numeric_limits<double>::infinity())) continue;  // ports walled in
    const double c = optimum->cost;
    // The bound a caller would pass (above the optimum, as refine's removed length) and
    // targets below, at and above the optimum.
    for (const double bound : {c * 1.3, std::numeric_limits<double>::infinity()}) {
      auto reference = plain.solve(graph, problem.view(bound, std::numeric_limits<double>::infinity()));
      REQUIRE(reference.ok());
      CHECK(reference->cost == doctest::Approx(c).epsilon(1e-12));
      for (const double target : {c * 0.7, c * 0.99, c, c * 1.01, c * 1.2}) {
        CAPTURE(target);
        auto r = targeted.solve(graph, problem.view(bound, target));
        REQUIRE(r.ok());
        if (r->target_ruled_out) {
          ++ruled_out;
          CHECK(c >= target);  // the optimum could not have beaten the target
          CHECK(r->halfedges.empty());
        } else {
          ++kept;
          CHECK(r->cost == reference->cost);  // the same tree as without a target
          CHECK(r->halfedges == reference->halfedges);
        }
        // A target the optimum beats is never ruled out.
        if (c < target) CHECK_FALSE(r->target_ruled_out);
      }
    }
  }
  CHECK(ruled_out > 0);
  CHECK(kept > 0);
}

}  // namespace seam_dreyfus_wagner_test
