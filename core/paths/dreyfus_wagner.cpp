#include "core/paths/dreyfus_wagner.h"

#include <algorithm>
#include <bit>

namespace seam::core {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr std::uint32_t kNone = 0xffffffffu;
constexpr std::uint32_t kMerge = 0x80000000u;

bool singleton(std::uint32_t s) { return (s & (s - 1)) == 0; }

}  // namespace

void DreyfusWagner::Rows::reset(std::size_t rows, std::size_t n) {
  for (std::size_t r = 0; r < finite.size(); ++r) {
    for (std::uint32_t v : finite[r]) {
      value[r * stride + v] = kInf;
      back[r * stride + v] = kNone;
    }
    finite[r].clear();
  }
  if (rows * n > value.size()) {
    value.resize(rows * n, kInf);
    back.resize(rows * n, kNone);
  }
  finite.resize(rows);
  stride = n;
}

struct DreyfusWagner::LowerBound {
  std::vector<const double*> rows;  // distance rows of the ports still to join (and the root's)
  double at(std::uint32_t v) const {
    double lower = 0.0;
    for (const double* r : rows) lower = std::max(lower, r[v]);
    return lower;
  }
};

namespace {

// grow()'s visitor: one table row as the distance array; a vertex beyond the bound is
// never entered, a closed one (see `expandable`) is settled but not expanded.
template <class Beyond, class Expandable>
struct RowVisitor {
  double* row;
  std::uint32_t* back;
  std::vector<std::uint32_t>& reached;
  SeededHeap& frontier;
  Beyond& beyond;
  Expandable& expandable;

  SettleAction settle(std::uint32_t v, double d) {
    return d > row[v] || !expandable(v) ? SettleAction::kSkip : SettleAction::kExpand;  // stale or closed
  }
  double distance(std::uint32_t v) const { return row[v]; }
  static std::uint32_t graph_vertex(std::uint32_t v) { return v; }
  void relax(std::uint32_t, std::uint32_t w, double nd, std::uint32_t slot) {
    if (nd < row[w] && !beyond(w, nd)) {
      if (row[w] == kInf) reached.push_back(w);
      row[w] = nd;
      back[w] = slot;
      frontier.push(nd, w);
    }
  }
};

}  // namespace

// A row grown along shortest paths: a multi-source Dijkstra seeded with the row's finite
// entries. After merging many vertices are seeds, so the seeds are sorted once and streamed
// in order alongside a heap that only holds improvements. With `lower` (a lower bound per
// vertex on what the rest of any tree through it costs), states whose value plus it reaches
// the bound are dropped: a tree cheaper than the bound never needs them (A*-like, exact).
Status DreyfusWagner::grow(const EdgeGraph& graph, const GroupSteinerProblem& problem, std::uint32_t s, Rows& rows,
                           std::uint32_t r, const LowerBound* lower, const CancelToken& cancel) {
  double* row = rows.value.data() + static_cast<std::size_t>(r) * rows.stride;
  std::uint32_t* back = rows.back.data() + static_cast<std::size_t>(r) * rows.stride;
  const double bound = problem.bound;
  auto beyond = [&](std::uint32_t v, double d) { return lower ? d + lower->at(v) >= bound : d >= bound; };
  auto expandable = [&](std::uint32_t v) {
    if (!problem.obstacle[v]) return true;
    return (problem.port_mask[v] & s) != 0 && (!problem.leaf_only[v] || singleton(s));
  };
  seeds_.clear();
  reached_.clear();
  for (std::uint32_t v : rows.finite[r]) {
    if (beyond(v, row[v])) {
      row[v] = kInf;
      back[v] = kNone;
      continue;
    }
    seeds_.emplace_back(row[v], v);
    reached_.push_back(v);
  }
  std::sort(seeds_.begin(), seeds_.end());
  heap_.clear();
  SeededHeap frontier(seeds_, heap_);
  RowVisitor<decltype(beyond), decltype(expandable)> visitor{row, back, reached_, frontier, beyond, expandable};
  if (Status status = run_dijkstra(graph, frontier, visitor, cancel, "Dreyfus-Wagner", polls_); !status.ok()) {
    return status;
  }
  rows.finite[r].swap(reached_);
  return Ok{};
}

