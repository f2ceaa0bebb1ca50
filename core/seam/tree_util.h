// Small helpers shared by the skeleton seam's modules (tour, straighten, refine, improve): a
// union-find, a compact index of a tree's vertices and pruning of dangling branches. Internal
// to core.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <numeric>
#include <span>
#include <utility>
#include <vector>

#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/radix_sort.h"

namespace seam::core::detail {

struct UnionFind {
  std::vector<std::uint32_t> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  std::uint32_t find(std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  bool unite(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    parent[std::max(a, b)] = std::min(a, b);
    return true;
  }
};

// The vertices of some edges (and of `extra`), sorted and unique: a compact index for work on
// a tree that must not cost the mesh's size. `ends` gives each edge's ends by that index, so
// walking the tree needs no lookups. O(m) to build (a radix sort of the m ends), O(log m) per
// lookup by vertex.
struct TreeVertices {
  std::vector<VertexId> vertices;
  std::vector<std::uint32_t> ends;  ///< per edge i: ends[2i] indexes its tail, ends[2i + 1] its head
  TreeVertices(const HalfedgeMesh& mesh, std::span<const EdgeId> edges, std::span<const VertexId> extra = {}) {
    // (vertex, slot): slots 2i and 2i + 1 are edge i's tail and head, the rest `extra`.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> uses;
    uses.reserve(2 * edges.size() + extra.size());
    for (EdgeId e : edges) {
      const HalfedgeId h = HalfedgeMesh::halfedge(e);
      uses.emplace_back(mesh.tail(h).value(), static_cast<std::uint32_t>(uses.size()));
      uses.emplace_back(mesh.head(h).value(), static_cast<std::uint32_t>(uses.size()));
    }
    for (VertexId v : extra) uses.emplace_back(v.value(), static_cast<std::uint32_t>(uses.size()));
    const auto bits = static_cast<unsigned>(std::bit_width(mesh.num_vertices()));
    radix_sort(uses, bits, [](const std::pair<std::uint32_t, std::uint32_t>& u) { return u.first; });
    ends.resize(2 * edges.size());
    for (const auto& [v, slot] : uses) {
      if (vertices.empty() || vertices.back().value() != v) vertices.push_back(VertexId(v));
      if (slot < ends.size()) ends[slot] = static_cast<std::uint32_t>(vertices.size() - 1);
    }
  }
  std::size_t size() const { return vertices.size(); }
  bool contains(VertexId v) const { return std::binary_search(vertices.begin(), vertices.end(), v); }
  // Precondition: contains(v).
  std::uint32_t index(VertexId v) const {
    return static_cast<std::uint32_t>(std::lower_bound(vertices.begin(), vertices.end(), v) - vertices.begin());
  }

  // Each vertex's edge ends: the slots s (edge s / 2, its tail when s is even, its head when
  // odd; ends[s ^ 1] is the other end) of vertex v are slots[offsets[v] .. offsets[v + 1]),
  // in slot order. O(m).
  struct Incidence {
    std::vector<std::uint32_t> offsets;
    std::vector<std::uint32_t> slots;
    std::uint32_t degree(std::uint32_t v) const { return offsets[v + 1] - offsets[v]; }
  };
  Incidence incidence() const {
    Incidence in{std::vector<std::uint32_t>(size() + 1, 0), std::vector<std::uint32_t>(ends.size())};
    for (std::uint32_t end : ends) ++in.offsets[end + 1];
    std::partial_sum(in.offsets.begin(), in.offsets.end(), in.offsets.begin());
    std::vector<std::uint32_t> fill(in.offsets.begin(), in.offsets.end() - 1);
    for (std::uint32_t s = 0; s < ends.size(); ++s) in.slots[fill[ends[s]]++] = s;
    return in;
  }
};

// Removes non-terminal leaves until none is left. `edges` must form a forest. The work is
// indexed by the forest's own vertices: O(m) for m edges, whatever the mesh's size.
inline std::vector<EdgeId> prune_dangling(const HalfedgeMesh& mesh, std::vector<EdgeId> edges,
                                          std::span<const VertexId> terminals) {
  const TreeVertices tree(mesh, edges);
  const std::size_t n = tree.size();
  std::vector<std::uint32_t> degree(n, 0);
  for (std::uint32_t end : tree.ends) ++degree[end];
  std::vector<std::uint8_t> is_terminal(n, 0);
  for (VertexId t : terminals) {
    if (tree.contains(t)) is_terminal[tree.index(t)] = 1;
  }
  auto dangling = [&](std::uint32_t v) { return degree[v] == 1 && !is_terminal[v]; };
  // Each pass removes the current dangling edges; a long dangling chain needs one pass per
  // edge, so iterate with a worklist of vertices instead.
  std::vector<std::uint32_t> work;
  for (std::uint32_t v = 0; v < n; ++v) {
    if (dangling(v)) work.push_back(v);
  }
  if (work.empty()) return edges;
  const TreeVertices::Incidence incidence = tree.incidence();
  std::vector<std::uint8_t> removed_edge(edges.size(), 0);
  while (!work.empty()) {
    const std::uint32_t v = work.back();
    work.pop_back();
    if (degree[v] != 1) continue;
    for (std::uint32_t k = incidence.offsets[v]; k < incidence.offsets[v + 1]; ++k) {
      const std::uint32_t s = incidence.slots[k];
      const std::uint32_t i = s / 2;
      if (removed_edge[i]) continue;
      removed_edge[i] = 1;
      const std::uint32_t w = tree.ends[s ^ 1u];
      --degree[v];
      --degree[w];
      if (dangling(w)) work.push_back(w);
      break;
    }
  }
  std::vector<EdgeId> kept;
  for (std::size_t i = 0; i < edges.size(); ++i) {
    if (!removed_edge[i]) kept.push_back(edges[i]);
  }
  return kept;
}

}  // namespace seam::core::detail
