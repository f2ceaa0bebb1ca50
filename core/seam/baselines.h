// The seams the paper compares against (Fig. 1): Sheffer's MST seam and Gu et al.'s greedy seam,
// and the exact optimum the paper never measured against.
#pragma once

#include <limits>
#include <span>

#include "core/cancel.h"
#include "core/error.h"
#include "core/paths/search_surface.h"
#include "core/paths/steiner.h"

namespace seam::core {

/// Sheffer 2002: the union of the shortest paths along the MST (Kruskal) of the complete
/// terminal graph, `paths` being a table on `surface`. Terminals may end up interior. Same
/// preconditions as skeleton_seam.
/// Errors: kInvalidArgument (fewer than two, repeated or out-of-range terminals; terminals
/// not all connected), kCancelled.
Result<SteinerTree> mst_seam(const SearchSurface& surface, const TerminalPaths& paths,
                             const CancelToken& cancel = CancelToken::none());

/// Gu et al. 2002: start at terminal 0, repeatedly add the shortest path from the current
/// tree to the nearest unconnected terminal (multi-source Dijkstra from the tree).
/// Errors: kInvalidArgument (fewer than two, repeated or out-of-range terminals; terminals
/// not all connected), kCancelled.
Result<SteinerTree> greedy_seam(const SearchSurface& surface, std::span<const VertexId> terminals,
                                const CancelToken& cancel = CancelToken::none());

/// The exact minimum Steiner tree in which every terminal is a leaf (Dreyfus–Wagner dynamic
/// programming over terminal subsets, with paths never passing through a terminal).
/// With a finite `upper_bound` (the length of a known full-component tree, slightly raised),
/// states that cannot lead to a tree below it are dropped (their value plus the largest
/// terminal-avoiding distance to a terminal still to join reaches the bound), which leaves the
/// answer unchanged and settles far fewer vertices per subset; if no tree is below the bound
/// the result has no edges. Errors: kTooManyTerminals above `max_terminals` or when the table
/// (2^(k-1) x V x 12 bytes) would exceed 512 MB, kInvalidArgument (fewer than two, repeated
/// or out-of-range terminals; unbounded and not all connected), kCancelled.
/// Complexity: O(3^k V + 2^k E log V).
Result<SteinerTree> optimal_seam(const SearchSurface& surface, std::span<const VertexId> terminals,
                                 std::size_t max_terminals, const CancelToken& cancel = CancelToken::none(),
                                 double upper_bound = std::numeric_limits<double>::infinity());

}  // namespace seam::core
