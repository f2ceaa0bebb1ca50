#include "core/seam/baselines.h"

#include <algorithm>
#include <bit>
#include <limits>
#include <numeric>
#include <queue>
#include <string>
#include <utility>
#include <vector>

#include "core/paths/forest.h"

namespace seam::core {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The Dreyfus–Wagner table is 2^(k-1) rows of V doubles plus back-pointers; above this it is
// refused rather than risking the process (many requests share one machine).
constexpr std::size_t kMaxOptimalTableBytes = std::size_t{512} << 20;

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

using Entry = std::pair<double, std::uint32_t>;
using MinQueue = std::priority_queue<Entry, std::vector<Entry>, std::greater<>>;

}  // namespace

Result<SteinerTree> mst_seam(const HalfedgeMesh& mesh, const EdgeGraph& graph, std::span<const double> edge_weights,
                             const TerminalPaths& paths, const CancelToken& cancel) {
  const std::size_t k = paths.size();
  if (auto status = validate_terminals(graph, paths.terminals, "mst seam"); !status.ok()) return status.take_error();
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
  const auto tree_edges = pruned_spanning_forest(mesh, edges, paths.terminals, edge_weights);
  return make_steiner_tree(mesh, tree_edges, paths.terminals, edge_weights);
}

Result<SteinerTree> greedy_seam(const HalfedgeMesh& mesh, const EdgeGraph& graph, std::span<const double> edge_weights,
                                std::span<const VertexId> terminals, const CancelToken& cancel) {
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
    MinQueue queue;
    for (VertexId v : tree_vertices) {
      dist[v.index()] = 0;
      parent[v.index()] = HalfedgeId();
      touched.push_back(v.value());
      queue.emplace(0.0, v.value());
    }
    std::uint32_t found = VertexId::kInvalidValue;
    while (!queue.empty()) {
      if (cancel.poll(polls)) return cancelled_error("greedy seam");
      const auto [d, v] = queue.top();
      queue.pop();
      if (settled[v] || d > dist[v]) continue;
      settled[v] = 1;
      if (pending[v]) {
        found = v;
        break;
      }
      for (std::uint32_t slot = graph.offsets[v]; slot < graph.offsets[v + 1]; ++slot) {
        const std::uint32_t w = graph.head[slot].value();
        const double nd = d + graph.weight[slot];
        if (nd < dist[w]) {
          if (dist[w] == kInf) touched.push_back(w);
          dist[w] = nd;
          parent[w] = graph.halfedge[slot];
          queue.emplace(nd, w);
        }
      }
    }
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
  return make_steiner_tree(mesh, edges, terminals, edge_weights);
}

namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
constexpr std::uint32_t kMergeBit = 0x80000000u;

// Row S of the table from its splits: dp[S][v] = min over {A, S\A} of dp[A][v] + dp[S\A][v],
// each unordered split once (A holds S's lowest terminal); terminals are never merge points.
Status merge_row(std::span<const double> dp, std::size_t s, std::size_t nv, std::span<const VertexId> terminals,
                 double* row, std::uint32_t* brow, std::uint32_t& polls, const CancelToken& cancel) {
  const std::size_t low = s & (~s + 1);
  for (std::size_t a = (s - 1) & s; a > 0; a = (a - 1) & s) {
    if (!(a & low)) continue;
    if (cancel.poll(polls)) return cancelled_error("optimal seam");
    const double* ra = dp.data() + a * nv;
    const double* rb = dp.data() + (s ^ a) * nv;
    for (std::size_t v = 0; v < nv; ++v) {
      const double value = ra[v] + rb[v];
      if (value < row[v]) {
        row[v] = value;
        brow[v] = kMergeBit | static_cast<std::uint32_t>(a);
      }
    }
  }
  for (VertexId t : terminals) {
    row[t.index()] = kInf;
    brow[t.index()] = kNone;
  }
  return Ok{};
}

