// libFuzzer target for the connection front's head parser (server/http_head.h): the input is
// the byte stream of one connection. Like the front, the target cuts heads with
// find_head_end, parses each with parse_request_head (under the production limits and under
// tight ones, so that the 431/413 paths are reached by small inputs), skips a Content-Length
// body and goes on with the next pipelined head (at most 8).
//
// Besides "no crash, no sanitizer report, no exception", every violation of these properties
// is a __builtin_trap (a crash for libFuzzer):
// - without a head end, parse_request_head fails;
// - a refusal is one of the contract's codes (400, 405, 413, 415, 431), and a head longer
//   than max_head_bytes is always a 431;
// - an accepted head holds its limits: content_length <= max_body_bytes, at most max_fields
//   fields, each field line at most max_field_bytes; a token method other than TRACE and
//   CONNECT; never Content-Length with chunked; chunked only on HTTP/1.1; names are tokens,
//   values trimmed and free of CR, LF and NUL;
// - sanitized_head(head) is one complete head that parses again with the same method,
//   target, path, version, content_length and chunked and the same fields minus Range and If-Range
//   (and Expect in HTTP/1.0; a 100-continue expectation in any case spelt in lower case;
//   Content-Type changed in letter case only, its media type in lower case),
//   and sanitizing that again gives the same bytes. The re-parse allows one byte more per
//   field line and per field: `name:value` is re-spelt `name: value`, so a head at the limits
//   may grow by that much (the front hands it to the library, which does not apply
//   max_head_bytes; see docs/fuzzing.md for the library's own line limit);
// - an accepted HTTP/1.1 head has exactly one Host field, an HTTP/1.0 one at most one;
// - a head with a bare LF before its end is refused whole (has_bare_lf agrees with the parser);
// - after a chunked head, ChunkedFraming takes the same bytes to the same verdict whether fed
//   at once or byte by byte, never takes a byte past the message's end, and a message it
//   calls done ends with "0" (and extensions) CRLF CRLF; the next head starts after it.
// - the same bytes as an answer head (closing_response_head, which the front applies to what
//   the library writes): a head it changes loses exactly its Keep-Alive lines, keeps every
//   other byte in order, still ends with its blank line, and is left alone the second time.
#include <algorithm>
#include <cctype>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "server/http_head.h"

namespace {

using seam::api::ApiErrorCode;
using seam::server::ChunkedFraming;
using seam::server::closing_response_head;
using seam::server::find_head_end;
using seam::server::has_bare_lf;
using seam::server::HeadLimits;
using seam::server::parse_request_head;
using seam::server::RequestHead;
using seam::server::sanitized_head;

void check(bool property) {
  if (!property) __builtin_trap();
}

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const auto x = static_cast<unsigned char>(a[i]);
    const auto y = static_cast<unsigned char>(b[i]);
    if (std::tolower(x) != std::tolower(y)) return false;
  }
  return true;
}

bool is_tchar(char c) {
  const auto u = static_cast<unsigned char>(c);
  return std::isalnum(u) || std::string_view("!#$%&'*+-.^_`|~").find(c) != std::string_view::npos;
}

bool is_token(std::string_view s) {
  if (s.empty()) return false;
  for (const char c : s) {
    if (!is_tchar(c)) return false;
  }
  return true;
}

bool same_head(const RequestHead& a, const RequestHead& b) {
  return a.method == b.method && a.target == b.target && a.path == b.path && a.minor_version == b.minor_version &&
         a.content_length == b.content_length && a.chunked == b.chunked;
}

void check_accepted(std::string_view bytes, const RequestHead& head, const HeadLimits& limits) {
  check(bytes.size() <= limits.max_head_bytes);
  check(!head.content_length || *head.content_length <= limits.max_body_bytes);
  check(head.fields.size() <= limits.max_fields);
  check(is_token(head.method) && head.method != "TRACE" && head.method != "CONNECT");
  check(head.minor_version == 0 || head.minor_version == 1);
  check(!(head.chunked && head.content_length));
  check(!head.chunked || head.minor_version == 1);
  check(!head.target.empty());  // the path (http_head.h defines it) is compared on re-parsing
  check(head.has_body() == (head.chunked || head.content_length.value_or(0) > 0));
  const auto hosts =
      std::count_if(head.fields.begin(), head.fields.end(), [](const auto& f) { return iequals(f.first, "Host"); });
  check(head.minor_version == 1 ? hosts == 1 : hosts <= 1);
  check(!has_bare_lf(bytes));
  for (const auto& [name, value] : head.fields) {
    check(is_token(name));
    check(name.size() + 1 + value.size() <= limits.max_field_bytes);
    check(value.find_first_of(std::string_view("\r\n\0", 3)) == std::string::npos);
    check(value.empty() || (value.front() != ' ' && value.front() != '\t' && value.back() != ' ' && value.back() != '\t'));
    const auto first = head.field(name);
    check(first.has_value());
  }

  const std::string sanitized = sanitized_head(head);
  check(find_head_end(sanitized) == sanitized.size());
  HeadLimits relaxed = limits;
  relaxed.max_head_bytes += head.fields.size();
  relaxed.max_field_bytes += 1;
  auto again = parse_request_head(sanitized, relaxed);
  check(again.ok());
  check(same_head(head, *again));
  std::size_t kept = 0;
  for (const auto& [name, value] : head.fields) {
    if (iequals(name, "Range") || iequals(name, "If-Range")) continue;
    if (iequals(name, "Expect") && head.minor_version == 0) continue;
    const std::string_view expected =
        iequals(name, "Expect") && iequals(value, "100-continue") ? std::string_view("100-continue") : value;
    check(kept < again->fields.size() && again->fields[kept].first == name);
    const std::string_view got = again->fields[kept].second;
    if (iequals(name, "Content-Type")) {
      // Only letter case changes, and the media type before any parameter is in lower case.
      check(iequals(got, value));
      const std::string_view type = got.substr(0, got.find(';'));
      check(std::none_of(type.begin(), type.end(), [](char c) { return std::isupper(static_cast<unsigned char>(c)); }));
    } else {
      check(got == expected);
    }
    ++kept;
  }
  check(kept == again->fields.size());
  check(sanitized_head(*again) == sanitized);

  // Under the limits themselves the sanitized head may only fail by its size.
  auto strict = parse_request_head(sanitized, limits);
  check(strict.ok() || strict.error().code == ApiErrorCode::kHeadersTooLarge);
}

