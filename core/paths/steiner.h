// The shared vocabulary of the seam methods: a Steiner tree on a closed genus-0 surface
// whose terminals are vertices, and the pairwise terminal shortest paths they all start from.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "core/cancel.h"
#include "core/error.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/paths/geodesic.h"
#include "core/paths/path_search.h"
#include "core/paths/search_surface.h"

namespace seam::core {

/// A tree of mesh edges connecting the terminals.
struct SteinerTree {
  std::vector<EdgeId> edges;                     ///< sorted, unique
  std::vector<VertexId> steiner_points;          ///< non-terminal vertices of degree >= 3, sorted
  std::vector<std::vector<HalfedgeId>> branches; ///< paths between terminals/Steiner points
  double length = 0.0;                           ///< sum of edge weights
};

/// Shortest paths between the terminals (Section 4.1's preprocessing), and the minimum
/// spanning tree of the terminal distance graph that the MST-based methods start from.
/// Either complete (compute_terminal_paths: every pair searched up front) or on demand
/// (terminal_paths_on_demand: the MST from one multi-source search, other pairs searched the
/// first time they are asked for). Both answer every query with an exact shortest distance
/// and a shortest path; on ties the paths of the two modes may differ, never their lengths.
/// An on-demand table is request-local: its queries fill a cache and run searches on the
/// surface it was built on (which must outlive it), so it is not for concurrent use.
class TerminalPaths {
 public:
  std::vector<VertexId> terminals;
  /// The k - 1 pairs (i < j) of a minimum spanning tree of the terminal distance graph, in
  /// Kruskal order (by distance, ties by index); fewer when the terminals are disconnected.
  std::vector<std::array<std::uint32_t, 2>> mst;

  std::size_t size() const { return terminals.size(); }
  /// Shortest-path length from terminal i to j (infinite if unreachable).
  double dist(std::size_t i, std::size_t j) const;
  /// Half-edges of a shortest path from terminal i to j (path j->i is its reverse).
  const std::vector<HalfedgeId>& path_between(std::size_t i, std::size_t j) const;
  /// A lower bound on dist(i, j) that runs no search: the distance when it is known, else
  /// (on-demand tables with Euclidean weights) the straight-line distance less a relative
  /// 1e-12 for rounding, else 0.
  double lower_bound(std::size_t i, std::size_t j) const;
  /// Pair searches run on demand so far (0 for a complete table).
  std::size_t searches() const { return searches_; }

 private:
  friend Result<TerminalPaths> compute_terminal_paths(const SearchSurface&, std::span<const VertexId>, unsigned,
                                                      const CancelToken&);
  friend Result<TerminalPaths> terminal_paths_on_demand(const SearchSurface&, std::span<const VertexId>,
                                                        const CancelToken&);
  void set(std::size_t i, std::size_t j, double d, std::vector<HalfedgeId> path) const;
  void search_pair(std::size_t i, std::size_t j) const;

  // distance_[i * k + j] is NaN until known; path_[i * k + j] then holds the path.
  mutable std::vector<double> distance_;
  mutable std::vector<std::vector<HalfedgeId>> path_;
  mutable std::size_t searches_ = 0;
  const HalfedgeMesh* mesh_ = nullptr;     // set only on demand
  std::shared_ptr<PathSearch> search_;     // set only on demand
  bool astar_ = false;                     // pair searches may use A* (Euclidean lower bounds)
  std::vector<double> nearest_;            // on demand: each vertex's distance to its nearest terminal
};

/// Runs one early-exit Dijkstra per terminal but the last, each stopping once the later
/// terminals are settled (on up to `threads` threads; 0 = hardware concurrency), and records
/// all pairwise distances and paths; the MST is Kruskal's on that table. Deterministic
/// regardless of the thread count.
/// Errors: kInvalidArgument (fewer than 2 terminals, repeated or out-of-range terminal),
/// kCancelled. Complexity: O(k E log V) work, k = number of terminals.
Result<TerminalPaths> compute_terminal_paths(const SearchSurface& surface, std::span<const VertexId> terminals,
                                             unsigned threads = 0, const CancelToken& cancel = CancelToken::none());

/// The same table filled on demand. The MST comes from one multi-source Dijkstra from all
/// terminals (Mehlhorn 1988): each edge joining two Voronoi regions proposes the path
/// source-u-v-source for its two terminals, and Kruskal on those proposals gives a minimum
/// spanning tree of the complete distance graph whose proposed paths are shortest paths.
/// Other pairs are searched (one early-exit Dijkstra from the lower-index terminal, whose
/// other settled terminals are recorded too) when first asked for; the tour asks for few,
/// mostly near, pairs. `surface` must outlive the table. On a Euclidean surface
/// (SearchSurface::euclidean) pair searches are A* towards the target, estimating the larger
/// of the straight-line distance and the vertex's distance to its nearest terminal (kept from
/// the first search, 8 bytes per vertex), which settles fewer vertices and gives the same
/// distances.
/// Errors: kInvalidArgument (as compute_terminal_paths), kCancelled (during the first search;
/// later searches are not cancellable but each is one bounded Dijkstra).
/// Complexity: O(E log V + k^2 log k) up front.
Result<TerminalPaths> terminal_paths_on_demand(const SearchSurface& surface, std::span<const VertexId> terminals,
                                               const CancelToken& cancel = CancelToken::none());

/// Builds the SteinerTree summary (sorted unique edges, Steiner points, branches split at
/// terminals and vertices of degree >= 3, length) from a set of edges forming a forest.
/// `edge_weights` as in build_edge_graph (empty: Euclidean). O(|edges| log |edges|).
SteinerTree make_steiner_tree(const HalfedgeMesh& mesh, std::span<const EdgeId> edges,
                              std::span<const VertexId> terminals, std::span<const double> edge_weights = {});

/// The same, measured in `surface`'s weights.
inline SteinerTree make_steiner_tree(const SearchSurface& surface, std::span<const EdgeId> edges,
                                     std::span<const VertexId> terminals) {
  return make_steiner_tree(surface.mesh(), edges, terminals, surface.edge_weights());
}

}  // namespace seam::core
