#include "server/http_head.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cstdio>
#include <ctime>

namespace seam::server {
namespace {

using api::ApiErrorCode;
using api::make_api_error;

bool iequals(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
         });
}

// RFC 9110 §5.6.2 tchar.
bool is_tchar(char c) {
  const auto u = static_cast<unsigned char>(c);
  if (std::isalnum(u)) return true;
  constexpr std::string_view kExtra = "!#$%&'*+-.^_`|~";
  return kExtra.find(c) != std::string_view::npos;
}

bool is_token(std::string_view s) { return !s.empty() && std::all_of(s.begin(), s.end(), is_tchar); }

// Field values: visible ASCII, obs-text (>= 0x80), space and tab; no other control bytes.
bool is_field_value(std::string_view s) {
  return std::all_of(s.begin(), s.end(), [](char c) {
    const auto u = static_cast<unsigned char>(c);
    return u == '\t' || u >= 0x20 ? u != 0x7f : false;
  });
}

std::string_view trim_ows(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

// A Content-Type value with its type, subtype and parameter names in lower case (RFC 9110
// §8.3.1: they are case-insensitive) and every other byte kept, parameter values (quoted ones
// whole) included: cpp-httplib 0.11 matches "multipart/form-data" and "boundary=" exactly.
std::string lowercase_media_type(std::string_view value) {
  std::string out(value);
  enum class Part { kType, kName, kValue } part = Part::kType;
  bool quoted = false;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const char c = out[i];
    if (quoted) {
      if (c == '\\')
        ++i;  // a quoted pair: the next byte is literal
      else if (c == '"')
        quoted = false;
      continue;
    }
    if (c == ';') {
      part = Part::kName;
    } else if (part == Part::kName && c == '=') {
      part = Part::kValue;
    } else if (part == Part::kValue && c == '"') {
      quoted = true;
    } else if (part != Part::kValue) {
      out[i] = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    }
  }
  return out;
}

// The path the library routes on: the target up to '?' or '#', percent-decoded (as
// cpp-httplib's decode_url does), so that "/se%61m" is checked as the "/seam" it reaches.
std::string routed_path(std::string_view target) {
  target = target.substr(0, std::min(target.find('?'), target.find('#')));
  std::string out;
  out.reserve(target.size());
  auto hex = [](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  };
  for (std::size_t i = 0; i < target.size(); ++i) {
    if (target[i] == '%' && i + 2 < target.size() && hex(target[i + 1]) >= 0 && hex(target[i + 2]) >= 0) {
      out += static_cast<char>(hex(target[i + 1]) * 16 + hex(target[i + 2]));
      i += 2;
    } else {
      out += target[i];
    }
  }
  return out;
}

api::ApiError malformed(std::string message) {
  return make_api_error(ApiErrorCode::kMalformedRequest, "malformed HTTP request: " + std::move(message));
}

api::ApiResult<core::Ok> parse_request_line(std::string_view line, RequestHead& out) {
  const auto sp1 = line.find(' ');
  const auto sp2 = sp1 == std::string_view::npos ? sp1 : line.find(' ', sp1 + 1);
  if (sp2 == std::string_view::npos || line.find(' ', sp2 + 1) != std::string_view::npos) {
    return malformed("the request line must be 'METHOD SP target SP HTTP/1.1'");
  }
  const auto method = line.substr(0, sp1);
  const auto target = line.substr(sp1 + 1, sp2 - sp1 - 1);
  const auto version = line.substr(sp2 + 1);
  if (!is_token(method)) return malformed("the method is not a token");
  if (method == "TRACE" || method == "CONNECT") {
    return make_api_error(ApiErrorCode::kMethodNotAllowed,
                          std::string(method) + " is not served; the service takes GET, HEAD, POST and OPTIONS",
                          {{"allow", "GET, HEAD, POST, OPTIONS"}});
  }
  if (target.empty() || !std::all_of(target.begin(), target.end(), [](char c) {
        const auto u = static_cast<unsigned char>(c);
        return u > 0x20 && u != 0x7f;
      })) {
    return malformed("the request target is empty or holds spaces or control bytes");
  }
  // Origin form ("/path?query"), "*" for OPTIONS, or the absolute form a server must also take
  // (RFC 9112 §3.2.2), turned into the origin form here: the library only ever sees a target
  // that starts with '/' (it would route "?/seam" as "/seam" without the checks made on the
  // path: http_head_fuzz, multipart_fuzz). The Host field is not used for anything.
  std::string origin(target);
  if (const auto scheme = target.find("://");
      scheme != std::string_view::npos &&
      (iequals(target.substr(0, scheme), "http") || iequals(target.substr(0, scheme), "https"))) {
    const auto rest = target.substr(scheme + 3);
    const auto authority = rest.substr(0, rest.find_first_of("/?#"));
    if (authority.empty() || authority.find('@') != std::string_view::npos) {
      return malformed("an absolute request target needs a host and no user information");
    }
    const auto tail = rest.substr(authority.size());
    origin = tail.starts_with('/') ? std::string(tail) : "/" + std::string(tail);
  } else if (!(target.starts_with('/') || (target == "*" && method == "OPTIONS"))) {
    return malformed("the request target must be a path starting with '/' or an absolute http(s) URI");
  }
  if (version == "HTTP/1.1") {
    out.minor_version = 1;
  } else if (version == "HTTP/1.0") {
    out.minor_version = 0;
  } else {
    return malformed("only HTTP/1.0 and HTTP/1.1 are served");
  }
  out.method = method;
  out.path = routed_path(origin);
  out.target = std::move(origin);
  return core::Ok{};
}

