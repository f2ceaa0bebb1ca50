// Splitting sprawling charts before packing (issue 12): a chart that fills little of its own
// smallest enclosing square (an animal's flattened limbs, a knot's strip) is cut into pieces
// at its narrowest cross-sections. The pieces keep their UVs, so the map's distortion is
// unchanged; only the seam grows by the cuts.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/atlas/pack.h"
#include "core/error.h"
#include "core/mesh/types.h"

namespace seam::core {

struct SplitOptions {
  /// A chart (or piece) whose UV area is below this fraction of its minimal enclosing
  /// rectangle's area is split; 0 splits nothing. In [0, 1].
  double min_fill = 0.65;
  /// At most this many pieces per chart (>= 1).
  std::size_t max_pieces = 12;
  /// Pieces of fewer triangles are not split further (>= 2).
  std::size_t min_triangles = 64;
};

/// One piece of an input chart: its vertices (indices into the chart's uv, in order of first
/// use) and its triangles over them. Vertices on a cut appear in each piece that touches them.
struct ChartPiece {
  std::size_t chart = 0;
  std::vector<std::uint32_t> vertices;
  std::vector<Triangle> triangles;
  /// For each of `triangles`, its index in the chart's triangles (a chart may hold the same
  /// triangle twice: duplicate faces stay in the asset).
  std::vector<std::uint32_t> chart_triangles;
  /// The chart's surface_area times the piece's share of the chart's UV area, so the piece
  /// packs at the chart's own scale.
  double surface_area = 0;
  /// The piece's triangles all turn clockwise: negate its u (a mirror image) before packing
  /// and none is flipped (untangle_charts sets it; split_sprawling_charts never does).
  bool mirrored = false;
};

struct SplitResult {
  std::vector<ChartPiece> pieces;  ///< in order of input chart; a chart not split is one piece
  std::size_t charts_split = 0;
  /// Length of the new cuts, in unit-density units (UV scaled so UV area = surface area,
  /// about the mesh's length unit), and the charts' boundary length before, alike.
  double cut_length = 0;
  double boundary_length = 0;
};

/// The pieces of one chart and the lengths their cuts add.
struct ChartPieces {
  std::vector<ChartPiece> pieces;
  double cut_length = 0;       ///< as SplitResult::cut_length
  double boundary_length = 0;  ///< as SplitResult::boundary_length
};

/// The pieces of chart number `index` whose triangles (indices into chart.triangles) are each
/// of `parts`, in that order: each piece's vertices in order of first use, its surface_area the
/// chart's times its share of the UV area (|signed area|). An edge that triangles of two parts
/// use is a cut, an edge one triangle uses a border; edges are between vertices, or between
/// the points `point` names (each vertex's representative among the vertices at its UV point,
/// so a flat-shaded chart's triangles share edges) when it is not empty.
/// Preconditions: every triangle in exactly one part, the chart's UV area > 0, `point` empty
/// or one id per chart vertex, each a vertex at the same UV point (SEAM_ASSERT). O(T log T).
ChartPieces chart_pieces(const PackChart& chart, std::size_t index, std::span<const std::vector<std::uint32_t>> parts,
                         std::span<const std::uint32_t> point = {});

/// Splits each chart whose fill (UV area / its minimal enclosing rectangle's area) is below
/// options.min_fill, recursively (the largest piece first), into at most options.max_pieces
/// pieces per chart. A cut is a straight line across the piece's minimal rectangle (parallel
/// to either side, at 1/8 to 7/8 of the way): of the 16 lines with the narrowest
/// cross-section relative to the smaller side's area (length / sqrt(area)), and the 4 best
/// parallel to each side, the one whose parts fill their rectangles best (their area / the
/// sum of their rectangles' areas) wins, if that beats the piece's own fill. Triangles go to the side of their centroid and each
/// side's connected parts (through shared vertices) become pieces.
/// Deterministic. Errors: kInvalidArgument (options out of range; the charts' errors as
/// pack_charts reports them). O(T * (96 + 24 log T)) per split of a piece of T triangles.
Result<SplitResult> split_sprawling_charts(std::span<const PackChart> charts, const SplitOptions& options = {});

}  // namespace seam::core
