// Shortest paths on the mesh's edge graph (Dijkstra), the distance the seam is measured in.
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "core/cancel.h"
#include "core/error.h"
#include "core/mesh/halfedge_mesh.h"

namespace seam::core {

/// Euclidean length of every edge. O(E).
EdgeData<double> edge_lengths(const HalfedgeMesh& mesh);

/// Compressed adjacency of the edge graph, built once and shared by many Dijkstra runs.
/// Row v lists, counter-clockwise from vertex_halfedge(v), the outgoing half-edges of v
/// with their head and weight. Immutable, so concurrent searches may share it.
struct EdgeGraph {
  std::vector<std::uint32_t> offsets;  ///< num_vertices + 1 row starts
  std::vector<VertexId> head;          ///< neighbour at the other end
  std::vector<HalfedgeId> halfedge;    ///< the outgoing half-edge v -> head
  std::vector<double> weight;          ///< its edge's weight

  std::size_t num_vertices() const { return offsets.empty() ? 0 : offsets.size() - 1; }
};

/// Builds the edge graph. `edge_weights` (one per edge, each finite and >= 0) overrides the
/// Euclidean lengths; empty means Euclidean. Precondition: edge_weights is empty or has
/// num_edges() entries (SEAM_ASSERT). O(E).
EdgeGraph build_edge_graph(const HalfedgeMesh& mesh, std::span<const double> edge_weights = {});

struct DijkstraOptions {
  /// Stop as soon as every one of these vertices is settled; empty settles everything.
  std::span<const VertexId> targets;
  /// Do not settle vertices farther than this.
  double max_distance = std::numeric_limits<double>::infinity();
  /// Optional, one byte per vertex: nonzero vertices may end a path but no path passes
  /// through them (they are settled but never expanded). Sources are always expanded.
  std::span<const std::uint8_t> blocked;
};

/// Distances and the shortest-path forest from the source set.
struct ShortestPathTree {
  static constexpr double kUnreached = std::numeric_limits<double>::infinity();
  std::vector<double> distance;    ///< per vertex; kUnreached where not settled
  std::vector<HalfedgeId> parent;  ///< per vertex: the half-edge into it on its path; invalid at sources
  std::vector<std::uint32_t> source;  ///< per vertex: index into `sources` of its nearest source

  bool reached(VertexId v) const { return distance[v.index()] != kUnreached; }
};

/// Multi-source Dijkstra: all `sources` start at distance 0 (a boundary loop passed as
/// its vertices acts as one source). Deterministic: the queue orders ties by vertex id, and
/// a parent changes only on a strictly shorter distance, so equal inputs give equal trees.
/// Errors: kInvalidArgument (no sources, a source or target out of range),
/// kCancelled. Complexity: O(E log V), less with targets or max_distance.
Result<ShortestPathTree> dijkstra(const EdgeGraph& graph, std::span<const VertexId> sources,
                                  const DijkstraOptions& options = {},
                                  const CancelToken& cancel = CancelToken::none());

/// The path to `target` as half-edges in order from its source to target; empty when target
/// is a source or was not reached. O(path length).
std::vector<HalfedgeId> trace_path(const HalfedgeMesh& mesh, const ShortestPathTree& tree, VertexId target);

/// Sum of the weights of `path`'s edges under `edge_weights` (empty: Euclidean).
double path_length(const HalfedgeMesh& mesh, std::span<const HalfedgeId> path,
                   std::span<const double> edge_weights = {});

}  // namespace seam::core
