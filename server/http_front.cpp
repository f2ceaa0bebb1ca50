#include "server/http_front.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <fstream>

namespace seam::server {
namespace {

using Clock = std::chrono::steady_clock;
using api::ApiErrorCode;
using api::make_api_error;

constexpr std::size_t kRecvBlock = 64u << 10;
// Polls are sliced so that a drain is noticed within this.
constexpr auto kPollSlice = std::chrono::milliseconds(200);
// After a refusal the unread rest of a body is drained for at most this long (and this many
// bytes), so the client reads the answer instead of a reset (a "lingering close").
constexpr auto kLingerTime = std::chrono::milliseconds(1000);
constexpr std::size_t kLingerBytes = 16u << 20;

const char* reason_phrase(int status) {
  switch (status) {
    case 400: return "Bad Request";
    case 405: return "Method Not Allowed";
    case 408: return "Request Timeout";
    case 411: return "Length Required";
    case 413: return "Payload Too Large";
    case 415: return "Unsupported Media Type";
    case 431: return "Request Header Fields Too Large";
    case 503: return "Service Unavailable";
    default: return "Error";
  }
}

std::string peer_string(int fd, bool remote, int& port) {
  sockaddr_storage addr{};
  socklen_t len = sizeof addr;
  const int rc = remote ? getpeername(fd, reinterpret_cast<sockaddr*>(&addr), &len)
                        : getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len);
  port = 0;
  if (rc != 0) return {};
  char buf[INET6_ADDRSTRLEN] = {};
  if (addr.ss_family == AF_INET) {
    const auto* a = reinterpret_cast<const sockaddr_in*>(&addr);
    inet_ntop(AF_INET, &a->sin_addr, buf, sizeof buf);
    port = ntohs(a->sin_port);
  } else if (addr.ss_family == AF_INET6) {
    const auto* a = reinterpret_cast<const sockaddr_in6*>(&addr);
    inet_ntop(AF_INET6, &a->sin6_addr, buf, sizeof buf);
    port = ntohs(a->sin6_port);
  }
  return buf;
}

int somaxconn() {
  std::ifstream in("/proc/sys/net/core/somaxconn");
  int n = 0;
  return (in >> n) && n > 0 ? n : 4096;
}

Refusal refusal(ApiErrorCode code, std::string message, nlohmann::json details = nlohmann::json::object()) {
  return Refusal{make_api_error(code, std::move(message), std::move(details)), {}};
}

}  // namespace

bool ByteBudget::try_take(std::uint64_t bytes) {
  auto held = held_.load();
  do {
    if (held != 0 && held + bytes > capacity_) return false;
  } while (!held_.compare_exchange_weak(held, held + bytes));
  return true;
}

void ByteBudget::give_back(std::uint64_t bytes) { held_.fetch_sub(bytes); }

// One client connection: the Stream the library reads requests from and writes answers to.
// Input goes through one buffer for the connection's whole life, so bytes of a pipelined next
// request read along with this one's body wait there for the next head.
class Connection final : public httplib::Stream {
 public:
  Connection(int fd, const FrontConfig& config, const std::atomic<std::int64_t>& drain_deadline_ns, ByteBudget& budget)
      : fd_(fd), config_(config), drain_deadline_ns_(drain_deadline_ns), budget_(budget) {
    remote_ = peer_string(fd_, true, remote_port_);
  }
  ~Connection() override { end_request(); }

  enum class HeadRead { kComplete, kNone, kRefused };

  // Reads the next head into head_bytes(); kNone when the client sent nothing before the idle
  // (or first-request) timeout or closed, kRefused with refusal() set otherwise.
  HeadRead read_head(bool first) {
    discard_leading_crlf();
    if (available() == 0) {
      const auto idle = first ? config_.request_timeout : config_.idle_timeout;
      if (!fill(Clock::now() + idle, /*head=*/true)) return HeadRead::kNone;
      discard_leading_crlf();
    }
    const auto deadline = Clock::now() + config_.request_timeout;
    request_start_ = Clock::now();
    std::size_t scanned = 0;
    for (;;) {
      const std::string_view view(in_.data() + in_pos_, available());
      if (const auto end = find_head_end(view.substr(scanned >= 3 ? scanned - 3 : 0)); end) {
        head_len_ = (scanned >= 3 ? scanned - 3 : 0) + *end;
        return HeadRead::kComplete;
      }
      if (has_bare_lf(view, scanned)) {
        failure_ = refusal(ApiErrorCode::kMalformedRequest,
                           "malformed HTTP request: the head's lines must end with CRLF, not a bare LF");
        return HeadRead::kRefused;
      }
      scanned = view.size();
      if (view.size() > config_.head.max_head_bytes) {
        failure_ = refusal(ApiErrorCode::kHeadersTooLarge,
                           "request head too large: more than " + std::to_string(config_.head.max_head_bytes) +
                               " bytes without the end of the head",
                           {{"max_head_bytes", config_.head.max_head_bytes}});
        return HeadRead::kRefused;
      }
      if (!fill(deadline, /*head=*/true)) {
        if (!failure_) return HeadRead::kNone;  // the client closed mid-head: nobody to answer
        return HeadRead::kRefused;
      }
    }
  }
  std::string_view head_bytes() const { return {in_.data() + in_pos_, head_len_}; }

