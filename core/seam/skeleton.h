// The paper's seam: MST tour (Algorithms 1-2, §4.2), shrinking it to a skeleton
// (Algorithm 3, §4.3), straightening between Steiner points (§4.4).
#pragma once

#include <span>

#include "core/cancel.h"
#include "core/error.h"
#include "core/paths/search_surface.h"
#include "core/paths/steiner.h"

namespace seam::core {

struct SkeletonOptions {
  /// After §4.4, shorten the tree while every terminal stays a leaf (relocate Steiner
  /// points, re-straighten). On by default only where measured to help.
  bool refine = true;
  /// After §4.4 and the refinement, move whole branches by key-path exchange
  /// and key-vertex elimination (core/seam/improve.h) while every terminal stays a leaf.
  bool improve = true;
  /// false: skip the paper's three steps and start from the terminal-avoiding star tree, the
  /// fallback used where those steps fail on a degenerate input (for tests and benchmarks).
  bool paper_steps = true;
  /// With refine and improve: 2 or more runs the moves' other two starts (on the straightened
  /// and on the nearest-terminal tree) on a second thread beside the refinement; 0 or 1 runs
  /// the three starts one after another. The result is the same either way.
  unsigned threads = 1;
};

struct SkeletonStats {
  double tour_ms = 0;
  double shrink_ms = 0;
  double straighten_ms = 0;
  double refine_ms = 0;
  double improve_ms = 0;
  double length_before_refine = 0;
  std::size_t removals = 0;           ///< repeated visits removed by Algorithm 2
  std::size_t rejected_removals = 0;  ///< removals refused because the tour would self-intersect
  /// The paper's steps could not produce a full-component tree on this input (a degenerate
  /// tour or skeleton) and the terminal-avoiding star tree was returned instead.
  bool fallback = false;
};

struct SkeletonResult {
  SteinerTree tree;
  SkeletonStats stats;
};

/// Computes a full-component Steiner tree (every terminal a leaf) on `surface`, measured in
/// its weights. Preconditions: the mesh is one closed genus-0 component (boundaries already
/// coned); `paths` are the pairwise shortest paths of the >= 2 terminals on `surface`.
/// Errors: kInvalidArgument (fewer than two or out-of-range terminals, terminals not all
/// connected, or no tree with every terminal a leaf exists: the star-tree fallback failed),
/// kTopologyViolation (the refinement could not list the tree's structure; not expected on
/// a valid full component), kCancelled.
/// Complexity: O(k^2 log k) for the tour, O(E) for the shrink, O(s E log V) to straighten.
Result<SkeletonResult> skeleton_seam(const SearchSurface& surface, const TerminalPaths& paths,
                                     const SkeletonOptions& options = {},
                                     const CancelToken& cancel = CancelToken::none());

}  // namespace seam::core
