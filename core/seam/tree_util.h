// Small helpers shared by the skeleton seam's modules (tour, straighten, refine, improve): a
// union-find, a compact index of a tree's vertices and pruning of dangling branches. Internal
// to core.
#pragma once

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <span>
#include <vector>

#include "core/mesh/halfedge_mesh.h"

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
// a tree that must not cost the mesh's size. O(m log m) to build, O(log m) per lookup.
struct TreeVertices {
  std::vector<VertexId> vertices;
  TreeVertices(const HalfedgeMesh& mesh, std::span<const EdgeId> edges, std::span<const VertexId> extra = {}) {
    vertices.reserve(2 * edges.size() + extra.size());
    for (EdgeId e : edges) {
      vertices.push_back(mesh.tail(HalfedgeMesh::halfedge(e)));
      vertices.push_back(mesh.head(HalfedgeMesh::halfedge(e)));
    }
    vertices.insert(vertices.end(), extra.begin(), extra.end());
    std::sort(vertices.begin(), vertices.end());
    vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  }
  std::size_t size() const { return vertices.size(); }
  bool contains(VertexId v) const { return std::binary_search(vertices.begin(), vertices.end(), v); }
  // Precondition: contains(v).
  std::uint32_t index(VertexId v) const {
    return static_cast<std::uint32_t>(std::lower_bound(vertices.begin(), vertices.end(), v) - vertices.begin());
  }
};

// Removes non-terminal leaves until none is left. `edges` must form a forest.
inline std::vector<EdgeId> prune_dangling(const HalfedgeMesh& mesh, std::vector<EdgeId> edges,
                                   std::span<const VertexId> terminals) {
  std::vector<std::uint32_t> degree(mesh.num_vertices(), 0);
  std::vector<std::uint8_t> is_terminal(mesh.num_vertices(), 0);
  for (VertexId t : terminals) is_terminal[t.index()] = 1;
  for (EdgeId e : edges) {
    ++degree[mesh.tail(HalfedgeMesh::halfedge(e)).index()];
    ++degree[mesh.head(HalfedgeMesh::halfedge(e)).index()];
  }
  // Each pass removes the current dangling edges; a long dangling chain needs one pass per
  // edge, so iterate with a worklist of vertices instead.
  std::vector<std::uint8_t> removed_edge(edges.size(), 0);
  bool any = false;
  for (std::size_t v = 0; v < degree.size() && !any; ++v) any = degree[v] == 1 && !is_terminal[v];
  if (!any) return edges;
  std::vector<std::uint32_t> first(mesh.num_vertices(), UINT32_MAX);
  std::vector<std::uint32_t> next_slot(2 * edges.size(), UINT32_MAX);
  for (std::uint32_t i = 0; i < edges.size(); ++i) {
    const HalfedgeId h = HalfedgeMesh::halfedge(edges[i]);
    for (std::uint32_t side = 0; side < 2; ++side) {
      const std::uint32_t v = side == 0 ? mesh.tail(h).value() : mesh.head(h).value();
      next_slot[2 * i + side] = first[v];
      first[v] = 2 * i + side;
    }
  }
  std::vector<std::uint32_t> work;
  for (std::uint32_t v = 0; v < degree.size(); ++v) {
    if (degree[v] == 1 && !is_terminal[v]) work.push_back(v);
  }
  while (!work.empty()) {
    const std::uint32_t v = work.back();
    work.pop_back();
    if (degree[v] != 1) continue;
    for (std::uint32_t s = first[v]; s != UINT32_MAX; s = next_slot[s]) {
      const std::uint32_t i = s / 2;
      if (removed_edge[i]) continue;
      removed_edge[i] = 1;
      const HalfedgeId h = HalfedgeMesh::halfedge(edges[i]);
      const std::uint32_t w = mesh.tail(h).value() == v ? mesh.head(h).value() : mesh.tail(h).value();
      --degree[v];
      if (--degree[w] == 1 && !is_terminal[w]) work.push_back(w);
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
