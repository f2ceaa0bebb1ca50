// Topology queries: connected components, ordered boundary loops, Euler characteristic, genus.
#pragma once

#include <cstdint>
#include <vector>

#include "core/error.h"
#include "core/mesh/halfedge_mesh.h"

namespace seam::core {

/// Counts for one connected component (a maximal set of faces joined by edges).
struct ComponentInfo {
  std::size_t vertices = 0;
  std::size_t edges = 0;
  std::size_t faces = 0;
  std::size_t boundary_loops = 0;
  int euler_characteristic = 0;  ///< V - E + F
  int genus = 0;                 ///< (2 - chi - boundary_loops) / 2
};

struct Topology {
  /// Component of each face / vertex (isolated vertices: kInvalidValue). Components are
  /// numbered in order of their smallest face id.
  FaceData<std::uint32_t> face_component;
  VertexData<std::uint32_t> vertex_component;
  std::vector<ComponentInfo> components;
  /// Each boundary loop as its boundary half-edges in next() order, starting at the
  /// half-edge with the smallest id; loops sorted by that id.
  std::vector<std::vector<HalfedgeId>> boundary_loops;
  std::vector<std::uint32_t> boundary_loop_component;

  /// Totals over all components (genus summed).
  int total_genus() const;
  int euler_characteristic() const;
};

/// Each boundary loop of `mesh` as its boundary half-edges in next() order, starting at the
/// half-edge with the smallest id; loops sorted by that id (Topology::boundary_loops). O(H).
std::vector<std::vector<HalfedgeId>> boundary_loops(const HalfedgeMesh& mesh);

/// Computes components, boundary loops, Euler characteristic and genus. O(V + E + F).
Topology compute_topology(const HalfedgeMesh& mesh);

/// For entry points that take a caller's topology: kInvalidArgument when `topology` does not
/// have `mesh`'s faces and vertices (it was computed from another mesh). O(1).
Status check_topology_of(const HalfedgeMesh& mesh, const Topology& topology);

}  // namespace seam::core
