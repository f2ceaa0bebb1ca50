// The surface the seam's searches run on: a mesh, its edge weights and the edge graph built
// from them, made once per component and passed to every stage as one value.
#pragma once

#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "core/mesh/halfedge_mesh.h"
#include "core/paths/geodesic.h"

namespace seam::core {

/// A mesh with the weights its seam is measured in and the edge graph over those weights.
/// The three are built together, so the graph always belongs to the mesh and the weights, and
/// every search, tree length and A* bound of one request reads the same numbers. Immutable
/// once built, so threads may share it. It refers to `mesh`, which must outlive it and stay
/// where it is. Moving it keeps graph() where it was (searches and path tables built on the
/// graph stay valid); it is not copied.
class SearchSurface {
 public:
  /// `edge_weights`: one finite weight >= 0 per edge, or empty for the Euclidean lengths.
  /// Precondition (SEAM_ASSERT): edge_weights is empty or has mesh.num_edges() entries.
  /// O(E): builds the edge graph.
  explicit SearchSurface(const HalfedgeMesh& mesh, std::vector<double> edge_weights = {})
      : mesh_(&mesh),
        weights_(std::move(edge_weights)),
        graph_(std::make_unique<const EdgeGraph>(build_edge_graph(mesh, weights_))) {}
  SearchSurface(HalfedgeMesh&&, std::vector<double> = {}) = delete;  // would outlive its mesh
  SearchSurface(SearchSurface&&) noexcept = default;
  SearchSurface& operator=(SearchSurface&&) noexcept = default;

  const HalfedgeMesh& mesh() const { return *mesh_; }
  const EdgeGraph& graph() const { return *graph_; }
  /// One weight per edge, or empty: the Euclidean lengths.
  std::span<const double> edge_weights() const { return weights_; }
  /// The weights are the edges' lengths, so the straight line between two vertices bounds
  /// every path between them from below (what A* may use).
  bool euclidean() const { return weights_.empty(); }

  double weight(EdgeId e) const { return weights_.empty() ? mesh_->edge_length(e) : weights_[e.index()]; }
  /// Sum of the weights of `edges` (a tree's or a path's length).
  double length(std::span<const EdgeId> edges) const {
    double total = 0.0;
    for (EdgeId e : edges) total += weight(e);
    return total;
  }
  /// Sum of the weights of the edges of `path`.
  double path_length(std::span<const HalfedgeId> path) const {
    double total = 0.0;
    for (HalfedgeId h : path) total += weight(HalfedgeMesh::edge(h));
    return total;
  }

 private:
  const HalfedgeMesh* mesh_;
  std::vector<double> weights_;
  std::unique_ptr<const EdgeGraph> graph_;  // on the heap: its address survives a move
};

}  // namespace seam::core
