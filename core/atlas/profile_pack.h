// Internal to pack.cpp: packing charts by their column profiles ("Tetris" drop onto a
// skyline of columns), which lets a chart's concave underside nest over the charts below it.
#pragma once

#include <array>
#include <vector>

#include "core/mesh/types.h"

namespace seam::core::detail {

/// A chart in its own frame: boundary segments at unit density, already rotated to its
/// minimal-area rectangle and moved so that the rectangle is [0, size.x] x [0, size.y].
struct ProfileChart {
  std::vector<std::array<Vec2, 2>> boundary;
  Vec2 size = Vec2::Zero();
};

/// Where a chart goes: turned by `turn` quarter turns counter-clockwise inside its rectangle
/// (turn_point), then translated by `shift`, in the square's units.
struct ProfileSlot {
  int turn = 0;
  Vec2 shift = Vec2::Zero();
};

/// p in [0, size.x] x [0, size.y] turned by k quarter turns and moved back into the positive
/// quadrant: k = 1 gives (size.y - p.y, p.x).
Vec2 turn_point(const Vec2& p, int k, const Vec2& size);

/// Packs the charts (in `order`) into a square of side `side` divided into `columns`
/// columns: each chart, in each allowed turn, is dropped at every column until its bottom
/// profile (grown by the margin) rests on the skyline; the lowest resulting top wins (then the
/// leftmost column, then the smaller turn). Points of two charts are at least margin apart
/// (along x or y), and margin/2 from the square's border. False if some chart does not fit.
/// O(n * turns * (columns * W + S * W)) for W columns per chart, S boundary segments.
bool profile_pack_square(const std::vector<ProfileChart>& charts, const std::vector<std::size_t>& order,
                         double side, double margin, bool rotate, int columns, std::vector<ProfileSlot>& slots);

}  // namespace seam::core::detail
