#include "server/request.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdlib>

#include "api/base64.h"
#include "api/json_limits.h"

namespace seam::server {
namespace {

using api::ApiErrorCode;
using api::make_api_error;

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

}  // namespace

std::string media_type(std::string_view content_type) {
  const auto semi = content_type.find(';');
  std::string out(trim(content_type.substr(0, semi)));
  for (auto& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

std::optional<api::AssetKind> asset_kind_for_media_type(std::string_view media) {
  if (media == "model/gltf-binary") return api::AssetKind::kGlb;
  if (media == "model/gltf+json") return api::AssetKind::kGltfJson;
  // Draco has no registered media type; octet-stream is sniffed (GLB and glTF JSON too).
  if (media == "application/octet-stream") return api::AssetKind::kAuto;
  return std::nullopt;
}

api::ApiResult<SeamRequest> parse_json_request(std::string_view body) {
  // Depth is checked while parsing, so the whole body (mesh.gltf included) is at most 64
  // levels deep before anything below walks or re-serialises it.
  auto parsed = api::parse_json_limited(body);
  if (!parsed.ok()) {
    api::ApiError error = parsed.take_error();
    error.message = "the request body: " + error.message;
    return error;
  }
  nlohmann::json json = std::move(parsed).value();
  if (!json.is_object()) {
    return make_api_error(ApiErrorCode::kMalformedRequest,
                          "the request body must be a JSON object: {\"mesh\": {\"glb_base64\": ...}, ...parameters}");
  }
  const auto mesh_it = json.find("mesh");
  if (mesh_it == json.end() || !mesh_it->is_object()) {
    return make_api_error(ApiErrorCode::kMalformedRequest,
                          "missing \"mesh\": give {\"mesh\": {\"glb_base64\": \"...\"}} or {\"mesh\": {\"gltf\": {...}}}");
  }
  SeamRequest out;
  const auto& mesh = *mesh_it;
  const auto b64 = mesh.find("glb_base64");
  const auto gltf = mesh.find("gltf");
  if ((b64 != mesh.end()) == (gltf != mesh.end()) || mesh.size() != 1) {
    return make_api_error(ApiErrorCode::kMalformedRequest,
                          "\"mesh\" must have exactly one of \"glb_base64\" (a string) or \"gltf\" (an object)");
  }
  if (b64 != mesh.end()) {
    if (!b64->is_string()) {
      return make_api_error(ApiErrorCode::kMalformedRequest, "mesh.glb_base64 must be a base64 string");
    }
    auto decoded = api::decode_base64(b64->get_ref<const std::string&>());
    if (!decoded.ok()) {
      const api::Base64Error& e = decoded.error();
      nlohmann::json details = nlohmann::json::object();
      if (e.kind == api::Base64Error::Kind::kBadCharacter) details["offset"] = e.offset;
      return make_api_error(ApiErrorCode::kMalformedRequest, "mesh.glb_base64 is not valid base64: " + e.describe(),
                            std::move(details));
    }
    out.asset = std::move(decoded).value();
    out.kind = api::AssetKind::kAuto;  // GLB normally; a base64 Draco mesh is sniffed too
  } else {
    if (!gltf->is_object()) {
      return make_api_error(ApiErrorCode::kMalformedRequest, "mesh.gltf must be a glTF JSON object");
    }
    out.asset = gltf->dump();  // safe: parse_json_limited bounded its depth
    out.kind = api::AssetKind::kGltfJson;
  }
  json.erase(mesh_it);
  SEAM_TRY(out.params, api::params_from_json(json));
  return out;
}

api::ApiResult<api::SeamParams> parse_params_part(std::string_view text) {
  if (trim(text).empty()) return api::params_from_json(nlohmann::json::object());
  auto parsed = api::parse_json_limited(text);
  if (!parsed.ok()) {
    api::ApiError error = parsed.take_error();
    error.message = "the params part: " + error.message;
    return error;
  }
  if (!parsed->is_object()) {
    return make_api_error(ApiErrorCode::kMalformedRequest, "the params part must be a JSON object, e.g. {\"extrema\":[1,2,3]}");
  }
  return api::params_from_json(*parsed);
}

api::ApiResult<api::SeamParams> parse_query_params(const std::vector<std::pair<std::string, std::string>>& query) {
  return api::params_from_query(query);
}

std::optional<double> accept_quality(std::string_view accept, std::string_view media) {
  std::size_t start = 0;
  while (start <= accept.size()) {
    const auto comma = accept.find(',', start);
    const auto item = accept.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start);
    if (media_type(item) == media) {
      // The media type's parameters: only q counts. A q that does not parse counts as 1, the
      // default (a client that meant to refuse writes q=0).
      double q = 1.0;
      for (auto semi = item.find(';'); semi != std::string_view::npos;) {
        const auto next = item.find(';', semi + 1);
        const auto param =
            trim(item.substr(semi + 1, next == std::string_view::npos ? std::string_view::npos : next - semi - 1));
        if (param.size() > 2 && (param[0] == 'q' || param[0] == 'Q') && param[1] == '=') {
          const std::string value(trim(param.substr(2)));
          char* end = nullptr;
          const double parsed = std::strtod(value.c_str(), &end);
          if (end != value.c_str() && *end == '\0' && parsed >= 0 && parsed <= 1) q = parsed;
        }
        semi = next;
      }
      return q;
    }
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return std::nullopt;
}

bool accepts_glb(std::string_view accept) {
  return accept_quality(accept, "model/gltf-binary").value_or(0) > 0;
}

api::ApiResult<api::OutputFormat> choose_output(const api::SeamParams& params, std::string_view accept) {
  if (params.output_given) return params.output;
  if (accepts_glb(accept)) return api::OutputFormat::kGlb;
  if (accept_quality(accept, "image/svg+xml").value_or(0) > 0) return api::OutputFormat::kSvg;
  if (accept_quality(accept, "application/json") == 0.0) {
    return make_api_error(ApiErrorCode::kNotAcceptable,
                          "Accept refuses application/json (q=0) and accepts neither model/gltf-binary nor "
                          "image/svg+xml; accept one of them, or name the format with the output parameter",
                          {{"acceptable", {"application/json", "model/gltf-binary", "image/svg+xml"}}});
  }
  return api::OutputFormat::kJson;
}

api::ApiError unsupported_media_type(std::string_view media) {
  const std::string shown(media.substr(0, 100));
  return api::make_api_error(api::ApiErrorCode::kUnsupportedMediaType,
                             "unsupported Content-Type '" + shown +
                                 "': use multipart/form-data, application/json, model/gltf-binary, model/gltf+json or "
                                 "application/octet-stream",
                             {{"content_type", shown}});
}

namespace {

// Unknown parameters are refused, not ignored (api/params.h); so is a part the service would
// not read: `-F parms=...` used to run with the defaults, a second params or mesh part lost.
std::optional<api::ApiError> check_part_names(const std::vector<std::string>& names) {
  for (const std::string& name : names) {
    const std::string shown = name.substr(0, 60);  // client bytes: bounded in the answer
    if (name != "mesh" && name != "params") {
      return make_api_error(ApiErrorCode::kMalformedRequest,
                            "multipart part \"" + shown +
                                "\" is not one the service reads: send the asset as part \"mesh\" and the "
                                "parameters as one JSON object in part \"params\"",
                            {{"part", shown}});
    }
    const auto count = std::count(names.begin(), names.end(), name);
    if (count > 1) {
      return make_api_error(ApiErrorCode::kMalformedRequest,
                            "multipart part \"" + name + "\" is given " + std::to_string(count) +
                                " times; send it once (put every parameter in one params object)",
                            {{"part", name}, {"count", count}});
    }
  }
  return std::nullopt;
}

}  // namespace

api::ApiResult<SeamRequest> decode_seam_request(const SeamRequestParts& parts) {
  using api::ApiErrorCode;
  using api::make_api_error;
  const auto media = media_type(parts.content_type);
  if (media == "multipart/form-data") {
    if (auto refused = check_part_names(parts.part_names)) return *refused;
    if (!parts.mesh) {
      return make_api_error(ApiErrorCode::kMalformedRequest,
                            "multipart request without a 'mesh' part: curl -F mesh=@asset.glb ...");
    }
    SeamRequest out;
    const auto kind = asset_kind_for_media_type(media_type(parts.mesh->content_type));
    out.kind = kind ? *kind : api::AssetKind::kAuto;  // curl labels files by extension, or not at all
    out.asset = std::string(parts.mesh->content);
    if (parts.params) {
      if (!parts.query.empty()) {
        return make_api_error(ApiErrorCode::kInvalidParameter,
                              "parameters given both in the params part and in the query string; use one");
      }
      SEAM_TRY(out.params, parse_params_part(parts.params->content));
    } else {
      SEAM_TRY(out.params, parse_query_params(parts.query));
    }
    return out;
  }
  if (media == "application/json") {
    if (!parts.query.empty()) {
      return make_api_error(ApiErrorCode::kInvalidParameter,
                            "with a JSON body the parameters go in the body, not the query string");
    }
    return parse_json_request(parts.body);
  }
  const auto kind = asset_kind_for_media_type(media);
  if (!kind) return unsupported_media_type(media);
  SeamRequest out;
  out.kind = *kind;
  out.asset = std::string(parts.body);
  SEAM_TRY(out.params, parse_query_params(parts.query));
  return out;
}

}  // namespace seam::server
