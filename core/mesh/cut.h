// Cutting a mesh open along edges: the seam and cut graph become boundary.
#pragma once

#include <span>

#include "core/cancel.h"
#include "core/error.h"
#include "core/mesh/halfedge_mesh.h"

namespace seam::core {

/// The cut mesh plus the map back. Faces keep their ids and corner order: face f of the cut
/// mesh is face f of the input, with corners possibly on duplicated vertices.
struct CutMesh {
  HalfedgeMesh mesh;
  VertexData<VertexId> to_original;  ///< cut vertex -> vertex of the input mesh
};

/// Duplicates vertices along `edges` so that those edges become boundary. A vertex is
/// duplicated once per wedge (maximal fan of faces between cut edges or boundary).
/// Errors: kInvalidArgument (edge id out of range). O(V + E + F).
Result<CutMesh> cut_along_edges(const HalfedgeMesh& mesh, std::span<const EdgeId> edges);

/// Checks that every connected component of `mesh` is a topological disc (Euler
/// characteristic 1, exactly one boundary loop); kTopologyViolation names the first that is not.
Status check_is_disc(const HalfedgeMesh& mesh);

}  // namespace seam::core
