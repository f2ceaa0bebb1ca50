// Flattening the cut disc(s) into the plane, and the distortion of the result.
#pragma once

#include <cstddef>

#include "core/cancel.h"
#include "core/error.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/topology.h"

namespace seam::core {

enum class UvMethod {
  kLscm,  ///< least-squares conformal maps, free boundary (Lévy et al. 2002)
  kBff,   ///< Boundary First Flattening, free boundary with u = 0 (Sawhney & Crane 2017)
  kArap,  ///< as-rigid-as-possible local/global iterations started from BFF (Liu et al. 2008)
  kSlim,  ///< symmetric Dirichlet by SLIM started from BFF (Rabinovich et al. 2017)
};

/// SLIM's proxy for the symmetric Dirichlet energy (see slim.h). Declared here, not in slim.h,
/// so that this header stays free of Eigen's sparse module (httplib's <resolv.h> defines a
/// `_res` macro that breaks it in the server's translation units).
enum class SlimProxy {
  kIsotropic,    ///< per-triangle weight (w1^2 + w2^2)/2: one n x n system for u and v
  kAnisotropic,  ///< the paper's 2x2 weight matrix: one 2n x 2n system, fewer iterations
};

/// "lscm", "bff", "arap" or "slim".
const char* uv_method_name(UvMethod method);

struct UvOptions {
  /// SLIM from BFF: the lowest area and angle distortion measured, no flips, and no ARAP
  /// "locking" (bench/uv_bench.cpp seam table, docs/uv.md).
  UvMethod method = UvMethod::kSlim;
  /// ARAP only: local/global iterations, 0..1000 (0 returns the BFF start).
  int arap_iterations = 10;
  /// SLIM only: upper bound on its reweighted global steps, 0..1000 (0 returns the BFF start);
  /// it stops earlier once a step lowers the energy by less than 0.1%.
  int slim_iterations = 12;
  /// SLIM only: its proxy (see slim.h); the isotropic one is several times faster per step.
  SlimProxy slim_proxy = SlimProxy::kIsotropic;
  /// SLIM only: charts of at least this many triangles (0: none) are optimised on a coarser
  /// triangulation of their BFF start (1/12 of the vertices, at least 30,000; multilevel.h)
  /// and the fine map follows it; a chart where that would fold or overlap itself gets SLIM
  /// on the chart itself. At 1.07M faces that takes the default map from 3.2x to 1.2x BFF's
  /// time with area_g 1.765 against 1.864 (flatten_bench); below 200k faces SLIM on the
  /// whole chart costs little and every row of the distortion table stays as it was.
  std::size_t multilevel_min_faces = 200000;
  /// SLIM only: keep every chart globally injective, not only fold-free (SlimOptions::injective).
  bool injective = true;
  /// Gap between packed charts, as a fraction of the square root of the total chart area.
  /// 0..1. Unused with a single chart.
  double chart_gap = 0.02;
};

/// Distortion of a 3D->2D map, per triangle from the singular values s1 >= s2 of its
/// Jacobian after one global scale normalisation (total unsigned 2D area = total 3D area).
/// Every mean is weighted by 3D triangle area. Per-triangle terms that are infinite (a UV
/// triangle of zero area) are capped at kDistortionCap so the numbers stay finite in JSON.
struct Distortion {
  double area = 1;            ///< area-weighted mean of max(s1 s2, 1/(s1 s2))
  double area_geometric = 1;  ///< exp(area-weighted mean of |log(s1 s2)|)
  double angle = 1;           ///< area-weighted mean of s1/s2
  double stretch_l2 = 1;      ///< Sander et al. 2001's L2 stretch of the texture->surface map:
                              ///< sqrt(mean of (1/s1^2 + 1/s2^2)/2)
  double stretch_linf = 1;    ///< Sander et al.'s L-infinity stretch: max over triangles of 1/s2
  std::size_t flipped = 0;    ///< triangles with non-positive signed UV area
};
inline constexpr double kDistortionCap = 1e12;

struct UvResult {
  VertexData<Vec2> uv;    ///< per vertex of the disc mesh, fitted into [0,1]^2 (aspect kept);
                          ///< values lie on the UV grid (kUvGrid: float32, and so is 1 - v).
                          ///< Isolated vertices get (0, 0).
  Distortion distortion;  ///< measured on the stored (float32-rounded) UVs
  /// Triangles positive in double precision that became degenerate or flipped by rounding to
  /// the UV grid. Each gets a one-step nudge of a corner when that fixes it without harming its
  /// neighbours; float32_unrepaired counts those still non-positive (they are also in
  /// distortion.flipped).
  std::size_t float32_degenerate = 0;
  std::size_t float32_unrepaired = 0;
  std::size_t charts = 0;  ///< connected components flattened
  UvMethod method_used = UvMethod::kBff;  ///< differs from the request only as kArap documents
  double solve_ms = 0;     ///< flattening time (all charts), without packing and measuring
  /// Overlap of the stored UVs (core/atlas/overlap.h): the area covered by two triangles, in
  /// UV units of the [0,1]^2 layout, and as a fraction of the charts' UV area; within one
  /// chart or between charts. 0 for the default method (the test suite checks it).
  double overlap_area = 0;
  double overlap_fraction = 0;
  /// SLIM charts whose start overlapped itself (restarted from Tutte), and charts that are not
  /// injective after flattening (any method; kSlim with `injective` leaves only charts it
  /// flattened without the collision bounds because they stayed squeezed, SlimOptions::injective).
  std::size_t overlapping_starts = 0;
  std::size_t charts_not_injective = 0;
  /// SLIM charts flattened on a coarse copy (UvOptions::multilevel_min_faces), and those large
  /// enough whose coarse result would have folded and that got SLIM on the whole chart instead.
  std::size_t two_level_charts = 0;
  std::size_t two_level_fallbacks = 0;
  double overlap_ms = 0;   ///< time of the exact overlap measurement
};

/// Flattens every component of `disc_mesh` (each must be a topological disc) with
/// options.method, scales each chart so its UV area equals its 3D area, packs several charts
/// side by side (shelf packing, no overlap), fits the whole into [0,1]^2 keeping the aspect,
/// rounds to the UV grid (float32 values whose 1 - v is float32), and measures the distortion
/// of what is stored.
/// kArap starts from BFF; for a chart where ARAP ends with more flipped triangles than its
/// BFF start, that chart keeps the BFF map (method_used reports kBff if any chart did).
/// kSlim starts from BFF (or from Tutte's embedding where BFF folds or overlaps itself), never
/// adds a fold and, with options.injective, keeps each chart's boundary a simple curve, so no
/// chart overlaps itself (but a chart it could only unsqueeze without that bound, which the
/// pack step then cuts into pieces); the shelf packing keeps charts apart. The stored UVs' overlap is
/// measured exactly (overlap_area).
/// Errors: kInvalidArgument (options out of range), kEmptyMesh (no faces),
/// kTopologyViolation (a component is not a disc), kSolverFailed, kCancelled.
/// Complexity: one or two sparse Cholesky factorizations per chart (see lscm.h, bff.h, arap.h),
/// plus one per SLIM step (slim.h), on the coarse chart from multilevel_min_faces on.
Result<UvResult> parameterize(const HalfedgeMesh& disc_mesh, const UvOptions& options = {},
                              const CancelToken& cancel = CancelToken::none());

/// The same with the mesh's topology (compute_topology(disc_mesh)) from the caller, which a
/// request has already computed. Errors as above, and kInvalidArgument when `topology` does
/// not have the mesh's faces and vertices.
Result<UvResult> parameterize(const HalfedgeMesh& disc_mesh, const Topology& topology, const UvOptions& options = {},
                              const CancelToken& cancel = CancelToken::none());

/// Measures the distortion of a given per-vertex UV map (see Distortion). uv.size() must be
/// mesh.num_vertices() (SEAM_ASSERT). O(F).
Distortion measure_distortion(const HalfedgeMesh& mesh, const VertexData<Vec2>& uv);

}  // namespace seam::core