api::ApiResult<std::uint64_t> parse_content_length(std::string_view value) {
  std::uint64_t n = 0;
  if (value.empty() || value.size() > 19 || !std::all_of(value.begin(), value.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    return malformed("Content-Length must be a decimal number");
  }
  std::from_chars(value.data(), value.data() + value.size(), n);
  return n;
}

// Framing fields (RFC 9112 §6): the body's length is known before any of it is read.
api::ApiResult<core::Ok> check_framing(RequestHead& out, const HeadLimits& limits) {
  bool has_te = false;
  for (const auto& [name, value] : out.fields) {
    if (iequals(name, "Content-Length")) {
      SEAM_TRY(const auto n, parse_content_length(value));
      if (out.content_length && *out.content_length != n) return malformed("Content-Length is given twice with different values");
      out.content_length = n;
    } else if (iequals(name, "Transfer-Encoding")) {
      if (has_te || !iequals(trim_ows(value), "chunked")) {
        return malformed("Transfer-Encoding must be exactly 'chunked' (no other coding is accepted)");
      }
      has_te = true;
    } else if (iequals(name, "Content-Encoding") && !iequals(trim_ows(value), "identity")) {
      return make_api_error(ApiErrorCode::kUnsupportedMediaType,
                            "Content-Encoding '" + std::string(value.substr(0, 40)) +
                                "' is not accepted: send the body uncompressed (GLB and Draco are compressed already)",
                            {{"content_encoding", std::string(value.substr(0, 40))}});
    }
  }
  if (has_te && out.content_length) return malformed("Transfer-Encoding and Content-Length together (request smuggling)");
  if (has_te && out.minor_version == 0) return malformed("chunked framing needs HTTP/1.1");
  out.chunked = has_te;
  if (out.content_length && *out.content_length > limits.max_body_bytes) {
    return make_api_error(ApiErrorCode::kPayloadTooLarge,
                          "the request body of " + std::to_string(*out.content_length) +
                              " bytes is larger than the limit of " + std::to_string(limits.max_body_bytes) +
                              " bytes (--max-body-bytes)",
                          {{"limit_bytes", limits.max_body_bytes}, {"content_length", *out.content_length}});
  }
  return core::Ok{};
}

api::ApiError too_large(std::string what, const HeadLimits& limits) {
  return make_api_error(ApiErrorCode::kHeadersTooLarge,
                        "request head too large: " + std::move(what) + " (limits: " +
                            std::to_string(limits.max_fields) + " fields, " + std::to_string(limits.max_head_bytes) +
                            " bytes)",
                        {{"max_fields", limits.max_fields}, {"max_head_bytes", limits.max_head_bytes}});
}

}  // namespace

std::optional<std::string_view> RequestHead::field(std::string_view name) const {
  for (const auto& [n, v] : fields) {
    if (iequals(n, name)) return std::string_view(v);
  }
  return std::nullopt;
}

bool RequestHead::expects_continue() const {
  const auto e = field("Expect");
  return e && iequals(trim_ows(*e), "100-continue");
}

bool RequestHead::asks_to_close() const {
  for (const auto& [name, value] : fields) {
    if (!iequals(name, "Connection")) continue;
    std::string_view rest = value;
    while (!rest.empty()) {
      const auto comma = rest.find(',');
      if (iequals(trim_ows(rest.substr(0, comma)), "close")) return true;
      if (comma == std::string_view::npos) break;
      rest.remove_prefix(comma + 1);
    }
  }
  return false;
}

std::optional<std::size_t> find_head_end(std::string_view bytes) {
  const auto end = bytes.find("\r\n\r\n");
  if (end == std::string_view::npos) return std::nullopt;
  return end + 4;
}

bool has_bare_lf(std::string_view bytes, std::size_t from) {
  for (auto at = bytes.find('\n', from); at != std::string_view::npos; at = bytes.find('\n', at + 1)) {
    if (at == 0 || bytes[at - 1] != '\r') return true;
  }
  return false;
}

