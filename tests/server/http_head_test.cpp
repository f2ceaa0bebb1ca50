// The strict request-head parser (server/http_head.h): every rule with its exact error code.
#include <doctest/doctest.h>

#include "server/http_head.h"

namespace seam_http_head_test {

using seam::api::ApiErrorCode;
using seam::server::ChunkedFraming;
using seam::server::closing_response_head;
using seam::server::find_head_end;
using seam::server::has_bare_lf;
using seam::server::HeadLimits;
using seam::server::http_date;
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

  auto chunked = parse_request_head("POST /seam HTTP/1.1\r\nHost: a\r\nTransfer-Encoding: Chunked\r\n\r\n", {});
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
           "GET /x HTTP/1.1\r\nHost: a\r\nContent-Length : 5\r\n\r\n",  // space before the colon
           "GET /x HTTP/1.1\r\nHost: a\r\nX-A: b\r\n c\r\n\r\n",        // obsolete line folding
           "POST /x HTTP/1.1\r\nHost: a\r\nContent-Length: 4\r\nTransfer-Encoding: chunked\r\n\r\n",
           "POST /x HTTP/1.1\r\nHost: a\r\nTransfer-Encoding: gzip\r\n\r\n",
           "POST /x HTTP/1.1\r\nHost: a\r\nTransfer-Encoding: chunked\r\nTransfer-Encoding: chunked\r\n\r\n",
           "POST /x HTTP/1.0\r\nTransfer-Encoding: chunked\r\n\r\n",
           "POST /x HTTP/1.1\r\nHost: a\r\nContent-Length: 4\r\nContent-Length: 5\r\n\r\n",
           "POST /x HTTP/1.1\r\nHost: a\r\nContent-Length: -4\r\n\r\n",
           "POST /x HTTP/1.1\r\nHost: a\r\nContent-Length: 0x10\r\n\r\n",
           "POST /x HTTP/1.1\r\nHost: a\r\nContent-Length: 99999999999999999999\r\n\r\n",
           "GET /x HTTP/1.1\r\nHost: a\r\nNo colon here\r\n\r\n",
           "GET /x HTTP/1.1\r\nHost: a\r\nX-A: b\rc\r\n\r\n",   // bare CR
           "GET /x HTTP/1.1\r\nHost: a\r\nX-A: b\x01\r\n\r\n",  // control byte
           "GET /x HTTP/1.1\r\nHost: a\r\n: empty name\r\n\r\n",
           "GET  /x HTTP/1.1\r\nHost: a\r\n\r\n",
           "GET /x  HTTP/1.1\r\nHost: a\r\n\r\n",
           "GET /x HTTP/2\r\n\r\n",
           "GET /x\r\n\r\n",
           "G(T /x HTTP/1.1\r\nHost: a\r\n\r\n",
           "GET /a\x7f HTTP/1.1\r\nHost: a\r\n\r\n",
           "GET /x HTTP/1.1\r\nHost: a\r\n\r",
       }) {
    CAPTURE(bad);
    CHECK(code_of(bad) == ApiErrorCode::kMalformedRequest);
  }
}

TEST_CASE("http_head: limits on fields, bytes and the declared length") {
  const HeadLimits limits{.max_head_bytes = 4096, .max_fields = 10, .max_field_bytes = 200, .max_body_bytes = 1000};
  CHECK(parse_request_head("GET / HTTP/1.1\r\nHost: a\r\n" + fields(9) + "\r\n", limits).ok());
  CHECK(code_of("GET / HTTP/1.1\r\nHost: a\r\n" + fields(10) + "\r\n", limits) == ApiErrorCode::kHeadersTooLarge);
  CHECK(code_of("GET / HTTP/1.1\r\nHost: a\r\nX: " + std::string(300, 'a') + "\r\n\r\n", limits) ==
        ApiErrorCode::kHeadersTooLarge);
  CHECK(code_of("GET / HTTP/1.1\r\nHost: a\r\n" + std::string(5000, 'a') + "\r\n\r\n", limits) ==
        ApiErrorCode::kHeadersTooLarge);
  CHECK(parse_request_head("POST / HTTP/1.1\r\nHost: a\r\nContent-Length: 1000\r\n\r\n", limits).ok());
  CHECK(code_of("POST / HTTP/1.1\r\nHost: a\r\nContent-Length: 1001\r\n\r\n", limits) ==
        ApiErrorCode::kPayloadTooLarge);
}

