#include "core/paths/dreyfus_wagner.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <new>
#include <utility>

#if __has_include(<sys/mman.h>)
#include <sys/mman.h>
#endif

namespace seam::core {

namespace {

constexpr std::uint32_t kMerge = 0x80000000u;

constexpr std::size_t kLargePage = std::size_t{2} << 20;

bool singleton(std::uint32_t s) { return (s & (s - 1)) == 0; }

}  // namespace

template <class T>
T* DreyfusWagner::LargePages<T>::allocate(std::size_t count) {
  const std::size_t bytes = count * sizeof(T);
  if (bytes < 2 * kLargePage) return std::allocator<T>().allocate(count);
  const std::size_t rounded = (bytes + kLargePage - 1) / kLargePage * kLargePage;
  void* p = std::aligned_alloc(kLargePage, rounded);
  if (p == nullptr) throw std::bad_alloc();
#ifdef MADV_HUGEPAGE
  (void)madvise(p, rounded, MADV_HUGEPAGE);  // advice only: without it the pages are small
#endif
  return static_cast<T*>(p);
}

template <class T>
void DreyfusWagner::LargePages<T>::deallocate(T* p, std::size_t count) {
  if (count * sizeof(T) < 2 * kLargePage) {
    std::allocator<T>().deallocate(p, count);
    return;
  }
  std::free(p);
}

template struct DreyfusWagner::LargePages<double>;
template struct DreyfusWagner::LargePages<std::uint32_t>;

void DreyfusWagner::Rows::reset(std::size_t rows, std::size_t n) {
  for (std::size_t r = 0; r < finite.size(); ++r) {
    for (std::uint32_t v : finite[r]) {
      value[r * stride + v] = kInf;
      back[r * stride + v] = kNone;
    }
    finite[r].clear();
  }
  if (rows * n > value.size()) {  // every entry is kInf / kNone here: nothing to copy
    value.assign(rows * n, kInf);
    back.assign(rows * n, kNone);
  }
  finite.resize(rows);
  stride = n;
}

// A lower bound on the rest of any tree through v (the goal-oriented bounds of Hougardy,
// Silvanus and Vygen 2017): the rest is a tree joining v to every lower row still to join (the
// ports, and the root), each of whose paths costs at least the rows' distances. Doubled, it
// is a closed walk through v and one vertex of each such row, so it costs at least half the
// shortest such tour by those distances: v's distances to the tour's two ends plus the
// shortest Hamiltonian path between them through the rows (by apart_, Held-Karp). With many
// rows the path is bounded by a minimum spanning tree instead (a 1-tree). Either way also the
// largest distance. The bound is consistent (1-Lipschitz along an edge, and a merge's part
// costs at least what it takes off the bound), so every state of a tree cheaper than the
// bound is below it too, and no state such a tree needs is dropped.
struct DreyfusWagner::LowerBound {
  static constexpr std::size_t kTourRows = 10;  // Held-Karp up to this many rows
  const float* near = nullptr;   // near_
  std::size_t width = 0;
  std::size_t count = 0;         // rows still to join
  std::array<std::uint8_t, 32> rows{};  // ... their indices (`ports`: the root)
  std::array<double, kTourRows * kTourRows> path{};  // count x count shortest Hamiltonian paths
  bool tour = false;             // path holds them; else half_tree bounds the rest
  double half_tree = 0.0;        // half a minimum spanning tree on the rows
  double at(std::uint32_t v) const {
    const float* d = near + static_cast<std::size_t>(v) * width;
    double x[32];
    double far = 0.0;
    for (std::size_t i = 0; i < count; ++i) x[i] = d[rows[i]], far = std::max(far, x[i]);
    if (count < 2) return far;
    if (tour) {
      double best = kInf;
      for (std::size_t i = 0; i < count; ++i) {
        double inner = kInf;
        for (std::size_t j = 0; j < count; ++j) inner = std::min(inner, path[i * count + j] + x[j]);
        best = std::min(best, x[i] + inner);
      }
      return std::max(far, 0.5 * best);
    }
    double first = kInf, second = kInf;
    for (std::size_t i = 0; i < count; ++i) {
      second = std::min(second, std::max(first, x[i]));
      first = std::min(first, x[i]);
    }
    return std::max(far, half_tree + 0.5 * (first + second));
  }
};

namespace {

// grow()'s visitor: one table row as the distance array; a vertex beyond the bound is
// never entered, a closed one (see `expandable`) is settled but not expanded.
template <class Beyond, class Expandable>
struct RowVisitor {
  std::uint32_t stop;  // the search ends once this vertex is settled (kNone: never)
  double* row;
  std::uint32_t* back;
  std::uint64_t* marks;  // the row's finite entries (bits)
  SeededHeap& frontier;
  Beyond& beyond;
  Expandable& expandable;