  // Serves `head` to the library next, then the body from the connection, counted.
  bool begin_request(const RequestHead& head) {
    in_pos_ += head_len_;
    head_len_ = 0;
    head_out_ = sanitized_head(head);
    head_pos_ = 0;
    response_head_pending_ = true;
    body_served_ = 0;
    chunked_ = head.chunked;
    framing_ = ChunkedFraming();
    declared_ = head.content_length.value_or(0);
    body_deadline_ = request_start_ + config_.request_timeout +
                     std::chrono::milliseconds(declared_ * 1000 / std::max<std::size_t>(1, config_.min_body_rate));
    return reserve(chunked_ ? kRecvBlock : declared_);
  }

  // Whether the library read the request's whole body (a chunked one up to its last CRLF).
  // When it did not (it refused the framing, or stopped early), where the next request starts
  // is unknown, and the connection must close.
  bool body_complete() const { return chunked_ ? framing_.done() : body_served_ == declared_; }

  void end_request() {
    budget_.give_back(reserved_);
    reserved_ = 0;
  }

  const std::optional<Refusal>& failure() const { return failure_; }
  void set_failure(Refusal r) { failure_ = std::move(r); }
  bool peer_gone() const { return peer_gone_ || abandoned_; }
  void abandon() { abandoned_ = true; }
  bool abandoned() const { return abandoned_; }
  const std::string& remote() const { return remote_; }

  bool peer_closed() const {
    pollfd p{fd_, POLLRDHUP, 0};
    return ::poll(&p, 1, 0) > 0 && (p.revents & (POLLRDHUP | POLLHUP | POLLERR)) != 0;
  }

  // Writes all of `bytes` within the io timeout (false on error or timeout); an abandoned
  // connection drops them, as write() does.
  bool write_all(std::string_view bytes) { return abandoned_ || send_all(bytes); }

  // Half-closes, then reads and drops what the client still sends for a short while, so that
  // it sees the answer rather than a reset; the caller closes the socket.
  void linger() {
    ::shutdown(fd_, SHUT_WR);
    const auto until = Clock::now() + kLingerTime;
    std::size_t dropped = 0;
    char sink[16384];
    while (dropped < kLingerBytes && Clock::now() < until) {
      pollfd p{fd_, POLLIN, 0};
      if (::poll(&p, 1, 100) <= 0) continue;
      const auto n = ::recv(fd_, sink, sizeof sink, 0);
      if (n <= 0) break;
      dropped += static_cast<std::size_t>(n);
    }
  }

  // ---- httplib::Stream ----------------------------------------------------------------

  bool is_readable() const override {
    if (head_pos_ < head_out_.size() || available() > 0) return true;
    pollfd p{fd_, POLLIN, 0};
    return ::poll(&p, 1, static_cast<int>(config_.io_timeout.count())) > 0;
  }

  bool is_writable() const override {
    pollfd p{fd_, POLLOUT, 0};
    return ::poll(&p, 1, static_cast<int>(config_.io_timeout.count())) > 0 && (p.revents & POLLOUT) != 0;
  }