// The singleton rows: distances from each port, bounded by the problem's bound. With
// `prune` (a bounded problem whose relaxed rows exist) those rows prune these like the
// others: a tree through port q's state at v also joins every other port (and the root) from v.
Status DreyfusWagner::singleton_rows(const EdgeGraph& graph, const GroupSteinerProblem& problem, bool prune,
                                     const CancelToken& cancel) {
  const std::size_t n = graph.num_vertices();
  const std::size_t p = problem.ports;
  LowerBound lower;
  for (std::size_t q = 0; q < p; ++q) {
    const std::uint32_t s = std::uint32_t{1} << q;
    for (std::uint32_t v : port_vertices_[q]) table_.value[s * n + v] = 0.0;
    table_.finite[s] = port_vertices_[q];
    // Without relaxed rows the singleton rows are the other rows' lower bounds: not pruned.
    lower.rows.clear();
    if (prune) {
      if (problem.root.valid()) lower.rows.push_back(relaxed_.value.data() + p * n);
      for (std::size_t r = 0; r < p; ++r) {
        if (r != q) lower.rows.push_back(relaxed_.value.data() + r * n);
      }
    }
    if (auto st = grow(graph, problem, s, table_, s, prune ? &lower : nullptr, cancel); !st.ok()) {
      return st.take_error();
    }
  }
  return Ok{};
}

// A lower bound on any tree's cost from distance rows that bound each port's (and the root's)
// tree paths from below: any three of them are joined by a subtree with at most one branch
// vertex c, whose legs are edge-disjoint tree paths, so it costs at least the rows' sum at c.
// The bound is the largest, over triples (or the one pair), of the smallest such sum.
double DreyfusWagner::rows_bound(std::span<const std::uint32_t> rows, const Rows& from) const {
  const std::size_t n = from.stride;
  auto at = [&](std::uint32_t r, std::uint32_t v) { return from.value[static_cast<std::size_t>(r) * n + v]; };
  auto smallest_sum = [&](std::span<const std::uint32_t> group) {
    std::uint32_t walk = group[0];  // a sum is finite only on every row's list: walk the shortest
    for (std::uint32_t r : group) walk = from.finite[r].size() < from.finite[walk].size() ? r : walk;
    double best = kInf;
    for (std::uint32_t v : from.finite[walk]) {
      double sum = 0.0;
      for (std::uint32_t r : group) sum += at(r, v);
      best = std::min(best, sum);
    }
    return best;
  };
  if (rows.size() < 2) return 0.0;
  if (rows.size() == 2) return smallest_sum(rows);
  double lower = 0.0;
  for (std::size_t a = 0; a < rows.size(); ++a) {
    for (std::size_t b = a + 1; b < rows.size(); ++b) {
      for (std::size_t c = b + 1; c < rows.size(); ++c) {
        const std::uint32_t group[] = {rows[a], rows[b], rows[c]};
        lower = std::max(lower, smallest_sum(group));
      }
    }
  }
  return lower;
}