// Parses one head under `limits`; returns the head when accepted.
std::optional<RequestHead> check_head(std::string_view bytes, const HeadLimits& limits) {
  auto parsed = parse_request_head(bytes, limits);
  if (!parsed.ok()) {
    const auto code = parsed.error().code;
    check(code == ApiErrorCode::kMalformedRequest || code == ApiErrorCode::kHeadersTooLarge ||
          code == ApiErrorCode::kPayloadTooLarge || code == ApiErrorCode::kMethodNotAllowed ||
          code == ApiErrorCode::kUnsupportedMediaType);
    check(!parsed.error().message.empty());
    if (bytes.size() > limits.max_head_bytes) check(code == ApiErrorCode::kHeadersTooLarge);
    return std::nullopt;
  }
  check_accepted(bytes, *parsed, limits);
  return std::move(parsed).value();
}

// The chunked body at the front of `stream`: its length when the checker calls it done,
// nullopt when it failed or wants more. Fed whole and byte by byte, with the same verdict.
std::optional<std::size_t> check_chunked(std::string_view stream) {
  ChunkedFraming whole;
  const auto used = whole.feed(stream);
  check(used <= stream.size());
  check(!(whole.done() && whole.failed()));
  check(whole.failed() == !whole.error().empty());
  check(whole.done() || whole.failed() || used == stream.size());
  ChunkedFraming bytewise;
  std::size_t fed = 0;
  while (fed < stream.size() && !bytewise.done() && !bytewise.failed()) fed += bytewise.feed(stream.substr(fed, 1));
  check(fed == used && bytewise.done() == whole.done() && bytewise.failed() == whole.failed());
  check(bytewise.error() == whole.error());
  if (!whole.done()) return std::nullopt;
  const auto message = stream.substr(0, used);
  check(used >= 5 && message.substr(used - 4) == "\r\n\r\n");
  check(whole.feed(stream.substr(used)) == 0);  // nothing after the end
  return used;
}

}  // namespace

// closing_response_head's properties; the oracle drops the Keep-Alive lines by its own scan.
void check_response_head(std::string_view bytes) {
  const auto out = closing_response_head(bytes);
  if (!out) return;
  check(bytes.starts_with("HTTP/1.") && out->ends_with("\r\n\r\n") && out->size() < bytes.size());
  std::string expected;
  for (std::size_t at = 0; at < bytes.size();) {
    const std::size_t end = std::min(bytes.find("\r\n", at), bytes.size() - 2) + 2;
    const std::string_view line = bytes.substr(at, end - at);
    const std::size_t colon = line.find(':');
    if (at == 0 || colon == std::string_view::npos || !iequals(line.substr(0, colon), "Keep-Alive")) expected += line;
    at = end;
  }
  check(*out == expected);
  check(!closing_response_head(*out));
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string_view stream(reinterpret_cast<const char*>(data), size);
  check_response_head(stream);
  const HeadLimits production;
  HeadLimits tight;
  tight.max_head_bytes = 512;
  tight.max_fields = 6;
  tight.max_field_bytes = 64;
  tight.max_body_bytes = 4096;

  for (int request = 0; request < 8; ++request) {
    const auto end = find_head_end(stream);
    if (!end) {
      // An incomplete head never parses.
      check(!parse_request_head(stream, production).ok());
      check(!parse_request_head(stream, tight).ok());
      return 0;
    }
    check(*end >= 4 && *end <= stream.size() && stream.substr(*end - 4, 4) == "\r\n\r\n");
    check(stream.substr(0, *end - 1).find("\r\n\r\n") == std::string_view::npos);
    const auto head_bytes = stream.substr(0, *end);
    stream.remove_prefix(*end);
    check_head(head_bytes, tight);
    const auto head = check_head(head_bytes, production);
    if (!head) return 0;  // the front answers and closes
    if (head->chunked) {
      const auto body = check_chunked(stream);
      if (!body) return 0;  // refused or incomplete: the front closes
      stream.remove_prefix(*body);
      continue;
    }
    const auto body = static_cast<std::size_t>(std::min<std::uint64_t>(head->content_length.value_or(0), stream.size()));
    stream.remove_prefix(body);
  }
  return 0;
}
