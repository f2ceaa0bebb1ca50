// Internal to pack.cpp: packing charts by their shapes on a grid of cells (as xatlas does):
// each chart rasterized conservatively in several orientations, grown by half the margin, and
// placed where the square around all placed charts stays smallest, so concave charts
// interlock and small charts fill the holes of big ones.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
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

/// +1 or -1 as triangle t turns counter-clockwise or clockwise in `uv`, strictly: its signed
/// area beyond 1e-12 of the product of two edge lengths (clear of rounding); else 0.
int strict_turn(std::span<const Vec2> uv, const Triangle& t);

/// The outline of a chart whose triangles all turn one way, strictly (strict_turn): its directed edges whose two
/// directions do not cancel, each as often as its net count, with vertices at one UV point taken as one
/// (same_point_representatives: a mesh split along hard edges or seams repeats its vertices).
/// Every point where the chart's triangles end lies on it, and the winding number of the
/// outline around a point is (up to sign) the number of triangles over it. nullopt when some
/// triangle turns the other way or has no area: a fold may then reach past any outline.
/// Indices are into `uv`. O(T + V log V) for T triangles, V vertices in use.
std::optional<std::vector<std::array<std::uint32_t, 2>>> chart_outline(std::span<const Vec2> uv,
                                                                       std::span<const Triangle> triangles);

/// The cells of a grid (unit cells of side `cell`) that a chart, rotated by an angle, touches:
/// each closed triangle marks every closed cell it meets (to within 1e-9 of a cell), so a
/// chart's mask never misses a point of it. Built once per chart, then asked per angle.
///
/// Where every triangle has one strict orientation (a flattening without flips, which the
/// default map is), the chart's triangles are not drawn one by one: the cells its outline
/// meets are marked (the edges whose two directions do not cancel, i.e. the boundary of the
/// sum of the triangles), and a cell the outline misses is marked when its centre has a
/// non-zero winding number. With one orientation the winding number at a point is (up to
/// sign) the number of triangles covering it, and a cell that meets the chart but not its
/// outline lies inside it, so both ways give the same cells, overlapping triangles
/// included: O(V + B * rows + cells) per angle (B outline edges) instead of O(T * rows).
/// Triangles of mixed or zero orientation (folds, degenerate UVs) are drawn one by one, and
/// so are charts whose outline crosses the rows more than about 4 times per cell (a comb of
/// long thin teeth), whose crossings would not fit the mask's memory.
class ChartCells {
 public:
  /// O(T log T): the outline (directed edges sorted and cancelled) and the vertices in use.
  /// Keeps the chart's spans (not its angles), which must outlive this.
  explicit ChartCells(const RasterChart& chart);

  struct Cells {
    int w = 0;                       ///< cells across
    int h = 0;                       ///< cells up
    Vec2 lo = Vec2::Zero();          ///< the rotated chart's bounding box; cell (0, 0)'s
    Vec2 hi = Vec2::Zero();          ///< lower-left corner is lo
    int words = 0;                   ///< 64-bit words per row
    std::vector<std::uint64_t> bits;  ///< h rows of `words`: bit x % 64 of word x / 64 is cell x
    bool at(int x, int y) const { return (bits[static_cast<std::size_t>(y) * words + x / 64] >> (x % 64)) & 1; }
  };
  /// The chart's points scale * uv rotated counter-clockwise by `angle`, on cells of side `cell`.
  Cells cells(double angle, double cell) const;

  /// Whether cells() fills from the outline (every triangle of one strict orientation).
  bool by_outline() const { return by_outline_; }

 private:
  std::span<const Vec2> uv_;
  std::span<const Triangle> triangles_;
  double scale_ = 1;
  std::vector<std::uint32_t> used_;  // vertices of the triangles, ascending
  bool by_outline_ = false;
  std::vector<std::array<std::uint32_t, 2>> outline_;  // directed, multiplicity repeated
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
