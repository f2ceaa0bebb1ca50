#include "core/seam/baselines.h"

#include <algorithm>
#include <bit>
#include <limits>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "core/paths/dijkstra_kernel.h"
#include "core/paths/dreyfus_wagner.h"
#include "core/paths/forest.h"

namespace seam::core {

namespace {

// The Dreyfus–Wagner table is 2^(k-1) rows of V doubles plus back-pointers; above this it is
// refused rather than risking the process (many requests share one machine).
constexpr std::size_t kMaxOptimalTableBytes = std::size_t{512} << 20;

// The exact seam's table for k >= 2 terminals on nv vertices: 2^(k-1) rows (terminal k-1 is
// the root, added last) of nv (distance, back-pointer) entries.
std::size_t optimal_table_bytes(std::size_t k, std::size_t nv) {
  return (std::size_t{1} << (k - 1)) * nv * (sizeof(double) + sizeof(std::uint32_t));
}

Status validate_terminals(const EdgeGraph& graph, std::span<const VertexId> terminals, const char* method) {
  if (terminals.size() < 2) {
    return make_error(ErrorCode::kInvalidArgument, std::string(method) + " needs at least two terminals");
  }
  std::vector<VertexId> sorted(terminals.begin(), terminals.end());
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    if (!sorted[i].valid() || sorted[i].index() >= graph.num_vertices()) {
      return make_error(ErrorCode::kInvalidArgument,
                        std::string(method) + ": terminal " + std::to_string(sorted[i].value()) + " is out of range",
                        {sorted[i].value()});
    }
    if (i > 0 && sorted[i] == sorted[i - 1]) {
      return make_error(ErrorCode::kInvalidArgument,
                        std::string(method) + ": terminal " + std::to_string(sorted[i].value()) + " is given twice",
                        {sorted[i].value()});
    }
  }
  return Ok{};
}

// greedy_seam's search from the tree: stops at the first pending terminal it settles.
// Distances start at kInf; `touched` lists what to reset for the next search.
struct NearestVisitor {
  const EdgeGraph& graph;
  const std::vector<std::uint8_t>& pending;
  std::vector<double>& dist;
  std::vector<HalfedgeId>& parent;
  std::vector<std::uint8_t>& settled;
  std::vector<std::uint32_t>& touched;
  LazyHeap& queue;
  std::uint32_t found = VertexId::kInvalidValue;

  SettleAction settle(std::uint32_t v, double d) {
    if (settled[v] || d > dist[v]) return SettleAction::kSkip;  // stale entry
    settled[v] = 1;
    if (!pending[v]) return SettleAction::kExpand;
    found = v;
    return SettleAction::kStop;
  }
  double distance(std::uint32_t v) const { return dist[v]; }
  static std::uint32_t graph_vertex(std::uint32_t v) { return v; }
  void relax(std::uint32_t, std::uint32_t w, double nd, std::uint32_t slot) {
    if (nd < dist[w]) {
      if (dist[w] == kInf) touched.push_back(w);
      dist[w] = nd;
      parent[w] = graph.halfedge[slot];
      queue.push(nd, w);
    }
  }
};

}  // namespace

Result<SteinerTree> mst_seam(const SearchSurface& surface, const TerminalPaths& paths, const CancelToken& cancel) {
  const std::size_t k = paths.size();
  if (auto status = validate_terminals(surface.graph(), paths.terminals, "mst seam"); !status.ok()) {
    return status.take_error();
  }
  std::vector<EdgeId> edges;
  std::size_t joined = 0;
  for (const auto& [i, j] : paths.mst) {
    if (cancel.is_cancelled()) return cancelled_error("mst seam");
    ++joined;
    for (HalfedgeId h : paths.path_between(i, j)) edges.push_back(HalfedgeMesh::edge(h));
  }
  if (joined + 1 != k) {
    return make_error(ErrorCode::kInvalidArgument, "mst seam: the terminals are not all connected");
  }
  // Shortest paths along different MST edges may share or cross vertices; the union could
  // then hold a cycle, which would cut a piece off. Sheffer's seam is a tree, so keep the
  // minimum spanning forest of the union and drop dangling bits.
  const auto tree_edges = pruned_spanning_forest(surface.mesh(), edges, paths.terminals, surface.edge_weights());
  return make_steiner_tree(surface, tree_edges, paths.terminals);
}

