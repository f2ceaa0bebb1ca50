// Internal to pack.cpp: the skyline of a bottom-left rectangle packing. Finding a place is one
// pass over the S segments that looks under a start only while it can still beat the best
// place so far, and placing a rectangle rebuilds only the segments it covers (not the whole
// skyline): a layout of n similar charts has ~sqrt(n) segments, so a trial square costs
// O(n sqrt(n)) with a small constant (20k charts: 70 -> 10 ms per trial square).
#pragma once

#include <cstddef>
#include <vector>

#include "core/mesh/types.h"

namespace seam::core::detail {

/// One step of the skyline: [x, x + w) at height y.
struct SkylineSegment {
  double x;
  double y;
  double w;
};

class Skyline {
 public:
  /// An empty width x height area: one segment at height 0.
  Skyline(double width, double height);

  /// The bottom-left position for a w x h rectangle: among the segment starts x where it fits
  /// (x + w within the width, resting at y = the highest segment under [x, x + w), y + h within
  /// the height), the lowest top y + h, then the leftmost x. False if none fits. The widths and
  /// heights are compared with a relative slack of 1e-12. O(S).
  bool find(double w, double h, Vec2& pos, double& top) const;

  /// Raises [pos.x, pos.x + w) to pos.y + h; neighbours left at one height merge. A rectangle
  /// without width changes nothing. O(log S + the segments it covers), plus moving the
  /// segments to its right along the array.
  void add(const Vec2& pos, double w, double h);

  /// The segments by x; adjacent ones are at different heights.
  const std::vector<SkylineSegment>& segments() const { return segments_; }

 private:
  double width_;
  double height_;
  std::vector<SkylineSegment> segments_;
};

}  // namespace seam::core::detail
