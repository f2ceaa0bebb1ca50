// One seam request from asset bytes and parameters to the contract's response: parse, select
// the primitives, run each one's job (api/primitive_job.h) in parallel, write the asset once.
// Shared by the HTTP server and the command line.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/error.h"
#include "api/gltf_reader.h"
#include "api/params.h"
#include "core/cancel.h"

namespace seam::api {

/// Per-request cost caps and the request's thread budget (the server's --max-faces,
/// --max-extrema and threads per request).
struct PipelineLimits {
  /// Larger primitives are a 422 (kMeshTooLarge). Also bounds what a Draco payload may claim
  /// before it is decoded (decode_draco).
  std::size_t max_faces = 5'000'000;
  /// Explicit extrema (indices plus positions) beyond this are a 422 (kTooManyExtrema) before
  /// any mesh work; automatic detection keeps at most this many, the most prominent, minus
  /// the explicit ones. The seam's cost grows with the square of the extrema count.
  std::size_t max_extrema = 256;
  /// More selected triangle primitives than this are a 422 (kMeshTooLarge) before any is
  /// read: each costs ~15 KB and ~0.15 ms however small (its job, report and output
  /// accessors), so 5 MB of glTF naming one tetrahedron 100,000 times took 1.7 GB and 15 s.
  std::size_t max_primitives = 10'000;
  /// Threads the job may run at once (extrema detection, terminal-path Dijkstra); 0 = the
  /// hardware concurrency. The result does not depend on it.
  unsigned threads = 0;
};

struct PipelineOutput {
  nlohmann::json body;  ///< the 200 response object of API.md (with asset.glb_base64 when kJson)
  std::string glb;      ///< the cut asset as GLB bytes (always filled)
  std::string svg;      ///< output "svg": the new UV sets' layout (api/svg.h), else empty
  double total_ms = 0;
};

/// Runs one seam request. Never throws for bad input: every failure is an ApiError with the
/// contract's code. Errors: kTooManyExtrema (more explicit extrema in the whole request than
/// limits.max_extrema, checked before the asset is parsed); the loader's (parse_asset,
/// read_primitive); kInvalidParameter (a primitives entry naming no mesh or a primitive twice;
/// top-level extrema naming vertices while several primitives are selected);
/// kNoTrianglePrimitive (nothing to cut); kMeshTooLarge (more selected primitives than
/// limits.max_primitives, or more than limits.max_faces faces in all); process_primitive's errors, with details.mesh
/// and details.primitive and, when several are processed, the message prefixed by them (the first failing primitive in
/// asset order); kTimeout (cancelled); kInternal. Uses at most max(1, limits.threads) threads (hardware concurrency
/// when 0): min(threads, primitives) primitives at once, each with an equal share. The result does not depend on it.
ApiResult<PipelineOutput> run_seam_pipeline(const std::string& asset_bytes, AssetKind kind,
                                            const SeamParams& params, const PipelineLimits& limits,
                                            const core::CancelToken& cancel);

}  // namespace seam::api
