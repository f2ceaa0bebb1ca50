// The seam pipeline's entry point: terminals, preprocessing to a disc, the chosen method,
// and the result mapped back to the input mesh. (Paper §4.1 preprocessing + §4.2–4.4.)
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/cancel.h"
#include "core/error.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/topology.h"

namespace seam::core {

enum class SeamMethod {
  kSkeleton,  ///< the paper: MST tour (Alg. 2), shrink (Alg. 3), straighten (§4.4)
  kMst,       ///< Sheffer's baseline: union of shortest paths along the terminals' MST
  kGreedy,    ///< Gu et al.'s baseline: grow from one terminal, nearest terminal first
  kOptimal,   ///< exact minimum full-component Steiner tree (Dreyfus–Wagner), small k only
};

/// "skeleton", "mst", "greedy" or "optimal" (the API's names).
const char* seam_method_name(SeamMethod method);

struct SeamOptions {
  SeamMethod method = SeamMethod::kSkeleton;
  /// Skeleton only: shorten the straightened skeleton while keeping every extremum a leaf,
  /// by the three steps below. false: the paper's seam as it is (none of them).
  bool refine = true;
  /// With refine: move whole branches by key-path exchange and key-vertex elimination
  /// (core/seam/improve.h), after the local refinement and on its own, keeping the shorter.
  bool improve = true;
  /// With refine: the local exact re-optimisation of pieces (core/seam/refine.h).
  bool local_refine = true;
  /// With refine: when the exact optimum is cheap, return it instead (SeamResult::optimal).
  /// Its cost is estimated as 2^(k-1) x V (k terminals on the component, boundary terminal
  /// included; V its vertices): the Dreyfus–Wagner rows, each one Dijkstra. The exact seam is
  /// used when that is at most this and k <= optimal_max_terminals. 0: never. The table takes
  /// 12 bytes per unit (at most 60 MB at the default). The default admits 8 terminals on 39k
  /// vertices (~78k faces), 6 on 156k, 4 on 625k; measured (seam_quality_bench) the exact seam
  /// then costs about as much as the refinement it replaces up to ~20k faces, and less
  /// than 2x it at 52k-75k faces.
  double exact_budget = 5.0e6;
  /// kOptimal refuses more terminals per component than this (kTooManyTerminals).
  std::size_t optimal_max_terminals = 10;
  /// Threads the skeleton may use (SkeletonOptions::threads): 2 or more runs the global moves'
  /// other starts beside the refinement, 0 or 1 runs everything on the calling thread. The
  /// seam does not depend on it.
  unsigned threads = 0;
  /// Optional cost multiplier per edge of the input mesh (empty: all 1). Every method then
  /// minimises the weighted length (Euclidean length x multiplier) with the same code;
  /// SeamResult::length stays Euclidean and SeamResult::cost is the weighted length. The
  /// cut graph of genus > 0 is not weighted. Each multiplier must be finite and > 0.
  std::span<const double> edge_costs;
};

struct SeamStats {
  double preprocess_ms = 0;  ///< cut graph, boundary terminals
  double paths_ms = 0;       ///< the terminals' multi-source search (on-demand pair searches count as method)
  double method_ms = 0;      ///< tour + skeleton + straighten, or the baseline
  std::size_t terminals = 0;
  std::size_t exact_components = 0;  ///< components solved exactly by the skeleton's exact_budget
};

/// A seam on a welded mesh. Vertex and edge ids are those of the mesh passed in.
struct SeamResult {
  std::vector<EdgeId> seam_edges;       ///< the seam proper (sorted, unique)
  std::vector<EdgeId> cut_graph_edges;  ///< edges opening genus/extra boundaries (sorted)
  std::vector<VertexId> extrema;        ///< the extrema used, as given (deduplicated)
  std::vector<VertexId> terminals;      ///< extrema plus, per boundary terminal, the boundary vertex the seam reaches
  std::vector<VertexId> steiner_points; ///< seam vertices of degree >= 3 that are not terminals
  std::vector<std::vector<VertexId>> branches;  ///< seam paths between terminals/Steiner points
  double length = 0;                    ///< Euclidean length of seam_edges
  double cut_graph_length = 0;          ///< Euclidean length of cut_graph_edges
  double cost = 0;                      ///< sum over seam_edges of length x edge_costs (= length without)
  /// True when every component's seam is a minimum full-component tree for its terminals
  /// (method kOptimal, the skeleton within exact_budget, or two terminals joined by their
  /// shortest path), so no other method can be shorter (measured in the search weights).
  bool optimal = false;
  SeamStats stats;
};

/// Every edge to cut along: seam_edges and cut_graph_edges, sorted and without repeats.
std::vector<EdgeId> all_cut_edges(const SeamResult& seam);

/// Computes the seam on every connected component of `mesh`, each with the extrema that lie
/// on it. Skeleton and optimal make every extremum a leaf wherever a tree can: where none can
/// (no vertex reaches every terminal without passing through another, e.g. a tetrahedron
/// whose four vertices are all extrema) the component gets the MST seam, which opens it all
/// the same, and `optimal` is false. Preconditions: `mesh` came from build_halfedge_mesh.
/// Errors: kIndexOutOfRange (an extremum >= num_vertices or isolated), kInvalidArgument
/// (edge_costs neither empty nor one finite positive value per edge), kTooManyTerminals
/// (kOptimal above options.optimal_max_terminals), kTopologyViolation (a bug: the result
/// does not cut every component into a disc), kCancelled.
Result<SeamResult> compute_seam(const HalfedgeMesh& mesh, std::span<const VertexId> extrema,
                                const SeamOptions& options = {}, const CancelToken& cancel = CancelToken::none());

/// The same with the mesh's topology (compute_topology(mesh)) from the caller, which a request
/// has already computed; SeamStats::preprocess_ms then leaves it out. Errors as above, and
/// kInvalidArgument when `topology` does not have the mesh's faces and vertices.
Result<SeamResult> compute_seam(const HalfedgeMesh& mesh, const Topology& topology, std::span<const VertexId> extrema,
                                const SeamOptions& options = {}, const CancelToken& cancel = CancelToken::none());

}  // namespace seam::core
