// Pieces of a mesh as meshes of their own: one connected component, and a closed surface
// made by coning every boundary loop (so "the whole boundary is one terminal", §4.1).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/error.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/topology.h"

namespace seam::core {

/// A set of faces (one connected component, in compute_seam) as its own mesh. Local vertices are numbered in increasing order
/// of their parent ids and faces keep their relative order, so the result is deterministic.
struct ComponentMesh {
  HalfedgeMesh mesh;
  std::vector<VertexId> to_parent;  ///< local vertex -> vertex of the parent mesh
  std::vector<FaceId> face_to_parent;  ///< local face -> face of the parent mesh
};

/// Extracts the given faces (in the given order) and the vertices they use as a mesh.
/// Costs O(f log f) in the number of faces only, so extracting every component of a mesh with
/// many small parts stays O(F log F) in total. Errors: those of build_halfedge_mesh (e.g.
/// kNonManifoldVertex when the faces are not a whole component and meet at a vertex only).
Result<ComponentMesh> extract_faces(const HalfedgeMesh& mesh, std::span<const FaceId> faces);

/// `mesh` closed by one virtual apex vertex per boundary loop, joined to every vertex of that
/// loop by a fan of triangles. Vertices of `mesh` keep their ids; apexes follow them, one per
/// loop in Topology::boundary_loops order. Edge ids differ from `mesh` (use to_original_edges).
struct ConedMesh {
  HalfedgeMesh mesh;
  /// One per edge of `mesh` (the coned one): Euclidean length, 0 on edges at an apex, so a
  /// shortest path may reach the boundary anywhere and run "along" it for free.
  std::vector<double> edge_weights;
  std::vector<VertexId> apexes;
  std::size_t num_original_vertices = 0;

  bool is_apex(VertexId v) const { return v.index() >= num_original_vertices; }
  bool is_virtual(EdgeId e) const {
    const HalfedgeId h = HalfedgeMesh::halfedge(e);
    return is_apex(mesh.tail(h)) || is_apex(mesh.head(h));
  }
};

/// Cones every boundary loop of `mesh` (which may have several components). The apex sits
/// at the loop's centroid lifted along its (Newell) normal by half its mean radius, so no
/// cone triangle has zero area. Errors: those of build_halfedge_mesh (only if the input was
/// not built by it). O(V + F). A mesh without boundary comes back unchanged (with weights).
Result<ConedMesh> cone_boundary_loops(const HalfedgeMesh& mesh);

/// Maps edges of `from` to edges of `to` through a vertex map (from-vertex -> to-vertex,
/// invalid for vertices with no counterpart, e.g. apexes). Edges with an unmapped end or
/// whose ends are not adjacent in `to` are dropped. Output sorted and unique.
/// O(sum of valences).
std::vector<EdgeId> map_edges(const HalfedgeMesh& from, std::span<const VertexId> vertex_map, const HalfedgeMesh& to,
                              std::span<const EdgeId> edges);

}  // namespace seam::core
