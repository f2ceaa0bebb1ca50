// The one Dreyfus–Wagner kernel of the seam: the exact minimum tree joining groups of vertices
// (ports) on an edge graph, under the full-component rules of the skeleton seam (terminals
// stay leaves). Used for the exact seam (optimal_seam, every terminal a port) and for the
// local re-optimisation of refine_tree (every loose subtree a port).
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "core/cancel.h"
#include "core/error.h"
#include "core/paths/dijkstra_kernel.h"
#include "core/paths/geodesic.h"

namespace seam::core {

/// A group Steiner problem on `graph` (any EdgeGraph: the mesh's or a region's, whose
/// `halfedge` entries are only carried through to the answer). Per vertex:
/// - `port_mask`: the ports (bits 0..ports-1) the vertex belongs to; a tree joins port q at
///   any vertex with bit q;
/// - `obstacle`: nonzero where no path passes and no paths meet, except for the ports the
///   partial tree already holds (a loose subtree may be passed along or joined anywhere);
/// - `leaf_only`: nonzero for terminals: never passed through nor a meeting point (a
///   terminal port is joined only as a leaf). A leaf-only vertex must also be an obstacle.
struct GroupSteinerProblem {
  std::size_t ports = 0;  ///< 1..30
  std::span<const std::uint32_t> port_mask;
  std::span<const std::uint8_t> obstacle;
  std::span<const std::uint8_t> leaf_only;
  /// Valid: the tree must also reach this vertex (a leaf-only non-port, e.g. the last
  /// terminal), which saves the table half its rows. Invalid: the tree may end anywhere.
  VertexId root;
  /// Only trees cheaper than this are looked for; states that cannot lead to one (their value
  /// plus a lower bound on the rest, from the distances to the ports still to join computed
  /// with every loose subtree passable: half the shortest tour through them and the state's
  /// vertex, and the largest distance) are dropped, which leaves the answer unchanged. The
  /// kernel lowers its own bound to the trees its table already holds (just above them), so
  /// an infinite bound prunes too; the answer is the same minimum tree either way.
  double bound = std::numeric_limits<double>::infinity();
  /// Finite: the caller only wants a tree cheaper than this. When a lower bound from the
  /// distance rows (the cheapest subtree joining any three ports, or the two, with every loose
  /// subtree passable) shows that none is, no tree is returned and target_ruled_out is set,
  /// before the 2^ports table is filled. Exact: a tree is only left out if it costs at least
  /// the bound, which is at least `target`. Infinite: no such test (the answer is the minimum
  /// tree below `bound`).
  double target = std::numeric_limits<double>::infinity();
};

struct GroupSteinerTree {
  double cost = std::numeric_limits<double>::infinity();  ///< infinite: no tree (below the bound)
  std::vector<HalfedgeId> halfedges;  ///< graph.halfedge of the tree's edges (any order)
  bool target_ruled_out = false;  ///< no tree: the distance rows showed none costs less than the target
};

/// A reusable workspace (its tables are kept between solves). Not thread-safe.
class DreyfusWagner {
 public:
  /// Dreyfus–Wagner over the 2^ports port subsets: merge rows at meeting points, then grow
  /// each row by a multi-source Dijkstra. Ties by vertex id; deterministic.
  /// Preconditions (SEAM_ASSERT): the spans have graph.num_vertices() entries, 1 <= ports <= 30.
  /// Errors: kCancelled. Memory: 2^ports x V x 12 bytes (the caller caps it), plus
  /// (ports + 1) x V doubles and, up to 9 ports, 2^(ports+1) x (ports+1)^2 doubles of bounds.
  /// Complexity: O(3^p V + 2^p E log V), p = ports (times O(p^2) per lower-bound evaluation);
  /// with a target that the lower bound rules out, O(p E log V + p^3 V).
  Result<GroupSteinerTree> solve(const EdgeGraph& graph, const GroupSteinerProblem& problem,
                                 const CancelToken& cancel = CancelToken::none());

