// The service's error taxonomy: one enum, one exhaustive mapping to codes and HTTP statuses,
// one renderer of the JSON error body. Core errors map into it one to one.
#pragma once

#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "core/error.h"

namespace seam::api {

enum class ApiErrorCode {
  // 400: the request or the asset cannot be parsed.
  kMalformedRequest,    // bad multipart, bad JSON, bad base64, missing part
  kInvalidParameter,    // a parameter has the wrong type or an unknown value
  kMalformedAsset,      // malformed glTF/GLB/Draco/OFF/OBJ bytes or structure
  // 404 / 405 / 406: routing and negotiation.
  kNotFound,
  kMethodNotAllowed,
  kNotAcceptable,            // Accept refuses JSON (q=0) and accepts no other format we make
  // 408 / 411 / 413 / 415 / 431: HTTP framing, enforced before the handler reads the body.
  kRequestTimeout,            // the request did not arrive whole within --request-timeout-s
  kLengthRequired,            // a POST with neither Content-Length nor chunked framing
  kPayloadTooLarge,
  kUnsupportedMediaType,
  kHeadersTooLarge,           // more than 100 header fields or 64 KiB of request head
  // 422: a well-formed asset that cannot be processed.
  kNoTrianglePrimitive,       // mesh/primitive index missing, or not triangles
  kUnsupportedPrimitiveMode,  // points or lines
  kExternalUri,               // a buffer or image URI that is not a data URI
  kUnsupportedExtension,      // extensionsRequired names an extension the reader cannot honour
  kExtremumOutOfRange,        // an extremum index >= the primitive's vertex count
  kMeshTooLarge,              // more faces than the configured limit
  kEmptyMesh,
  kIndexOutOfRange,
  kNonFinitePosition,
  kDegenerateFace,
  kNonManifoldEdge,
  kNonManifoldVertex,
  kInconsistentOrientation,
  kTooManyTerminals,
  kTooManyExtrema,            // more extrema than --max-extrema
  kTopologyViolation,
  kSolverFailed,
  // 499: the client closed the connection before its answer (logged, never received).
  kClientClosed,
  // 503 / 504 / 500.
  kQueueFull,
  kOverloaded,                // the bytes-in-flight budget is spent; retry later
  kTimeout,
  kInternal,
};

struct ApiError {
  ApiErrorCode code = ApiErrorCode::kInternal;
  std::string message;
  nlohmann::json details = nlohmann::json::object();
};

/// The snake_case code string of the contract, e.g. "non_manifold_edge".
std::string_view code_name(ApiErrorCode code);
/// The HTTP status the contract assigns to the code.
int http_status(ApiErrorCode code);
/// Maps a core error (keeping its message; its elements go to details.elements, its named
/// values to details.<name>).
ApiError from_core(const core::Error& error);
/// The one JSON error body: {"error": {"code", "message", "details"}}.
nlohmann::json error_body(const ApiError& error);
/// error_body as text. Messages may quote client bytes that are not UTF-8 (a media type, a
/// field name): those are replaced by U+FFFD, never a throw (a 500 instead of the error).
std::string error_text(const ApiError& error);

inline ApiError make_api_error(ApiErrorCode code, std::string message,
                               nlohmann::json details = nlohmann::json::object()) {
  return ApiError{code, std::move(message), std::move(details)};
}

/// The asset readers' error: the bytes break the format (malformed_asset, HTTP 400).
inline ApiError malformed_asset(std::string message) {
  return make_api_error(ApiErrorCode::kMalformedAsset, std::move(message));
}

/// Either a value or an ApiError.
template <class T>
using ApiResult = core::Result<T, ApiError>;

}  // namespace seam::api
