#include "core/paths/dreyfus_wagner.h"

#include <algorithm>
#include <functional>

namespace seam::core {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr std::uint32_t kNone = 0xffffffffu;
constexpr std::uint32_t kMerge = 0x80000000u;

bool singleton(std::uint32_t s) { return (s & (s - 1)) == 0; }

}  // namespace

// A row grown along shortest paths: a multi-source Dijkstra seeded with the whole row. After
// merging nearly every vertex is a seed, so the seeds are sorted once and streamed in order
// alongside a heap that only holds improvements, instead of pushing V entries per subset.
// With `lower` (a lower bound per vertex on what the rest of any tree through it costs),
// states whose value plus it reaches the bound are dropped: a tree cheaper than the bound
// never needs them (A*-like pruning, exact).
Status DreyfusWagner::grow(const EdgeGraph& graph, const GroupSteinerProblem& problem, std::uint32_t s, double* row,
                           std::uint32_t* back, const double* lower, const CancelToken& cancel) {
  const std::size_t n = graph.num_vertices();
  const double bound = problem.bound;
  auto beyond = [&](std::size_t v, double d) { return lower ? d + lower[v] >= bound : d >= bound; };
  auto expandable = [&](std::uint32_t v) {
    if (!problem.obstacle[v]) return true;
    return (problem.port_mask[v] & s) != 0 && (!problem.leaf_only[v] || singleton(s));
  };
  seeds_.clear();
  for (std::size_t v = 0; v < n; ++v) {
    if (row[v] == kInf) continue;
    if (beyond(v, row[v])) {
      row[v] = kInf;
      back[v] = kNone;
      continue;
    }
    seeds_.emplace_back(row[v], static_cast<std::uint32_t>(v));
  }
  std::sort(seeds_.begin(), seeds_.end());
  std::size_t next_seed = 0;
  heap_.clear();
  while (next_seed < seeds_.size() || !heap_.empty()) {
    if (cancel.poll(polls_)) return cancelled_error("Dreyfus-Wagner");
    Entry top;
    if (heap_.empty() || (next_seed < seeds_.size() && seeds_[next_seed] < heap_.front())) {
      top = seeds_[next_seed++];
    } else {
      std::pop_heap(heap_.begin(), heap_.end(), std::greater<>());
      top = heap_.back();
      heap_.pop_back();
    }
    const auto [d, v] = top;
    if (d > row[v] || !expandable(v)) continue;
    for (std::uint32_t slot = graph.offsets[v]; slot < graph.offsets[v + 1]; ++slot) {
      const std::uint32_t w = graph.head[slot].value();
      const double nd = d + graph.weight[slot];
      if (nd < row[w] && !beyond(w, nd)) {
        row[w] = nd;
        back[w] = slot;
        heap_.emplace_back(nd, w);
        std::push_heap(heap_.begin(), heap_.end(), std::greater<>());
      }
    }
  }
  return Ok{};
}

// Distances from the vertices of the ports in `seeds_mask` (or from `seed`), bounded by the
// problem's bound. `relaxed`: every loose subtree is passable (only terminals block), which
// makes the row a lower bound on any tree path to the port.
Status DreyfusWagner::distance_row(const EdgeGraph& graph, const GroupSteinerProblem& problem,
                                   std::uint32_t seeds_mask, VertexId seed, bool relaxed, double* row,
                                   std::uint32_t* back, const CancelToken& cancel) {
  const std::size_t n = graph.num_vertices();
  std::fill(row, row + n, kInf);
  std::fill(back, back + n, kNone);
  for (std::size_t v = 0; v < n; ++v) {
    if (problem.port_mask[v] & seeds_mask) row[v] = 0.0;
  }
  if (seed.valid()) row[seed.index()] = 0.0;
  if (!relaxed && !seed.valid()) return grow(graph, problem, seeds_mask, row, back, nullptr, cancel);
  // Relaxed (or rooted) rows: a problem whose obstacles are its leaf-only vertices and whose
  // seeds count as its single port, so only terminals other than the seeds block.
  scratch_.assign(n, 0);
  std::vector<std::uint8_t> leaf(problem.leaf_only.begin(), problem.leaf_only.end());
  for (std::size_t v = 0; v < n; ++v) {
    if (row[v] == 0.0) scratch_[v] = 1, leaf[v] = 0;
  }
  GroupSteinerProblem open = problem;
  open.port_mask = scratch_;
  open.obstacle = leaf;
  open.leaf_only = leaf;
  return grow(graph, open, 1u, row, back, nullptr, cancel);
}

