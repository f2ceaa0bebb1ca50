// One primitive's seam job: weld -> repair -> build -> extrema -> seam -> cut -> flatten,
// and the contract's per-primitive summary. Pure: it reads a primitive and returns its cut in
// terms of the input's vertices; the asset is written once for all primitives (pipeline.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/error.h"
#include "api/gltf_reader.h"
#include "api/gltf_writer.h"
#include "api/params.h"
#include "core/cancel.h"

namespace seam::api {

struct PrimitiveJobOptions {
  std::size_t max_extrema = 256;  ///< the request's --max-extrema (explicit ones refused beyond)
  unsigned threads = 1;           ///< this primitive's share of the request's thread budget
};

struct PrimitiveResult {
  CutPrimitive cut;  ///< source_vertex, triangles, uv (empty with uv "none"), seam_extras
  std::vector<std::uint32_t> chart;  ///< per output vertex: its chart (a component of the cut)
  std::vector<double> chart_area;    ///< per chart: its 3D surface area
  /// {"seam", "topology", "repairs", "cut", "uv", "timings_ms"} of API.md v2; uv.channel is
  /// added by the caller once the writer has chosen it.
  nlohmann::json summary;
};

/// Explicit extrema (indices plus positions) beyond max_extrema are a kTooManyExtrema, checked
/// before the asset is parsed. Returns the explicit count.
ApiResult<std::size_t> explicit_extrema_count(const ExtremaSpec& spec, std::size_t max_extrema);

/// Runs the seam job on one primitive with `extrema` (its own or the request's) and the
/// request's method, uv, refine, repair, weld and charts parameters (charts "features": the
/// surface is cut along its sharp edges too, core::find_feature_edges). Error messages and
/// details name input elements (face = index in the primitive's index order, vertex =
/// POSITION index). Errors: kEmptyMesh (no triangle with area), kDegenerateFace,
/// kNonManifoldEdge, kInconsistentOrientation (repair: false only), kNonFinitePosition,
/// kExtremumOutOfRange (an index past the vertices, or a vertex in no face with area),
/// kTooManyExtrema, kTooManyTerminals (optimal), kSolverFailed, kTimeout (cancelled),
/// kInternal. Uses at most max(1, options.threads) threads; the result does not depend on it.
ApiResult<PrimitiveResult> process_primitive(const PrimitiveData& data, const ExtremaSpec& extrema,
                                             const SeamParams& params, const PrimitiveJobOptions& options,
                                             const core::CancelToken& cancel);

}  // namespace seam::api
