// Turning a union of paths into a tree: a minimum spanning forest of the edge set with
// dangling non-terminal branches pruned. Shared by the baselines and the seam pipeline.
#pragma once

#include <span>
#include <vector>

#include "core/mesh/halfedge_mesh.h"

namespace seam::core {

/// Returns the minimum spanning forest (Kruskal, ties by edge id) of the subgraph formed by
/// `edges`, where all vertices in `merged` count as one node (e.g. the whole boundary of a
/// disc, which must be touched once per tree), after repeatedly removing leaves that are
/// neither in `keep` nor in `merged`. Connectivity between kept vertices is preserved.
/// `edge_weights` as in build_edge_graph (empty: Euclidean). Output sorted and unique.
/// O(m log m) in the number of edges.
std::vector<EdgeId> pruned_spanning_forest(const HalfedgeMesh& mesh, std::span<const EdgeId> edges,
                                           std::span<const VertexId> keep, std::span<const double> edge_weights = {},
                                           std::span<const VertexId> merged = {});

}  // namespace seam::core
