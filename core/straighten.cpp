#include "core/straighten.h"

#include <algorithm>
#include <numeric>
#include <string>

#include "core/path_search.h"

namespace seam::core {

namespace {

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

// Removes non-terminal leaves until none is left. `edges` must form a forest.
std::vector<EdgeId> prune_dangling(const HalfedgeMesh& mesh, std::vector<EdgeId> edges,
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

}  // namespace

Status check_full_component_tree(const HalfedgeMesh& mesh, std::span<const EdgeId> edges,
                                 std::span<const VertexId> terminals) {
  if (edges.empty()) return make_error(ErrorCode::kTopologyViolation, "the seam tree has no edges");
  const std::size_t nv = mesh.num_vertices();
  std::vector<std::uint32_t> degree(nv, 0);
  UnionFind uf(nv);
  for (EdgeId e : edges) {
    if (!e.valid() || e.index() >= mesh.num_edges()) {
      return make_error(ErrorCode::kTopologyViolation, "seam edge out of range", {e.value()});
    }
    const HalfedgeId h = HalfedgeMesh::halfedge(e);
    const VertexId a = mesh.tail(h);
    const VertexId b = mesh.head(h);
    ++degree[a.index()];
    ++degree[b.index()];
    if (!uf.unite(a.value(), b.value())) {
      return make_error(ErrorCode::kTopologyViolation,
                        "the seam has a cycle through edge " + std::to_string(e.value()) + " (or repeats it)",
                        {e.value()});
    }
  }
  std::vector<std::uint8_t> is_terminal(nv, 0);
  for (VertexId t : terminals) {
    if (!t.valid() || t.index() >= nv) {
      return make_error(ErrorCode::kTopologyViolation, "terminal out of range", {t.value()});
    }
    is_terminal[t.index()] = 1;
    if (degree[t.index()] != 1) {
      return make_error(ErrorCode::kTopologyViolation,
                        "terminal " + std::to_string(t.value()) + " has degree " +
                            std::to_string(degree[t.index()]) + " in the seam, not 1 (a leaf)",
                        {t.value()});
    }
  }
  const std::uint32_t root = terminals.empty() ? mesh.tail(HalfedgeMesh::halfedge(edges[0])).value()
                                               : uf.find(terminals[0].value());
  for (std::size_t v = 0; v < nv; ++v) {
    if (degree[v] == 0) continue;
    if (uf.find(static_cast<std::uint32_t>(v)) != uf.find(root)) {
      return make_error(ErrorCode::kTopologyViolation,
                        "the seam is not connected: vertex " + std::to_string(v) + " is apart",
                        {static_cast<std::uint32_t>(v)});
    }
    if (degree[v] == 1 && !is_terminal[v]) {
      return make_error(ErrorCode::kTopologyViolation,
                        "vertex " + std::to_string(v) + " is a dangling leaf that is not a terminal",
                        {static_cast<std::uint32_t>(v)});
    }
  }
  return Ok{};
}

Result<std::vector<EdgeId>> star_tree(const HalfedgeMesh& mesh, const EdgeGraph& graph,
                                      std::span<const VertexId> terminals, const CancelToken& cancel) {
  const std::size_t nv = mesh.num_vertices();
  const std::size_t k = terminals.size();
  if (k < 2) return make_error(ErrorCode::kInvalidArgument, "a seam tree needs at least two terminals");
  PathSearch search(graph);
  for (VertexId t : terminals) search.block(t);
  // Sum of terminal-avoiding distances from every terminal; the centre must be reached by all.
  std::vector<double> sum(nv, 0.0);
  std::vector<std::uint32_t> count(nv, 0);
  for (VertexId t : terminals) {
    search.reset();
    search.add_source(t);
    if (auto st = search.run({}, PathSearch::kUnreached, cancel); !st.ok()) return st.take_error();
    for (VertexId v : search.settled()) {
      sum[v.index()] += search.distance(v);
      ++count[v.index()];
    }
  }
  VertexId centre;
  for (std::size_t v = 0; v < nv; ++v) {
    if (count[v] != k || search.is_blocked(VertexId(v))) continue;
    if (!centre.valid() || sum[v] < sum[centre.index()]) centre = VertexId(v);
  }
  if (!centre.valid()) {
    if (k == 2 && mesh.find_halfedge(terminals[0], terminals[1]).valid()) {
      return std::vector<EdgeId>{HalfedgeMesh::edge(mesh.find_halfedge(terminals[0], terminals[1]))};
    }
    return make_error(ErrorCode::kInvalidArgument,
                      "no seam tree with every terminal a leaf exists: no vertex reaches every terminal "
                      "without passing through another terminal");
  }
  search.reset();
  search.add_source(centre);
  if (auto st = search.run(terminals, PathSearch::kUnreached, cancel); !st.ok()) return st.take_error();
  std::vector<EdgeId> edges;
  for (VertexId t : terminals) {
    for (HalfedgeId h : search.path_to(mesh, t)) edges.push_back(HalfedgeMesh::edge(h));
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return prune_dangling(mesh, std::move(edges), terminals);
}

std::vector<EdgeId> topology_edges(const TreeTopology& topology) {
  std::vector<EdgeId> edges;
  for (const auto& path : topology.paths) {
    for (HalfedgeId h : path) edges.push_back(HalfedgeMesh::edge(h));
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

}  // namespace seam::core