  ssize_t read(char* ptr, size_t size) override {
    if (head_pos_ < head_out_.size()) {
      const auto n = std::min(size, head_out_.size() - head_pos_);
      std::copy_n(head_out_.data() + head_pos_, n, ptr);
      head_pos_ += n;
      return static_cast<ssize_t>(n);
    }
    if (failure_) return -1;
    if (body_complete()) return 0;  // never a byte of the next request as this one's body
    if (available() == 0 && !fill(body_deadline(), /*head=*/false)) return -1;
    auto n = std::min(size, available());
    if (chunked_) {
      n = framing_.feed({in_.data() + in_pos_, n});
      if (framing_.failed()) {
        failure_ = refusal(ApiErrorCode::kMalformedRequest, framing_.error());
        return -1;
      }
    } else {
      n = static_cast<std::size_t>(std::min<std::uint64_t>(n, declared_ - body_served_));
    }
    if (body_served_ + n > config_.head.max_body_bytes) {
      failure_ = refusal(ApiErrorCode::kPayloadTooLarge,
                         "the request body is larger than the limit of " + std::to_string(config_.head.max_body_bytes) +
                             " bytes (--max-body-bytes; chunked bodies are counted on the wire)",
                         {{"limit_bytes", config_.head.max_body_bytes}});
      return -1;
    }
    if (chunked_ && body_served_ + n > reserved_ / config_.budget_factor && !reserve(kRecvBlock)) {
      failure_ = over_budget();
      return -1;
    }
    std::copy_n(in_.data() + in_pos_, n, ptr);
    in_pos_ += n;
    body_served_ += n;
    return static_cast<ssize_t>(n);
  }

  ssize_t write(const char* ptr, size_t size) override {
    if (abandoned_) return static_cast<ssize_t>(size);  // nobody reads it: drop, as if sent
    if (response_head_pending_) {
      // The library writes each answer's head in one call (after any 100 Continue); one that
      // closes the connection goes out without the Keep-Alive the library adds to it.
      const std::string_view bytes(ptr, size);
      if (!bytes.starts_with("HTTP/1.1 1")) {
        response_head_pending_ = false;
        if (const auto head = closing_response_head(bytes); head) {
          return send_all(*head) ? static_cast<ssize_t>(size) : -1;
        }
      }
    }
    return send_some(ptr, size);
  }

  void get_remote_ip_and_port(std::string& ip, int& port) const override {
    ip = remote_;
    port = remote_port_;
  }
  void get_local_ip_and_port(std::string& ip, int& port) const override { ip = peer_string(fd_, false, port); }
  socket_t socket() const override { return fd_; }

 private:
  // One send within the io timeout: the bytes sent (maybe fewer than `size`), or -1.
  ssize_t send_some(const char* ptr, size_t size) {
    const auto until = Clock::now() + config_.io_timeout;
    for (;;) {
      const auto n = ::send(fd_, ptr, size, MSG_NOSIGNAL);
      if (n >= 0) return n;
      if (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) return -1;
      pollfd p{fd_, POLLOUT, 0};
      if (Clock::now() >= until || ::poll(&p, 1, static_cast<int>(kPollSlice.count())) < 0) return -1;
    }
  }

  // send_some until all of `bytes` are sent (false on error or timeout).
  bool send_all(std::string_view bytes) {
    while (!bytes.empty()) {
      const auto n = send_some(bytes.data(), bytes.size());
      if (n <= 0) return false;
      bytes.remove_prefix(static_cast<std::size_t>(n));
    }
    return true;
  }

  std::size_t available() const { return in_.size() - in_pos_; }

  void discard_leading_crlf() {
    while (available() >= 2 && in_[in_pos_] == '\r' && in_[in_pos_ + 1] == '\n') in_pos_ += 2;
  }

  Clock::time_point body_deadline() const {
    if (!chunked_) return body_deadline_;
    return request_start_ + config_.request_timeout +
           std::chrono::milliseconds(body_served_ * 1000 / std::max<std::size_t>(1, config_.min_body_rate));
  }

  std::optional<Clock::time_point> drain_deadline() const {
    const auto ns = drain_deadline_ns_.load();
    if (ns == 0) return std::nullopt;
    return Clock::time_point(std::chrono::nanoseconds(ns));
  }

  Refusal over_budget() const {
    Refusal r = refusal(ApiErrorCode::kOverloaded,
                        "the server holds its limit of " + std::to_string(budget_.capacity()) +
                            " bytes of requests in flight; retry later",
                        {{"max_inflight_bytes", budget_.capacity()}});
    r.headers.emplace_back("Retry-After", "1");
    return r;
  }

  bool reserve(std::uint64_t body_bytes) {
    const auto bytes = body_bytes * config_.budget_factor;
    if (bytes == 0) return true;
    if (!budget_.try_take(bytes)) {
      failure_ = over_budget();
      return false;
    }
    reserved_ += bytes;
    return true;
  }

