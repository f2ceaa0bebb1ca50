// libFuzzer target for what cpp-httplib reads of a request, multipart/form-data included,
// reached the way seamd reaches it: our connection front (server/http_head.h) cuts and
// parses each head, refuses what it refuses, and hands the library the sanitized head plus
// the rest of the connection's bytes through httplib::Server::process_request, whose
// POST /seam handler decodes the request with the server's own decode_seam_request
// (server/http_request.h) and renders errors as its send_error() does (api::error_text),
// library-set statuses through the server's library_status_error. The first input byte picks the framing:
//   'R'  the rest is a connection's raw bytes: one or more (pipelined) requests
//   'L'  the rest is "target\ncontent-type\nbody": a POST with a Content-Length
//   'C'  the same, the body sent in chunks (Transfer-Encoding: chunked)
// any other byte maps to one of them (byte % 3).
//
// cpp-httplib is Debian's compiled libcpp-httplib.so: it runs here as it runs in seamd, but
// carries no coverage instrumentation, so libFuzzer is guided only by our code around it.
// httplib.h must come after every Eigen header (its <resolv.h> defines _res), and the
// target must be compiled with httplib's pkg-config flags (the library's ABI).
//
// Properties, each a __builtin_trap when violated:
// - no exception escapes process_request or our handlers, and the library never answers 500
//   (it turns an exception thrown while routing into a 500);
// - every head the front accepts, the library reads too (the setup callback runs), unless
//   the library refuses it for a reason of its own that the front leaves to it: a method
//   outside its list, a request line over CPPHTTPLIB_REQUEST_URI_MAX_LENGTH (414), a target
//   with more than one '?';
// - every error our handlers answer renders as server.cpp renders it, api::error_text(e), as
//   valid JSON, and has a 4xx status; accepted parameters are in range.
// The server code it runs (admission, decoding, library-set statuses) is the server's own,
// from server/http_request.h.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "api/error.h"
#include "server/http_head.h"
#include "server/request.h"
#include "server/http_request.h"
#include "tests/fuzz/tolerate.h"

#include <httplib.h>  // after Eigen (pulled in by server/request.h)

namespace {

using seam::api::ApiError;
using seam::api::ApiErrorCode;
using seam::api::make_api_error;
using seam::server::RequestHead;
using seam::server::SeamRequest;

void check(bool property) {
  if (!property) __builtin_trap();
}

// A connection held in memory: the sanitized head first, then the bytes after the head as
// the client sent them (body and any pipelined requests); answers go nowhere. socket() is
// -1, which passes the library's FD_SETSIZE check (a descriptor >= FD_SETSIZE is a 500).
class MemoryStream final : public httplib::Stream {
 public:
  MemoryStream(std::string head, std::string_view rest) : head_(std::move(head)), rest_(rest) {}

  bool is_readable() const override { return true; }
  bool is_writable() const override { return true; }
  ssize_t read(char* ptr, size_t size) override {
    if (head_pos_ < head_.size()) {
      const auto n = std::min(size, head_.size() - head_pos_);
      std::copy_n(head_.data() + head_pos_, n, ptr);
      head_pos_ += n;
      return static_cast<ssize_t>(n);
    }
    const auto n = std::min(size, rest_.size() - rest_pos_);
    std::copy_n(rest_.data() + rest_pos_, n, ptr);
    rest_pos_ += n;
    return static_cast<ssize_t>(n);
  }
  ssize_t write(const char* /*ptr*/, size_t size) override { return static_cast<ssize_t>(size); }
  void get_remote_ip_and_port(std::string& ip, int& port) const override {
    ip = "127.0.0.1";
    port = 40000;
  }
  void get_local_ip_and_port(std::string& ip, int& port) const override {
    ip = "127.0.0.1";
    port = 8080;
  }
  socket_t socket() const override { return -1; }

  std::size_t rest_consumed() const { return rest_pos_; }

