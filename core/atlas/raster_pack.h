// Internal to pack.cpp: packing charts by their shapes on a grid of cells (as xatlas does):
// each chart rasterized conservatively in several orientations, grown by half the margin, and
// placed where the square around all placed charts stays smallest, so concave charts
// interlock and small charts fill the holes of big ones.
#pragma once

#include <cstddef>
#include <limits>
#include <span>
#include <vector>

#include "core/mesh/types.h"

namespace seam::core::detail {

/// A chart at unit density (its points are scale * uv) and the rotations to try.
struct RasterChart {
  std::span<const Vec2> uv;
  std::span<const Triangle> triangles;
  double scale = 1;
  std::vector<double> angles;  ///< radians, counter-clockwise; at least one
};

/// Where a chart goes (in every packer of pack.cpp): p' = Rot(angle) (scale * uv) + offset,
/// in unit-density units, with its points in the box [lo, hi].
struct PlacedChart {
  double angle = 0;
  Vec2 offset = Vec2::Zero();
  Vec2 lo = Vec2::Zero();
  Vec2 hi = Vec2::Zero();
};

struct RasterLayout {
  double side = std::numeric_limits<double>::infinity();  ///< infinity: the charts did not fit
  std::vector<PlacedChart> slots;                           ///< one per chart, in input order
};

/// Packs the charts (in `order`) into a square of side at most `bound` (unit-density units)
/// divided into grid x grid cells. Each chart, in each of its angles, is rasterized
/// conservatively (every cell its triangles touch) and grown by ceil(d / 2) cells, d =
/// ceil(margin_fraction * grid); it goes to the free position that keeps the square around
/// the placed cells smallest, then its area smallest, then lowest, leftmost, first angle. The
/// returned side is the tight one: the charts' points plus margin_fraction * side / 2 of
/// border. Two charts' points then differ by at least margin_fraction * side along x or y,
/// and lie margin_fraction * side / 2 inside the square. Side infinity if some chart does not
/// fit. Deterministic. O(sum of rasterized cells * angles + positions tried * rows / 64).
RasterLayout raster_pack(std::span<const RasterChart> charts, std::span<const std::size_t> order, double bound,
                         double margin_fraction, int grid);

}  // namespace seam::core::detail