Result<SteinerTree> greedy_seam(const SearchSurface& surface, std::span<const VertexId> terminals,
                                const CancelToken& cancel) {
  const HalfedgeMesh& mesh = surface.mesh();
  const EdgeGraph& graph = surface.graph();
  if (auto status = validate_terminals(graph, terminals, "greedy seam"); !status.ok()) return status.take_error();
  const std::size_t nv = graph.num_vertices();
  std::vector<std::uint8_t> pending(nv, 0);
  std::vector<std::uint8_t> in_tree(nv, 0);
  for (std::size_t i = 1; i < terminals.size(); ++i) pending[terminals[i].index()] = 1;
  std::size_t left = terminals.size() - 1;
  std::vector<VertexId> tree_vertices{terminals[0]};
  in_tree[terminals[0].index()] = 1;
  std::vector<EdgeId> edges;

  // One multi-source search per added terminal, each stopping at the first pending terminal
  // it settles (the nearest). Buffers are reused and reset only where touched, so a step
  // costs the explored ball, not O(V).
  std::vector<double> dist(nv, kInf);
  std::vector<HalfedgeId> parent(nv);
  std::vector<std::uint8_t> settled(nv, 0);
  std::vector<std::uint32_t> touched;
  std::uint32_t polls = 0;
  while (left > 0) {
    LazyHeap queue;
    for (VertexId v : tree_vertices) {
      dist[v.index()] = 0;
      parent[v.index()] = HalfedgeId();
      touched.push_back(v.value());
      queue.push(0.0, v.value());
    }
    NearestVisitor visitor{graph, pending, dist, parent, settled, touched, queue};
    if (auto status = run_dijkstra(graph, queue, visitor, cancel, "greedy seam", polls); !status.ok()) {
      return status.take_error();
    }
    const std::uint32_t found = visitor.found;
    if (found == VertexId::kInvalidValue) {
      return make_error(ErrorCode::kInvalidArgument, "greedy seam: the terminals are not all connected");
    }
    for (VertexId v(found); parent[v.index()].valid(); v = mesh.tail(parent[v.index()])) {
      edges.push_back(HalfedgeMesh::edge(parent[v.index()]));
      if (!in_tree[v.index()]) {
        in_tree[v.index()] = 1;
        tree_vertices.push_back(v);
      }
      if (pending[v.index()]) {  // only the endpoint, unless zero-weight edges tie
        pending[v.index()] = 0;
        --left;
      }
    }
    for (std::uint32_t v : touched) {
      dist[v] = kInf;
      settled[v] = 0;
    }
    touched.clear();
  }
  return make_steiner_tree(surface, edges, terminals);
}

Result<SteinerTree> optimal_seam(const SearchSurface& surface, std::span<const VertexId> terminals,
                                 std::size_t max_terminals, const CancelToken& cancel, double upper_bound) {
  const HalfedgeMesh& mesh = surface.mesh();
  const EdgeGraph& graph = surface.graph();
  const std::size_t k = terminals.size();
  if (k > max_terminals) {
    Error error = make_error(ErrorCode::kTooManyTerminals,
                             "the exact seam takes at most " + std::to_string(max_terminals) + " terminals, got " +
                                 std::to_string(k) + "; use the skeleton method or fewer extrema");
    error.values = {{"count", k}, {"limit", max_terminals}};
    return error;
  }
  if (auto status = validate_terminals(graph, terminals, "optimal seam"); !status.ok()) return status.take_error();
  const std::size_t nv = graph.num_vertices();
  const std::size_t m = k - 1;  // terminal k-1 is the root, added last as a leaf
  if (optimal_table_bytes(k, nv) > kMaxOptimalTableBytes) {
    Error error = make_error(ErrorCode::kTooManyTerminals,
                             "the exact seam with " + std::to_string(k) + " terminals on " + std::to_string(nv) +
                                 " vertices needs more than " + std::to_string(kMaxOptimalTableBytes >> 20) +
                                 " MB; use fewer extrema or the skeleton method");
    // The terminal limit here depends on the mesh (the table's bytes are what is bounded):
    // the most terminals whose table fits on these vertices.
    std::size_t limit = 1;
    while (limit < k && optimal_table_bytes(limit + 1, nv) <= kMaxOptimalTableBytes) ++limit;
    error.values = {{"count", k}, {"limit", limit}, {"vertices", nv}, {"limit_bytes", kMaxOptimalTableBytes}};
    return error;
  }

  // dp[S][v]: the shortest tree joining the terminals in S and v in which every terminal is
  // a leaf: terminals are never passed through and never meeting points (the full-component
  // constraint). Terminal k-1 is the root, reached last as a leaf. With a bound, the
  // terminal-avoiding distances give the kernel's lower bounds.
  std::vector<std::uint8_t> is_terminal(nv, 0);
  std::vector<std::uint32_t> port_mask(nv, 0);
  for (VertexId t : terminals) is_terminal[t.index()] = 1;
  for (std::size_t i = 0; i < m; ++i) port_mask[terminals[i].index()] = std::uint32_t{1} << i;
  DreyfusWagner kernel;
  SEAM_TRY(GroupSteinerTree tree, kernel.solve(graph,
                                               GroupSteinerProblem{.ports = m,
                                                                   .port_mask = port_mask,
                                                                   .obstacle = is_terminal,
                                                                   .leaf_only = is_terminal,
                                                                   .root = terminals[k - 1],
                                                                   .bound = upper_bound},
                                               cancel));
  if (tree.cost == kInf) {
    if (upper_bound < kInf) return SteinerTree{};  // nothing shorter than the bound
    return make_error(ErrorCode::kInvalidArgument, "optimal seam: the terminals are not all connected");
  }
  std::vector<EdgeId> edges;
  for (HalfedgeId h : tree.halfedges) edges.push_back(HalfedgeMesh::edge(h));
  // With positive weights the edges already form a tree; zero-weight (virtual) edges can tie
  // into a cycle, which the forest step removes without touching a terminal's only edge.
  // Every end is kept, so only a cycle's edge can go.
  std::vector<VertexId> ends;
  for (EdgeId e : edges) {
    ends.push_back(mesh.tail(HalfedgeMesh::halfedge(e)));
    ends.push_back(mesh.head(HalfedgeMesh::halfedge(e)));
  }
  const auto tree_edges = pruned_spanning_forest(mesh, edges, ends, surface.edge_weights());
  return make_steiner_tree(surface, tree_edges, terminals);
}

}  // namespace seam::core