 private:
  using Entry = std::pair<double, std::uint32_t>;
  // The rows are sparse: a bounded problem leaves most states infinite, so every row keeps
  // the list of its finite entries and all work (merging, growing, resetting) walks lists.
  // Large tables are asked for in transparent huge pages (where the OS has them): a fresh
  // table is otherwise first touched in thousands of 4 KB page faults.
  template <class T>
  struct LargePages {
    using value_type = T;
    LargePages() = default;
    template <class U>
    LargePages(const LargePages<U>&) {}
    T* allocate(std::size_t count);
    void deallocate(T* p, std::size_t count);
    template <class U>
    bool operator==(const LargePages<U>&) const { return true; }
  };
  struct Rows {
    std::vector<double, LargePages<double>> value;  // row-major, stride = vertex count; kInf off the lists
    std::vector<std::uint32_t, LargePages<std::uint32_t>> back;  // slot of the last edge, kMerge | split, kNone at a seed
    std::vector<std::vector<std::uint32_t>> finite;  // per row: its finite entries
    std::size_t stride = 0;
    void reset(std::size_t rows, std::size_t n);  // O(previous finite entries) + growth
  };
  struct LowerBound;  // what the rest of any tree through a vertex costs at least
  Status grow(const EdgeGraph& graph, const GroupSteinerProblem& problem, std::uint32_t s, Rows& rows,
              std::uint32_t row, const LowerBound* lower, std::uint32_t stop, const CancelToken& cancel);
  Result<bool> distance_rows(const EdgeGraph& graph, const GroupSteinerProblem& problem, const CancelToken& cancel);
  Status singleton_rows(const EdgeGraph& graph, const GroupSteinerProblem& problem, bool prune,
                        const CancelToken& cancel);
  double rows_bound(std::span<const std::uint32_t> rows, const Rows& from) const;
  Status relaxed_rows(const EdgeGraph& graph, const GroupSteinerProblem& problem, bool passable,
                      const CancelToken& cancel);
  void pack_lower_rows(const GroupSteinerProblem& problem);
  void tour_paths();
  LowerBound lower_bound(std::uint32_t still) const;
  std::vector<std::uint32_t> row_order(const GroupSteinerProblem& problem);
  void tighten_bound(const GroupSteinerProblem& problem, std::uint32_t s);
  void merge(const GroupSteinerProblem& problem, std::uint32_t s);
  void take_marks(std::vector<std::uint32_t>& list);
  void sort_seeds();
  std::vector<HalfedgeId> trace(const EdgeGraph& graph, std::uint32_t full, std::uint32_t root) const;

  Rows table_;    // row s: the subset s of ports
  Rows relaxed_;  // row q: distances to port q with every loose subtree passable; row p: the root's
  std::vector<std::vector<std::uint32_t>> port_vertices_;
  std::vector<std::uint32_t> seed_mask_;       // the relaxed rows' problem: its seeds as port 0
  std::vector<std::uint8_t> seed_blocks_;      // ... and only terminals other than its seeds block
  std::vector<Entry> seeds_;
  std::vector<Entry> spare_;  // sort_seeds' other buffer
  LazyHeap heap_;
  std::vector<std::uint64_t> marks_;  // a row's finite entries while it is merged or grown
  bool lower_from_table_ = false;  // the singleton rows serve as the relaxed rows
  // The lower rows packed per vertex: near_[v * (ports + 1) + q], q = ports the root's;
  // floats rounded down (half the cache lines of the lower bounds' hottest loads).
  std::vector<float> near_;
  std::size_t width_ = 0;          // ports + 1
  std::vector<double> apart_;      // (ports + 1)^2: lower bounds on the tree path between two ports
  std::vector<double> tours_;      // Held-Karp paths over apart_ (see tour_paths); empty: too many rows
  std::vector<std::uint8_t> done_;  // per row: done (its complement may tighten the bound)
  struct Memo {
    double lower = 0.0;
    std::uint32_t epoch = 0;
  };
  std::vector<Memo> memo_;  // per vertex: its lower bound in the row being grown (epoch_)
  std::uint32_t epoch_ = 0;
  double bound_ = 0.0;             // problem.bound, lowered by the trees the table already holds
  std::uint32_t polls_ = 0;
};

}  // namespace seam::core