// For a bounded problem, the lower bounds' rows: where loose subtrees could be passed
// (`passable`), distances with every one of them passable (only terminals other than the
// seeds block), which bound any tree path to the port from below; and the root's distances.
Status DreyfusWagner::relaxed_rows(const EdgeGraph& graph, const GroupSteinerProblem& problem, bool passable,
                                   const CancelToken& cancel) {
  const std::size_t n = graph.num_vertices();
  const std::size_t p = problem.ports;
  seed_mask_.assign(n, 0);
  seed_blocks_.assign(problem.leaf_only.begin(), problem.leaf_only.end());
  GroupSteinerProblem open = problem;
  open.port_mask = seed_mask_;
  open.obstacle = seed_blocks_;
  open.leaf_only = seed_blocks_;
  auto relaxed_row = [&](std::size_t r, std::span<const std::uint32_t> seeds) -> Status {
    for (std::uint32_t v : seeds) seed_mask_[v] = 1, seed_blocks_[v] = 0, relaxed_.value[r * n + v] = 0.0;
    relaxed_.finite[r].assign(seeds.begin(), seeds.end());
    auto st = grow(graph, open, 1u, relaxed_, static_cast<std::uint32_t>(r), nullptr, cancel);
    for (std::uint32_t v : seeds) seed_mask_[v] = 0, seed_blocks_[v] = problem.leaf_only[v];
    return st;
  };
  for (std::size_t q = 0; q < p && passable; ++q) {
    if (auto st = relaxed_row(q, port_vertices_[q]); !st.ok()) return st.take_error();
  }
  if (problem.root.valid()) {
    const std::uint32_t root[] = {problem.root.value()};
    if (auto st = relaxed_row(p, root); !st.ok()) return st.take_error();
  }
  return Ok{};
}

void DreyfusWagner::merge(const GroupSteinerProblem& problem, std::uint32_t s) {
  const std::size_t n = table_.stride;
  double* row = table_.value.data() + static_cast<std::size_t>(s) * n;
  std::uint32_t* back = table_.back.data() + static_cast<std::size_t>(s) * n;
  auto& list = table_.finite[s];
  // Partial trees meet only at free vertices and at vertices of ports they already hold.
  auto meeting_point = [&](std::uint32_t v) {
    return !problem.obstacle[v] || (!problem.leaf_only[v] && (problem.port_mask[v] & s) != 0);
  };
  // Each unordered split {a, s \ a} once: a holds s's lowest port.
  const std::uint32_t low = s & (~s + 1);
  for (std::uint32_t a = (s - 1) & s; a > 0; a = (a - 1) & s) {
    if (!(a & low)) continue;
    const std::uint32_t b = s ^ a;
    const double* ra = table_.value.data() + static_cast<std::size_t>(a) * n;
    const double* rb = table_.value.data() + static_cast<std::size_t>(b) * n;
    const auto& walk = table_.finite[a].size() <= table_.finite[b].size() ? table_.finite[a] : table_.finite[b];
    for (std::uint32_t v : walk) {
      const double value = ra[v] + rb[v];
      if (!(value < row[v]) || !meeting_point(v)) continue;
      if (row[v] == kInf) list.push_back(v);
      row[v] = value;
      back[v] = kMerge | a;
    }
  }
}

std::vector<HalfedgeId> DreyfusWagner::trace(const EdgeGraph& graph, std::uint32_t full, std::uint32_t root) const {
  const std::size_t n = table_.stride;
  std::vector<HalfedgeId> out;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> stack{{full, root}};
  while (!stack.empty()) {
    const auto [s, v] = stack.back();
    stack.pop_back();
    const std::uint32_t b = table_.back[static_cast<std::size_t>(s) * n + v];
    if (b == kNone) continue;  // a seed
    if (b & kMerge) {
      stack.emplace_back(b & ~kMerge, v);
      stack.emplace_back(s ^ (b & ~kMerge), v);
      continue;
    }
    out.push_back(graph.halfedge[b]);
    const auto tail = std::upper_bound(graph.offsets.begin(), graph.offsets.end(), b) - graph.offsets.begin() - 1;
    stack.emplace_back(s, static_cast<std::uint32_t>(tail));
  }
  return out;
}

