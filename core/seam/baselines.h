// The seams the paper compares against (Fig. 1): Sheffer's MST seam and Gu et al.'s greedy seam,
// and the exact optimum the paper never measured against.
#pragma once

#include <span>

#include "core/cancel.h"
#include "core/error.h"
#include "core/paths/geodesic.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/paths/steiner.h"

namespace seam::core {

/// Sheffer 2002: the union of the shortest paths along the MST (Kruskal) of the complete
/// terminal graph. Terminals may end up interior. Same preconditions as skeleton_seam.
Result<SteinerTree> mst_seam(const HalfedgeMesh& mesh, const EdgeGraph& graph, std::span<const double> edge_weights,
                             const TerminalPaths& paths, const CancelToken& cancel = CancelToken::none());

/// Gu et al. 2002: start at terminal 0, repeatedly add the shortest path from the current
/// tree to the nearest unconnected terminal (multi-source Dijkstra from the tree).
Result<SteinerTree> greedy_seam(const HalfedgeMesh& mesh, const EdgeGraph& graph, std::span<const double> edge_weights,
                                std::span<const VertexId> terminals, const CancelToken& cancel = CancelToken::none());

/// The exact minimum Steiner tree in which every terminal is a leaf (Dreyfus–Wagner dynamic
/// programming over terminal subsets, with paths never passing through a terminal).
/// Errors: kTooManyTerminals above `max_terminals`, kCancelled.
/// Complexity: O(3^k V + 2^k E log V).
Result<SteinerTree> optimal_seam(const HalfedgeMesh& mesh, const EdgeGraph& graph, std::span<const double> edge_weights,
                                 std::span<const VertexId> terminals, std::size_t max_terminals,
                                 const CancelToken& cancel = CancelToken::none());

}  // namespace seam::core
