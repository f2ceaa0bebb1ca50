// Cutting a mesh open along edges: the seam and cut graph become boundary.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

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
/// Errors: kInvalidArgument (edge id out of range), kTopologyViolation (an edge that would be a
/// slit, see is_slit; the message and elements name the first). O(V + E + F).
Result<CutMesh> cut_along_edges(const HalfedgeMesh& mesh, std::span<const EdgeId> edges);

/// Per vertex, how many of the flagged edges (`is_cut`: one flag per edge) meet it. O(V + E).
std::vector<std::uint32_t> cut_degrees(const HalfedgeMesh& mesh, std::span<const std::uint8_t> is_cut);

/// Whether cutting edge e, with `cut_degree` from cut_degrees over the whole cut, would open a
/// slit that cut_along_edges refuses: e is interior and both its ends are interior vertices on
/// no other cut edge, so each keeps a single wedge and the two-edge boundary loop would not be
/// a simplicial mesh. O(1).
bool is_slit(const HalfedgeMesh& mesh, std::span<const std::uint32_t> cut_degree, EdgeId e);

/// Checks that every connected component of `mesh` is a topological disc (Euler
/// characteristic 1, exactly one boundary loop); kTopologyViolation names the first that is not.
Status check_is_disc(const HalfedgeMesh& mesh);

}  // namespace seam::core
