#include <doctest/doctest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "core/paths/dreyfus_wagner.h"
#include "fixtures.h"

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

}  // namespace

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
