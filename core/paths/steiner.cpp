#include "core/paths/steiner.h"

#include <algorithm>
#include <atomic>
#include <set>
#include <thread>
#include <unordered_map>

namespace seam::core {

Result<TerminalPaths> compute_terminal_paths(const HalfedgeMesh& mesh, const EdgeGraph& graph,
                                             std::span<const VertexId> terminals, unsigned threads,
                                             const CancelToken& cancel) {
  const std::size_t k = terminals.size();
  if (k < 2) return make_error(ErrorCode::kInvalidArgument, "shortest paths need at least two terminals");
  {
    std::vector<VertexId> sorted(terminals.begin(), terminals.end());
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t i = 0; i < k; ++i) {
      if (!sorted[i].valid() || sorted[i].index() >= mesh.num_vertices()) {
        return make_error(ErrorCode::kInvalidArgument, "terminal vertex out of range", {sorted[i].value()});
      }
      if (i > 0 && sorted[i] == sorted[i - 1]) {
        return make_error(ErrorCode::kInvalidArgument, "terminal vertex given twice", {sorted[i].value()});
      }
    }
  }
  TerminalPaths result;
  result.terminals.assign(terminals.begin(), terminals.end());
  result.distance.assign(k * k, ShortestPathTree::kUnreached);
  result.path.assign(k * k, {});

  // Each worker takes source terminals from a shared counter and writes only row i, so
  // the output does not depend on scheduling.
  std::atomic<std::size_t> next{0};
  std::vector<Error> errors(k);
  std::vector<std::uint8_t> failed(k, 0);
  // Distances are symmetric, so the search from terminal i only has to settle terminals
  // i+1..k-1 (rows j < i are mirrored below) and the last terminal needs no search: about
  // half the work of k full searches, since each stops once its later terminals are settled.
  auto work = [&] {
    for (std::size_t i = next++; i + 1 < k; i = next++) {
      const VertexId source[] = {terminals[i]};
      const std::span<const VertexId> later = terminals.subspan(i + 1);
      auto tree = dijkstra(graph, source, {.targets = later}, cancel);
      if (!tree.ok()) {
        errors[i] = tree.take_error();
        failed[i] = 1;
        continue;
      }
      result.distance[i * k + i] = 0.0;
      for (std::size_t j = i + 1; j < k; ++j) {
        result.distance[i * k + j] = tree->distance[terminals[j].index()];
        result.path[i * k + j] = trace_path(mesh, *tree, terminals[j]);
      }
    }
  };
  const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
  const unsigned n = static_cast<unsigned>(std::min<std::size_t>(k - 1, threads == 0 ? hw : threads));
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < n; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  for (std::size_t i = 0; i < k; ++i) {
    if (failed[i]) return errors[i];
  }
  result.distance[(k - 1) * k + (k - 1)] = 0.0;
  // Use the lower-index row's path for both directions so i->j and j->i are the same edges.
  for (std::size_t i = 0; i < k; ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      auto& forward = result.path[j * k + i];
      std::vector<HalfedgeId> reverse(forward.rbegin(), forward.rend());
      for (auto& h : reverse) h = HalfedgeMesh::twin(h);
      result.path[i * k + j] = std::move(reverse);
      result.distance[i * k + j] = result.distance[j * k + i];
    }
  }
  return result;
}

SteinerTree make_steiner_tree(const HalfedgeMesh& mesh, std::span<const EdgeId> edges,
                              std::span<const VertexId> terminals, std::span<const double> edge_weights) {
  SteinerTree tree;
  tree.edges.assign(edges.begin(), edges.end());
  std::sort(tree.edges.begin(), tree.edges.end());
  tree.edges.erase(std::unique(tree.edges.begin(), tree.edges.end()), tree.edges.end());

  std::unordered_map<std::uint32_t, std::vector<HalfedgeId>> incident;  // vertex -> outgoing tree half-edges
  for (EdgeId e : tree.edges) {
    tree.length += edge_weights.empty() ? mesh.edge_length(e) : edge_weights[e.index()];
    const HalfedgeId h = HalfedgeMesh::halfedge(e);
    incident[mesh.tail(h).value()].push_back(h);
    incident[mesh.head(h).value()].push_back(HalfedgeMesh::twin(h));
  }
  std::set<std::uint32_t> is_terminal;
  for (VertexId t : terminals) is_terminal.insert(t.value());
  auto is_node = [&](std::uint32_t v) { return is_terminal.count(v) || incident[v].size() != 2; };
  for (const auto& [v, hs] : incident) {
    if (hs.size() >= 3 && !is_terminal.count(v)) tree.steiner_points.push_back(VertexId(v));
  }
  std::sort(tree.steiner_points.begin(), tree.steiner_points.end());

  // Walk each branch from a node along degree-2 vertices; visit nodes in id order so the
  // branch list is deterministic. A cycle of degree-2 vertices (not a tree) is skipped.
  std::vector<std::uint32_t> nodes;
  for (const auto& [v, hs] : incident) {
    if (is_node(v)) nodes.push_back(v);
  }
  std::sort(nodes.begin(), nodes.end());
  std::set<std::uint32_t> used_edges;
  for (std::uint32_t v : nodes) {
    auto outgoing = incident[v];
    std::sort(outgoing.begin(), outgoing.end());
    for (HalfedgeId start : outgoing) {
      if (used_edges.count(HalfedgeMesh::edge(start).value())) continue;
      std::vector<HalfedgeId> branch;
      HalfedgeId h = start;
      while (true) {
        used_edges.insert(HalfedgeMesh::edge(h).value());
        branch.push_back(h);
        const std::uint32_t w = mesh.head(h).value();
        if (is_node(w)) break;
        const auto& hs = incident[w];
        const HalfedgeId back = HalfedgeMesh::twin(h);
        h = hs[0] == back ? hs[1] : hs[0];
      }
      tree.branches.push_back(std::move(branch));
    }
  }
  return tree;
}

}  // namespace seam::core
