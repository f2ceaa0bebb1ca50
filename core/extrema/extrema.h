// Automatic extrema: the tips of a surface's protrusions (the paper's §6 future work).
//
// Method. The paper (§2, §6) takes the extrema as given and names their detection as future
// work; we use the tips of the average geodesic distance (AGD), filtered by persistence:
//
// 1. Per connected component, f(v) = sum_i w_i d(s_i, v), the AGD estimated from `samples`
//    geodesic sources s_i chosen by farthest-point sampling (Hilaga et al., SIGGRAPH 2001,
//    "base vertices"), each weighted by the area of its geodesic Voronoi cell, w_i = A_i / A.
//    The sampling runs cost about three Dijkstra passes in all (each new source explores only
//    its Voronoi cell); the `samples` full passes for f run in parallel.
//    d is Dijkstra's distance on the edge graph (core/paths/geodesic.h). AGD is nearly constant on
//    a round body and grows along every protrusion, so its local maxima are the tips
//    (Zhang, Mischaikow & Turk, "Feature-based surface parameterization and texture
//    mapping", ACM TOG 2005, §3).
// 2. The local maxima are ranked by the persistence of the superlevel sets of f
//    (Edelsbrunner, Letscher & Zomorodian 2002; the merge tree): a maximum's prominence is
//    f(tip) - f(saddle), where the saddle is the vertex at which its region first joins the
//    region of a higher maximum. The component's highest maximum has prominence
//    f(max) - f(min). Along a thin protrusion f rises by (nearly) one unit per unit of
//    length, so the prominence is the protrusion's length from the tip to where it joins
//    the body, measured in AGD.
// 3. A tip is kept when prominence >= min_protrusion * sqrt(component area); the most
//    prominent max_count survive.
//
// 4. Multi-resolution, as the paper's §6 proposes ("find all big protrusions at low
//    resolution"): a component of 16k vertices or more runs steps 1-3 on the graph of the
//    cells (grown breadth-first) of ~V/32 (at least 8k) seed vertices, picked by a fixed
//    hash of the vertex id with probability proportional to vertex area. Cell-graph edges
//    are seed-to-seed path lengths, rescaled by the ratio to exact distances from one seed
//    so prominences keep the exact path's scale. Tips and saddles are reported at the
//    cells' seeds (an error of a few edges, ~0.006 sqrt(area) at 8k cells).
//
// Properties: deterministic (ties are broken by vertex id); invariant to rigid motion and
// uniform scale (only geodesic distances and area ratios enter); insensitive to the
// tessellation (f approximates a continuous function and the threshold removes its
// discretisation wiggles; a finer mesh of the same shape gives the same tips up to a small
// geodesic tolerance). A round shape without protrusions (a sphere) has no extrema.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/cancel.h"
#include "core/error.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/topology.h"

