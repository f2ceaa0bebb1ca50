// A reusable Dijkstra workspace for the many small searches of the skeleton seam (§4.4
// straightening, Steiner point relocation): buffers are allocated once per mesh and reset
// in constant time (a new generation), not in time proportional to the mesh size.
#pragma once

#include <cstdint>
#include <cstddef>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include "core/cancel.h"
#include "core/error.h"
#include "core/paths/dijkstra_kernel.h"
#include "core/paths/geodesic.h"
#include "core/mesh/halfedge_mesh.h"

namespace seam::core {

/// Dijkstra on an EdgeGraph with O(touched) resets between runs. Not thread-safe; one per
/// thread. Vertex states set with block()/forbid() persist across runs until clear_marks().
class PathSearch {
 public:
  static constexpr double kUnreached = std::numeric_limits<double>::infinity();

  /// `graph` must outlive the search. O(V) allocation, once.
  explicit PathSearch(const EdgeGraph& graph);

  /// A blocked vertex may end a path (it is settled) but no path passes through it;
  /// sources are always expanded. A forbidden vertex is never entered at all.
  void block(VertexId v);
  void forbid(VertexId v);
  /// Lifts every block() and forbid(). O(number of marked vertices).
  void clear_marks();
  bool is_blocked(VertexId v) const { return mark_[v.index()] == kBlocked; }
  bool is_forbidden(VertexId v) const { return mark_[v.index()] == kForbidden; }

  /// Starts a new search: forgets the previous one's distances. O(1) (O(V) once in 2^30 resets).
  void reset();
  /// Adds a source at distance `offset` (>= 0); a repeated source keeps its smaller offset.
  void add_source(VertexId v, double offset = 0.0);
  /// Runs until every target is settled (empty: until exhausted) or the next vertex is
  /// farther than max_distance. Errors: kCancelled. O(touched log touched).
  Status run(std::span<const VertexId> targets = {}, double max_distance = kUnreached,
             const CancelToken& cancel = CancelToken::none()) {
    return run_impl(targets, max_distance, false, cancel);
  }
  /// A* towards one target with the straight-line distance to `positions[target]` as the
  /// estimate. Valid only when every edge weighs at least its Euclidean length (the default
  /// weights); distances and paths are then exactly Dijkstra's. Errors: kCancelled.
  Status run_astar(VertexId target, std::span<const Vec3> positions, const CancelToken& cancel = CancelToken::none()) {
    return run_astar(target, positions, {}, cancel);
  }
  /// The same with the estimate max(straight line, floor[v]): `floor` (empty: none) must be
  /// a lower bound on every vertex's distance to the target that no edge's weight undercuts
  /// (floor[u] <= weight(u, v) + floor[v]), e.g. the distance to the nearest of a set of
  /// vertices that holds the target. Errors: kCancelled.
  Status run_astar(VertexId target, std::span<const Vec3> positions, std::span<const double> floor,
                   const CancelToken& cancel = CancelToken::none());
  /// Like run() without targets, but also stops once `max_settled` vertices are settled.
  /// Errors: kCancelled.
  Status run_limited(double max_distance, std::size_t max_settled, const CancelToken& cancel = CancelToken::none()) {
    max_settled_ = max_settled;
    auto st = run_impl({}, max_distance, false, cancel);
    max_settled_ = SIZE_MAX;
    return st;
  }
  /// Runs until the first of `targets` is settled (the nearest one), or the next vertex is
  /// farther than max_distance (then no target is reached). Errors: kCancelled.
  /// Also stops once `max_settled` vertices are settled (then no target may be reached).
  Status run_to_nearest(std::span<const VertexId> targets, const CancelToken& cancel = CancelToken::none(),
                        double max_distance = kUnreached, std::size_t max_settled = SIZE_MAX) {
    max_settled_ = max_settled;
    auto st = run_impl(targets, max_distance, true, cancel);
    max_settled_ = SIZE_MAX;
    return st;
  }

  /// Settled distance of v from the sources, kUnreached if not settled by the last run.
  double distance(VertexId v) const {
    const Node& n = nodes_[v.index()];
    return current(n) && settled(n) ? n.dist : kUnreached;
  }
  bool reached(VertexId v) const { return distance(v) != kUnreached; }
  /// Half-edge into v on its shortest path (invalid at a source or when unreached).
  HalfedgeId parent(VertexId v) const {
    const Node& n = nodes_[v.index()];
    return current(n) ? n.parent : HalfedgeId();
  }
  /// The path from its source to v, in order; empty when v is a source or unreached.
  std::vector<HalfedgeId> path_to(const HalfedgeMesh& mesh, VertexId v) const;
  /// Vertices settled by the last run, in settling order (nondecreasing distance).
  std::span<const VertexId> settled() const { return settled_order_; }

 private:
  static constexpr std::uint8_t kFree = 0;
  static constexpr std::uint8_t kBlocked = 1;
  static constexpr std::uint8_t kForbidden = 2;

  // What a search keeps per vertex, in one 16-byte record so that relaxing an edge reads one
  // cache line: the distance, the half-edge in, and `state`: the run's generation (a multiple
  // of 4) plus the settled and source flags. A record of an older generation is unset.
  static constexpr std::uint32_t kSettled = 1;
  static constexpr std::uint32_t kSource = 2;
  static constexpr std::uint32_t kGenerationStep = 4;
  struct Node {
    double dist = kUnreached;
    HalfedgeId parent;
    std::uint32_t state = 0;
  };
  static_assert(sizeof(Node) == 16);
  bool current(const Node& n) const { return (n.state & ~(kSettled | kSource)) == generation_; }
  static bool settled(const Node& n) { return n.state & kSettled; }
  // Gives v this search's defaults the first time the search meets it.
  Node& touch(std::uint32_t v) {
    Node& n = nodes_[v];
    if (!current(n)) n = Node{kUnreached, HalfedgeId(), generation_};
    return n;
  }
  // The visitor of run_dijkstra (dijkstra_kernel.h): `OnSettle` decides for a popped entry,
  // `Key(w, nd)` is the heap key of an improved vertex (nd, or nd plus the A* estimate).
  template <class OnSettle, class Key>
  struct Visitor;
  // Settled v is expanded unless it is blocked and not a source.
  SettleAction expand_unless_blocked(std::uint32_t v) const {
    return mark_[v] == kBlocked && !(nodes_[v].state & kSource) ? SettleAction::kSkip : SettleAction::kExpand;
  }
  Status run_impl(std::span<const VertexId> targets, double max_distance, bool nearest_only,
                  const CancelToken& cancel);

  const EdgeGraph* graph_;
  std::vector<Node> nodes_;
  std::vector<std::uint8_t> mark_;
  std::vector<std::uint32_t> marked_;
  std::vector<VertexId> settled_order_;
  LazyHeap heap_;
  std::vector<std::uint8_t> is_target_;
  std::uint32_t generation_ = kGenerationStep;
  std::size_t max_settled_ = SIZE_MAX;
};

}  // namespace seam::core