// The tree of table entry (full, root), following back-pointers: merges split the subset,
// path steps go back along their half-edge.
SteinerTree trace_table(const HalfedgeMesh& mesh, std::span<const std::uint32_t> back, std::size_t nv,
                        std::size_t full, VertexId root, std::span<const VertexId> terminals,
                        std::span<const double> edge_weights) {
  std::vector<EdgeId> edges;
  std::vector<std::pair<std::size_t, std::uint32_t>> stack{{full, root.value()}};
  while (!stack.empty()) {
    const auto [s, v] = stack.back();
    stack.pop_back();
    const std::uint32_t b = back[s * nv + v];
    if (b == kNone) continue;  // the source of a singleton
    if (b & kMergeBit) {
      const std::size_t a = b & ~kMergeBit;
      stack.emplace_back(a, v);
      stack.emplace_back(s ^ a, v);
    } else {
      const HalfedgeId h(b);
      edges.push_back(HalfedgeMesh::edge(h));
      stack.emplace_back(s, mesh.tail(h).value());
    }
  }
  // With positive weights the edges already form a tree; zero-weight (virtual) edges can tie
  // into a cycle, which the forest step removes without touching a terminal's only edge.
  // Nothing is pruned: with a contracted graph (see seam.cpp) a path ends on a vertex that
  // the graph never names, which must stay.
  std::vector<VertexId> ends;
  for (EdgeId e : edges) {
    ends.push_back(mesh.tail(HalfedgeMesh::halfedge(e)));
    ends.push_back(mesh.head(HalfedgeMesh::halfedge(e)));
  }
  const auto tree_edges = pruned_spanning_forest(mesh, edges, ends, edge_weights);
  return make_steiner_tree(mesh, tree_edges, terminals, edge_weights);
}

// One Dreyfus–Wagner row grown along shortest paths: a multi-source Dijkstra seeded with the
// whole row. After merging nearly every vertex is a seed, so the seeds are sorted once and
// streamed in order alongside a heap that only holds improvements; that keeps the heap small
// instead of pushing V entries per subset. With `lower` (a lower bound per vertex on what the
// rest of any tree through it costs), states whose value plus that bound reaches `bound` are
// dropped: a tree cheaper than `bound` never needs them (A*-like pruning, exact).
Status grow_row(const EdgeGraph& graph, const std::vector<std::uint8_t>& is_terminal, std::uint32_t source,
                double* row, std::uint32_t* brow, const double* lower, double bound, std::vector<Entry>& initial,
                std::uint32_t& polls, const CancelToken& cancel) {
  const std::size_t nv = graph.num_vertices();
  initial.clear();
  for (std::size_t v = 0; v < nv; ++v) {
    if (row[v] == kInf) continue;
    if (lower && row[v] + lower[v] >= bound) {
      row[v] = kInf;
      continue;
    }
    initial.emplace_back(row[v], static_cast<std::uint32_t>(v));
  }
  std::sort(initial.begin(), initial.end());
  std::size_t next_seed = 0;
  MinQueue queue;
  while (next_seed < initial.size() || !queue.empty()) {
    if (cancel.poll(polls)) return cancelled_error("optimal seam");
    Entry top;
    if (queue.empty() || (next_seed < initial.size() && initial[next_seed] < queue.top())) {
      top = initial[next_seed++];
    } else {
      top = queue.top();
      queue.pop();
    }
    const auto [d, v] = top;
    if (d > row[v]) continue;
    if (is_terminal[v] && v != source) continue;  // reached as a leaf, never passed through
    for (std::uint32_t slot = graph.offsets[v]; slot < graph.offsets[v + 1]; ++slot) {
      const std::uint32_t w = graph.head[slot].value();
      const double nd = d + graph.weight[slot];
      if (nd < row[w] && (!lower || nd + lower[w] < bound)) {
        row[w] = nd;
        brow[w] = graph.halfedge[slot].value();
        queue.emplace(nd, w);
      }
    }
  }
  return Ok{};
}

// The bounded table's first rows: terminal-avoiding distances from every terminal (the
// singleton rows, and the root's into `root_distance`), the lower bounds of the pruning.
Status distance_rows(const EdgeGraph& graph, const std::vector<std::uint8_t>& is_terminal,
                     std::span<const VertexId> terminals, std::vector<double>& dp, std::vector<std::uint32_t>& back,
                     std::vector<double>& root_distance, std::vector<Entry>& initial, std::uint32_t& polls,
                     const CancelToken& cancel) {
  const std::size_t nv = graph.num_vertices();
  const std::size_t m = terminals.size() - 1;
  std::vector<std::uint32_t> scratch(nv, kNone);
  root_distance.assign(nv, kInf);
  for (std::size_t i = 0; i <= m; ++i) {
    double* row = i < m ? dp.data() + (std::size_t{1} << i) * nv : root_distance.data();
    std::uint32_t* brow = i < m ? back.data() + (std::size_t{1} << i) * nv : scratch.data();
    row[terminals[i].index()] = 0;
    if (auto st = grow_row(graph, is_terminal, terminals[i].value(), row, brow, nullptr, kInf, initial, polls, cancel);
        !st.ok()) {
      return st.take_error();
    }
  }
  return Ok{};
}

}  // namespace

