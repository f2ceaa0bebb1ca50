// The atlas step of a request: the new UV sets of the processed primitives packed by group
// into one [0,1]² layout each (API.md v2 `pack`), at one texel density, then measured:
// coverage, exact overlap, and the triangles float32 rounding turned over.
#pragma once

#include <cstdint>
#include <vector>

#include "api/error.h"
#include "api/gltf_reader.h"
#include "api/params.h"
#include "api/primitive_job.h"
#include "core/atlas/pack.h"
#include "core/cancel.h"

namespace seam::api {

/// One processed primitive: where it is in the asset and its job's result (UVs rewritten).
struct PackMember {
  std::uint32_t mesh = 0;
  std::uint32_t primitive = 0;
  PrimitiveResult* result = nullptr;
};

/// What the untangling (core::untangle_charts) did to a primitive's charts before packing.
struct UntangleOutcome {
  std::size_t charts = 0;           ///< charts that folded or overlapped themselves
  std::size_t pieces_added = 0;     ///< pieces beyond one per such chart
  std::size_t pieces_mirrored = 0;  ///< pieces that turned clockwise, mirrored
  std::size_t unflipped = 0;        ///< flipped triangles that mirroring turned right way round
  double cut_length = 0;            ///< length of the new cuts (surface units)
};

/// What a primitive's `uv` reports after packing.
struct PackOutcome {
  std::uint32_t group = 0;     ///< index of its group, in order of first member
  double coverage = 0;         ///< its group's chart area / atlas area
  double overlap_area = 0;     ///< area covered twice in its group's layout (exact; 0 expected)
  std::size_t flipped = 0;     ///< its triangles whose orientation the packing's rounding changed
  double texel_density = 0;    ///< texels per unit length at texture_size
  int texture_size = 0;        ///< with params.enabled: the texture its group was packed for
  std::size_t charts = 0;      ///< its charts after packing (and splitting)
  std::size_t charts_split = 0;  ///< with params.split: its charts that were cut
  double split_cut_length = 0;   ///< with params.split: length of its new cuts (surface units)
  UntangleOutcome untangle;      ///< with params.enabled
};

/// The options group of `charts` charts packs with: params' texture_size, margin_px and rotate;
/// with texture_size and margin_px left at their defaults (!params.sized_by_caller) and more
/// charts than their margins leave room for (core::margins_fit: 65,536 at 1024 px and 4 px),
/// the smallest power-of-two texture_size up to 65,536 at which the margins cover at most a
/// quarter of the atlas (charts x margin_px^2 <= texture_size^2 / 4), so an asset of many small
/// parts gets an atlas rather than a 400 after all its flattening. Errors: kInvalidParameter
/// (the caller's sizes, or 65,536 px, hold too few; details name pack.texture_size and the
/// charts). O(1).
ApiResult<core::PackOptions> atlas_options(const PackParams& params, std::size_t charts);

/// Packs the members' new UV sets (members without UVs are skipped) group by group with
/// core::pack_charts: each chart of each member (PrimitiveResult::chart) scaled to the group's
/// texel density, rotated, placed margin_px apart. Members are grouped by params.group_by: the
/// whole asset, the mesh, the primitive's `material` (none is a group of its own), or each
/// primitive alone. Before packing, a chart that folds (a clockwise triangle) or overlaps itself
/// is cut into pieces that are each flip- and overlap-free (core::untangle_charts; a piece
/// turning clockwise is mirrored), so the atlas has no overlap whatever the method; charts
/// that are valid (every `uv: slim` chart) are untouched. With params.split, sprawling charts are then cut into pieces
/// (core::split_sprawling_charts). Either way a piece's vertices on a cut are duplicated in the
/// member's CutPrimitive (same source vertex and UV), so the output gets the new seams. With
/// params.enabled false nothing moves and only the measurements are made (each primitive
/// its own group). Each group packs with atlas_options (PackOutcome::texture_size says which
/// texture); placed UVs are rounded to core::kUvGrid, triangles the rounding turned get
/// core::restore_turns, and a group whose placed layout overlaps is untangled on its placed
/// UVs and packed once more. Errors: kInvalidParameter (atlas_options refused a group),
/// kInternal (the packer refused a chart: a bug upstream), kTimeout (cancelled). O(UV vertices
/// + triangles) plus the packer's cost.
ApiResult<std::vector<PackOutcome>> pack_uv_sets(const GltfDocument& doc, const std::vector<PackMember>& members,
                                                 const PackParams& params, const core::CancelToken& cancel);

}  // namespace seam::api
