// Untangling charts before packing (API.md v2 "An atlas, not only charts": every chart
// overlap-free, not only flip-free). `uv: lscm`, `bff` and `arap` can fold a chart (flipped
// triangles) or lay it over itself; a production atlas tool (xatlas) splits such a chart into
// pieces that are each valid. The pieces keep every triangle's UVs, so the map's distortion is
// unchanged; only the seam grows by the cuts (and a piece that turns clockwise is mirrored).
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "core/atlas/pack.h"
#include "core/atlas/split.h"
#include "core/cancel.h"
#include "core/error.h"

namespace seam::core {

struct UntangleResult {
  /// In order of input chart; a chart left alone is one piece (its triangles in order, its
  /// vertices in order of first use), an untangled chart one or more.
  std::vector<ChartPiece> pieces;
  std::size_t charts_untangled = 0;  ///< charts with a clockwise triangle or an overlap
  std::size_t pieces_added = 0;      ///< pieces beyond one per untangled chart
  std::size_t pieces_mirrored = 0;   ///< pieces whose triangles all turn clockwise (mirrored)
  /// Triangles clockwise in the input, counter-clockwise once their piece is mirrored: all of
  /// the input's clockwise triangles.
  std::size_t unflipped = 0;
  /// Length of the new cuts, in unit-density units as SplitResult::cut_length.
  double cut_length = 0;
  double ms = 0;  ///< wall time
};

/// Splits every chart that has a clockwise triangle (exact orient2d) or whose triangles'
/// interiors overlap (find_overlaps) into pieces, each connected through shared edges,
/// turning one way, and free of overlap; charts that are valid already stay one piece,
/// untouched. Pieces grow greedily, breadth-first over edge-adjacent triangles from the
/// lowest-numbered triangle not yet taken (non-degenerate seeds first): a triangle joins if it
/// turns the piece's way and its interior meets no interior of the piece's triangles (exact,
/// triangle_interiors_intersect, candidates from a bounding-volume hierarchy over the chart's
/// triangles). A triangle of zero UV area covers nothing and joins the first piece that reaches
/// it. Triangles meet through shared edges between equal UV points, so an asset split along
/// hard edges (three vertices a face) grows pieces as a welded one does. A piece of clockwise
/// triangles gets `mirrored`. Deterministic.
/// Errors: as validate_pack_charts (kInvalidArgument, kIndexOutOfRange, kNonFinitePosition),
/// kInvalidArgument (a chart with zero UV area), kCancelled.
/// Complexity: O(T log T) per chart of T triangles for the check, and for an untangled chart
/// O(T log T + C) where C is the number of candidate pairs whose boxes meet: O(T) for charts
/// overlapping themselves a bounded number of times.
Result<UntangleResult> untangle_charts(std::span<const PackChart> charts,
                                       const CancelToken& cancel = CancelToken::none());

}  // namespace seam::core
