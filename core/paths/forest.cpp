#include "core/paths/forest.h"

#include <algorithm>
#include <array>
#include <numeric>
#include <unordered_map>

namespace seam::core {

namespace {

// The edges, each once, by increasing weight (ties by edge id).
std::vector<EdgeId> by_weight(const HalfedgeMesh& mesh, std::span<const EdgeId> edges,
                              std::span<const double> edge_weights) {
  std::vector<EdgeId> sorted(edges.begin(), edges.end());
  std::sort(sorted.begin(), sorted.end());
  sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
  auto weight = [&](EdgeId e) { return edge_weights.empty() ? mesh.edge_length(e) : edge_weights[e.index()]; };
  std::stable_sort(sorted.begin(), sorted.end(), [&](EdgeId a, EdgeId b) { return weight(a) < weight(b); });
  return sorted;
}

// A spanning forest over a compact node numbering of the touched vertices only, so the cost
// follows the seam's size and not the mesh's. Node 0 is the merged super node.
struct NodeForest {
  std::unordered_map<std::uint32_t, std::uint32_t> node_of;  // vertex -> node
  std::uint32_t num_nodes = 1;
  std::vector<EdgeId> edges;
  std::vector<std::array<std::uint32_t, 2>> ends;  // the nodes of each edge
};

// Kruskal over `sorted` (already in weight order), with union-find on the nodes numbered as
// the edges reach them.
NodeForest kruskal(const HalfedgeMesh& mesh, std::span<const EdgeId> sorted, std::span<const VertexId> merged) {
  NodeForest forest;
  forest.node_of.reserve(2 * sorted.size() + merged.size() + 1);
  for (VertexId v : merged) forest.node_of[v.value()] = 0;
  auto node = [&](VertexId v) {
    auto [it, inserted] = forest.node_of.try_emplace(v.value(), forest.num_nodes);
    if (inserted) ++forest.num_nodes;
    return it->second;
  };
  std::vector<std::uint32_t> parent;
  auto find = [&](std::uint32_t x) {
    while (parent[x] != x) {
      parent[x] = parent[parent[x]];
      x = parent[x];
    }
    return x;
  };
  for (EdgeId e : sorted) {
    const HalfedgeId h = HalfedgeMesh::halfedge(e);
    const std::uint32_t a = node(mesh.tail(h));
    const std::uint32_t b = node(mesh.head(h));
    if (parent.size() < forest.num_nodes) {
      const std::size_t old = parent.size();
      parent.resize(forest.num_nodes);
      std::iota(parent.begin() + static_cast<std::ptrdiff_t>(old), parent.end(), static_cast<std::uint32_t>(old));
    }
    const std::uint32_t ra = find(a);
    const std::uint32_t rb = find(b);
    if (ra == rb) continue;  // closes a cycle (or both ends on the merged node)
    parent[ra] = rb;
    forest.edges.push_back(e);
    forest.ends.push_back({a, b});
  }
  return forest;
}

// Per node: 1 for the merged node and the nodes of `keep`, which are never peeled.
std::vector<std::uint8_t> kept_nodes(const NodeForest& forest, std::span<const VertexId> keep) {
  std::vector<std::uint8_t> kept(forest.num_nodes, 0);
  kept[0] = 1;
  for (VertexId v : keep) {
    auto it = forest.node_of.find(v.value());
    if (it != forest.node_of.end()) kept[it->second] = 1;
  }
  return kept;
}

// Peels leaves that nothing needs: a leaf that is not kept loses its edge, until every leaf
// is kept. Returns per forest edge 1 when it was peeled.
std::vector<std::uint8_t> peel_leaves(const NodeForest& forest, std::span<const std::uint8_t> kept) {
  const std::uint32_t num_nodes = forest.num_nodes;
  const std::vector<std::array<std::uint32_t, 2>>& ends = forest.ends;
  std::vector<std::vector<std::uint32_t>> incident(num_nodes);
  std::vector<std::uint32_t> degree(num_nodes, 0);
  for (std::uint32_t i = 0; i < forest.edges.size(); ++i) {
    for (std::uint32_t n : ends[i]) {
      incident[n].push_back(i);
      ++degree[n];
    }
  }
  std::vector<std::uint8_t> removed(forest.edges.size(), 0);
  std::vector<std::uint32_t> stack;
  for (std::uint32_t n = 0; n < num_nodes; ++n) {
    if (degree[n] == 1 && !kept[n]) stack.push_back(n);
  }
  while (!stack.empty()) {
    const std::uint32_t n = stack.back();
    stack.pop_back();
    if (degree[n] != 1 || kept[n]) continue;
    for (std::uint32_t i : incident[n]) {
      if (removed[i]) continue;
      removed[i] = 1;
      for (std::uint32_t m : ends[i]) {
        --degree[m];
        if (m != n && degree[m] == 1 && !kept[m]) stack.push_back(m);
      }
      break;
    }
  }
  return removed;
}

}  // namespace

std::vector<EdgeId> pruned_spanning_forest(const HalfedgeMesh& mesh, std::span<const EdgeId> edges,
                                           std::span<const VertexId> keep, std::span<const double> edge_weights,
                                           std::span<const VertexId> merged) {
  const std::vector<EdgeId> sorted = by_weight(mesh, edges, edge_weights);
  const NodeForest forest = kruskal(mesh, sorted, merged);
  const std::vector<std::uint8_t> removed = peel_leaves(forest, kept_nodes(forest, keep));
  std::vector<EdgeId> out;
  for (std::size_t i = 0; i < forest.edges.size(); ++i) {
    if (!removed[i]) out.push_back(forest.edges[i]);
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace seam::core