api::ApiResult<RequestHead> parse_request_head(std::string_view head, const HeadLimits& limits) {
  if (head.size() > limits.max_head_bytes) {
    return too_large(std::to_string(head.size()) + " bytes", limits);
  }
  while (head.substr(0, 2) == "\r\n") head.remove_prefix(2);  // RFC 9112 §2.2
  if (head.size() < 4 || head.substr(head.size() - 4) != "\r\n\r\n") return malformed("the head does not end with a blank line");
  head.remove_suffix(2);  // every line, the last included, now ends with CRLF
  RequestHead out;
  bool first = true;
  while (!head.empty()) {
    const auto eol = head.find("\r\n");
    const auto line = head.substr(0, eol);
    head.remove_prefix(eol + 2);
    if (line.find('\r') != std::string_view::npos || line.find('\n') != std::string_view::npos ||
        line.find('\0') != std::string_view::npos) {
      return malformed("a bare CR, LF or NUL inside a line");
    }
    if (first) {
      if (auto parsed = parse_request_line(line, out); !parsed.ok()) return parsed.take_error();
      first = false;
      continue;
    }
    if (line.empty() || line.front() == ' ' || line.front() == '\t') {
      return malformed("obsolete line folding or an empty field line");
    }
    if (out.fields.size() == limits.max_fields) return too_large("more than " + std::to_string(limits.max_fields) + " fields", limits);
    // Counted as the library will read it: "name: value" and its CRLF (sanitized_head writes
    // one space after the colon), against its own 8 KiB line buffer (http_head_fuzz).
    const auto colon_at = line.find(':');
    const auto sanitized_bytes = colon_at == std::string_view::npos
                                     ? line.size() + 2
                                     : colon_at + 2 + trim_ows(line.substr(colon_at + 1)).size() + 2;
    if (sanitized_bytes > limits.max_field_bytes) {
      return too_large("a field line of " + std::to_string(line.size()) + " bytes (at most " +
                           std::to_string(limits.max_field_bytes) + " each, with the line end)",
                       limits);
    }
    const auto colon = line.find(':');
    if (colon == std::string_view::npos) return malformed("a field line without a colon");
    const auto name = line.substr(0, colon);
    if (!is_token(name)) {
      return malformed("field name '" + std::string(name.substr(0, 40)) +
                       "' is not a token (no space is allowed before the colon)");
    }
    const auto value = trim_ows(line.substr(colon + 1));
    if (!is_field_value(value)) return malformed("field '" + std::string(name.substr(0, 40)) + "' holds control bytes");
    out.fields.emplace_back(std::string(name), std::string(value));
  }
  const auto hosts =
      std::count_if(out.fields.begin(), out.fields.end(), [](const auto& f) { return iequals(f.first, "Host"); });
  if (hosts > 1 || (hosts == 0 && out.minor_version == 1)) {
    return malformed(hosts > 1 ? "more than one Host field" : "an HTTP/1.1 request needs a Host field");
  }
  if (auto framing = check_framing(out, limits); !framing.ok()) return framing.take_error();
  return out;
}

bool ChunkedFraming::fail(std::string why) {
  state_ = State::kFailed;
  error_ = "malformed chunked body: " + std::move(why);
  return false;
}

bool ChunkedFraming::step(char c) {
  const auto u = static_cast<unsigned char>(c);
  const bool control = (u < 0x20 && u != '\t') || u == 0x7f;
  switch (state_) {
    case State::kSize: {
      const int digit = std::isxdigit(u) ? (std::isdigit(u) ? u - '0' : std::tolower(u) - 'a' + 10) : -1;
      if (digit >= 0) {
        if (digits_ == 15) return fail("a chunk size of more than 15 hex digits");
        size_ = size_ * 16 + static_cast<std::uint64_t>(digit);
        ++digits_;
        return true;
      }
      if (digits_ == 0) return fail("a chunk size line must start with the size in hex digits");
      if (c == '\r') return state_ = State::kSizeLf, true;
      if (c == '\n') return fail("a chunk size line must end with CRLF");
      if (c == ';' || c == ' ' || c == '\t') return state_ = State::kExtension, true;
      return fail("a chunk size must be hex digits, optionally followed by ';' and an extension");
    }
    case State::kExtension:
      if (c == '\r') return state_ = State::kSizeLf, true;
      return control ? fail("a control byte or bare LF in a chunk extension") : true;
    case State::kSizeLf:
      if (c != '\n') return fail("a chunk size line must end with CRLF");
      state_ = size_ == 0 ? State::kEndCr : State::kData;
      return true;
    case State::kDataCr:
      return c == '\r' ? (state_ = State::kDataLf, true) : fail("a chunk's data must end with CRLF");
    case State::kDataLf:
      if (c != '\n') return fail("a chunk's data must end with CRLF");
      state_ = State::kSize;
      digits_ = 0;
      return true;
    case State::kEndCr:
      return c == '\r' ? (state_ = State::kEndLf, true)
                       : fail("trailer fields after the last chunk are not accepted (send them as header fields)");
    case State::kEndLf:
      return c == '\n' ? (state_ = State::kDone, true) : fail("the last chunk must be followed by CRLF");
    case State::kData:
    case State::kDone:
    case State::kFailed:
      break;
  }
  return false;  // not reached: feed() handles data, and stops at the end or a failure
}

