#include "api/error.h"

namespace seam::api {

// Exhaustive switches with no default: a new enumerator that is not mapped is a compile
// warning (an error in CI), so the table can never drift out of step with the enum.
std::string_view code_name(ApiErrorCode code) {
  switch (code) {
    case ApiErrorCode::kMalformedRequest: return "malformed_request";
    case ApiErrorCode::kInvalidParameter: return "invalid_parameter";
    case ApiErrorCode::kMalformedAsset: return "malformed_asset";
    case ApiErrorCode::kNotFound: return "not_found";
    case ApiErrorCode::kMethodNotAllowed: return "method_not_allowed";
    case ApiErrorCode::kNotAcceptable: return "not_acceptable";
    case ApiErrorCode::kRequestTimeout: return "request_timeout";
    case ApiErrorCode::kLengthRequired: return "length_required";
    case ApiErrorCode::kPayloadTooLarge: return "payload_too_large";
    case ApiErrorCode::kUnsupportedMediaType: return "unsupported_media_type";
    case ApiErrorCode::kHeadersTooLarge: return "headers_too_large";
    case ApiErrorCode::kNoTrianglePrimitive: return "no_triangle_primitive";
    case ApiErrorCode::kUnsupportedPrimitiveMode: return "unsupported_primitive_mode";
    case ApiErrorCode::kExternalUri: return "external_uri";
    case ApiErrorCode::kUnsupportedExtension: return "unsupported_extension";
    case ApiErrorCode::kExtremumOutOfRange: return "extremum_out_of_range";
    case ApiErrorCode::kMeshTooLarge: return "mesh_too_large";
    case ApiErrorCode::kEmptyMesh: return "empty_mesh";
    case ApiErrorCode::kIndexOutOfRange: return "index_out_of_range";
    case ApiErrorCode::kNonFinitePosition: return "non_finite_position";
    case ApiErrorCode::kDegenerateFace: return "degenerate_face";
    case ApiErrorCode::kNonManifoldEdge: return "non_manifold_edge";
    case ApiErrorCode::kNonManifoldVertex: return "non_manifold_vertex";
    case ApiErrorCode::kInconsistentOrientation: return "inconsistent_orientation";
    case ApiErrorCode::kTooManyTerminals: return "too_many_terminals";
    case ApiErrorCode::kTooManyExtrema: return "too_many_extrema";
    case ApiErrorCode::kTopologyViolation: return "topology_violation";
    case ApiErrorCode::kSolverFailed: return "solver_failed";
    case ApiErrorCode::kClientClosed: return "client_closed";
    case ApiErrorCode::kQueueFull: return "queue_full";
    case ApiErrorCode::kOverloaded: return "overloaded";
    case ApiErrorCode::kTimeout: return "timeout";
    case ApiErrorCode::kInternal: return "internal";
  }
  return "internal";
}

int http_status(ApiErrorCode code) {
  switch (code) {
    case ApiErrorCode::kMalformedRequest:
    case ApiErrorCode::kInvalidParameter:
    case ApiErrorCode::kMalformedAsset: return 400;
    case ApiErrorCode::kNotFound: return 404;
    case ApiErrorCode::kMethodNotAllowed: return 405;
    case ApiErrorCode::kNotAcceptable: return 406;
    case ApiErrorCode::kRequestTimeout: return 408;
    case ApiErrorCode::kLengthRequired: return 411;
    case ApiErrorCode::kPayloadTooLarge: return 413;
    case ApiErrorCode::kUnsupportedMediaType: return 415;
    case ApiErrorCode::kHeadersTooLarge: return 431;
    case ApiErrorCode::kNoTrianglePrimitive:
    case ApiErrorCode::kUnsupportedPrimitiveMode:
    case ApiErrorCode::kExternalUri:
    case ApiErrorCode::kUnsupportedExtension:
    case ApiErrorCode::kExtremumOutOfRange:
    case ApiErrorCode::kMeshTooLarge:
    case ApiErrorCode::kEmptyMesh:
    case ApiErrorCode::kIndexOutOfRange:
    case ApiErrorCode::kNonFinitePosition:
    case ApiErrorCode::kDegenerateFace:
    case ApiErrorCode::kNonManifoldEdge:
    case ApiErrorCode::kNonManifoldVertex:
    case ApiErrorCode::kInconsistentOrientation:
    case ApiErrorCode::kTooManyTerminals:
    case ApiErrorCode::kTooManyExtrema: return 422;
    case ApiErrorCode::kClientClosed: return 499;  // nginx's convention; only the log sees it
    case ApiErrorCode::kQueueFull:
    case ApiErrorCode::kOverloaded: return 503;
    case ApiErrorCode::kTimeout: return 504;
    // A seam that fails its own disc check or a solver that fails is our bug, not the
    // caller's: 500, logged with the request id.
    case ApiErrorCode::kTopologyViolation:
    case ApiErrorCode::kSolverFailed:
    case ApiErrorCode::kInternal: return 500;
  }
  return 500;
}

ApiError from_core(const core::Error& error) {
  ApiErrorCode code = ApiErrorCode::kInternal;
  switch (error.code) {
    case core::ErrorCode::kInvalidArgument: code = ApiErrorCode::kInvalidParameter; break;
    case core::ErrorCode::kEmptyMesh: code = ApiErrorCode::kEmptyMesh; break;
    case core::ErrorCode::kIndexOutOfRange: code = ApiErrorCode::kIndexOutOfRange; break;
    case core::ErrorCode::kNonFinitePosition: code = ApiErrorCode::kNonFinitePosition; break;
    case core::ErrorCode::kDegenerateFace: code = ApiErrorCode::kDegenerateFace; break;
    case core::ErrorCode::kNonManifoldEdge: code = ApiErrorCode::kNonManifoldEdge; break;
    case core::ErrorCode::kNonManifoldVertex: code = ApiErrorCode::kNonManifoldVertex; break;
    case core::ErrorCode::kInconsistentOrientation: code = ApiErrorCode::kInconsistentOrientation; break;
    case core::ErrorCode::kTooManyTerminals: code = ApiErrorCode::kTooManyTerminals; break;
    case core::ErrorCode::kTopologyViolation: code = ApiErrorCode::kTopologyViolation; break;
    case core::ErrorCode::kSolverFailed: code = ApiErrorCode::kSolverFailed; break;
    case core::ErrorCode::kCancelled: code = ApiErrorCode::kTimeout; break;
  }
  nlohmann::json details = nlohmann::json::object();
  if (!error.elements.empty()) details["elements"] = error.elements;
  for (const auto& [name, value] : error.values) details[name] = value;
  return ApiError{code, error.message, std::move(details)};
}

nlohmann::json error_body(const ApiError& error) {
  return {{"error", {{"code", code_name(error.code)}, {"message", error.message}, {"details", error.details}}}};
}

std::string error_text(const ApiError& error) {
  return error_body(error).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace seam::api
