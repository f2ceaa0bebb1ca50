#include "core/skeleton.h"

#include <chrono>
#include <string>

#include "core/straighten.h"

namespace seam::core {

namespace {

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

Status validate_inputs(const HalfedgeMesh& mesh, const EdgeGraph& graph, std::span<const double> edge_weights,
                       const TerminalPaths& paths) {
  const std::size_t k = paths.size();
  if (k < 2) return make_error(ErrorCode::kInvalidArgument, "the skeleton seam needs at least two terminals");
  if (graph.num_vertices() != mesh.num_vertices()) {
    return make_error(ErrorCode::kInvalidArgument, "the edge graph was not built from this mesh");
  }
  if (!edge_weights.empty() && edge_weights.size() != mesh.num_edges()) {
    return make_error(ErrorCode::kInvalidArgument, "edge_weights must be empty or have one weight per edge");
  }
  if (paths.distance.size() != k * k || paths.path.size() != k * k) {
    return make_error(ErrorCode::kInvalidArgument, "terminal paths are not a k x k table");
  }
  for (VertexId t : paths.terminals) {
    if (!t.valid() || t.index() >= mesh.num_vertices()) {
      return make_error(ErrorCode::kInvalidArgument, "terminal out of range", {t.value()});
    }
  }
  for (std::size_t i = 0; i < k; ++i) {
    for (std::size_t j = i + 1; j < k; ++j) {
      if (paths.dist(i, j) == ShortestPathTree::kUnreached) {
        return make_error(ErrorCode::kInvalidArgument,
                          "terminals " + std::to_string(paths.terminals[i].value()) + " and " +
                              std::to_string(paths.terminals[j].value()) + " are not connected",
                          {paths.terminals[i].value(), paths.terminals[j].value()});
      }
    }
  }
  return Ok{};
}

}  // namespace

Result<SkeletonResult> skeleton_seam(const HalfedgeMesh& mesh, const EdgeGraph& graph,
                                     std::span<const double> edge_weights, const TerminalPaths& paths,
                                     const SkeletonOptions& options, const CancelToken& cancel) {
  if (auto st = validate_inputs(mesh, graph, edge_weights, paths); !st.ok()) return st.take_error();
  (void)options;
  SkeletonResult result;
  const auto start = std::chrono::steady_clock::now();
  std::vector<EdgeId> edges;
  if (paths.size() == 2) {
    // §4.1: with two terminals the seam is their shortest path.
    for (HalfedgeId h : paths.path_between(0, 1)) edges.push_back(HalfedgeMesh::edge(h));
  } else {
    SEAM_TRY(edges, star_tree(mesh, graph, paths.terminals, cancel));
  }
  result.stats.straighten_ms = ms_since(start);
  result.tree = make_steiner_tree(mesh, edges, paths.terminals, edge_weights);
  result.stats.length_before_refine = result.tree.length;
  return result;
}

}  // namespace seam::core
