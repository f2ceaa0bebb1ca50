#include "server/http_request.h"

namespace seam::server {

using api::ApiErrorCode;
using api::make_api_error;

api::ApiResult<SeamRequest> decode_seam_request(const httplib::Request& req) {
  const std::string content_type = req.get_header_value("Content-Type");  // parts views it
  SeamRequestParts parts{.content_type = content_type, .query = {req.params.begin(), req.params.end()}, .body = req.body};
  for (const auto& [name, part] : req.files) parts.part_names.push_back(name);
  if (const auto it = req.files.find("mesh"); it != req.files.end()) {
    parts.mesh = FormPart{it->second.content, it->second.content_type};
  }
  if (const auto it = req.files.find("params"); it != req.files.end()) {
    parts.params = FormPart{it->second.content, it->second.content_type};
  }
  return decode_seam_request(parts);
}

std::optional<api::ApiError> refuse_before_body(const RequestHead& head) {
  if (head.method != "POST") return std::nullopt;
  const auto media = media_type(head.field("Content-Type").value_or(""));
  if (media == "application/x-www-form-urlencoded") return unsupported_media_type(media);
  if (head.path != "/seam") return std::nullopt;
  if (media == "multipart/form-data" || media == "application/json" || asset_kind_for_media_type(media)) {
    return std::nullopt;
  }
  return unsupported_media_type(media);
}

api::ApiError library_status_error(int status, const std::string& path, std::size_t max_body_bytes) {
  switch (status) {
    case 404:
      return make_api_error(ApiErrorCode::kNotFound,
                            "no route " + path +
                                "; routes: POST /seam, GET / (the viewer), /openapi.json, /sample.glb, /healthz, "
                                "/readyz, /metrics, /version");
    case 413:
      return make_api_error(ApiErrorCode::kPayloadTooLarge,
                            "the request body is larger than the limit of " + std::to_string(max_body_bytes) +
                                " bytes (--max-body-bytes)",
                            {{"limit_bytes", max_body_bytes}});
    case 415: return make_api_error(ApiErrorCode::kUnsupportedMediaType, "unsupported media type");
    case 400:
      return make_api_error(ApiErrorCode::kMalformedRequest,
                            "malformed HTTP request (bad request line, headers, chunking or multipart body)");
    default:
      if (status >= 500) return make_api_error(ApiErrorCode::kInternal, "internal error");
      return make_api_error(ApiErrorCode::kMalformedRequest, "request failed with HTTP status " + std::to_string(status));
  }
}

}  // namespace seam::server
