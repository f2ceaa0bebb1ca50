// One atlas for several meshes' UV maps: the entry point for `pack.group_by` (issue 12).
#pragma once

#include <cstddef>
#include <functional>
#include <span>
#include <vector>

#include "core/atlas/pack.h"
#include "core/cancel.h"
#include "core/error.h"
#include "core/mesh/halfedge_mesh.h"

namespace seam::core {

/// One member of a group: a mesh whose components are discs (e.g. the cut mesh given to
/// parameterize) and its per-vertex UVs (e.g. UvResult::uv).
struct AtlasMesh {
  std::reference_wrapper<const HalfedgeMesh> mesh;
  std::reference_wrapper<const VertexData<Vec2>> uv;
};

struct AtlasResult {
  std::vector<VertexData<Vec2>> uv;  ///< per member, per vertex: in [0,1]^2, float32-exact
  std::size_t charts = 0;            ///< charts packed (components of all members)
  double coverage = 0;               ///< PackResult::coverage of the group
  double density_ratio = 1;          ///< max/min texel density over the group's charts, as stored
  /// Exact overlap of the stored UVs over the whole group (find_overlaps): within one chart and
  /// between charts (of the same or different members). 0 for injective charts.
  double overlap_area = 0;
  double overlap_fraction = 0;
  double between_charts_area = 0;
  std::size_t float32_degenerate = 0;  ///< as UvResult: triangles degenerate by rounding
  std::size_t float32_unrepaired = 0;
  double pack_ms = 0;
  double overlap_ms = 0;
};

/// Packs the charts of all members into one [0,1]^2 layout with pack_charts (one texel
/// density for the whole group, margins at options.texture_size), applies each chart's
/// similarity to its UVs, rounds them to the UV grid (round_to_float32, one-step nudges for
/// triangles the rounding degenerates) and measures the group's exact overlap.
/// Errors: kInvalidArgument (a member's uv size differs from its vertex count, or pack_charts'
/// option errors), kTopologyViolation (a member's component is not a disc), kEmptyMesh (a
/// member without faces), errors of pack_charts, kCancelled.
/// Complexity: O(V + F) per member plus pack_charts and find_overlaps over the group.
Result<AtlasResult> pack_atlas(std::span<const AtlasMesh> members, const PackOptions& options = {},
                               const CancelToken& cancel = CancelToken::none());

}  // namespace seam::core