namespace seam::core {

struct ExtremaOptions {
  /// A protrusion counts only if its length (geodesic, from tip to where it joins the body)
  /// is at least this fraction of sqrt(surface area). 0 keeps every local maximum.
  /// Must be finite and >= 0. The area is that of the tip's connected component.
  /// The length is measured as the rise of the AGD (see above), which equals the length for a
  /// thin protrusion and is smaller for a stubby one. 0.05 keeps the feet, ears and trunk of
  /// CGAL's elephant (prominences 0.08-0.39) and drops its wiggles (<= 0.014); see
  /// tests/core/extrema_test.cpp and bench/extrema_bench.cpp for the measured gaps.
  double min_protrusion = 0.05;
  /// At most this many extrema per component (the most prominent first). 0 = no limit.
  std::size_t max_count = 16;
  /// Farthest-point geodesic sources per component for the AGD estimate (capped at the
  /// component's vertex count). More samples: a smoother f at a linear cost in time.
  /// Must be >= 2.
  std::size_t samples = 16;
  /// Tips closer than this fraction of their component's bounding-box diagonal (geodesic
  /// distance on the edge graph) to a more prominent kept tip are dropped, so one tube end
  /// or one corner never carries several tips. 0 keeps them all. Must be finite and >= 0.
  double min_separation = 0.05;
  /// A closed component (no boundary) whose bounding-box diagonal is below this fraction of
  /// the largest component's is a small part (a screw, a bracket of a machine). When none of
  /// its tips reaches small_part_protrusion it has no real protrusion (its "tips" would be
  /// corners) and gets none: it is only cut to a disc. A small part that does protrude (a
  /// spiky ball, a rod) keeps its tips as any component. 0 disables. Finite and >= 0.
  double small_part = 0.25;
  /// The prominence one tip of a small part needs for the part to count as protruding;
  /// measured in tests/core/extrema_test.cpp ("small closed parts"): the corners of a flat
  /// plate part reach 0.11, the ends of an 8:1 rod 0.29. Finite and >= 0.
  double small_part_protrusion = 0.15;
  /// Threads for the per-source Dijkstra runs (0 = hardware concurrency); components under
  /// 10k vertices (or cells) use one. The result does not depend on it (bit-identical).
  unsigned threads = 0;
};

/// One detected protrusion tip.
struct Extremum {
  VertexId vertex;            ///< the tip
  VertexId saddle;            ///< where its region joins a higher one; invalid for a component's highest tip
  double prominence = 0;      ///< (f(tip) - f(saddle)) / sqrt(component area), dimensionless
  std::uint32_t component = 0;  ///< as numbered by compute_topology (core/mesh/topology.h)
};

struct ExtremaStats {
  double milliseconds = 0;     ///< wall time of the whole detection
  std::size_t components = 0;  ///< components with at least one face
  std::size_t samples = 0;     ///< geodesic sources used, summed over components
  std::size_t local_maxima = 0;  ///< local maxima of f before the prominence filter
};

struct ExtremaResult {
  /// Grouped by component (ascending); within one, most prominent first (ties: lower id).
  std::vector<Extremum> extrema;
  ExtremaStats stats;
};

/// Detects protrusion tips on every component with their prominence (method above).
/// Preconditions: `mesh` came from build_halfedge_mesh. Isolated vertices are ignored.
/// Never returns one vertex twice; kept tips of one component are at least min_separation
/// apart (geodesic); small closed parts without a tip of small_part_protrusion get none.
/// Errors: kInvalidArgument (min_protrusion, min_separation, small_part or
/// small_part_protrusion negative or not finite, samples < 2), kCancelled.
/// Complexity: O(samples * E log V) for the geodesic sources (divided among `threads`) plus
/// O(V log V) for the merge tree, plus one Dijkstra bounded by the separation radius per
/// candidate tip (O(V) memory each); memory O(threads * V).
Result<ExtremaResult> detect_extrema(const HalfedgeMesh& mesh, const ExtremaOptions& options = {},
                                     const CancelToken& cancel = CancelToken::none());

/// The same with the mesh's topology (compute_topology(mesh)) from the caller, which a request
/// has already computed. Errors as above, and kInvalidArgument when `topology` does not have
/// the mesh's faces and vertices.
Result<ExtremaResult> detect_extrema(const HalfedgeMesh& mesh, const Topology& topology,
                                     const ExtremaOptions& options = {},
                                     const CancelToken& cancel = CancelToken::none());

/// Finds protrusion tips on every component: the vertices of detect_extrema() in its order.
/// Deterministic; invariant to rigid motion and uniform scale. Errors: kInvalidArgument (bad
/// options), kCancelled. Complexity as detect_extrema().
Result<std::vector<VertexId>> find_extrema(const HalfedgeMesh& mesh, const ExtremaOptions& options = {},
                                           const CancelToken& cancel = CancelToken::none());

/// The per-vertex function whose maxima detect_extrema() ranks: the area-weighted
/// farthest-point estimate of the average geodesic distance, divided by sqrt(component
/// area) (so it is scale free); on components of 16k vertices or more, the value of the
/// vertex's coarse cell (step 4). Isolated vertices get 0. Errors and complexity as
/// detect_extrema(). Exposed for tests and visualisation.
Result<VertexData<double>> average_geodesic_distance(const HalfedgeMesh& mesh, std::size_t samples,
                                                     const CancelToken& cancel = CancelToken::none());

}  // namespace seam::core
