// Two-level flattening of large charts: a flattened disc is coarsened in its own UV plane, the
// coarse chart is optimised (SLIM, slim.h), and the fine map follows as the composition of the
// start with the coarse chart's piecewise-affine change.
//
// Why this works for SLIM started from BFF: BFF's map is conformal, so its distortion is a
// smooth scale field, and what SLIM changes is smooth too. A coarse triangle covering dozens
// of fine ones can carry that change; the fine map keeps BFF's angles inside it. And it stays
// valid by construction: every fine vertex lies in one coarse triangle of the start map, each
// coarse triangle moves by an orientation-preserving affine map, and every boundary vertex is
// kept, so the fine boundary is the coarse boundary and injective when that is.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/cancel.h"
#include "core/error.h"
#include "core/uv/slim.h"
#include "core/uv/uv_patch.h"

namespace seam::core {

/// A coarser triangulation of a flattened disc and where every fine vertex sits in it.
struct CoarseChart {
  /// The coarse disc: the kept vertices (every boundary vertex among them) with their 3D
  /// positions, and triangles that tile the same region of the start map as the fine ones.
  DiscPatch patch;
  std::vector<Vec2> start;                 ///< the start map at the coarse vertices
  std::vector<std::uint32_t> fine_vertex;  ///< coarse vertex -> fine vertex
  /// Per fine vertex: the coarse triangle that holds it in the start map, and its barycentric
  /// coordinates there (a kept vertex is a corner of its triangle, weight 1).
  std::vector<std::uint32_t> host;
  std::vector<Vec3> barycentric;
};

struct CoarsenOptions {
  /// Stop once at most this many vertices are left (boundary vertices are all kept, so a
  /// chart can stay above it), or when a round of collapses removes less than 1%.
  std::size_t target_vertices = 0;
  /// No collapse makes a triangle worse shaped than this (4 sqrt(3) area / sum of squared
  /// edges: 1 equilateral) in the start map or in 3D, unless the fine triangles around it
  /// already were.
  double min_quality = 0.15;
  /// No vertex gets more neighbours than this.
  std::size_t max_valence = 12;
  /// No coarse triangle joins vertices whose scales in the start map (UV over 3D length, the
  /// mean over each vertex's triangles) differ by more than this factor. A conformal start
  /// shrinks a limb exponentially towards its tip; a coarse triangle spanning that squeeze
  /// would carry its fine triangles' shrinking into the result (down to float32 resolution
  /// at 1.25M faces). So the coarse chart stays finer where the start's scale changes fast.
  double max_scale_ratio = 2.0;
};

/// Coarsens `patch` by half-edge collapses of interior vertices onto their neighbours (nearest
/// in 3D first, in matching rounds: a vertex absorbs at most one neighbour per round), each
/// kept only when it keeps the mesh a manifold disc (the link condition) and every new triangle
/// positively oriented in `uv` within the shape, valence and scale bounds. Then locates every
/// fine vertex in the coarse triangles by a walk from the vertex it was collapsed onto (a scan
/// of all coarse triangles where a walk does not arrive within 256 steps).
/// Errors: kInvalidArgument (`uv` not one point per vertex, a triangle of `uv` not positively
/// oriented, or a vertex on no triangle), kSolverFailed (no coarse triangle to hold a vertex,
/// which a valid start rules out), kCancelled. O((V + F) x rounds) plus O(V x walk length)
/// for the location. Deterministic.
Result<CoarseChart> coarsen_chart(const DiscPatch& patch, const std::vector<Vec2>& uv, const CoarsenOptions& options,
                                  const CancelToken& cancel = CancelToken::none());

/// The fine map for a map of the coarse chart: each fine vertex at its barycentric place in its
/// host triangle. `coarse_uv` has one point per coarse vertex (SEAM_ASSERT). O(V).
std::vector<Vec2> prolongate(const CoarseChart& coarse, const std::vector<Vec2>& coarse_uv);

struct TwoLevelResult {
  /// The fine map, at 3D scale; empty when the two-level map would fold or overlap itself
  /// (then the caller flattens the chart itself).
  std::vector<Vec2> uv;
  SlimResult coarse;  ///< SLIM on the coarse chart (its uv is the coarse map)
  std::size_t coarse_vertices = 0;
  std::size_t folds_untangled = 0;  ///< fine triangles folded by the prolongation, then unfolded
  /// Triangles left thinner than float32 keeps in the unit square (doubled area below 1e-11
  /// of the chart's extent squared) after fattening them (untangle with that floor).
  std::size_t thin_left = 0;
  double coarsen_ms = 0;            ///< coarsen_chart
  double slim_ms = 0;               ///< SLIM on the coarse chart
  double finish_ms = 0;             ///< prolongation, untangling and the boundary check
};

/// The coarse chart's size on parameterize()'s two-level path: 1/12 of `fine_vertices`, at
/// least 30,000 (the floor decides below 360k vertices, about 720k faces). Measured with flatten_bench (area_g
/// two-level against SLIM on the whole chart; the default map's time against `uv: bff`):
/// lion-head at 1.07M faces 1/16 1.876 against 1.864, 1/12 1.765 (1.17x), 1/8 1.740
/// (1.20x); the camel cut open at 1.25M faces, every coarse step contact-limited, 1/16 1.181
/// against 1.170, 1/12 1.173 (1.47-1.50x), 1/10 1.173 (1.58-1.61x), 1/8 1.173 (1.69-1.70x);
/// at 267k faces (the floor) 30k vertices 1.710 against 1.840, 16.7k 1.969. O(1).
std::size_t default_coarse_vertices(std::size_t fine_vertices);

/// `slim` as parameterize()'s two-level path runs it on the coarse chart:
/// - 96 contact solves per step (SlimOptions::contact_solves; 32 elsewhere): the coarse factor
///   is simplicial and small (52k vertices at 1.25M faces), so a solve costs little, and a
///   contact that is solved lets its vertex slide where a spring holds it. Camel x64 cut open, in
///   the service's triangle order, coarse sizes 1/12, 1/16, 1/20, and the chart of camel64.glb:
///   area_g with 32 solves 1.205 / 1.173 / 1.174 / 1.347, with 96 1.175 / 1.176 / 1.177 / 1.181
///   (whole-chart SLIM 1.177); 128 was worse at 1/16 (1.190), 64 at 1/12 (1.200).
/// - Twice `slim`'s tolerance (SLIM's default 1e-3 -> 2e-3): the last steps of a contact-limited
///   descent gain little. Camel x64 at 1/12 stops after 10 steps instead of 12, its coarse SLIM
///   976-1,049 -> 877-890 ms (three interleaved pairs), area_g 1.1747 -> 1.1776 (whole-chart
///   SLIM 1.177); at 1/8, 1/10 and 1/14 the same steps (5, 5, 12), at 1/16 and 1/20 two fewer
///   (area_g +0.001 each); lion-head x16 (4 steps, no contacts) unchanged.
/// The tolerance stays within SLIM's 0..1. O(1).
SlimOptions coarse_slim_options(SlimOptions slim);

/// SLIM on a coarse copy of `patch` (coarsen_chart to `coarse_vertices`, then flatten_slim
/// with `slim`, whose vertex_order must be empty), carried back by prolongate; triangles that
/// the composition folds are unfolded, and those too thin for float32 fattened, by untangle
/// (uv_patch.h). `start` must be fold-free
/// (BFF's map after repair_flips). Errors: those of coarsen_chart and flatten_slim
/// (kInvalidArgument, kSolverFailed, kCancelled). O(V + F) plus SLIM on the coarse chart.
Result<TwoLevelResult> slim_two_level(const DiscPatch& patch, const std::vector<Vec2>& start,
                                      std::size_t coarse_vertices, const SlimOptions& slim,
                                      const CancelToken& cancel = CancelToken::none());

}  // namespace seam::core