  // Receives at least one byte before `deadline` (or the drain's, or the io timeout while a
  // body is read). False, with failure_ set to a 408 when a partial request timed out, on
  // timeout, close or error.
  bool fill(Clock::time_point deadline, bool head) {
    if (in_pos_ == in_.size()) {
      in_.clear();
      in_pos_ = 0;
    } else if (in_pos_ > kRecvBlock) {
      in_.erase(0, in_pos_);
      in_pos_ = 0;
    }
    const bool started = !head || available() > 0;
    const auto io_until = Clock::now() + config_.io_timeout;
    for (;;) {
      auto until = std::min(deadline, head ? deadline : io_until);
      if (const auto drain = drain_deadline(); drain) {
        if (!started) return false;  // draining: a connection with no request pending just closes
        until = std::min(until, *drain);
      }
      const auto now = Clock::now();
      if (now >= until) {
        if (started) {
          failure_ = refusal(ApiErrorCode::kRequestTimeout,
                             "the request did not arrive in time: the head within " +
                                 std::to_string(config_.request_timeout.count() / 1000) +
                                 " s (--request-timeout-s), the body at " + std::to_string(config_.min_body_rate) +
                                 " bytes/s or faster (--min-body-rate)",
                             {{"request_timeout_s", config_.request_timeout.count() / 1000},
                              {"min_body_rate", config_.min_body_rate}});
        }
        return false;
      }
      const auto wait = std::min<std::chrono::milliseconds>(
          kPollSlice, std::chrono::duration_cast<std::chrono::milliseconds>(until - now) + std::chrono::milliseconds(1));
      pollfd p{fd_, POLLIN, 0};
      const int rc = ::poll(&p, 1, static_cast<int>(wait.count()));
      if (rc < 0 && errno != EINTR) return false;
      if (rc <= 0) continue;
      const auto old = in_.size();
      in_.resize(old + kRecvBlock);
      const auto n = ::recv(fd_, in_.data() + old, kRecvBlock, 0);
      in_.resize(old + static_cast<std::size_t>(std::max<ssize_t>(n, 0)));
      if (n > 0) return true;
      if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) continue;
      peer_gone_ = true;
      return false;
    }
  }

  int fd_;
  const FrontConfig& config_;
  const std::atomic<std::int64_t>& drain_deadline_ns_;
  ByteBudget& budget_;
  std::string remote_;
  int remote_port_ = 0;

  std::string in_;
  std::size_t in_pos_ = 0;
  std::size_t head_len_ = 0;
  std::string head_out_;
  std::size_t head_pos_ = 0;
  bool response_head_pending_ = false;  // the library has yet to write this request's answer head

  Clock::time_point request_start_{};
  Clock::time_point body_deadline_{};
  bool chunked_ = false;
  ChunkedFraming framing_;
  std::uint64_t declared_ = 0;
  std::uint64_t body_served_ = 0;
  std::uint64_t reserved_ = 0;
  std::optional<Refusal> failure_;
  bool peer_gone_ = false;
  std::atomic<bool> abandoned_{false};
};

FrontServer::FrontServer(FrontConfig config, Hooks hooks)
    : config_(std::move(config)), hooks_(std::move(hooks)), budget_(config_.max_inflight_bytes) {
  // Replaces the library's default socket options (SO_REUSEADDR and, in some versions,
  // SO_REUSEPORT, which would let a second seamd bind the same port silently) and learns the
  // listening descriptor, whose backlog bind_with_backlog raises.
  set_socket_options([this](socket_t sock) {
    int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    listen_fd_ = sock;
  });
}

int FrontServer::bind_with_backlog(const std::string& host, int port) {
  const int bound = port == 0 ? bind_to_any_port(host) : (bind_to_port(host, port) ? port : -1);
  if (bound < 0 || listen_fd_ < 0) return -1;
  // The library listened with CPPHTTPLIB_LISTEN_BACKLOG (5, compiled into Debian's shared
  // library). Linux lets listen() be called again on a listening socket to change the backlog.
  effective_backlog_ = std::min(config_.backlog, somaxconn());
  if (::listen(listen_fd_, effective_backlog_) != 0) return -1;
  return bound;
}

void FrontServer::begin_drain(std::chrono::steady_clock::time_point deadline) {
  std::int64_t expected = 0;
  const auto ns = std::max<std::int64_t>(1, deadline.time_since_epoch().count());
  drain_deadline_ns_.compare_exchange_strong(expected, ns);
}

