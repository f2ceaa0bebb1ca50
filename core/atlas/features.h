// Feature (sharp) edges for `charts: "features"`: seams along creases so that a hard-surface
// model opens into its flat or smooth sides (issue 12).
#pragma once

#include <cstddef>
#include <vector>

#include "core/cancel.h"
#include "core/error.h"
#include "core/mesh/halfedge_mesh.h"

namespace seam::core {

struct FeatureOptions {
  /// An interior edge is a feature when the angle between its two face normals exceeds this,
  /// in degrees, 0..180 (a cube's edges: 90; a flat mesh: 0).
  double feature_angle_deg = 60;
  /// Dangling pieces: a chain of feature edges from a feature endpoint of degree 1 (not on the
  /// mesh boundary) up to the first vertex where it meets other features or the boundary. Such
  /// a slit separates nothing; pieces shorter than this fraction of the bounding-box diagonal
  /// are dropped (repeatedly, as dropping one can leave another). 0..1; 0 keeps them all, 1
  /// drops every dangling piece. A lone edge (both ends interior and on no other feature) is
  /// dropped whatever its length and this fraction: cutting cannot open it (cut_along_edges
  /// refuses the slit; fuzz F17).
  double max_dangling_fraction = 0.1;
};

struct FeatureEdges {
  std::vector<EdgeId> edges;  ///< sorted, unique, interior edges only
  std::size_t sharp = 0;      ///< edges above the angle, before pruning
  std::size_t pruned = 0;     ///< of those, dropped as dangling pieces (short ones, and lone edges)
  double ms = 0;
};

/// The feature edges of `mesh`: interior edges whose dihedral angle (between the unit normals
/// of their two faces) exceeds options.feature_angle_deg, minus short dangling pieces. Edges
/// with a zero-area face are never features. Cutting along them (cut_along_edges) separates
/// the creased sides into charts; the extrema seam then runs inside each.
/// Errors: kInvalidArgument (options out of range), kCancelled. Complexity: O(E) plus O(E)
/// per pruning round (rounds bounded by the longest pruned tree, in practice a few).
Result<FeatureEdges> find_feature_edges(const HalfedgeMesh& mesh, const FeatureOptions& options = {},
                                        const CancelToken& cancel = CancelToken::none());

}  // namespace seam::core