// The relaxed rows (for a bounded or targeted problem), then the singleton rows, with the
// target's test as soon as the rows it needs exist. False: the target is ruled out.
Result<bool> DreyfusWagner::distance_rows(const EdgeGraph& graph, const GroupSteinerProblem& problem,
                                          const CancelToken& cancel) {
  const std::size_t n = graph.num_vertices();
  const std::size_t p = problem.ports;
  const bool bounded = problem.bound < kInf;
  const bool targeted = problem.target < kInf;
  bool passable = false;  // obstacles that are loose subtrees, not only terminals
  for (std::size_t v = 0; v < n && !passable; ++v) passable = problem.obstacle[v] && !problem.leaf_only[v];
  // Where only terminals block, each singleton row is its own relaxed row.
  lower_from_table_ = !passable;
  relaxed_.reset(p + 1, n);
  if ((bounded || targeted) && (passable || problem.root.valid())) {
    if (auto st = relaxed_rows(graph, problem, passable, cancel); !st.ok()) return st.take_error();
  }
  std::vector<std::uint32_t> rows;  // the rows of the target's test: per port, and the root's
  auto below_target = [&](const Rows& port_rows, bool singletons) {
    rows.clear();
    for (std::uint32_t q = 0; q < p; ++q) rows.push_back(singletons ? std::uint32_t{1} << q : q);
    if (problem.root.valid() && !singletons) rows.push_back(static_cast<std::uint32_t>(p));
    return rows_bound(rows, port_rows) < problem.target;
  };
  if (targeted && passable && !below_target(relaxed_, false)) return false;
  if (auto st = singleton_rows(graph, problem, passable && bounded, cancel); !st.ok()) return st.take_error();
  return !(targeted && !passable && !below_target(table_, true));
}

Result<GroupSteinerTree> DreyfusWagner::solve(const EdgeGraph& graph, const GroupSteinerProblem& problem,
                                              const CancelToken& cancel) {
  const std::size_t n = graph.num_vertices();
  const std::size_t p = problem.ports;
  SEAM_ASSERT(p >= 1 && p <= 30);
  SEAM_ASSERT(problem.port_mask.size() == n && problem.obstacle.size() == n && problem.leaf_only.size() == n);
  const auto rows = std::uint32_t{1} << p;
  const std::uint32_t full = rows - 1;
  table_.reset(rows, n);
  port_vertices_.assign(p, {});
  for (std::uint32_t v = 0; v < n; ++v) {
    for (std::uint32_t m = problem.port_mask[v]; m != 0; m &= m - 1) {
      port_vertices_[static_cast<std::size_t>(std::countr_zero(m))].push_back(v);
    }
  }
  SEAM_TRY(const bool open, distance_rows(graph, problem, cancel));
  GroupSteinerTree tree;
  if (!open) {
    tree.target_ruled_out = true;
    return tree;
  }
  const bool bounded = problem.bound < kInf;
  LowerBound lower;
  for (std::uint32_t s = 1; s < rows; ++s) {
    if (singleton(s)) continue;
    merge(problem, s);
    if (bounded) {
      lower.rows.clear();
      if (problem.root.valid()) lower.rows.push_back(relaxed_.value.data() + p * n);
      for (std::size_t q = 0; q < p; ++q) {
        if (s & (std::uint32_t{1} << q)) continue;
        lower.rows.push_back(lower_from_table_ ? table_.value.data() + (std::size_t{1} << q) * n
                                               : relaxed_.value.data() + q * n);
      }
    }
    if (auto st = grow(graph, problem, s, table_, s, bounded ? &lower : nullptr, cancel); !st.ok()) {
      return st.take_error();
    }
  }
  const double* last = table_.value.data() + static_cast<std::size_t>(full) * n;
  std::uint32_t root = kNone;
  if (problem.root.valid()) {
    if (last[problem.root.index()] < kInf) root = problem.root.value();
  } else {
    for (std::uint32_t v : table_.finite[full]) {
      if (root == kNone || last[v] < last[root] || (last[v] == last[root] && v < root)) root = v;
    }
  }
  if (root == kNone) return tree;
  tree.cost = last[root];
  tree.halfedges = trace(graph, full, root);
  return tree;
}

}  // namespace seam::core
