// Strict parsing of an HTTP/1.x request head (RFC 9112 §2-3, §5-7), before cpp-httplib sees
// it. Pure (no sockets): the connection front (server/http_front.h) reads the head bytes with
// its own deadline and limits, parses them here, refuses what the service must not read
// further, and hands the library a sanitized copy. Kept apart so that every rule is unit
// tested and fuzzed (tests/fuzz/http_head_fuzz.cpp).
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "api/error.h"

namespace seam::server {

/// The limits a head is checked against. 0 is not a valid value for any of them.
struct HeadLimits {
  std::size_t max_head_bytes = 64u << 10;  ///< request line + header fields + CRLFs; then 431
  std::size_t max_fields = 100;            ///< header fields; then 431
  std::size_t max_field_bytes = 8192;      ///< one field line with its CRLF (cpp-httplib's own line limit); then 431
  std::size_t max_body_bytes = 256u << 20; ///< a larger Content-Length is a 413
};

/// One parsed request head. Field names keep their spelling; lookups ignore case.
struct RequestHead {
  std::string method;  ///< e.g. "POST"
  /// The request-target in origin form, e.g. "/seam?method=mst" (an absolute one such as
  /// "http://host/seam?method=mst" is turned into it), or "*" for OPTIONS.
  std::string target;
  std::string path;    ///< the path the library routes on: target up to '?' or '#', percent-decoded
  int minor_version = 1;  ///< HTTP/1.<minor_version>: 0 or 1
  std::vector<std::pair<std::string, std::string>> fields;
  std::optional<std::uint64_t> content_length;  ///< from Content-Length
  bool chunked = false;                          ///< Transfer-Encoding: chunked

  /// The first value of the field (case-insensitive name), or nullopt.
  std::optional<std::string_view> field(std::string_view name) const;
  /// True when the client expects "100 Continue" before sending the body.
  bool expects_continue() const;
  /// True when a Connection field lists the "close" option (RFC 9110 §7.6.1: a comma-separated
  /// list of tokens, compared case-insensitively), e.g. "Close" or "keep-alive, close". The
  /// front then ends the connection after the answer, which says `Connection: close`
  /// (cpp-httplib 0.11 only knows the exact value "close").
  bool asks_to_close() const;
  /// True when the request announces a body (a length > 0 or chunked framing).
  bool has_body() const { return chunked || content_length.value_or(0) > 0; }
};

/// Where the head ends in `bytes`: the offset just past the blank line ("\r\n\r\n"), or
/// nullopt when the head is not complete yet. Leading empty lines (RFC 9112 §2.2) are part of
/// the head. O(n).
std::optional<std::size_t> find_head_end(std::string_view bytes);

/// True when `bytes` hold an LF at or after offset `from` that no CR precedes: a head that can
/// never end with the blank line find_head_end looks for, refused at once (400) rather than
/// left to time out. O(bytes.size() - from), so a head trickled in is scanned once.
bool has_bare_lf(std::string_view bytes, std::size_t from = 0);

/// Parses a complete head (as delimited by find_head_end) strictly:
/// - request line `METHOD SP target SP HTTP/1.0|HTTP/1.1`, one space each, no control bytes;
/// - every field `name: value` with a token name and nothing between name and colon (a space
///   there is request smuggling, RFC 9112 §5.1), no obsolete line folding, CRLF line ends;
/// - Content-Length digits only, repeated values equal; Transfer-Encoding only `chunked`,
///   never together with Content-Length (§6.3);
/// - exactly one Host field in an HTTP/1.1 request, at most one in HTTP/1.0 (§3.2).
/// Errors: kHeadersTooLarge (431) above the limits; kPayloadTooLarge (413) when the declared
/// length exceeds max_body_bytes; kMalformedRequest (400) for every syntax rule above;
/// kMethodNotAllowed (405) for TRACE and CONNECT, which the service never routes;
/// kUnsupportedMediaType (415) for a Content-Encoding other than identity (the service does
/// not inflate bodies: a 486 KB gzip body can claim 500 MB).
/// Complexity: O(head bytes).
api::ApiResult<RequestHead> parse_request_head(std::string_view head, const HeadLimits& limits);

/// A chunked body (RFC 9112 §7.1) checked byte by byte on its way to cpp-httplib, which decodes
/// it itself but reads past framing errors (0.11.4 takes "3\r\nabcXX0\r\n\r\n" as the body
/// "abc") and keeps the connection open after the ones it does refuse, so that the rest of a
/// broken body would be read as the next request (request smuggling). The front serves the
/// library no byte this refuses and none past the message's end, and closes a connection whose
/// body did not end here. Accepts: hex chunk sizes (at most 15 digits), chunk extensions
/// (`;name[=value]`: visible bytes, spaces and tabs), CRLF after every size line and every
/// chunk's data, and the final CRLF. Trailer fields are refused with a clear message (the
/// library would refuse them with a vague one).
class ChunkedFraming {
 public:
  /// Consumes the prefix of `bytes` that belongs to the message: all of it, or fewer when the
  /// message ended (done()) or a byte broke the framing (failed(); the count excludes it).
  /// O(bytes); chunk data is skipped, not scanned.
  std::size_t feed(std::string_view bytes);
  bool done() const { return state_ == State::kDone; }
  bool failed() const { return state_ == State::kFailed; }
  /// What broke the framing (empty unless failed()), e.g. "a chunk's data must end with CRLF".
  const std::string& error() const { return error_; }

 private:
  enum class State { kSize, kExtension, kSizeLf, kData, kDataCr, kDataLf, kEndCr, kEndLf, kDone, kFailed };
  bool fail(std::string why);
  bool step(char c);  // one byte of a size line or a CRLF; false when it failed

  State state_ = State::kSize;
  std::uint64_t size_ = 0;  // of the chunk whose size line is read, then its data left
  int digits_ = 0;
  std::string error_;
};

/// The head handed to cpp-httplib: the request line and fields of `head` minus the ones the
/// front has dealt with or refuses to honour (Range and If-Range: a range request never
/// turns an answer into a larger one; Expect in HTTP/1.0), with a 100-continue expectation
/// in any case, and Content-Type's type, subtype and parameter names, spelt in the lower case
/// the library matches (its parameter values as they are). Ends with the blank line.
/// O(head bytes).
std::string sanitized_head(const RequestHead& head);

/// A response head as cpp-httplib 0.11 writes it (status line to blank line, one write), with
/// its `Keep-Alive` fields dropped when the head also says `Connection: close`: the library adds
/// Keep-Alive to every answer to a request that did not ask to close, even one whose handler
/// closes the connection (the 408, 413 and 503 the front stops a body with), which then
/// contradicted itself. nullopt when there is nothing to drop (the bytes go out as they are:
/// other heads, 1xx heads, anything that is not a head). Names and `close` are matched
/// case-insensitively. O(head bytes).
std::optional<std::string> closing_response_head(std::string_view bytes);

/// `t` as an HTTP date (RFC 9110 §5.6.7, IMF-fixdate in GMT), e.g. "Sun, 06 Nov 1994 08:49:37
/// GMT", for the Date field every answer carries (§6.6.1: a server with a clock must send it).
/// Independent of the locale. O(1).
std::string http_date(std::chrono::system_clock::time_point t);

}  // namespace seam::server