std::size_t ChunkedFraming::feed(std::string_view bytes) {
  std::size_t used = 0;
  while (used < bytes.size() && state_ != State::kDone && state_ != State::kFailed) {
    if (state_ == State::kData) {
      const auto skip = static_cast<std::size_t>(std::min<std::uint64_t>(size_, bytes.size() - used));
      used += skip;
      size_ -= skip;
      if (size_ == 0) state_ = State::kDataCr;
      continue;
    }
    if (!step(bytes[used])) break;
    ++used;
  }
  return used;
}

std::string sanitized_head(const RequestHead& head) {
  std::string out;
  out.reserve(256 + head.fields.size() * 48);
  out += head.method;
  out += ' ';
  out += head.target;
  out += head.minor_version == 0 ? " HTTP/1.0\r\n" : " HTTP/1.1\r\n";
  for (const auto& [name, value] : head.fields) {
    if (iequals(name, "Range") || iequals(name, "If-Range")) continue;
    // The media type in the lower case the library matches (lowercase_media_type).
    if (iequals(name, "Content-Type")) {
      out += name;
      out += ": ";
      out += lowercase_media_type(value);
      out += "\r\n";
      continue;
    }
    // A 100-continue expectation: ignored in HTTP/1.0 (RFC 9110 §10.1.1: no 100 Continue goes
    // to a 1.0 client), and in any case the token the library answers, which compares it with
    // "100-continue" exactly.
    if (iequals(name, "Expect")) {
      if (head.minor_version == 0) continue;
      if (iequals(trim_ows(value), "100-continue")) {
        out += name;
        out += ": 100-continue\r\n";
        continue;
      }
    }
    out += name;
    out += ": ";
    out += value;
    out += "\r\n";
  }
  out += "\r\n";
  return out;
}

std::optional<std::string> closing_response_head(std::string_view bytes) {
  if (!bytes.starts_with("HTTP/1.") || !bytes.ends_with("\r\n\r\n")) return std::nullopt;
  bool closing = false;
  std::vector<std::pair<std::size_t, std::size_t>> keep_alive;  // [start, end) of each such line
  std::size_t at = bytes.find("\r\n") + 2;                      // the first field line
  while (at < bytes.size() - 2) {
    const std::size_t end = bytes.find("\r\n", at);
    const std::string_view line = bytes.substr(at, end - at);
    const std::size_t colon = line.find(':');
    if (colon == std::string_view::npos) return std::nullopt;  // not a head alone (a body follows)
    const std::string_view name = line.substr(0, colon);
    if (iequals(name, "Connection") && iequals(trim_ows(line.substr(colon + 1)), "close")) closing = true;
    if (iequals(name, "Keep-Alive")) keep_alive.emplace_back(at, end + 2);
    at = end + 2;
  }
  if (!closing || keep_alive.empty()) return std::nullopt;
  std::string out;
  out.reserve(bytes.size());
  std::size_t from = 0;
  for (const auto& [start, end] : keep_alive) {
    out += bytes.substr(from, start - from);
    from = end;
  }
  out += bytes.substr(from);
  return out;
}

std::string http_date(std::chrono::system_clock::time_point t) {
  static constexpr std::array<const char*, 7> kDays = {"Sun", "Mon", "Tue", "Wed", "Thu", "Fri", "Sat"};
  static constexpr std::array<const char*, 12> kMonths = {"Jan", "Feb", "Mar", "Apr", "May", "Jun",
                                                          "Jul", "Aug", "Sep", "Oct", "Nov", "Dec"};
  const std::time_t seconds = std::chrono::system_clock::to_time_t(t);
  std::tm tm{};
  gmtime_r(&seconds, &tm);
  char out[32];
  std::snprintf(out, sizeof out, "%s, %02d %s %04d %02d:%02d:%02d GMT", kDays[static_cast<std::size_t>(tm.tm_wday)],
                tm.tm_mday, kMonths[static_cast<std::size_t>(tm.tm_mon)], tm.tm_year + 1900, tm.tm_hour, tm.tm_min,
                tm.tm_sec);
  return out;
}

}  // namespace seam::server
