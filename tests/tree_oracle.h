// Test oracles independent of the seam code: is an edge set a full-component Steiner tree,
// and the MST weight of a complete graph.
#pragma once

#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <functional>
#include <map>
#include <set>
#include <vector>

#include "core/mesh/halfedge_mesh.h"

namespace seam::test_oracle {

using core::EdgeId;
using core::HalfedgeId;
using core::HalfedgeMesh;
using core::VertexId;

// Independent check: one tree over the terminals, every terminal of degree 1, no other leaf.
// Returns its Euclidean length.
inline double full_component_length(const HalfedgeMesh& mesh, const std::vector<EdgeId>& edges,
                             const std::vector<VertexId>& terminals) {
  REQUIRE_FALSE(edges.empty());
  std::map<std::uint32_t, int> degree;
  std::map<std::uint32_t, std::uint32_t> parent;
  std::function<std::uint32_t(std::uint32_t)> find = [&](std::uint32_t x) {
    if (!parent.count(x)) parent[x] = x;
    return parent[x] == x ? x : parent[x] = find(parent[x]);
  };
  double length = 0;
  for (EdgeId e : edges) {
    const HalfedgeId h = HalfedgeMesh::halfedge(e);
    const auto a = mesh.tail(h).value(), b = mesh.head(h).value();
    ++degree[a];
    ++degree[b];
    const auto ra = find(a), rb = find(b);
    REQUIRE_MESSAGE(ra != rb, "a cycle");
    parent[ra] = rb;
    length += mesh.edge_length(e);
  }
  CHECK(degree.size() == edges.size() + 1);
  std::set<std::uint32_t> is_terminal;
  for (VertexId t : terminals) {
    is_terminal.insert(t.value());
    CHECK_MESSAGE(degree[t.value()] == 1, "terminal " << t.value() << " is not a leaf");
  }
  for (const auto& [v, d] : degree) {
    if (!is_terminal.count(v)) CHECK_MESSAGE(d >= 2, "dangling vertex " << v);
  }
  return length;
}

// Prim's algorithm on the complete graph of k nodes weighted by dist: the MST weight, an
// independent reference for Kruskal's.
inline double prim_mst_weight(std::size_t k, const std::function<double(std::size_t, std::size_t)>& dist) {
  std::vector<double> best(k, std::numeric_limits<double>::infinity());
  std::vector<bool> in(k, false);
  best[0] = 0.0;
  double total = 0.0;
  for (std::size_t step = 0; step < k; ++step) {
    std::size_t u = k;
    for (std::size_t v = 0; v < k; ++v) {
      if (!in[v] && (u == k || best[v] < best[u])) u = v;
    }
    in[u] = true;
    total += best[u];
    for (std::size_t v = 0; v < k; ++v) best[v] = std::min(best[v], dist(u, v));
  }
  return total;
}

}  // namespace seam::test_oracle
