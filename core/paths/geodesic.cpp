#include "core/paths/geodesic.h"

#include "core/paths/dijkstra_kernel.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

namespace seam::core {

EdgeData<double> edge_lengths(const HalfedgeMesh& mesh) {
  EdgeData<double> lengths(mesh.num_edges());
  for (std::size_t e = 0; e < mesh.num_edges(); ++e) lengths[EdgeId(e)] = mesh.edge_length(EdgeId(e));
  return lengths;
}

EdgeGraph build_edge_graph(const HalfedgeMesh& mesh, std::span<const double> edge_weights) {
  SEAM_ASSERT(edge_weights.empty() || edge_weights.size() == mesh.num_edges());
  EdgeGraph graph;
  const std::size_t nv = mesh.num_vertices();
  graph.offsets.assign(nv + 1, 0);
  for (std::size_t h = 0; h < mesh.num_halfedges(); ++h) ++graph.offsets[mesh.tail(HalfedgeId(h)).index() + 1];
  for (std::size_t v = 0; v < nv; ++v) graph.offsets[v + 1] += graph.offsets[v];
  graph.head.resize(mesh.num_halfedges());
  graph.halfedge.resize(mesh.num_halfedges());
  graph.weight.resize(mesh.num_halfedges());
  for (std::size_t v = 0; v < nv; ++v) {
    std::uint32_t slot = graph.offsets[v];
    mesh.for_each_outgoing(VertexId(v), [&](HalfedgeId h) {
      const EdgeId e = HalfedgeMesh::edge(h);
      graph.head[slot] = mesh.head(h);
      graph.halfedge[slot] = h;
      graph.weight[slot] = edge_weights.empty() ? mesh.edge_length(e) : edge_weights[e.index()];
      ++slot;
    });
  }
  return graph;
}


namespace {

// dijkstra()'s visitor: one distance array in the tree, an IndexedHeap over it.
struct TreeVisitor {
  const EdgeGraph& graph;
  ShortestPathTree& tree;
  IndexedHeap& heap;
  const DijkstraOptions& options;
  const std::vector<std::uint8_t>& is_target;
  const std::vector<std::uint8_t>& is_source;
  std::vector<std::uint32_t>& unsettled;
  std::size_t& targets_left;

  SettleAction settle(std::uint32_t v, double d) {
    if (d > options.max_distance) {
      unsettled.push_back(v);
      return SettleAction::kStop;
    }
    if (!is_target.empty() && is_target[v] && --targets_left == 0) return SettleAction::kStop;
    if (!options.blocked.empty() && options.blocked[v] && !is_source[v]) return SettleAction::kSkip;
    return SettleAction::kExpand;
  }
  double distance(std::uint32_t v) const { return tree.distance[v]; }
  static std::uint32_t graph_vertex(std::uint32_t v) { return v; }
  void relax(std::uint32_t v, std::uint32_t w, double nd, std::uint32_t slot) {
    // With non-negative weights a settled w has distance[w] <= d <= nd, so it is never
    // decreased again.
    if (nd < tree.distance[w]) {
      tree.distance[w] = nd;
      tree.parent[w] = graph.halfedge[slot];
      tree.source[w] = tree.source[v];
      heap.push_or_decrease(w);
    }
  }
};

}  // namespace

Result<ShortestPathTree> dijkstra(const EdgeGraph& graph, std::span<const VertexId> sources,
                                  const DijkstraOptions& options, const CancelToken& cancel) {
  const std::size_t nv = graph.num_vertices();
  if (sources.empty()) return make_error(ErrorCode::kInvalidArgument, "Dijkstra needs at least one source");
  for (VertexId s : sources) {
    if (!s.valid() || s.index() >= nv) {
      return make_error(ErrorCode::kInvalidArgument, "Dijkstra source vertex out of range", {s.value()});
    }
  }
  for (VertexId t : options.targets) {
    if (!t.valid() || t.index() >= nv) {
      return make_error(ErrorCode::kInvalidArgument, "Dijkstra target vertex out of range", {t.value()});
    }
  }
  SEAM_ASSERT(options.blocked.empty() || options.blocked.size() == nv);

  ShortestPathTree tree;
  // Tentative distances are kept in `distance` while a vertex is in the heap; vertices never
  // settled are reset to unreached at the end, so callers see settled distances only.
  tree.distance.assign(nv, ShortestPathTree::kUnreached);
  tree.parent.assign(nv, HalfedgeId());
  tree.source.assign(nv, VertexId::kInvalidValue);
  std::vector<std::uint8_t> is_target(options.targets.empty() ? 0 : nv, 0);
  std::size_t targets_left = 0;
  for (VertexId t : options.targets) {
    if (!is_target[t.index()]) ++targets_left;
    is_target[t.index()] = 1;
  }

  IndexedHeap heap(tree.distance, nv);
  std::vector<std::uint8_t> is_source(options.blocked.empty() ? 0 : nv, 0);
  for (std::size_t i = 0; i < sources.size(); ++i) {
    const std::uint32_t s = sources[i].value();
    if (tree.distance[s] == 0.0) continue;  // a repeated source keeps its first index
    tree.distance[s] = 0.0;
    tree.source[s] = static_cast<std::uint32_t>(i);
    if (!is_source.empty()) is_source[s] = 1;
    heap.push_or_decrease(s);
  }

  std::vector<std::uint32_t> unsettled;  // popped beyond max_distance or left in the heap
  TreeVisitor visitor{graph, tree, heap, options, is_target, is_source, unsettled, targets_left};
  if (auto status = run_dijkstra(graph, heap, visitor, cancel, "shortest paths"); !status.ok()) {
    return status.take_error();
  }
  // Everything still in the heap (and a vertex popped beyond max_distance) was only reached
  // tentatively: report it as unreached.
  while (!heap.empty()) unsettled.push_back(heap.pop());
  for (std::uint32_t v : unsettled) {
    tree.distance[v] = ShortestPathTree::kUnreached;
    tree.parent[v] = HalfedgeId();
    tree.source[v] = VertexId::kInvalidValue;
  }
  return tree;
}

std::vector<HalfedgeId> trace_path(const HalfedgeMesh& mesh, const ShortestPathTree& tree, VertexId target) {
  std::vector<HalfedgeId> path;
  if (!target.valid() || target.index() >= tree.distance.size() || !tree.reached(target)) return path;
  VertexId v = target;
  while (tree.parent[v.index()].valid()) {
    const HalfedgeId h = tree.parent[v.index()];
    path.push_back(h);
    v = mesh.tail(h);
  }
  std::reverse(path.begin(), path.end());
  return path;
}

double path_length(const HalfedgeMesh& mesh, std::span<const HalfedgeId> path, std::span<const double> edge_weights) {
  double total = 0.0;
  for (HalfedgeId h : path) {
    const EdgeId e = HalfedgeMesh::edge(h);
    total += edge_weights.empty() ? mesh.edge_length(e) : edge_weights[e.index()];
  }
  return total;
}

}  // namespace seam::core