TEST_CASE("http_head: TRACE and CONNECT are 405, Content-Encoding a 415") {
  CHECK(code_of("TRACE / HTTP/1.1\r\nHost: a\r\n\r\n") == ApiErrorCode::kMethodNotAllowed);
  CHECK(code_of("CONNECT a:1 HTTP/1.1\r\nHost: a\r\n\r\n") == ApiErrorCode::kMethodNotAllowed);
  CHECK(code_of("POST / HTTP/1.1\r\nHost: a\r\nContent-Length: 3\r\nContent-Encoding: gzip\r\n\r\n") ==
        ApiErrorCode::kUnsupportedMediaType);
  CHECK(parse_request_head("POST / HTTP/1.1\r\nHost: a\r\nContent-Length: 3\r\nContent-Encoding: identity\r\n\r\n", {})
            .ok());
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

TEST_CASE(
    "http_head: the sanitized head ignores Expect in HTTP/1.0 and spells 100-continue and media types as the library "
    "matches them") {
  auto sanitize = [](std::string_view bytes) {
    auto head = parse_request_head(bytes, {});
    REQUIRE(head.ok());
    return sanitized_head(*head);
  };
  CHECK(sanitize("POST /seam HTTP/1.1\r\nHost: a\r\nExpect: 100-Continue\r\nContent-Length: 1\r\n\r\n") ==
        "POST /seam HTTP/1.1\r\nHost: a\r\nExpect: 100-continue\r\nContent-Length: 1\r\n\r\n");
  CHECK(sanitize("POST /seam HTTP/1.1\r\nHost: a\r\nexpect: 100-continue\r\n\r\n") ==
        "POST /seam HTTP/1.1\r\nHost: a\r\nexpect: 100-continue\r\n\r\n");
  CHECK(sanitize("POST /seam HTTP/1.0\r\nExpect: 100-continue\r\nContent-Length: 1\r\n\r\n") ==
        "POST /seam HTTP/1.0\r\nContent-Length: 1\r\n\r\n");
  // The media type and parameter names in lower case, parameter values (quoted ones whole,
  // with a quoted pair) as they are.
  CHECK(
      sanitize("POST /seam HTTP/1.1\r\nHost: a\r\nContent-Type: Multipart/Form-Data; Boundary=XyZ\r\n"
               "Content-Length: 1\r\n\r\n") ==
      "POST /seam HTTP/1.1\r\nHost: a\r\nContent-Type: multipart/form-data; boundary=XyZ\r\nContent-Length: 1\r\n\r\n");
  CHECK(sanitize("POST /seam HTTP/1.1\r\nHost: a\r\ncontent-type: Model/GLTF+JSON;CharSet=\"A;B=\\\"C\";X=Y\r\n\r\n") ==
        "POST /seam HTTP/1.1\r\nHost: a\r\ncontent-type: model/gltf+json;charset=\"A;B=\\\"C\";x=Y\r\n\r\n");
  // Other expectations pass as they are (the library ignores them).
  CHECK(sanitize("GET / HTTP/1.1\r\nHost: a\r\nExpect: something\r\n\r\n") ==
        "GET / HTTP/1.1\r\nHost: a\r\nExpect: something\r\n\r\n");
}

TEST_CASE("http_head: an answer head that closes the connection loses the Keep-Alive beside it, no other") {
  const std::string closing =
      "HTTP/1.1 408 Request Timeout\r\nConnection: close\r\nContent-Length: 2\r\n"
      "Keep-Alive: timeout=5, max=1000\r\nX-Request-Id: a\r\n\r\n";
  CHECK(closing_response_head(closing) ==
        "HTTP/1.1 408 Request Timeout\r\nConnection: close\r\nContent-Length: 2\r\nX-Request-Id: a\r\n\r\n");
  // Names and the token in any case, the value with blanks around it, the Keep-Alive first.
  CHECK(
      closing_response_head("HTTP/1.1 413 Payload Too Large\r\nkeep-alive: timeout=5\r\nCONNECTION:  Close \r\n\r\n") ==
      "HTTP/1.1 413 Payload Too Large\r\nCONNECTION:  Close \r\n\r\n");
  // Left as they are: a kept-alive answer, a closing one without Keep-Alive, a 100 Continue,
  // bytes that are not a head alone (a body follows, or the blank line is missing).
  CHECK_FALSE(closing_response_head("HTTP/1.1 200 OK\r\nKeep-Alive: timeout=5\r\nContent-Length: 0\r\n\r\n"));
  CHECK_FALSE(closing_response_head("HTTP/1.1 200 OK\r\nConnection: close\r\nContent-Length: 0\r\n\r\n"));
  CHECK_FALSE(closing_response_head("HTTP/1.1 100 Continue\r\n\r\n"));
  CHECK_FALSE(closing_response_head(closing + "{}"));
  CHECK_FALSE(closing_response_head("HTTP/1.1 200 OK\r\nConnection: close\r\n\r\nKeep-Alive: x\r\n\r\n"));
  CHECK_FALSE(closing_response_head(closing.substr(0, closing.size() - 2)));
  CHECK_FALSE(closing_response_head("{\"error\":{}}\r\n\r\n"));
  CHECK_FALSE(closing_response_head(""));
  // Connection: keep-alive, or close as part of another token, is no close.
  CHECK_FALSE(closing_response_head("HTTP/1.1 200 OK\r\nConnection: keep-alive\r\nKeep-Alive: timeout=5\r\n\r\n"));
  CHECK_FALSE(closing_response_head("HTTP/1.1 200 OK\r\nConnection: closed\r\nKeep-Alive: timeout=5\r\n\r\n"));
}

TEST_CASE("http_head: a Connection field asks to close in any case and anywhere in its list") {
  auto asks = [](std::string_view fields) {
    auto head = parse_request_head("GET / HTTP/1.1\r\nHost: a\r\n" + std::string(fields) + "\r\n", {});
    REQUIRE(head.ok());
    return head->asks_to_close();
  };
  CHECK(asks("Connection: close\r\n"));
  CHECK(asks("Connection: Close\r\n"));
  CHECK(asks("connection: CLOSE\r\n"));
  CHECK(asks("Connection: keep-alive, close\r\n"));
  CHECK(asks("Connection: TE ,close , foo\r\n"));
  CHECK(asks("Connection: keep-alive\r\nConnection: close\r\n"));
  CHECK_FALSE(asks(""));
  CHECK_FALSE(asks("Connection: keep-alive\r\n"));
  CHECK_FALSE(asks("Connection: closed, enclose\r\n"));
  CHECK_FALSE(asks("X-Connection: close\r\n"));
}

TEST_CASE("http_head: the Date field's IMF-fixdate") {
  using std::chrono::system_clock;
  CHECK(http_date(system_clock::from_time_t(784111777)) == "Sun, 06 Nov 1994 08:49:37 GMT");  // RFC 9110's
  CHECK(http_date(system_clock::from_time_t(0)) == "Thu, 01 Jan 1970 00:00:00 GMT");
  CHECK(http_date(system_clock::from_time_t(951782400)) == "Tue, 29 Feb 2000 00:00:00 GMT");
  CHECK(http_date(system_clock::from_time_t(1796428799)) == "Fri, 04 Dec 2026 23:59:59 GMT");
}

TEST_CASE("http_head: the path is the one the library routes on") {
  for (const auto& [target, path] : std::vector<std::pair<std::string, std::string>>{
           {"/seam?x=1", "/seam"}, {"/se%61m", "/seam"}, {"/seam#frag", "/seam"}, {"/a%2fb?c", "/a/b"},
           {"/bad%zz", "/bad%zz"}, {"/end%4", "/end%4"}}) {
    CAPTURE(target);
    auto head = parse_request_head("GET " + target + " HTTP/1.1\r\nHost: a\r\n\r\n", {});
    REQUIRE(head.ok());
    CHECK(head->path == path);
    CHECK(head->target == target);
  }
}

TEST_CASE("http_head: a field line is counted as the library reads it, and the target starts with '/'") {
  // sanitized "X: value\r\n" must fit cpp-httplib's 8192-byte line buffer (http_head_fuzz).
  CHECK(parse_request_head("GET / HTTP/1.1\r\nHost: a\r\nX: " + std::string(8187, 'a') + "\r\n\r\n", {}).ok());
  CHECK(code_of("GET / HTTP/1.1\r\nHost: a\r\nX: " + std::string(8188, 'a') + "\r\n\r\n") ==
        ApiErrorCode::kHeadersTooLarge);
  CHECK(code_of("GET / HTTP/1.1\r\nHost: a\r\nX:" + std::string(8188, 'a') + "\r\n\r\n") ==
        ApiErrorCode::kHeadersTooLarge);
  CHECK(code_of("GET ?/seam HTTP/1.1\r\nHost: a\r\n\r\n") == ApiErrorCode::kMalformedRequest);
  CHECK(code_of("GET * HTTP/1.1\r\nHost: a\r\n\r\n") == ApiErrorCode::kMalformedRequest);
  CHECK(parse_request_head("OPTIONS * HTTP/1.1\r\nHost: a\r\n\r\n", {}).ok());
}

TEST_CASE("http_head: an absolute request target is taken in its origin form, with a host and no user") {
  for (const auto& [target, origin] :
       std::vector<std::pair<std::string, std::string>>{{"http://x/seam?method=mst", "/seam?method=mst"},
                                                        {"HTTPS://x:8080/se%61m", "/se%61m"},
                                                        {"http://x", "/"},
                                                        {"http://x?q=1", "/?q=1"},
                                                        {"http://[::1]:80//healthz", "//healthz"}}) {
    CAPTURE(target);
    auto head = parse_request_head("POST " + target + " HTTP/1.1\r\nHost: a\r\nContent-Length: 1\r\n\r\n", {});
    REQUIRE(head.ok());
    CHECK(head->target == origin);
    CHECK(head->path == seam::server::parse_request_head("GET " + origin + " HTTP/1.1\r\nHost: a\r\n\r\n", {})->path);
    CHECK(sanitized_head(*head).starts_with("POST " + origin + " HTTP/1.1\r\n"));
  }
  for (const char* target : {"http:///seam", "http://user@x/seam", "ftp://x/seam", "http:/x/seam", "x/seam"}) {
    CAPTURE(target);
    CHECK(code_of(std::string("GET ") + target + " HTTP/1.1\r\nHost: a\r\n\r\n") == ApiErrorCode::kMalformedRequest);
  }
}

TEST_CASE("http_head: exactly one Host in HTTP/1.1, at most one in HTTP/1.0") {
  CHECK(code_of("GET / HTTP/1.1\r\n\r\n") == ApiErrorCode::kMalformedRequest);
  CHECK(code_of("GET / HTTP/1.1\r\nHost: a\r\nhost: b\r\n\r\n") == ApiErrorCode::kMalformedRequest);
  CHECK(code_of("GET / HTTP/1.0\r\nHost: a\r\nHost: a\r\n\r\n") == ApiErrorCode::kMalformedRequest);
  CHECK(parse_request_head("GET / HTTP/1.0\r\n\r\n", {}).ok());
  CHECK(parse_request_head("GET / HTTP/1.1\r\nHOST: a\r\n\r\n", {}).ok());
}

TEST_CASE("http_head: a bare LF is found where the scan starts, and CRLF is not one") {
  CHECK_FALSE(has_bare_lf("GET / HTTP/1.1\r\nHost: a\r\n"));
  CHECK(has_bare_lf("GET / HTTP/1.1\nHost"));
  CHECK(has_bare_lf("\nGET"));
  const std::string_view trickled = "GET /\r\nX: a\n";
  CHECK(has_bare_lf(trickled, 8));  // only the new bytes are scanned
  CHECK_FALSE(has_bare_lf(trickled, trickled.size()));
  CHECK_FALSE(has_bare_lf("GET /\r\n", 7));  // the LF at 7 has its CR at 6, before the scan
}

namespace {

// Feeds `body` to a fresh checker in pieces of `piece` bytes; returns the checker and how many
// bytes it took.
std::pair<ChunkedFraming, std::size_t> framed(std::string_view body, std::size_t piece) {
  ChunkedFraming framing;
  std::size_t used = 0;
  while (used < body.size() && !framing.done() && !framing.failed()) {
    const auto n = framing.feed(body.substr(used, piece));
    used += n;
    if (n < std::min(piece, body.size() - (used - n))) break;  // stopped inside the piece
  }
  return {framing, used};
}

}  // namespace

TEST_CASE("http_head: a chunked body ends at its last CRLF, in one piece or byte by byte") {
  const std::string body = "3\r\nabc\r\nA;name=\"v\" \r\n0123456789\r\n000\r\n\r\n";
  const std::string next = "GET /healthz HTTP/1.1\r\nHost: a\r\n\r\n";
  for (const std::size_t piece : {std::size_t{1}, std::size_t{2}, std::size_t{7}, std::size_t{4096}}) {
    CAPTURE(piece);
    const auto [framing, used] = framed(body + next, piece);
    CHECK(framing.done());
    CHECK_FALSE(framing.failed());
    CHECK(used == body.size());  // not a byte of the next request
    CHECK(framing.error().empty());
  }
  const auto [partial, used] = framed(body.substr(0, body.size() - 1), 4096);
  CHECK_FALSE(partial.done());
  CHECK_FALSE(partial.failed());
  CHECK(used == body.size() - 1);
}

TEST_CASE("http_head: every chunked framing error stops at the byte that breaks it") {
  struct Case {
    std::string body;
    std::size_t taken;  // bytes accepted before the one that breaks the framing
    std::string why;
  };
  for (const auto& c : std::vector<Case>{
           {"zz\r\nGET /version HTTP/1.1\r\n", 0, "start with the size"},  // the audit's desync
           {"3\r\nabcXX0\r\n\r\n", 6, "data must end with CRLF"},          // 0.11.4 took "abc"
           {"3\r\nabc\rX", 7, "data must end with CRLF"},
           {"3\nabc\r\n", 1, "size line must end with CRLF"},
           {"\r\n", 0, "start with the size"},
           {"-3\r\n", 0, "start with the size"},
           {"3x\r\n", 1, "hex digits"},
           {"1000000000000000\r\n", 15, "15 hex digits"},
           {"3;a\x01\r\n", 3, "control byte"},
           {"3;a\nabc", 3, "control byte"},
           {"0\r\nX-Trailer: 1\r\n\r\n", 3, "trailer fields"},
           {"0\r\n\rX", 4, "followed by CRLF"},
       }) {
    CAPTURE(c.body);
    for (const std::size_t piece : {std::size_t{1}, std::size_t{4096}}) {
      const auto [framing, used] = framed(c.body, piece);
      CHECK(framing.failed());
      CHECK_FALSE(framing.done());
      CHECK(used == c.taken);
      CHECK(framing.error().find(c.why) != std::string::npos);
      CHECK(framing.error().rfind("malformed chunked body: ", 0) == 0);
    }
  }
}

}  // namespace seam_http_head_test
