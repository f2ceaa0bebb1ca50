// Beyond the paper: shortening a full-component seam tree by exact local re-optimisation.
// A small piece of the tree around one Steiner point, or two adjacent ones, is removed and
// the loose ends are reconnected by the exact minimum tree (Dreyfus–Wagner on a local
// region), which both relocates Steiner points and changes the local topology.
#pragma once

#include <span>
#include <vector>

#include "core/cancel.h"
#include "core/error.h"
#include "core/paths/search_surface.h"

namespace seam::core {

struct RefineOptions {
  int max_passes = 4;            ///< sweeps over all pieces; stops early when a sweep gains nothing
  std::size_t max_ports = 5;     ///< pieces with more loose ends are skipped (cost grows as 3^ports)
  /// Bound on a piece's search region (vertices): a larger region is cut down by halving the
  /// reach (up to 4 times) and the piece is skipped if it is still too large.
  /// 8000 (was 3000): with the branch-and-bound of the local search it costs 10k faces with 8
  /// extrema 103 -> 128 ms and brings e.g. bunny00 k=4 from 1.19 to 1.05 of the optimum
  /// (README, seam length table).
  std::size_t max_region = 8000;
  /// Total work budget: the sum over solved pieces of region size times 2^ports. Refinement
  /// stops (keeping what it gained) when it is spent, which bounds its time on large meshes.
  std::size_t max_work = 2000000;
  /// How much of each branch at a piece is cut loose, as a fraction of the piece's longest
  /// branch; the search region is everything within that distance of the cut parts.
  double reach = 1.0;
  /// Exact shortcuts, on by default; off only to check them against the plain run (tests):
  /// a local problem whose lower bound (Dreyfus–Wagner's distance rows: the cheapest subtree
  /// joining any three of its loose parts, every loose subtree passable) shows no tree
  /// shorter than the removed piece is not solved further, and a region already searched for
  /// the same cut and reach is reused. Neither changes the result.
  bool shortcuts = true;
};

struct RefineStats {
  std::size_t pieces_tried = 0;
  std::size_t improvements = 0;
  std::size_t pieces_reused = 0;  ///< not solved again: the same local problem had no gain before
  std::size_t region_searches = 0;  ///< searches for a piece's region (one per reach tried)
  std::size_t pieces_solved = 0;    ///< local problems handed to Dreyfus–Wagner
  std::size_t solved_vertices = 0;  ///< their regions' vertices, summed
  std::size_t pieces_ruled_out = 0;  ///< of those, shown by the kernel's lower bound to have no gain
  double length_before = 0;
  double length_after = 0;
};

struct RefineResult {
  std::vector<EdgeId> edges;  ///< the refined tree (sorted)
  RefineStats stats;
};

/// Shortens `edges` (a full-component tree on `terminals`: check_full_component_tree holds),
/// measured in `surface`'s weights, while keeping every terminal a leaf. For each Steiner point s, and each pair of
/// adjacent Steiner points, the branches at the piece are removed, which leaves k <= max_ports loose subtrees; they are
/// reconnected by the minimum tree that may attach to any non-terminal vertex of a loose subtree (or to a loose
/// terminal itself, as a leaf), passes through no terminal and no other part of the tree, and stays inside a region
/// around the piece (Dreyfus–Wagner over the 2^k port subsets, with one Dijkstra per subset on the region). A move is
/// kept only if the tree stays valid and gets shorter, so the result is never longer than the input. Errors:
/// kInvalidArgument (input not a full-component tree, or max_ports above 20), kTopologyViolation (from
/// skeleton_topology on the current tree), kCancelled. Complexity per piece: O(3^k n + 2^k n log n), n = region size.
Result<RefineResult> refine_tree(const SearchSurface& surface, std::span<const VertexId> terminals,
                                 std::span<const EdgeId> edges, const RefineOptions& options = {},
                                 const CancelToken& cancel = CancelToken::none());

}  // namespace seam::core