void DreyfusWagner::merge(const GroupSteinerProblem& problem, std::uint32_t s, std::size_t n, double* row,
                          std::uint32_t* back) {
  // Each unordered split {a, s \ a} once: a holds s's lowest port.
  const std::uint32_t low = s & (~s + 1);
  for (std::uint32_t a = (s - 1) & s; a > 0; a = (a - 1) & s) {
    if (!(a & low)) continue;
    const double* ra = dp_.data() + static_cast<std::size_t>(a) * n;
    const double* rb = dp_.data() + static_cast<std::size_t>(s ^ a) * n;
    for (std::size_t v = 0; v < n; ++v) {
      const double value = ra[v] + rb[v];
      if (value < row[v]) {
        row[v] = value;
        back[v] = kMerge | a;
      }
    }
  }
  // Partial trees meet only at free vertices and at vertices of ports they already hold.
  for (std::uint32_t v : restricted_) {
    if (problem.leaf_only[v] || (problem.port_mask[v] & s) == 0) {
      row[v] = kInf;
      back[v] = kNone;
    }
  }
}

std::vector<HalfedgeId> DreyfusWagner::trace(const EdgeGraph& graph, std::uint32_t full, std::uint32_t root) const {
  const std::size_t n = graph.num_vertices();
  std::vector<HalfedgeId> out;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> stack{{full, root}};
  while (!stack.empty()) {
    const auto [s, v] = stack.back();
    stack.pop_back();
    const std::uint32_t b = back_[static_cast<std::size_t>(s) * n + v];
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

Result<GroupSteinerTree> DreyfusWagner::solve(const EdgeGraph& graph, const GroupSteinerProblem& problem,
                                              const CancelToken& cancel) {
  const std::size_t n = graph.num_vertices();
  const std::size_t p = problem.ports;
  SEAM_ASSERT(p >= 1 && p <= 30);
  SEAM_ASSERT(problem.port_mask.size() == n && problem.obstacle.size() == n && problem.leaf_only.size() == n);
  const auto rows = std::uint32_t{1} << p;
  const std::uint32_t full = rows - 1;
  dp_.assign(static_cast<std::size_t>(rows) * n, kInf);
  back_.assign(static_cast<std::size_t>(rows) * n, kNone);
  restricted_.clear();
  bool passable_obstacles = false;  // loose subtrees, not only terminals
  for (std::size_t v = 0; v < n; ++v) {
    if (!problem.obstacle[v]) continue;
    restricted_.push_back(static_cast<std::uint32_t>(v));
    if (!problem.leaf_only[v]) passable_obstacles = true;
  }
  auto row_of = [&](std::uint32_t s) { return dp_.data() + static_cast<std::size_t>(s) * n; };
  auto back_of = [&](std::uint32_t s) { return back_.data() + static_cast<std::size_t>(s) * n; };
  // Singleton rows first: with a bound they (or, where loose subtrees could be passed, their
  // relaxed versions) give the lower bound for every later row.
  for (std::size_t q = 0; q < p; ++q) {
    const std::uint32_t s = std::uint32_t{1} << q;
    if (auto st = distance_row(graph, problem, s, VertexId(), false, row_of(s), back_of(s), cancel); !st.ok()) {
      return st.take_error();
    }
  }
  const bool bounded = problem.bound < kInf;
  relaxed_.clear();
  root_row_.clear();
  if (bounded && passable_obstacles) {
    relaxed_.resize(p * n);
    scratch_.resize(n);
    std::vector<std::uint32_t> unused(n);
    for (std::size_t q = 0; q < p; ++q) {
      if (auto st = distance_row(graph, problem, std::uint32_t{1} << q, VertexId(), true, relaxed_.data() + q * n,
                                 unused.data(), cancel);
          !st.ok()) {
        return st.take_error();
      }
    }
  }
  if (bounded && problem.root.valid()) {
    root_row_.resize(n);
    std::vector<std::uint32_t> unused(n);
    if (auto st = distance_row(graph, problem, 0, problem.root, true, root_row_.data(), unused.data(), cancel);
        !st.ok()) {
      return st.take_error();
    }
  }
  for (std::uint32_t s = 1; s < rows; ++s) {
    if (singleton(s)) continue;
    merge(problem, s, n, row_of(s), back_of(s));
    const double* lower = nullptr;
    if (bounded) {
      lower_.assign(n, 0.0);
      if (!root_row_.empty()) lower_ = root_row_;
      for (std::size_t q = 0; q < p; ++q) {
        if (s & (std::uint32_t{1} << q)) continue;
        const double* rq = relaxed_.empty() ? row_of(std::uint32_t{1} << q) : relaxed_.data() + q * n;
        for (std::size_t v = 0; v < n; ++v) lower_[v] = std::max(lower_[v], rq[v]);
      }
      lower = lower_.data();
    }
    if (auto st = grow(graph, problem, s, row_of(s), back_of(s), lower, cancel); !st.ok()) return st.take_error();
  }
  GroupSteinerTree tree;
  std::size_t root = n;
  const double* last = row_of(full);
  if (problem.root.valid()) {
    if (last[problem.root.index()] < kInf) root = problem.root.index();
  } else {
    for (std::size_t v = 0; v < n; ++v) {
      if (last[v] < kInf && (root == n || last[v] < last[root])) root = v;
    }
  }
  if (root == n) return tree;
  tree.cost = last[root];
  tree.halfedges = trace(graph, full, static_cast<std::uint32_t>(root));
  return tree;
}

}  // namespace seam::core
