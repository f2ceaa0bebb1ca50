// The shared vocabulary of the seam methods: a Steiner tree on a closed genus-0 surface
// whose terminals are vertices, and the pairwise terminal shortest paths they all start from.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/cancel.h"
#include "core/error.h"
#include "core/paths/geodesic.h"
#include "core/mesh/halfedge_mesh.h"

namespace seam::core {

/// A tree of mesh edges connecting the terminals.
struct SteinerTree {
  std::vector<EdgeId> edges;                     ///< sorted, unique
  std::vector<VertexId> steiner_points;          ///< non-terminal vertices of degree >= 3, sorted
  std::vector<std::vector<HalfedgeId>> branches; ///< paths between terminals/Steiner points
  double length = 0.0;                           ///< sum of edge weights
};

/// Shortest paths between every pair of terminals (Section 4.1's preprocessing).
struct TerminalPaths {
  std::vector<VertexId> terminals;
  /// distance[i * k + j]: shortest-path length from terminal i to j (infinite if unreachable).
  std::vector<double> distance;
  /// path[i * k + j]: half-edges from terminal i to j (path[j*k+i] is its reverse).
  std::vector<std::vector<HalfedgeId>> path;

  std::size_t size() const { return terminals.size(); }
  double dist(std::size_t i, std::size_t j) const { return distance[i * size() + j]; }
  const std::vector<HalfedgeId>& path_between(std::size_t i, std::size_t j) const { return path[i * size() + j]; }
};

/// Runs one early-exit Dijkstra per terminal but the last, each stopping once the later
/// terminals are settled (on up to `threads` threads; 0 = hardware concurrency), and records
/// all pairwise distances and paths. Deterministic regardless of the thread count.
/// Errors: kInvalidArgument (fewer than 2 terminals, repeated or out-of-range terminal),
/// kCancelled. Complexity: O(k E log V) work, k = number of terminals.
Result<TerminalPaths> compute_terminal_paths(const HalfedgeMesh& mesh, const EdgeGraph& graph,
                                             std::span<const VertexId> terminals, unsigned threads = 0,
                                             const CancelToken& cancel = CancelToken::none());

/// Builds the SteinerTree summary (sorted unique edges, Steiner points, branches split at
/// terminals and vertices of degree >= 3, length) from a set of edges forming a forest.
/// `edge_weights` as in build_edge_graph (empty: Euclidean). O(|edges| log |edges|).
SteinerTree make_steiner_tree(const HalfedgeMesh& mesh, std::span<const EdgeId> edges,
                              std::span<const VertexId> terminals, std::span<const double> edge_weights = {});

}  // namespace seam::core
