// The strict request-head parser (server/http_head.h): every rule with its exact error code.
#include <doctest/doctest.h>

#include "server/http_head.h"

namespace seam_http_head_test {

using seam::api::ApiErrorCode;
using seam::server::find_head_end;
using seam::server::HeadLimits;
using seam::server::parse_request_head;
using seam::server::sanitized_head;

namespace {

ApiErrorCode code_of(std::string_view head, const HeadLimits& limits = {}) {
  auto parsed = parse_request_head(head, limits);
  REQUIRE_FALSE(parsed.ok());
  return parsed.error().code;
}

std::string fields(std::size_t n) {
  std::string out;
  for (std::size_t i = 0; i < n; ++i) out += "X-" + std::to_string(i) + ": v\r\n";
  return out;
}

}  // namespace

TEST_CASE("http_head: find_head_end finds the blank line, not before") {
  CHECK_FALSE(find_head_end("GET / HTTP/1.1\r\nHost: a\r\n").has_value());
  CHECK(find_head_end("GET / HTTP/1.1\r\n\r\nbody") == std::optional<std::size_t>(18));
  CHECK_FALSE(find_head_end("GET / HTTP/1.1\n\n").has_value());  // bare LF lines are not a head end
}

TEST_CASE("http_head: a valid head, its framing and its fields") {
  auto head = parse_request_head(
      "\r\nPOST /seam?method=mst HTTP/1.1\r\nHost: x\r\ncontent-length: 12\r\nContent-Length: 12\r\n"
      "Expect:  100-continue \r\nX-Request-Id: abc\r\n\r\n",
      {});
  REQUIRE(head.ok());
  CHECK(head->method == "POST");
  CHECK(head->target == "/seam?method=mst");
  CHECK(head->path == "/seam");
  CHECK(head->minor_version == 1);
  CHECK(head->content_length == std::optional<std::uint64_t>(12));
  CHECK_FALSE(head->chunked);
  CHECK(head->expects_continue());
  CHECK(head->has_body());
  CHECK(head->field("x-request-id") == std::optional<std::string_view>("abc"));
  CHECK_FALSE(head->field("Range").has_value());

  auto chunked = parse_request_head("POST /seam HTTP/1.1\r\nTransfer-Encoding: Chunked\r\n\r\n", {});
  REQUIRE(chunked.ok());
  CHECK(chunked->chunked);
  CHECK(chunked->has_body());
  auto get = parse_request_head("GET /healthz HTTP/1.0\r\n\r\n", {});
  REQUIRE(get.ok());
  CHECK(get->minor_version == 0);
  CHECK_FALSE(get->has_body());
}

TEST_CASE("http_head: request smuggling and malformed syntax are 400") {
  for (const char* bad : {
           "GET /x HTTP/1.1\r\nContent-Length : 5\r\n\r\n",              // space before the colon
           "GET /x HTTP/1.1\r\nX-A: b\r\n c\r\n\r\n",                    // obsolete line folding
           "POST /x HTTP/1.1\r\nContent-Length: 4\r\nTransfer-Encoding: chunked\r\n\r\n",
           "POST /x HTTP/1.1\r\nTransfer-Encoding: gzip\r\n\r\n",
           "POST /x HTTP/1.1\r\nTransfer-Encoding: chunked\r\nTransfer-Encoding: chunked\r\n\r\n",
           "POST /x HTTP/1.0\r\nTransfer-Encoding: chunked\r\n\r\n",
           "POST /x HTTP/1.1\r\nContent-Length: 4\r\nContent-Length: 5\r\n\r\n",
           "POST /x HTTP/1.1\r\nContent-Length: -4\r\n\r\n",
           "POST /x HTTP/1.1\r\nContent-Length: 0x10\r\n\r\n",
           "POST /x HTTP/1.1\r\nContent-Length: 99999999999999999999\r\n\r\n",
           "GET /x HTTP/1.1\r\nNo colon here\r\n\r\n",
           "GET /x HTTP/1.1\r\nX-A: b\rc\r\n\r\n",                        // bare CR
           "GET /x HTTP/1.1\r\nX-A: b\x01\r\n\r\n",                       // control byte
           "GET /x HTTP/1.1\r\n: empty name\r\n\r\n",
           "GET  /x HTTP/1.1\r\n\r\n", "GET /x  HTTP/1.1\r\n\r\n", "GET /x HTTP/2\r\n\r\n", "GET /x\r\n\r\n",
           "G(T /x HTTP/1.1\r\n\r\n", "GET /a\x7f HTTP/1.1\r\n\r\n", "GET /x HTTP/1.1\r\n\r",
       }) {
    CAPTURE(bad);
    CHECK(code_of(bad) == ApiErrorCode::kMalformedRequest);
  }
}

TEST_CASE("http_head: limits on fields, bytes and the declared length") {
  const HeadLimits limits{.max_head_bytes = 4096, .max_fields = 10, .max_field_bytes = 200, .max_body_bytes = 1000};
  CHECK(parse_request_head("GET / HTTP/1.1\r\n" + fields(10) + "\r\n", limits).ok());
  CHECK(code_of("GET / HTTP/1.1\r\n" + fields(11) + "\r\n", limits) == ApiErrorCode::kHeadersTooLarge);
  CHECK(code_of("GET / HTTP/1.1\r\nX: " + std::string(300, 'a') + "\r\n\r\n", limits) == ApiErrorCode::kHeadersTooLarge);
  CHECK(code_of("GET / HTTP/1.1\r\n" + std::string(5000, 'a') + "\r\n\r\n", limits) == ApiErrorCode::kHeadersTooLarge);
  CHECK(parse_request_head("POST / HTTP/1.1\r\nContent-Length: 1000\r\n\r\n", limits).ok());
  CHECK(code_of("POST / HTTP/1.1\r\nContent-Length: 1001\r\n\r\n", limits) == ApiErrorCode::kPayloadTooLarge);
}

TEST_CASE("http_head: TRACE and CONNECT are 405, Content-Encoding a 415") {
  CHECK(code_of("TRACE / HTTP/1.1\r\n\r\n") == ApiErrorCode::kMethodNotAllowed);
  CHECK(code_of("CONNECT a:1 HTTP/1.1\r\n\r\n") == ApiErrorCode::kMethodNotAllowed);
  CHECK(code_of("POST / HTTP/1.1\r\nContent-Length: 3\r\nContent-Encoding: gzip\r\n\r\n") == ApiErrorCode::kUnsupportedMediaType);
  CHECK(parse_request_head("POST / HTTP/1.1\r\nContent-Length: 3\r\nContent-Encoding: identity\r\n\r\n", {}).ok());
}

TEST_CASE("http_head: the sanitized head drops Range and parses to the same request") {
  auto head = parse_request_head(
      "GET /version HTTP/1.1\r\nHost: a\r\nRange: bytes=0-,0-\r\nIf-Range: x\r\nAccept: */*\r\n\r\n", {});
  REQUIRE(head.ok());
  const auto clean = sanitized_head(*head);
  CHECK(clean == "GET /version HTTP/1.1\r\nHost: a\r\nAccept: */*\r\n\r\n");
  auto again = parse_request_head(clean, {});
  REQUIRE(again.ok());
  CHECK(again->method == head->method);
  CHECK(again->target == head->target);
  CHECK(again->fields.size() == 2);
}

TEST_CASE("http_head: the path is the one the library routes on") {
  for (const auto& [target, path] : std::vector<std::pair<std::string, std::string>>{
           {"/seam?x=1", "/seam"}, {"/se%61m", "/seam"}, {"/seam#frag", "/seam"}, {"/a%2fb?c", "/a/b"},
           {"/bad%zz", "/bad%zz"}, {"/end%4", "/end%4"}}) {
    CAPTURE(target);
    auto head = parse_request_head("GET " + target + " HTTP/1.1\r\n\r\n", {});
    REQUIRE(head.ok());
    CHECK(head->path == path);
    CHECK(head->target == target);
  }
}

TEST_CASE("http_head: a field line is counted as the library reads it, and the target starts with '/'") {
  // sanitized "X: value\r\n" must fit cpp-httplib's 8192-byte line buffer (http_head_fuzz).
  CHECK(parse_request_head("GET / HTTP/1.1\r\nX: " + std::string(8187, 'a') + "\r\n\r\n", {}).ok());
  CHECK(code_of("GET / HTTP/1.1\r\nX: " + std::string(8188, 'a') + "\r\n\r\n") == ApiErrorCode::kHeadersTooLarge);
  CHECK(code_of("GET / HTTP/1.1\r\nX:" + std::string(8188, 'a') + "\r\n\r\n") == ApiErrorCode::kHeadersTooLarge);
  CHECK(code_of("GET ?/seam HTTP/1.1\r\n\r\n") == ApiErrorCode::kMalformedRequest);
  CHECK(code_of("POST http://x/seam HTTP/1.1\r\nContent-Length: 1\r\n\r\n") == ApiErrorCode::kMalformedRequest);
  CHECK(code_of("GET * HTTP/1.1\r\n\r\n") == ApiErrorCode::kMalformedRequest);
  CHECK(parse_request_head("OPTIONS * HTTP/1.1\r\n\r\n", {}).ok());
}

}  // namespace seam_http_head_test
