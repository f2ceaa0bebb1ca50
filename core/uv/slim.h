// Symmetric Dirichlet refinement of a flattening by Scalable Locally Injective Mappings
// (Rabinovich, Poranne, Panozzo, Sorkine-Hornung 2017, "Scalable Locally Injective Mappings",
// §4-5), with Smith & Schaefer 2015's injective step bound in the line search.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "core/cancel.h"
#include "core/error.h"
#include "core/uv/parameterize.h"
#include "core/uv/uv_patch.h"

namespace seam::core {

struct SlimOptions {
  /// Upper bound on reweighted global steps, 0..1000 (0 returns the start, scaled).
  int iterations = 12;
  /// Stop when one step lowers the energy by less than this fraction of it. 0..1.
  double tolerance = 1e-3;
  /// The isotropic proxy factors about 4x faster per step and, on the CGAL protrusion meshes,
  /// ends within 3% of the anisotropic one's distortion (bench/uv_bench.cpp, docs/uv.md).
  SlimProxy proxy = SlimProxy::kIsotropic;
  /// Keep the map globally injective (bijective onto its image), not only fold-free: start
  /// from Tutte's embedding when the given start's boundary is not a simple curve, and bound
  /// every step so that no boundary vertex reaches a boundary edge (collision.h). Costs one
  /// O(B) grid pass per step; it changes nothing on steps that collide with nothing. Boundary
  /// vertices keep 1e-4 of the chart's size (sqrt of its area) from the edges they face, so
  /// that rounding the map to float32 cannot close the gap. One exception, with `progressive`:
  /// a chart that stays squeezed beyond 1e4 with its boundary held apart is flattened once more
  /// without the bounds, and that fold-free map, if of lower energy, is returned with
  /// SlimResult::injective false (the pack step cuts it into overlap-free pieces).
  bool injective = true;
  /// Solves a contact-limited step may spend on linearised contacts before the vertices it
  /// still needs to hold get springs instead: the larger of this and the solves one
  /// factorization of the proxy is worth (0..100000).
  int contact_solves = 32;
  /// Where SLIM ends with a triangle stretched beyond 1e4 or squeezed below 1e-4 (its proxy
  /// found no descent from a start squeezed by orders of magnitude), rounds on progressive
  /// reference shapes (slim.cpp) from the start and SLIM again, and where that too stays
  /// squeezed with `injective`, once more without the collision bounds; off, such a map is
  /// returned as it is, below float32's resolution where it is extreme.
  bool progressive = true;
  /// When not empty: a fill-reducing order of the patch's vertices that the proxy's analysis
  /// uses instead of ordering the system itself (the one BFF's factorization used: at 1M
  /// faces METIS takes about 2.6 s of each analysis). Borrowed: must outlive the call.
  /// Precondition: empty or a permutation of the patch's vertices.
  std::span<const int> vertex_order;
};

/// Where SLIM's time went, in milliseconds (steady clock).
struct SlimTimings {
  double start_ms = 0;        ///< fold and boundary checks of the start, Tutte if needed, scaling
  double analyze_ms = 0;      ///< the proxy's pattern, slots and symbolic factorization (once)
  double assemble_ms = 0;     ///< proxy weights and system values, all steps
  double factor_ms = 0;       ///< numeric factorizations and solves, all steps
  double line_search_ms = 0;  ///< injective step bounds and energy evaluations, all steps
  double collision_ms = 0;    ///< boundary collision bounds and contact rounds, all steps
};

struct SlimResult {
  std::vector<Vec2> uv;  ///< one UV per local vertex, at 3D scale; no triangle flipped
  int iterations = 0;    ///< global steps taken
  int factorizations = 0;  ///< numeric factorizations of the proxy: one per step, plus a retry
                           ///< with capped weights, plus one per spring round (below) whose
                           ///< factor could not take the springs by an update
  /// Contact rounds that held new vertices by springs and solved the step again (any number
  /// per contact-limited step, up to its rounds).
  int spring_rounds = 0;
  /// Contact-limited steps whose sliding contacts gave no descent and whose colliding vertices
  /// were then held by springs from the first round instead (issue 12's way).
  int spring_fallbacks = 0;
  /// Spring rounds whose springs went into the step's factor by a low-rank update instead of
  /// a factorization (a simplicial factor: SparseCholesky::update_diagonal).
  int factor_updates = 0;
  /// Area-weighted mean symmetric Dirichlet energy s1^2 + 1/s1^2 + s2^2 + 1/s2^2 (4 for an
  /// isometry) of the start after scaling, and of the result.
  double energy_start = 0;
  double energy_end = 0;
  bool tutte_start = false;  ///< the given start had folds, so SLIM started from a Tutte map
  /// Rounds on progressive reference shapes (options.progressive): only where SLIM stalled on
  /// a map stretched beyond 1e4 or squeezed below 1e-4 somewhere, 0 otherwise.
  int progressive_rounds = 0;
  /// The proxy system could not be factored (numerically not positive definite) or solved:
  /// SLIM stopped at its last iterate, which is still fold-free.
  bool numerical_stop = false;
  /// With options.injective: the given start had no fold but its boundary crossed itself, so
  /// SLIM started from Tutte's embedding (tutte_start is then true as well).
  bool overlapping_start = false;
  /// Steps whose length the boundary collision bound shortened (contact-limited steps).
  int collision_limited_steps = 0;
  /// Solves with an existing factor for linearised boundary contacts (one per contact and
  /// round, plus one per round), in right-hand sides.
  int contact_solves = 0;
  /// The result's boundary is a simple closed curve and no triangle folds: the map is
  /// injective (true with options.injective, up to the rounding of the contact times, except
  /// for a squeezed chart flattened without the bounds: see options.injective).
  bool injective = false;
  SlimTimings timings;
};

/// Minimises the symmetric Dirichlet energy (area-weighted, free boundary) starting from
/// `initial`, one UV per local vertex of `patch` (e.g. BFF's map). The start is first scaled to
/// the 3D area. If it has a folded or degenerate triangle, SLIM starts instead from Tutte's
/// embedding (uniform weights, boundary on a circle by arc length), which has none. Each
/// iteration solves SLIM's reweighted proxy (a 2n x 2n sparse system of 2x2 blocks, symbolic
/// factorization once, numeric per iteration) and line-searches the true energy along the step,
/// never past the first degeneration of a triangle, so the result has no folds whenever the
/// start had none. Because the energy grows without bound as a triangle degenerates, nothing
/// "locks" the way ARAP's bounded steps do. With options.injective (the default) the map also
/// stays globally injective: a Tutte start when the given start's boundary crosses itself, and
/// each step bounded by Smith & Schaefer 2015's collision bound (no barrier term: a boundary
/// that would cross itself stops at 90% of the contact, step after step). A contact-limited
/// step re-minimises the proxy with the colliding vertex-edge pairs as linearised contacts,
/// solved with the step's own factor (the vertices slide along the edges they touch), so it
/// costs one factorization like any step. Where the contacts do not suffice (pairs that still
/// collide, or more than a factorization's worth of solves) the vertices are held by springs,
/// added to the step's factor by a low-rank update when it is simplicial (else by a second
/// factorization), and the step is solved again, in every round of the step that holds new
/// vertices; a step whose contacts give no descent is tried once more with every colliding
/// vertex held by springs (SlimResult::spring_fallbacks); the step budget is the same with or
/// without contacts
/// (3x iterations from a Tutte start), and a contact-limited step ends the descent when the
/// last 3 steps together gained less than 1.5x the tolerance (deterministic: counts, no clock).
/// Errors: kInvalidArgument (initial.size() != patch vertices, options out of range (iterations,
/// tolerance, contact_solves), a
/// vertex_order of another size),
/// kSolverFailed (only if the Tutte start cannot be solved), kCancelled.
/// Complexity: iterations x (sparse Cholesky of 2n x 2n + O(F) line search), plus per
/// contact-limited step at most max(contact_solves, one factorization's flops) worth of solves
/// and one spring update (or factorization) per contact round.
Result<SlimResult> flatten_slim(const DiscPatch& patch, std::vector<Vec2> initial, const SlimOptions& options,
                                const CancelToken& cancel);

}  // namespace seam::core
