// One seam job from asset bytes and parameters to the contract's response: parse, weld,
// seam, cut, flatten, encode. Shared by the HTTP server and the command line.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/error.h"
#include "core/cancel.h"
#include "core/extrema/extrema.h"
#include "core/uv/parameterize.h"
#include "core/seam/seam.h"

namespace seam::api {

/// How the extrema are chosen (API.md "extrema").
struct ExtremaSpec {
  bool automatic = true;                           ///< "auto", or {"auto": true, ...}
  std::vector<std::uint32_t> indices;              ///< input vertex indices (include list)
  std::vector<std::array<double, 3>> positions;    ///< snapped to the nearest vertex
  std::vector<std::uint32_t> exclude;              ///< input vertex indices to drop from auto
  core::ExtremaOptions auto_options;
};

enum class OutputFormat { kJson, kGlb };

/// The parameters of POST /seam (API.md "Parameters").
struct SeamParams {
  ExtremaSpec extrema;
  std::uint32_t mesh = 0;
  std::uint32_t primitive = 0;
  core::SeamMethod method = core::SeamMethod::kSkeleton;
  /// nullopt = "none"; the default is the core's default (the lowest-distortion flip-free method).
  std::optional<core::UvMethod> uv = core::UvOptions{}.method;
  OutputFormat output = OutputFormat::kJson;
  std::optional<bool> draco;  ///< nullopt = same as the input
  /// Skeleton only: the local re-optimisation after §4.4 (core::SkeletonOptions::refine).
  /// On: within a few percent of the optimum at ~0.2 s per request; off: the paper's seam,
  /// a few milliseconds at 10k faces.
  bool refine = core::SeamOptions{}.refine;
  double weld_epsilon = 0.0;
  /// Repair what the builder would refuse (core::repair_mesh: non-manifold edges split into
  /// sheets, orientation made consistent, degenerate faces left out of the topology but kept
  /// in the asset). false: v1's 422s (pinched vertices are split either way).
  bool repair = true;
};

/// Parses the parameter object (the multipart `params` part, or the JSON body minus "mesh").
/// Unknown keys are rejected (kInvalidParameter naming the key) so typos are not silent.
ApiResult<SeamParams> params_from_json(const nlohmann::json& params);

/// Parses query-string parameters (`?extrema=12,345&method=mst&uv=none`).
ApiResult<SeamParams> params_from_query(const std::vector<std::pair<std::string, std::string>>& query);

/// What kind of bytes the asset is. kAuto sniffs: "glTF" magic = GLB, '{' = glTF JSON,
/// "DRACO" magic = raw Draco mesh.
enum class AssetKind { kAuto, kGlb, kGltfJson, kDraco };

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
  /// Threads the job may run at once (extrema detection, terminal-path Dijkstra); 0 = the
  /// hardware concurrency. The result does not depend on it.
  unsigned threads = 0;
};

struct PipelineOutput {
  nlohmann::json body;  ///< the 200 response object of API.md (with asset.glb_base64 when kJson)
  std::string glb;      ///< the cut asset as GLB bytes (always filled)
  double total_ms = 0;
};

/// Runs one seam job. Never throws for bad input: every failure is an ApiError with the
/// contract's code. Cancelled work (time budget) returns kTimeout. Errors besides the
/// loader's, the core's and kTimeout: kTooManyExtrema (more explicit extrema than
/// limits.max_extrema, checked before the asset is parsed), kExtremumOutOfRange, kInternal.
/// Uses at most max(1, limits.threads) threads (hardware concurrency when 0).
ApiResult<PipelineOutput> run_seam_pipeline(const std::string& asset_bytes, AssetKind kind,
                                            const SeamParams& params, const PipelineLimits& limits,
                                            const core::CancelToken& cancel);

}  // namespace seam::api
