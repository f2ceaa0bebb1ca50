// The bridge between cpp-httplib's Request and the service's pure request layer
// (server/request.h), shared by the server and the multipart fuzz target so that the fuzzer
// walks the server's own code. Include after Eigen (httplib.h includes <resolv.h>).
#pragma once

#include <cstddef>
#include <optional>
#include <string>

#include "api/error.h"
#include "server/http_head.h"
#include "server/request.h"

#include <httplib.h>

namespace seam::server {

/// POST /seam's request as the library parsed it (headers, query, body, multipart parts),
/// decoded by decode_seam_request. Errors: as decode_seam_request. O(body).
api::ApiResult<SeamRequest> decode_seam_request(const httplib::Request& req);

/// The route-level refusal of a parsed head before any body byte is read: a form body on any
/// POST (the library would parse it before routing), and a media type POST /seam does not
/// take (415). nullopt admits the request. O(head).
std::optional<api::ApiError> refuse_before_body(const RequestHead& head);

/// The JSON error for a status the library set itself: 404 naming the routes, 413 naming
/// `max_body_bytes`, 415, 400 for an unparsable request, 500 internal, others malformed.
api::ApiError library_status_error(int status, const std::string& path, std::size_t max_body_bytes);

}  // namespace seam::server
