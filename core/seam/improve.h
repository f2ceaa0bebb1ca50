// Beyond the paper: global improvement of a full-component seam tree that can move whole
// branches, by key-path exchange and key-vertex elimination (Uchoa & Werneck 2010, adapted
// to the constraint that every terminal stays a leaf). Where refine.h re-optimises a bounded
// piece exactly, these moves reconnect the tree anywhere on the surface, each at the cost of
// one or a few radius-bounded Dijkstra searches.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/cancel.h"
#include "core/error.h"
#include "core/paths/search_surface.h"

namespace seam::core {

struct ImproveOptions {
  /// Sweeps over all key paths and key vertices; stops early after a sweep that gains nothing.
  int max_passes = 8;
  /// Accepted moves at most (each one shortens the tree; this only bounds pathological inputs).
  std::size_t max_moves = 256;
  /// Work budget: vertices settled by all searches together, as a multiple of the mesh's
  /// vertex count (0: unbounded). Moves stop (keeping what they gained) once it is spent, so
  /// the improvement costs at most about this many full Dijkstra runs. Longest key paths are
  /// tried first, so the budget goes where most is to gain.
  /// 8 (measured, seam_quality_bench): with 3 the moves stopped early on small meshes (hand
  /// random sets 1.0038 -> 1.069 of the optimum); unbounded, two runs cost up to 3x the
  /// refinement on 80k faces.
  double max_work = 8.0;
  /// The same budget as an absolute number of settled vertices (0: unbounded); the smaller
  /// one applies, so it binds above 125k vertices. 1e6 (a few tenths of a second): at 1.25M
  /// faces and 16 extrema, 8 x V made the moves cost 4x the paper's whole seam stage.
  std::size_t max_settled = 1000000;
};

struct ImproveStats {
  std::size_t moves_tried = 0;
  std::size_t path_exchanges = 0;     ///< accepted key-path exchanges
  std::size_t vertex_eliminations = 0;  ///< accepted key-vertex eliminations
  std::size_t settled = 0;  ///< vertices settled by all searches (the work)
  bool budget_spent = false;  ///< stopped by ImproveOptions::max_work
  double length_before = 0;
  double length_after = 0;
};

struct ImproveResult {
  std::vector<EdgeId> edges;  ///< sorted; a full-component tree never longer than the input
  ImproveStats stats;
};

/// Shortens `edges` (a full-component tree on `terminals`: check_full_component_tree holds)
/// by two moves, each accepted only when the tree gets strictly shorter:
/// - key-path exchange: a key path (a branch between two nodes, i.e. terminals or vertices of
///   degree >= 3) is removed and the two parts are rejoined by the shortest path between
///   them, which may end at any non-terminal vertex of either part (or at a terminal that is
///   its part alone, which stays a leaf) and passes through no tree vertex;
/// - key-vertex elimination: a Steiner point and its key paths are removed and the parts are
///   rejoined greedily (Prim over the parts: the nearest part first, each new path joinable).
/// Every search starts from the smaller side, is bounded by the length it must beat, and
/// blocks the rest of the tree, so a move costs a few local Dijkstra runs.
/// Lengths are in `surface`'s weights. Errors: kInvalidArgument (input not a full-component
/// tree), kCancelled.
/// Complexity per pass: O(sum over moves of n_m log n_m), n_m = vertices within the removed
/// length of the smaller side. Deterministic (ties by vertex id).
Result<ImproveResult> improve_tree(const SearchSurface& surface, std::span<const VertexId> terminals,
                                   std::span<const EdgeId> edges, const ImproveOptions& options = {},
                                   const CancelToken& cancel = CancelToken::none());

/// Another start for improve_tree: the shortest-path heuristic (Takahashi–Matsuyama) under
/// the full-component constraint. From terminals[0], repeatedly joins the nearest terminal
/// not yet in the tree by a shortest path from a non-terminal tree vertex (from the first
/// terminal itself for the first path) that passes through no terminal.
/// The joins share one growing search: a join adds its path's vertices as sources and the
/// search goes on, expanding again only the vertices they bring closer (a fresh search per
/// join gives the same tree, tests/core/improve_test.cpp; at 78k faces and 32 terminals
/// 74 -> 7 ms). Gives up, returning no edges, once it has expanded `max_settled` vertices.
/// Errors: kInvalidArgument (fewer than two terminals, or a terminal that cannot be joined
/// that way, e.g. two adjacent terminals first), kCancelled. O(k E log V) at worst; about
/// O(E log V) when the tree spreads evenly.
Result<std::vector<EdgeId>> nearest_terminal_tree(const SearchSurface& surface, std::span<const VertexId> terminals,
                                                  const CancelToken& cancel = CancelToken::none(),
                                                  std::size_t max_settled = SIZE_MAX);

}  // namespace seam::core