Connection* FrontServer::connection_of(const httplib::Request& req) const {
  std::lock_guard lock(requests_mutex_);
  const auto it = requests_.find(&req);
  return it == requests_.end() ? nullptr : it->second;
}

bool FrontServer::peer_closed(const httplib::Request& req) const {
  const auto* conn = connection_of(req);
  return conn != nullptr && conn->peer_closed();
}

void FrontServer::abandon(const httplib::Request& req) {
  if (auto* conn = connection_of(req); conn != nullptr) conn->abandon();
}

std::optional<Refusal> FrontServer::body_failure(const httplib::Request& req) const {
  const auto* conn = connection_of(req);
  if (conn == nullptr) return std::nullopt;
  return conn->failure();
}

bool FrontServer::body_incomplete(const httplib::Request& req) const {
  const auto* conn = connection_of(req);
  return conn != nullptr && !conn->body_complete();
}

void FrontServer::refuse(Connection& conn, const RequestHead* head, Refusal r) {
  if (hooks_.refused) hooks_.refused(head, r, conn.remote());
  const auto body = api::error_text(r.error);
  const int status = api::http_status(r.error.code);
  std::string out = "HTTP/1.1 " + std::to_string(status) + " " + reason_phrase(status) + "\r\n";
  out += "Date: " + http_date(std::chrono::system_clock::now()) + "\r\n";
  out += "Content-Type: application/json\r\nConnection: close\r\n";
  out += "Content-Length: " + std::to_string(body.size()) + "\r\n";
  for (const auto& [name, value] : r.headers) out += name + ": " + value + "\r\n";
  out += "\r\n";
  if (!head || head->method != "HEAD") out += body;
  conn.write_all(out);
}

bool FrontServer::process_and_close_socket(socket_t sock) {
  int yes = 1;
  setsockopt(sock, IPPROTO_TCP, TCP_NODELAY, &yes, sizeof yes);
  {
    Connection conn(sock, config_, drain_deadline_ns_, budget_);
    serve_connection(conn);
    if (conn.failure() && !conn.peer_gone()) conn.linger();
  }
  ::shutdown(sock, SHUT_RDWR);
  ::close(sock);
  return true;
}

void FrontServer::serve_connection(Connection& conn) {
  for (std::size_t count = 0; count < config_.keep_alive_max; ++count) {
    const auto read = conn.read_head(count == 0);
    if (read == Connection::HeadRead::kNone) return;
    if (read == Connection::HeadRead::kRefused) return refuse(conn, nullptr, *conn.failure());

    auto parsed = parse_request_head(conn.head_bytes(), config_.head);
    if (!parsed.ok()) {
      conn.set_failure(Refusal{parsed.take_error(), {}});
      return refuse(conn, nullptr, *conn.failure());
    }
    const RequestHead& head = parsed.value();
    std::optional<Refusal> refused;
    if (!head.has_body() && !head.content_length && (head.method == "POST" || head.method == "PUT" || head.method == "PATCH")) {
      refused = refusal(ApiErrorCode::kLengthRequired,
                        head.method + " needs a body with Content-Length or chunked framing");
    } else if (hooks_.admit) {
      refused = hooks_.admit(head);
    }
    if (!refused && !conn.begin_request(head)) refused = conn.failure();
    if (refused) {
      conn.set_failure(*refused);
      return refuse(conn, &head, std::move(*refused));
    }

    // HTTP/1.0 connections end after one answer (its keep-alive extension is not offered; the
    // library would otherwise close them after an answer that promised Keep-Alive).
    const bool close_connection = head.minor_version == 0 || head.asks_to_close() ||
                                  count + 1 == config_.keep_alive_max || drain_deadline_ns_.load() != 0;
    bool connection_closed = false;
    const httplib::Request* current = nullptr;
    const bool answered = process_request(conn, close_connection, connection_closed, [&](httplib::Request& req) {
      current = &req;
      std::lock_guard lock(requests_mutex_);
      requests_[&req] = &conn;
    });
    if (current) {
      std::lock_guard lock(requests_mutex_);
      requests_.erase(current);
    }
    conn.end_request();
    if (!answered || close_connection || connection_closed || conn.failure() || conn.abandoned() ||
        !conn.body_complete()) {
      return;
    }
  }
}

}  // namespace seam::server