 private:
  std::string head_;
  std::size_t head_pos_ = 0;
  std::string_view rest_;
  std::size_t rest_pos_ = 0;
};

// Renders an error as server.cpp's send_error() does; it must be JSON again (valid UTF-8
// whatever bytes the message quotes: finding F1 was a throw here).
void send_error(httplib::Response& res, const ApiError& error) {
  res.status = seam::api::http_status(error.code);
  check(res.status >= 400 && res.status < 500);
  std::string body = seam::api::error_text(error);
  check(nlohmann::json::accept(body));
  res.set_content(body, "application/json");
}

void check_params(const seam::api::SeamParams& p) {
  check(p.mesh < (1u << 31) && p.primitive < (1u << 31));
  check(std::isfinite(p.weld_epsilon) && p.weld_epsilon >= 0);
  for (const auto& x : p.extrema.positions) check(std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]));
}

// The server's admit(): the front's route-level check before the body is read.
bool admitted(const RequestHead& head) { return !seam::server::refuse_before_body(head).has_value(); }

class FuzzServer : public httplib::Server {
 public:
  FuzzServer() {
    set_payload_max_length(seam::server::HeadLimits{}.max_body_bytes);
    Post("/seam", [this](const httplib::Request& req, httplib::Response& res) {
      // The front admitted what the library routes here: a media type POST /seam takes
      // (finding F5, docs/fuzzing.md: fixed, the front checks the routed path).
      const auto media = seam::server::media_type(req.get_header_value("Content-Type"));
      const bool takes = media == "multipart/form-data" || media == "application/json" ||
                         seam::server::asset_kind_for_media_type(media).has_value();
      check(takes);
      try {
        auto decoded = seam::server::decode_seam_request(req);
        if (!decoded.ok()) return send_error(res, decoded.error());
        if (decoded->asset.empty()) {
          return send_error(res, make_api_error(ApiErrorCode::kMalformedRequest, "the request carries no asset bytes"));
        }
        check_params(decoded->params);
        res.set_content("{}", "application/json");
      } catch (...) {
        __builtin_trap();  // decoding reports errors as values
      }
    });
    // server.cpp's error handler, for the statuses the library sets itself.
    set_error_handler(HandlerWithResponse([](const httplib::Request& req, httplib::Response& res) {
      if (!res.body.empty()) return HandlerResponse::Unhandled;
      if (res.status == 500) {
        // The library caught an exception while routing (its message is in EXCEPTION_WHAT).
        std::fprintf(stderr, "multipart_fuzz: 500, exception: %s\n", res.get_header_value("EXCEPTION_WHAT").c_str());
        __builtin_trap();
      }
      const ApiError error = seam::server::library_status_error(res.status, req.path, seam::server::HeadLimits{}.max_body_bytes);
      const int status = res.status;
      send_error(res, error);
      res.status = status;
      return HandlerResponse::Handled;
    }));
    set_post_routing_handler([this](const httplib::Request&, httplib::Response& res) { status_ = res.status; });
  }

  struct Outcome {
    bool answered = false;
    bool head_read = false;  ///< the library parsed the head (its setup callback ran)
    bool connection_closed = false;
    int status = 0;
  };

  /// Serves one request whose head the front parsed as `head`.
  Outcome serve(httplib::Stream& stream, const RequestHead& head) {
    Outcome out;
    status_ = 0;
    front_path_ = head.path;
    out.answered = process_request(stream, /*close_connection=*/false, out.connection_closed,
                                   [&](httplib::Request&) { out.head_read = true; });
    out.status = status_;
    return out;
  }

 private:
  int status_ = 0;
  std::string front_path_;  ///< the path as the front saw it
};

// SEAM_FUZZ_VERBOSE=1: one line per request served (for reading reproducers and seeds).
bool verbose() {
  static const bool on = std::getenv("SEAM_FUZZ_VERBOSE") != nullptr;
  return on;
}

