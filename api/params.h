// The parameters of POST /seam (API.md "Parameters" and the v2 additions) and their parsing
// from JSON or the query string. Shared by the HTTP server and the command line.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/error.h"
#include "core/extrema/extrema.h"
#include "core/seam/seam.h"
#include "core/uv/parameterize.h"

namespace seam::api {

/// How the extrema are chosen (API.md "extrema").
struct ExtremaSpec {
  bool automatic = true;                           ///< "auto", or {"auto": true, ...}
  std::vector<std::uint32_t> indices;              ///< input vertex indices (include list)
  std::vector<std::array<double, 3>> positions;    ///< snapped to the nearest vertex
  std::vector<std::uint32_t> exclude;              ///< input vertex indices to drop from auto
  core::ExtremaOptions auto_options;

  /// Explicit extrema (indices and positions) name vertices of one primitive.
  bool names_vertices() const { return !indices.empty() || !positions.empty() || !exclude.empty(); }
};

enum class OutputFormat { kJson, kGlb, kSvg };

/// Which primitives' new UV sets share one [0,1]² layout (API.md v2 `pack.group_by`).
enum class PackGroup { kAsset, kMesh, kMaterial, kPrimitive };

/// `pack` (API.md v2 "An atlas, not only charts"); `pack: false` keeps each primitive's own
/// layout (core::parameterize's, charts side by side at their own scale); `pack: true` is the
/// default object.
struct PackParams {
  bool enabled = true;
  PackGroup group_by = PackGroup::kAsset;
  int texture_size = 1024;  ///< 16..65536
  double margin_px = 4;     ///< 0..texture_size/8
  bool rotate = true;
  /// Cut charts that fill under 0.65 of their smallest rectangle (core::split_sprawling_charts)
  /// before packing: more charts and a longer cut, a fuller atlas. Off by default: one chart
  /// per component is the paper's premise.
  bool split = false;
  /// The caller gave texture_size or margin_px: they hold as given (too many charts for them is
  /// an error). Left at their defaults, the texture grows for more charts than its margins
  /// leave room for (pack_step.h).
  bool sized_by_caller = false;
};

/// `charts`: "seam" (one chart per component, the paper's premise) or "features" (also cut
/// along sharp edges first, for hard-surface models).
enum class ChartMode { kSeam, kFeatures };

/// One entry of `primitives` (API.md v2 "Whole assets").
struct PrimitiveSelector {
  std::optional<std::uint32_t> mesh;       ///< the mesh index, or
  std::string mesh_name;                   ///< the mesh's name (when mesh is nullopt)
  std::optional<std::uint32_t> primitive;  ///< nullopt: every triangle primitive of the mesh
  std::optional<ExtremaSpec> extrema;      ///< nullopt: the request's top-level extrema
};

/// The parameters of POST /seam.
struct SeamParams {
  /// The extrema of every processed primitive without its own (a list entry's `extrema`).
  ExtremaSpec extrema;
  /// v1's selection: set when the request names `mesh` or `primitive`; exactly that one
  /// primitive (the other index 0) is processed.
  std::optional<std::uint32_t> mesh;
  std::optional<std::uint32_t> primitive;
  /// v2's selection: nullopt = "all" (every triangle primitive of every mesh), the default
  /// when neither mesh nor primitive is given.
  std::optional<std::vector<PrimitiveSelector>> primitives;
  core::SeamMethod method = core::SeamMethod::kSkeleton;
  /// nullopt = "none"; the default is the core's default (the lowest-distortion flip-free method).
  std::optional<core::UvMethod> uv = core::UvOptions{}.method;
  OutputFormat output = OutputFormat::kJson;
  /// The request named `output`: then it wins over an Accept header (server::choose_output).
  bool output_given = false;
  std::optional<bool> draco;  ///< nullopt = as each primitive was in the input
  /// Skeleton only: the local re-optimisation after §4.4 (core::SeamOptions::refine).
  bool refine = core::SeamOptions{}.refine;
  double weld_epsilon = 0.0;
  PackParams pack;
  ChartMode charts = ChartMode::kSeam;
  double feature_angle_deg = 60;  ///< charts "features": dihedral angle of a sharp edge, 0..180
  /// Seeing and steering (API.md v2, the paper's §6): directions in which cameras look; edges
  /// they see cost 1 + hide_strength times more. At most 64.
  std::vector<std::array<double, 3>> hide_from;
  bool hide_occluded = false;  ///< open places cost more, crevices less (ambient occlusion)
  double hide_strength = 4;    ///< 0..1000
  /// Repair what the builder would refuse (core::repair_mesh: non-manifold edges split into
  /// sheets, orientation made consistent, degenerate faces left out of the topology but kept
  /// in the asset). false: v1's 422s (pinched vertices are split either way).
  bool repair = true;
};

/// Parses the parameter object (the multipart `params` part, or the JSON body minus "mesh").
/// Unknown keys are rejected so typos are not silent. `pack: true` is the default object.
/// Errors: kInvalidParameter naming the parameter (details.parameter), also for `primitives`
/// given together with mesh/primitive, `feature_angle_deg` without `charts: "features"`, and
/// `extrema.max_count` 0.
ApiResult<SeamParams> params_from_json(const nlohmann::json& params);

/// Parses query-string parameters (`?extrema=12,345&method=mst&uv=none&primitives=all`);
/// each value becomes the JSON it stands for, then params_from_json's rules apply: strings as
/// they are; `mesh`, `primitive` decimal digits; booleans true/false/1/0; numbers in JSON
/// number syntax (decimal: 0x10, inf, nan refused); `extrema` auto, comma-separated indices
/// or JSON; `primitives` all or JSON; `pack` true/false/1/0 or a JSON object; `hide_from`
/// JSON. JSON values (URL-decoded) nest at most kMaxJsonDepth deep.
/// Errors: kInvalidParameter (details.parameter; for a JSON value that does not parse also
/// details.offset), also for a parameter given twice.
ApiResult<SeamParams> params_from_query(const std::vector<std::pair<std::string, std::string>>& query);

}  // namespace seam::api
