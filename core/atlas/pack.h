// Packing charts into one [0,1]^2 atlas at one texel density (issue 12, "An atlas, not only
// charts"): scale, rotate to the minimal-area bounding rectangle, skyline-pack with margins.
#pragma once

#include <cmath>
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "core/cancel.h"
#include "core/error.h"
#include "core/mesh/types.h"

namespace seam::core {

/// One chart to pack: its UVs at any scale and orientation (e.g. a chart of parameterize's
/// output, or SLIM's map at 3D scale), its triangles (indices into uv), and its 3D surface area.
struct PackChart {
  std::span<const Vec2> uv;
  std::span<const Triangle> triangles;
  double surface_area = 0;  ///< > 0, in the mesh's squared length unit
};

struct PackOptions {
  /// Texture side in texels, 16..65536: margins are whole texels at this size.
  int texture_size = 1024;
  /// Gap between any two charts, in texels (0..texture_size/8); charts also keep margin_px/2
  /// from the atlas border, so tiling keeps margin_px too.
  double margin_px = 4;
  /// Rotate charts to their minimal-area bounding rectangle, and by 90 degrees where that packs
  /// better. Without it charts keep their orientation (axis-aligned bounding boxes).
  bool rotate = true;
};

/// uv' = scale * Rot(angle) * uv + offset: a similarity (no reflection) taking a chart's input
/// UVs into the atlas.
struct ChartPlacement {
  double scale = 1;
  double angle = 0;  ///< radians, counter-clockwise
  Vec2 offset = Vec2::Zero();
  Vec2 rect_min = Vec2::Zero();  ///< the chart's rectangle in the atlas (its rotated minimal
  Vec2 rect_max = Vec2::Zero();  ///< one, or its bounding box as placed); the chart lies inside.
                                 ///< Rectangles of nested charts may overlap.
  Vec2 apply(const Vec2& uv) const {
    const double c = std::cos(angle);
    const double s = std::sin(angle);
    return scale * Vec2(c * uv.x() - s * uv.y(), s * uv.x() + c * uv.y()) + offset;
  }
};

struct PackResult {
  std::vector<ChartPlacement> placements;  ///< one per input chart, in input order
  double coverage = 0;       ///< total chart UV area in the atlas / atlas area (1)
  double rect_fill = 0;      ///< total chart UV area / total area of the charts' rectangles as
                             ///< placed (for rectangle-packed charts, the coverage a perfect
                             ///< rectangle packer without margins would reach)
  /// Texels per unit of 3D length (texture_size * sqrt(UV area / surface area)), equal for all
  /// charts; density_ratio is max/min of the per-chart values as placed (1 up to rounding).
  double texel_density = 0;
  double density_ratio = 1;
  double ms = 0;             ///< wall time
};

/// Packs `charts` into [0,1]^2. Each chart is scaled so UV area / surface area is the same for
/// all (one texel density), rotated (options.rotate) so that the minimal-area rectangle around
/// its convex hull (over the hull's edge directions, Freeman & Shapira 1975) is axis-aligned
/// and wider than tall. Three packers then look for the smallest square: (1) the rectangles
/// grown by the margin, skyline bottom-left, by bisection on the side (each tried upright and
/// turned 90 degrees with rotate; three size orders; charts longer than half the square
/// retried at the rotation that minimises their longer side, so a long strip lies diagonally);
/// (2) for at most 256 charts, the charts themselves dropped by their column profiles onto a
/// skyline of 256 columns in four quarter turns (profile_pack.h), so a concave chart's
/// underside nests over the charts below; (3) for at most 256 charts, the charts' shapes on a
/// grid of 512 x 512 cells (raster_pack.h, as xatlas does): each chart, largest surface first,
/// rasterized conservatively in 20 orientations (quarter turns of its minimal rectangle with
/// three steps between them, and of its smallest enclosing square; 12 above 16 charts, 8
/// above 64) and put where the square around the placed charts stays smallest, so charts
/// interlock and small charts fill the holes of big ones. The smallest square wins; it is
/// scaled to [0,1]^2. Deterministic (ties by input order). Any two charts are at least
/// margin_px texels apart at texture_size (their points differ by that much along x or y)
/// and margin_px/2 from the border; with margin_px = 0 they are still 1e-6 of the atlas apart,
/// so they never touch.
/// Errors: kInvalidArgument (options out of range, more charts than margins_fit allows, a
/// chart with no triangles, non-positive or
/// non-finite surface_area, or zero UV area; the message names the chart), kIndexOutOfRange
/// (a triangle names a missing UV), kNonFinitePosition (a UV is NaN or infinite), kCancelled.
/// Complexity: O(sum of H_i^2) for the rectangles (H_i hull sizes); packer (1) about 40
/// passes of O(n * S) (S skyline segments <= n + 1), O(n^2) worst; packer (2) about 20 passes
/// of O(n * 4 * (256 * W + B)) for W columns per chart and B boundary edges; packer (3)
/// O(T log T) per chart for its outline, then per orientation O(V + B * rows + cells) to
/// rasterize where all its triangles have one orientation (B outline edges; else O(T * rows),
/// T triangles), plus the positions tried, which skip runs of full cells. 1,000 charts
/// (packer 1 only): ~25 ms of CPU; atlas_bench's groups of 4-115 charts of 10^3-10^5
/// triangles: 77-195 ms of CPU (bench/atlas_bench.cpp).
Result<PackResult> pack_charts(std::span<const PackChart> charts, const PackOptions& options = {},
                               const CancelToken& cancel = CancelToken::none());

/// Whether `charts` charts can be packed at all: each keeps margin_px to its neighbours, so n
/// charts need n * margin_px^2 < texture_size^2 (with margin_px = 0, 1e-6 of the side). O(1).
bool margins_fit(std::size_t charts, const PackOptions& options);

/// Why margins_fit is false, with the texture size and the margin that would fit.
std::string margins_message(std::size_t charts, const PackOptions& options);

/// Checks charts as pack_charts does. Errors: kInvalidArgument (a chart with no triangles, or
/// a non-positive or non-finite surface_area; the message names the chart), kIndexOutOfRange
/// (a triangle names a missing UV), kNonFinitePosition (a UV is NaN or infinite). O(V + T).
Status validate_pack_charts(std::span<const PackChart> charts);

/// The convex hull of `points` (Andrew's monotone chain), counter-clockwise, no collinear
/// points, starting at the lowest-then-leftmost point. O(n log n).
std::vector<Vec2> convex_hull(std::span<const Vec2> points);

/// The minimal-area rectangle enclosing a convex polygon (counter-clockwise): the angle that
/// rotates it axis-aligned (one of its sides along a hull edge), its width >= height. O(H^2).
struct MinAreaRect {
  double angle = 0;  ///< rotating the points by this angle makes the rectangle axis-aligned
  Vec2 size = Vec2::Zero();
  Vec2 min = Vec2::Zero();  ///< lower-left corner after the rotation
};
MinAreaRect min_area_rect(std::span<const Vec2> hull);

/// The rotation of a hull that minimises its longer bounding side (a long strip fits a
/// smaller square diagonally), searched over half a turn in 0.5 degree steps, then turned
/// wider than tall. O(360 H).
MinAreaRect min_square_rect(std::span<const Vec2> hull);

}  // namespace seam::core