  SettleAction settle(std::uint32_t v, double d) {
    if (d > row[v]) return SettleAction::kSkip;  // stale
    if (v == stop) return SettleAction::kStop;
    return expandable(v) ? SettleAction::kExpand : SettleAction::kSkip;  // closed
  }
  double distance(std::uint32_t v) const { return row[v]; }
  static std::uint32_t graph_vertex(std::uint32_t v) { return v; }
  void relax(std::uint32_t, std::uint32_t w, double nd, std::uint32_t slot) {
    if (nd < row[w] && !beyond(w, nd)) {
      marks[w >> 6] |= std::uint64_t{1} << (w & 63);
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
// With a valid `stop`, the search ends once it is settled (its value is then final).
Status DreyfusWagner::grow(const EdgeGraph& graph, const GroupSteinerProblem& problem, std::uint32_t s, Rows& rows,
                           std::uint32_t r, const LowerBound* lower, std::uint32_t stop, const CancelToken& cancel) {
  double* row = rows.value.data() + static_cast<std::size_t>(r) * rows.stride;
  std::uint32_t* back = rows.back.data() + static_cast<std::size_t>(r) * rows.stride;
  const double bound = bound_;
  if (++epoch_ == 0) {
    std::fill(memo_.begin(), memo_.end(), Memo{});
    epoch_ = 1;
  }
  if (memo_.size() < rows.stride) memo_.resize(rows.stride);
  Memo* memo = memo_.data();
  const std::uint32_t epoch = epoch_;
  auto beyond = [&](std::uint32_t v, double d) {
    if (d >= bound) return true;
    if (!lower) return false;
    Memo& m = memo[v];
    if (m.epoch != epoch) m = {lower->at(v), epoch};
    return d + m.lower >= bound;
  };
  auto expandable = [&](std::uint32_t v) {
    if (!problem.obstacle[v]) return true;
    return (problem.port_mask[v] & s) != 0 && (!problem.leaf_only[v] || singleton(s));
  };
  seeds_.clear();
  for (std::uint32_t v : rows.finite[r]) {
    if (beyond(v, row[v])) {
      row[v] = kInf;
      back[v] = kNone;
      continue;
    }
    seeds_.emplace_back(row[v], v);
    marks_[v >> 6] |= std::uint64_t{1} << (v & 63);
  }
  sort_seeds();
  heap_.clear();
  SeededHeap frontier(seeds_, heap_);
  RowVisitor<decltype(beyond), decltype(expandable)> visitor{stop, row, back, marks_.data(), frontier, beyond, expandable};
  if (Status status = run_dijkstra(graph, frontier, visitor, cancel, "Dreyfus-Wagner", polls_); !status.ok()) {
    return status;
  }
  take_marks(rows.finite[r]);
  return Ok{};
}

// Sorts seeds_ by (value, vertex): they come in vertex order, so a stable LSD radix sort on
// the value's bits (non-negative doubles order as their bit patterns) is enough; digits every
// seed shares (the exponent's, mostly) cost a histogram and no pass.
void DreyfusWagner::sort_seeds() {
  constexpr int kBits = 11;
  constexpr std::size_t kBuckets = std::size_t{1} << kBits;
  if (seeds_.size() < 64) {
    std::sort(seeds_.begin(), seeds_.end());
    return;
  }
  std::array<std::uint32_t, kBuckets> count;
  spare_.resize(seeds_.size());
  for (int shift = 0; shift < 64; shift += kBits) {
    count.fill(0);
    auto digit = [&](const Entry& e) { return (std::bit_cast<std::uint64_t>(e.first) >> shift) & (kBuckets - 1); };
    for (const Entry& e : seeds_) ++count[digit(e)];
    if (count[digit(seeds_.front())] == seeds_.size()) continue;  // one digit: already in order
    std::uint32_t sum = 0;
    for (std::uint32_t& c : count) sum += std::exchange(c, sum);
    for (const Entry& e : seeds_) spare_[count[digit(e)]++] = e;
    seeds_.swap(spare_);
  }
}

// The marked vertices as a list in increasing order (so that merging and growing walk the
// rows forwards), allocated once at its size; the marks are cleared.
void DreyfusWagner::take_marks(std::vector<std::uint32_t>& list) {
  std::size_t count = 0;
  for (std::uint64_t word : marks_) count += static_cast<std::size_t>(std::popcount(word));
  list.clear();
  list.reserve(count);  // not resized: no zero fill
  for (std::size_t w = 0; w < marks_.size(); ++w) {
    for (std::uint64_t bits = marks_[w]; bits != 0; bits &= bits - 1) {
      list.push_back(static_cast<std::uint32_t>(w * 64 + static_cast<std::size_t>(std::countr_zero(bits))));
    }
    marks_[w] = 0;
  }
}

// The singleton rows: distances from each port, bounded by the bound. With `prune` (the
// relaxed rows exist and are packed) those rows prune these like the others: a tree through
// port q's state at v also joins every other port (and the root) from v.
Status DreyfusWagner::singleton_rows(const EdgeGraph& graph, const GroupSteinerProblem& problem, bool prune,
                                     const CancelToken& cancel) {
  const std::size_t n = graph.num_vertices();
  const std::size_t p = problem.ports;
  const std::uint32_t all = ((std::uint32_t{1} << p) - 1) | (problem.root.valid() ? std::uint32_t{1} << p : 0u);
  for (std::size_t q = 0; q < p; ++q) {
    const std::uint32_t s = std::uint32_t{1} << q;
    for (std::uint32_t v : port_vertices_[q]) table_.value[s * n + v] = 0.0;
    table_.finite[s] = port_vertices_[q];
    // Without relaxed rows the singleton rows are the other rows' lower bounds: not pruned.
    const LowerBound lower = prune ? lower_bound(all & ~s) : LowerBound{};
    if (auto st = grow(graph, problem, s, table_, s, prune ? &lower : nullptr, kNone, cancel); !st.ok()) {
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

// The lower bounds' rows: where loose subtrees could be passed
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
    auto st = grow(graph, open, 1u, relaxed_, static_cast<std::uint32_t>(r), nullptr, kNone, cancel);
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

// The lower rows (the singleton rows where only terminals block, else the relaxed rows, and
// the root's) packed per vertex for LowerBound, and between each two of them a lower bound on
// a tree path joining them: the smaller of the two rows' distances to the other's vertices.
void DreyfusWagner::pack_lower_rows(const GroupSteinerProblem& problem) {
  const std::size_t n = table_.stride;
  const std::size_t p = problem.ports;
  const std::size_t width = p + 1;
  width_ = width;
  near_.assign(n * width, std::numeric_limits<float>::infinity());
  auto pack = [&](std::size_t q, const Rows& from, std::size_t r) {
    const double* row = from.value.data() + r * n;
    for (std::uint32_t v : from.finite[r]) {
      float d = static_cast<float>(row[v]);
      if (static_cast<double>(d) > row[v]) d = std::nextafter(d, 0.0f);  // rounded down: still a lower bound
      near_[v * width + q] = d;
    }
  };
  for (std::size_t q = 0; q < p; ++q) {
    if (lower_from_table_) {
      pack(q, table_, std::size_t{1} << q);
    } else {
      pack(q, relaxed_, q);
    }
  }
  if (problem.root.valid()) pack(p, relaxed_, p);
  apart_.assign(width * width, kInf);
  for (std::size_t b = 0; b < width; ++b) {
    apart_[b * width + b] = 0.0;
    auto join = [&](std::uint32_t v) {
      for (std::size_t a = 0; a < width; ++a) apart_[a * width + b] = std::min(apart_[a * width + b], static_cast<double>(near_[v * width + a]));
    };
    if (b < p) {
      for (std::uint32_t v : port_vertices_[b]) join(v);
    } else if (problem.root.valid()) {
      join(problem.root.value());
    }
  }
  for (std::size_t a = 0; a < width; ++a) {
    for (std::size_t b = 0; b < a; ++b) {
      apart_[a * width + b] = apart_[b * width + a] = std::min(apart_[a * width + b], apart_[b * width + a]);
    }
  }
  tour_paths();
}

// The lower bound for the states that still have to join the lower rows `still`: their
// Hamiltonian paths (up to LowerBound::kTourRows rows), else a minimum spanning tree on them
// by apart_ (Prim).
DreyfusWagner::LowerBound DreyfusWagner::lower_bound(std::uint32_t still) const {
  const std::size_t width = width_;
  LowerBound lower;
  lower.near = near_.data();
  lower.width = width;
  for (std::uint32_t m = still; m != 0; m &= m - 1) lower.rows[lower.count++] = static_cast<std::uint8_t>(std::countr_zero(m));
  const std::size_t c = lower.count;
  if (c < 2) return lower;
  if (!tours_.empty()) {
    lower.tour = true;
    const double* at = tours_.data() + static_cast<std::size_t>(still) * width * width;
    for (std::size_t i = 0; i < c; ++i) {
      for (std::size_t j = 0; j < c; ++j) lower.path[i * c + j] = at[lower.rows[i] * width + lower.rows[j]];
    }
    return lower;
  }
  double link[32];
  std::uint32_t out = (std::uint32_t{1} << c) - 2;  // rows (by position) not yet in the tree
  for (std::size_t i = 1; i < c; ++i) link[i] = apart_[lower.rows[0] * width + lower.rows[i]];
  double tree = 0.0;
  while (out != 0) {
    std::size_t next = static_cast<std::size_t>(std::countr_zero(out));
    for (std::uint32_t m = out; m != 0; m &= m - 1) {
      if (link[std::countr_zero(m)] < link[next]) next = static_cast<std::size_t>(std::countr_zero(m));
    }
    tree += link[next];
    out &= ~(std::uint32_t{1} << next);
    for (std::uint32_t m = out; m != 0; m &= m - 1) {
      const auto i = static_cast<std::size_t>(std::countr_zero(m));
      link[i] = std::min(link[i], apart_[lower.rows[next] * width + lower.rows[i]]);
    }
  }
  lower.half_tree = 0.5 * tree;
  return lower;
}

// Held-Karp over the lower rows by apart_: tours_[(S * width + a) * width + b] is the shortest
// path from row a to row b through every row of S (a != b unless S = {a}; else infinite).
void DreyfusWagner::tour_paths() {
  const std::size_t w = width_;
  tours_.clear();
  if (w > LowerBound::kTourRows) return;
  const std::size_t subsets = std::size_t{1} << w;
  tours_.assign(subsets * w * w, kInf);
  for (std::size_t a = 0; a < w; ++a) tours_[((std::size_t{1} << a) * w + a) * w + a] = 0.0;
  for (std::size_t set = 1; set < subsets; ++set) {
    if (std::has_single_bit(set)) continue;
    double* at = tours_.data() + set * w * w;
    for (std::size_t b = 0; b < w; ++b) {
      if (!(set >> b & 1)) continue;
      const std::size_t rest = set & ~(std::size_t{1} << b);
      const double* before = tours_.data() + rest * w * w;
      for (std::size_t a = 0; a < w; ++a) {
        if (!(rest >> a & 1)) continue;
        double best = kInf;
        for (std::size_t c = 0; c < w; ++c) {
          if (rest >> c & 1) best = std::min(best, before[a * w + c] + apart_[c * w + b]);
        }
        at[a * w + b] = best;
      }
    }
  }
}

// The order of the rows above the singletons: first every subset of the two halves of a
// split {A, B} of the ports, so that tighten_bound lowers the bound early to the trees that
// merge a state of A with one of B, then every other row in increasing order (each after
// its subsets either way). Of the balanced splits (the cheapest first rows) the one whose
// lower bounds (LowerBound for A and for B at a vertex, plus its distance to the root) are
// smallest on a sample of the free vertices. Table states against increasing order alone:
// armadillo (26k vertices) 7 terminals 662k -> 501k, 8: 1207k -> 793k; hand x4 7: 144k -> 113k.
std::vector<std::uint32_t> DreyfusWagner::row_order(const GroupSteinerProblem& problem) {
  constexpr std::uint32_t kSample = 7;  // every 7th vertex (meshes are numbered spatially)
  const std::size_t n = table_.stride;
  const std::size_t p = problem.ports;
  const std::uint32_t full = (std::uint32_t{1} << p) - 1;
  std::uint32_t best_split = 0;
  double best = kInf;
  for (std::uint32_t a = 1; a < full && p >= 4; a += 2) {  // A holds port 0: each split once
    if (std::abs(2 * std::popcount(a) - static_cast<int>(p)) > 1) continue;
    const LowerBound on_a = lower_bound(a);
    const LowerBound on_b = lower_bound(full & ~a);
    double lower = kInf;
    for (std::uint32_t v = 0; v < n; v += kSample) {
      if (problem.obstacle[v]) continue;
      const double root = problem.root.valid() ? static_cast<double>(near_[v * width_ + p]) : 0.0;
      lower = std::min(lower, on_a.at(v) + on_b.at(v) + root);
    }
    if (lower < best) best = lower, best_split = a;
  }
  const std::uint32_t other = best_split != 0 ? full & ~best_split : 0u;
  auto first = [&](std::uint32_t s) { return (s & best_split) == s || (s & other) == s; };
  std::vector<std::uint32_t> order;
  for (std::uint32_t s = 1; s <= full; ++s) {
    if (!singleton(s) && first(s)) order.push_back(s);
  }
  for (std::uint32_t s = 1; s <= full; ++s) {
    if (!singleton(s) && !first(s)) order.push_back(s);
  }
  done_.assign(std::size_t{full} + 1, 0);
  for (std::size_t q = 0; q < p; ++q) done_[std::size_t{1} << q] = 1;
  return order;
}

// Lowers the bound to a tree the table already holds (with a margin, so that the optimum's
// states stay below it despite rounding): a free vertex's state in row s (s = 0: none) merged
// with its state in the complementary row where that row is done, else with its singleton
// rows' paths to every port still missing, and joined to the root by the root's row's path.
// Merging at a free vertex and growing to the root are steps of the table, so the optimum
// costs at most that sum. Only where those rows hold real paths: the table's rows, and the
// root's row where only terminals block (it then follows the full row's rules).
void DreyfusWagner::tighten_bound(const GroupSteinerProblem& problem, std::uint32_t s) {
  if (problem.root.valid() && !lower_from_table_) return;
  const std::size_t n = table_.stride;
  const std::size_t p = problem.ports;
  const std::uint32_t full = (std::uint32_t{1} << p) - 1;
  const std::uint32_t rest = full & ~s;
  const double* row = table_.value.data() + static_cast<std::size_t>(s) * n;
  const double* root_row = relaxed_.value.data() + p * n;  // exact sums: not the packed floats
  const double* other = rest != 0 && done_[rest] ? table_.value.data() + static_cast<std::size_t>(rest) * n : nullptr;
  double best = kInf;
  for (std::uint32_t v : table_.finite[s != 0 ? s : 1u]) {
    if (problem.obstacle[v]) continue;
    double sum = s != 0 ? row[v] : 0.0;
    if (other != nullptr) {
      sum += other[v];
    } else {
      for (std::uint32_t m = rest; m != 0; m &= m - 1) {
        const auto q = static_cast<std::size_t>(std::countr_zero(m));
        sum += table_.value[(std::size_t{1} << q) * n + v];
      }
    }
    if (problem.root.valid()) sum += root_row[v];
    best = std::min(best, sum);
  }
  bound_ = std::min(bound_, best * (1.0 + 1e-9) + std::numeric_limits<double>::denorm_min());
}

void DreyfusWagner::merge(const GroupSteinerProblem& problem, std::uint32_t s) {
  const std::size_t n = table_.stride;
  double* row = table_.value.data() + static_cast<std::size_t>(s) * n;
  std::uint32_t* back = table_.back.data() + static_cast<std::size_t>(s) * n;
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
      marks_[v >> 6] |= std::uint64_t{1} << (v & 63);
      row[v] = value;
      back[v] = kMerge | a;
    }
  }
  take_marks(table_.finite[s]);
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

// The relaxed rows (where loose subtrees could be passed, and the root's), then the singleton
// rows, with the target's test as soon as the rows it needs exist, and the lower rows packed
// once they exist. False: the target is ruled out.
Result<bool> DreyfusWagner::distance_rows(const EdgeGraph& graph, const GroupSteinerProblem& problem,
                                          const CancelToken& cancel) {
  const std::size_t n = graph.num_vertices();
  const std::size_t p = problem.ports;
  const bool targeted = problem.target < kInf;
  bool passable = false;  // obstacles that are loose subtrees, not only terminals
  for (std::size_t v = 0; v < n && !passable; ++v) passable = problem.obstacle[v] && !problem.leaf_only[v];
  // Where only terminals block, each singleton row is its own relaxed row.
  lower_from_table_ = !passable;
  relaxed_.reset(p + 1, n);
  if (passable || problem.root.valid()) {
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
  if (passable) pack_lower_rows(problem);
  if (auto st = singleton_rows(graph, problem, passable, cancel); !st.ok()) return st.take_error();
  if (!passable) pack_lower_rows(problem);
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
  marks_.assign((n + 63) / 64, 0);
  port_vertices_.assign(p, {});
  for (std::uint32_t v = 0; v < n; ++v) {
    for (std::uint32_t m = problem.port_mask[v]; m != 0; m &= m - 1) {
      port_vertices_[static_cast<std::size_t>(std::countr_zero(m))].push_back(v);
    }
  }
  bound_ = problem.bound;
  SEAM_TRY(const bool open, distance_rows(graph, problem, cancel));
  GroupSteinerTree tree;
  if (!open) {
    tree.target_ruled_out = true;
    return tree;
  }
  const std::vector<std::uint32_t> order = row_order(problem);
  tighten_bound(problem, 0);
  const std::uint32_t root_bit = problem.root.valid() ? std::uint32_t{1} << p : 0u;
  for (std::uint32_t s : order) {
    done_[s] = 1;
    merge(problem, s);
    const LowerBound lower = lower_bound((full & ~s) | root_bit);
    // The full row is only read at the root (when there is one): it ends there.
    const std::uint32_t stop = s == full && problem.root.valid() ? problem.root.value() : kNone;
    if (auto st = grow(graph, problem, s, table_, s, &lower, stop, cancel); !st.ok()) return st.take_error();
    if (s != full) tighten_bound(problem, s);
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
