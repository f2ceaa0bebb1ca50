// The skeleton seam with every intermediate stage exposed, for tests, benchmarks and
// debugging: the tour, the raw skeleton, the straightened tree, and whether a fallback ran.
#pragma once

#include <string>
#include <vector>

#include "core/seam/refine.h"
#include "core/seam/shrink.h"
#include "core/seam/skeleton.h"
#include "core/seam/straighten.h"
#include "core/seam/tour.h"

namespace seam::core {

struct SkeletonTrace {
  Tour tour;                          ///< after Algorithm 2 (empty with two terminals)
  TourStats tour_stats;
  std::vector<EdgeId> raw_skeleton;   ///< Algorithm 3's exported edges
  TreeTopology straightened;          ///< after §4.4
  StraightenStats straighten_stats;
  double straightened_length = 0;     ///< = SkeletonStats::length_before_refine
  RefineStats refine_stats;
  double refined_length = 0;          ///< after refine_tree (0 when refine is off)
  bool fallback = false;              ///< a stage failed and the star tree was returned instead
  std::string fallback_reason;
};

/// skeleton_seam, recording each stage into `trace` (may be null). Same contract and errors.
Result<SkeletonResult> skeleton_seam_traced(const SearchSurface& surface, const TerminalPaths& paths,
                                            const SkeletonOptions& options, SkeletonTrace* trace,
                                            const CancelToken& cancel = CancelToken::none());

}  // namespace seam::core
