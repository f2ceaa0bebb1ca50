// The skeleton seam's second step (Algorithm 3, §4.3): shrink the tour to a skeleton by
// propagating one mark per tour piece across the triangles of the tour's interior.
#pragma once

#include <vector>

#include "core/cancel.h"
#include "core/error.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/seam/tour.h"

namespace seam::core {

struct ShrinkResult {
  std::vector<EdgeId> skeleton;          ///< edges where different marks meet (sorted, unique)
  std::vector<std::int32_t> face_mark;   ///< per face: the piece whose wave reached it, -1 if none
};

/// Algorithm 3: every half-edge of piece i gets mark i and is queued; a queued half-edge
/// whose twin is unmarked passes its mark to the twin and the twin's two face neighbours
/// (which are queued), so the marks advance face by face into the region on the tour's
/// right (its interior), in first-in first-out order (the paper's uniform speed). Edges
/// whose two half-edges carry different marks are exported as the skeleton. Boundary
/// half-edges are ignored. Precondition: the tour's half-edges belong to `mesh`.
/// Errors: kCancelled. Complexity: O(H) time and memory.
Result<ShrinkResult> shrink_tour(const HalfedgeMesh& mesh, const Tour& tour,
                                 const CancelToken& cancel = CancelToken::none());

}  // namespace seam::core
