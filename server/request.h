// Pure request decoding for POST /seam (no sockets, no httplib): the three request forms of
// API.md turned into asset bytes, their kind and the parameters. Kept apart from the handler
// so every branch is testable without HTTP.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "api/error.h"
#include "api/pipeline.h"

namespace seam::server {

/// One decoded seam request.
struct SeamRequest {
  std::string asset;                         ///< the asset bytes
  api::AssetKind kind = api::AssetKind::kAuto;
  api::SeamParams params;
};

/// Lower-cased media type without parameters: "Model/GLTF-Binary; x=y" -> "model/gltf-binary".
std::string media_type(std::string_view content_type);

/// The asset kind a media type announces: model/gltf-binary -> kGlb, model/gltf+json ->
/// kGltfJson, application/octet-stream (Draco, or anything sniffable) -> kAuto.
/// nullopt for media types the service does not take (the caller answers 415).
std::optional<api::AssetKind> asset_kind_for_media_type(std::string_view media);

/// One part of a multipart/form-data body.
struct FormPart {
  std::string_view content;
  std::string_view content_type;  ///< as sent, e.g. "model/gltf-binary" (may be empty)
};

/// What POST /seam reads of an HTTP request, without the HTTP library.
struct SeamRequestParts {
  std::string_view content_type;  ///< the request's Content-Type header
  std::vector<std::pair<std::string, std::string>> query;
  std::string_view body;                ///< the raw body (forms 2 and 3)
  std::optional<FormPart> mesh;         ///< multipart "mesh" part (form 1)
  std::optional<FormPart> params;       ///< multipart "params" part (form 1)
  /// The name of every part of a multipart body, one entry per part (so a name sent twice
  /// appears twice): anything but one `mesh` and at most one `params` is refused.
  std::vector<std::string> part_names;
};

/// The three request forms of API.md, chosen by the Content-Type: multipart (mesh part, params
/// part or query), JSON body (no query), or the asset as the body (query parameters).
/// Errors: kMalformedRequest (no mesh part; a part named other than mesh or params, or a
/// mesh or params part given twice, with details.part naming it; bad JSON or base64),
/// kInvalidParameter (params in two places, bad values), kUnsupportedMediaType (another
/// Content-Type). O(body).
api::ApiResult<SeamRequest> decode_seam_request(const SeamRequestParts& parts);

/// The 415 for a media type POST /seam does not take (also used before the body is read).
api::ApiError unsupported_media_type(std::string_view media);

/// Form 2: `{"mesh": {"glb_base64": "..."} | {"gltf": {...}}, ...parameters}`.
/// Errors: kMalformedRequest (bad JSON; JSON nested deeper than api::kMaxJsonDepth anywhere,
/// checked while parsing; no mesh; bad base64), whatever params_from_json returns.
api::ApiResult<SeamRequest> parse_json_request(std::string_view body);

/// Form 1's `params` part (may be empty: defaults). Errors as params_from_json, or
/// kMalformedRequest when it is not valid JSON, nests deeper than api::kMaxJsonDepth, or is
/// not a JSON object.
api::ApiResult<api::SeamParams> parse_params_part(std::string_view text);

/// Query parameters (`?extrema=1,2&method=mst`); an empty list gives the defaults.
api::ApiResult<api::SeamParams> parse_query_params(const std::vector<std::pair<std::string, std::string>>& query);

/// The q value `accept` (an Accept header) gives the exact media type `media` (lower case),
/// 0..1; 1 when it is listed without q or with a q that does not parse; nullopt when it is not
/// listed. Wildcards (`*/*`, `model/*`) are not expanded. O(accept).
std::optional<double> accept_quality(std::string_view accept, std::string_view media);

/// True when an Accept header asks for the binary asset (model/gltf-binary listed with q > 0).
bool accepts_glb(std::string_view accept);

/// The response format of POST /seam. An explicit `output` parameter wins whatever Accept
/// says; without one, Accept chooses: model/gltf-binary with q > 0 gives GLB, else
/// image/svg+xml with q > 0 gives SVG, else JSON (also for Accept types we cannot produce, so
/// `text/html` or `*/*` still get JSON). Errors: kNotAcceptable (406) when Accept refuses
/// application/json with q=0 and accepts neither other format. O(accept).
api::ApiResult<api::OutputFormat> choose_output(const api::SeamParams& params, std::string_view accept);

}  // namespace seam::server