// Heads the front passes that the library may still refuse by its own rules.
bool library_may_refuse(const RequestHead& head) {
  static const std::set<std::string> kMethods{"GET", "HEAD", "POST", "PUT", "DELETE", "CONNECT", "OPTIONS", "TRACE", "PATCH", "PRI"};
  const std::size_t request_line = head.method.size() + 1 + head.target.size() + 1 + 8 + 2;
  return kMethods.count(head.method) == 0 || request_line > CPPHTTPLIB_REQUEST_URI_MAX_LENGTH ||
         std::count(head.target.begin(), head.target.end(), '?') > 1;
}

// The front's loop over one connection (server/http_front.cpp serve_connection), at most 4
// requests.
void serve_connection(FuzzServer& server, std::string_view bytes) {
  const seam::server::HeadLimits limits;
  for (int request = 0; request < 4; ++request) {
    while (bytes.substr(0, 2) == "\r\n") bytes.remove_prefix(2);
    const auto end = seam::server::find_head_end(bytes);
    if (!end) return;  // the front waits for the rest, then closes or answers 408
    auto parsed = seam::server::parse_request_head(bytes.substr(0, *end), limits);
    if (!parsed.ok()) return;  // the front answers and closes
    const RequestHead& head = *parsed;
    bytes.remove_prefix(*end);
    const bool needs_length = head.method == "POST" || head.method == "PUT" || head.method == "PATCH";
    if (!head.has_body() && !head.content_length && needs_length) return;  // 411
    if (!admitted(head)) return;                                              // 415
    MemoryStream stream(seam::server::sanitized_head(head), bytes);
    const auto outcome = server.serve(stream, head);
    if (verbose()) {
      std::fprintf(stderr, "multipart_fuzz: %s %s -> read by the library: %d, status %d, closed %d\n", head.method.c_str(),
                   head.target.substr(0, 80).c_str(), outcome.head_read, outcome.status, outcome.connection_closed);
    }
    if (!library_may_refuse(head)) check(outcome.head_read);
    check(outcome.status != 500);
    if (!outcome.answered || outcome.connection_closed) return;
    bytes.remove_prefix(stream.rest_consumed());
  }
}

// "target\ncontent-type\nbody" as one POST, framed by Content-Length or in chunks.
std::optional<std::string> framed_request(std::string_view input, bool chunked) {
  const auto nl1 = input.find('\n');
  const auto nl2 = nl1 == std::string_view::npos ? nl1 : input.find('\n', nl1 + 1);
  if (nl2 == std::string_view::npos) return std::nullopt;
  const auto target = input.substr(0, nl1);
  const auto content_type = input.substr(nl1 + 1, nl2 - nl1 - 1);
  const auto body = input.substr(nl2 + 1);
  std::string out = "POST " + std::string(target) + " HTTP/1.1\r\nHost: fuzz\r\nContent-Type: " +
                    std::string(content_type) + "\r\n";
  if (!chunked) {
    out += "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n";
    out += body;
    return out;
  }
  out += "Transfer-Encoding: chunked\r\n\r\n";
  // Chunk sizes that vary with the body, so that chunk edges fall anywhere in it.
  std::size_t pos = 0;
  std::size_t step = 1 + body.size() % 61;
  while (pos < body.size()) {
    const auto n = std::min(step, body.size() - pos);
    char size[32];
    std::snprintf(size, sizeof size, "%zx\r\n", n);
    out += size;
    out += body.substr(pos, n);
    out += "\r\n";
    pos += n;
    step = step * 3 % 257 + 1;
  }
  out += "0\r\n\r\n";
  return out;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  static FuzzServer server;  // routes are regexes: compile them once
  const std::string_view input(reinterpret_cast<const char*>(data) + 1, size - 1);
  static constexpr std::string_view kSelectors = "RLC";
  char selector = static_cast<char>(data[0]);
  if (kSelectors.find(selector) == std::string_view::npos) selector = kSelectors[data[0] % kSelectors.size()];
  if (selector == 'R') {
    serve_connection(server, input);
  } else if (const auto request = framed_request(input, selector == 'C')) {
    serve_connection(server, *request);
  }
  return 0;
}
