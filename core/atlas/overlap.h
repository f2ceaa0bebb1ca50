// Exact detection of UV overlap: whether two triangles of a UV layout (one chart or several)
// cover a common point of positive area, and how much area they share.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "core/cancel.h"
#include "core/error.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/types.h"

namespace seam::core {

struct OverlapResult {
  /// Some two triangles share a point of positive area (decided exactly, see find_overlaps).
  bool overlaps = false;
  /// Sum over overlapping triangle pairs of the area of their intersection, in UV units. Equals
  /// the area covered twice or more wherever no point is covered three times (a point covered
  /// k times counts k(k-1)/2 times). Computed in double precision by clipping; a pair whose
  /// overlap is decided exactly but whose clipped area rounds to 0 adds that 0.
  double overlap_area = 0;
  double within_chart_area = 0;   ///< the part of overlap_area between triangles of one chart
  double between_charts_area = 0; ///< the part between triangles of different charts
  double uv_area = 0;             ///< sum of |signed area| of all triangles (the charts' area)
  /// overlap_area / uv_area (0 when uv_area is 0).
  double overlap_fraction = 0;
  std::size_t overlapping_pairs = 0;  ///< triangle pairs with a common interior point
  std::size_t candidate_pairs = 0;    ///< pairs whose bounding boxes meet (tested exactly; 0 when
                                      ///< proven_by_boundary)
  /// No pair was tested: the boundary alone proved the layout free of overlap (see find_overlaps).
  bool proven_by_boundary = false;
  std::size_t degenerate_triangles = 0;  ///< zero UV area: no interior, never overlapping
  /// The first overlapping pair in (lower, higher) triangle index order; both
  /// kInvalidValue-like (UINT32_MAX) when none.
  std::uint32_t first_pair[2] = {UINT32_MAX, UINT32_MAX};
  double ms = 0;  ///< wall time
};

/// Finds every pair of triangles of the layout whose interiors intersect. Triangles may be
/// clockwise or counter-clockwise (a flipped triangle's interior is its interior too); ones of
/// zero area have no interior. Touching along an edge, at a vertex, or collinearly is not
/// overlap. Exact: two convex polygons have disjoint interiors iff the supporting line of one
/// of their edges has the other polygon in its closed outer half-plane (the Minkowski
/// difference argument), and that test runs on the exact orient2d. Candidate pairs come from a
/// uniform grid over the layout (about one triangle per cell); each pair is tested once, in the
/// cell holding the lower-left corner of the intersection of their bounding boxes.
/// First, a shortcut that is exact as well: when every triangle turns the same way, no
/// directed edge is used twice, and the boundary edges (those whose reverse no triangle uses)
/// form simple, pairwise disjoint loops turning that way too, none of which holds another, the
/// number of triangles over any point is the winding number of those loops (at most 1), so
/// nothing overlaps and no pair is tested (proven_by_boundary): O(F) plus a grid over the B
/// boundary segments. Anything else (a touch, a pinch, a flipped triangle) takes the pair test.
/// `triangle_chart` (optional, empty or one id per triangle) splits overlap_area into
/// within- and between-chart parts; empty means one chart.
/// Errors: kIndexOutOfRange (a triangle names a missing UV; the message names it),
/// kNonFinitePosition (a UV is NaN or infinite), kInvalidArgument (triangle_chart of the wrong
/// size), kCancelled. Complexity: O(F + P) for P candidate pairs, O(F) for layouts of
/// similar-size triangles; O(F^2) worst case (every triangle over every other).
Result<OverlapResult> find_overlaps(std::span<const Vec2> uv, std::span<const Triangle> triangles,
                                    std::span<const std::uint32_t> triangle_chart = {},
                                    const CancelToken& cancel = CancelToken::none());

/// find_overlaps on a mesh's faces with one UV per vertex; charts are the mesh's connected
/// components. Errors as find_overlaps (kInvalidArgument if uv.size() != num_vertices).
Result<OverlapResult> find_overlaps(const HalfedgeMesh& mesh, const VertexData<Vec2>& uv,
                                    const CancelToken& cancel = CancelToken::none());

/// Area of the intersection of two triangles (any orientation), by clipping one against the
/// other (Sutherland-Hodgman) in double precision. 0 for degenerate triangles. O(1).
double triangle_intersection_area(const std::array<Vec2, 3>& a, const std::array<Vec2, 3>& b);

/// Whether the interiors of two triangles intersect, decided exactly (see find_overlaps).
/// False when either triangle has zero area. O(1).
bool triangle_interiors_intersect(const std::array<Vec2, 3>& a, const std::array<Vec2, 3>& b);

}  // namespace seam::core
