// Automatic extrema: the tips of a surface's protrusions (the paper's §6 future work).
#pragma once

#include <cstddef>
#include <vector>

#include "core/cancel.h"
#include "core/error.h"
#include "core/halfedge_mesh.h"

namespace seam::core {

struct ExtremaOptions {
  /// A protrusion counts only if its length (geodesic, from tip to where it joins the body)
  /// is at least this fraction of sqrt(surface area). 0 keeps every local maximum.
  double min_protrusion = 0.15;
  /// At most this many extrema per component (the most prominent first). 0 = no limit.
  std::size_t max_count = 16;
};

/// Finds protrusion tips on every component. Deterministic; invariant to rigid motion and
/// uniform scale. Errors: kInvalidArgument (bad options), kCancelled.
Result<std::vector<VertexId>> find_extrema(const HalfedgeMesh& mesh, const ExtremaOptions& options = {},
                                           const CancelToken& cancel = CancelToken::none());

}  // namespace seam::core