Result<SteinerTree> optimal_seam(const HalfedgeMesh& mesh, const EdgeGraph& graph, std::span<const double> edge_weights,
                                 std::span<const VertexId> terminals, std::size_t max_terminals,
                                 const CancelToken& cancel, double upper_bound) {
  const std::size_t k = terminals.size();
  if (k > max_terminals) {
    return make_error(ErrorCode::kTooManyTerminals,
                      "the exact seam takes at most " + std::to_string(max_terminals) + " terminals, got " +
                          std::to_string(k) + "; use the skeleton method or fewer extrema");
  }
  if (auto status = validate_terminals(graph, terminals, "optimal seam"); !status.ok()) return status.take_error();
  const std::size_t nv = graph.num_vertices();
  const std::size_t m = k - 1;  // terminal k-1 is the root, added last as a leaf
  const std::size_t rows = std::size_t{1} << m;
  if (rows * nv * (sizeof(double) + sizeof(std::uint32_t)) > kMaxOptimalTableBytes) {
    return make_error(ErrorCode::kTooManyTerminals,
                      "the exact seam with " + std::to_string(k) + " terminals on " + std::to_string(nv) +
                          " vertices needs more than " + std::to_string(kMaxOptimalTableBytes >> 20) +
                          " MB; use fewer extrema or the skeleton method");
  }

  std::vector<std::uint8_t> is_terminal(nv, 0);
  for (VertexId t : terminals) is_terminal[t.index()] = 1;

  // dp[S][v]: the shortest tree joining the terminals in S and v in which every terminal is
  // a leaf. Terminals are never expanded (no path passes through one) and merges happen only
  // at non-terminal vertices (a terminal never gets degree two): the full-component constraint.
  std::vector<double> dp(rows * nv, kInf);
  std::vector<std::uint32_t> back(rows * nv, kNone);
  std::uint32_t polls = 0;
  std::vector<Entry> initial;
  // With a bound, the singleton rows (terminal-avoiding distances) come first: the rest of a
  // tree through v that still has to reach terminal t costs at least t's distance to v.
  const bool bounded = upper_bound < kInf;
  std::vector<double> root_distance, lower;
  if (bounded) {
    if (auto st = distance_rows(graph, is_terminal, terminals, dp, back, root_distance, initial, polls, cancel);
        !st.ok()) {
      return st.take_error();
    }
    lower.resize(nv);
  }
  for (std::size_t s = 1; s < rows; ++s) {
    double* row = dp.data() + s * nv;
    std::uint32_t* brow = back.data() + s * nv;
    const bool singleton = (s & (s - 1)) == 0;
    if (singleton && bounded) continue;  // done above
    std::uint32_t source = kNone;
    if (singleton) {
      const auto i = static_cast<std::size_t>(std::countr_zero(s));
      source = terminals[i].value();
      row[source] = 0;
    } else {
      if (auto st = merge_row(dp, s, nv, terminals, row, brow, polls, cancel); !st.ok()) return st.take_error();
    }
    if (bounded) {
      lower = root_distance;
      for (std::size_t i = 0; i < m; ++i) {
        if (s & (std::size_t{1} << i)) continue;
        const double* ri = dp.data() + (std::size_t{1} << i) * nv;
        for (std::size_t v = 0; v < nv; ++v) lower[v] = std::max(lower[v], ri[v]);
      }
    }
    if (auto st = grow_row(graph, is_terminal, source, row, brow, bounded ? lower.data() : nullptr, upper_bound,
                           initial, polls, cancel);
        !st.ok()) {
      return st.take_error();
    }
  }
  const std::size_t full = rows - 1;
  const VertexId root = terminals[k - 1];
  if (dp[full * nv + root.index()] == kInf) {
    if (bounded) return SteinerTree{};  // nothing shorter than the bound
    return make_error(ErrorCode::kInvalidArgument, "optimal seam: the terminals are not all connected");
  }

  return trace_table(mesh, back, nv, full, root, terminals, edge_weights);
}

}  // namespace seam::core
