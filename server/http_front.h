// The connection front: every limit that cpp-httplib 0.11 cannot hold by itself, held around
// it (docs/http.md). The front owns each connection's loop: it reads a request head with a
// whole-request deadline, parses it strictly (server/http_head.h), refuses before reading the
// body what must not be read (413, 411, 415, 431, 408, 503), and then lets the library route
// the request through a Stream that serves a sanitized head and counts the body as it
// arrives, at a minimum rate. One buffer per connection, so pipelined requests are answered
// in order. The listening socket gets a backlog sized for bursts.
//
// Include after Eigen (httplib.h includes <resolv.h>, shared/notes/stack.md).
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "api/error.h"
#include "server/http_head.h"

#include <httplib.h>

namespace seam::server {

/// The front's limits. Every duration must be positive.
struct FrontConfig {
  HeadLimits head;
  /// The head must arrive whole within this; the body within it plus length / min_body_rate.
  std::chrono::milliseconds request_timeout{30'000};
  std::size_t min_body_rate = 64u << 10;             ///< bytes per second a body must average
  std::chrono::milliseconds idle_timeout{5'000};     ///< keep-alive wait for the next request
  std::chrono::milliseconds io_timeout{30'000};      ///< one read or write making no progress
  std::size_t keep_alive_max = 1000;                 ///< requests per connection
  int backlog = 1024;                                ///< listen backlog, clamped to somaxconn
  /// Bytes in flight across all requests: each request holds budget_factor x its body from its
  /// head to its answer; a request that would exceed it is a 503 (unless nothing else is in
  /// flight, so one request of any admissible size always gets through).
  std::uint64_t max_inflight_bytes = 4ull << 30;
  unsigned budget_factor = 4;  ///< bodies are buffered 1.7-4.3x while decoded (measured)
};

/// A request the front answers by itself, before (or instead of) the library.
struct Refusal {
  api::ApiError error;
  std::vector<std::pair<std::string, std::string>> headers;  ///< e.g. Retry-After
};

/// The sum of the bytes the requests in flight hold. Thread-safe.
class ByteBudget {
 public:
  explicit ByteBudget(std::uint64_t capacity) : capacity_(capacity) {}
  /// Takes `bytes` if they fit, or if nothing is held at all. O(1).
  bool try_take(std::uint64_t bytes);
  void give_back(std::uint64_t bytes);
  std::uint64_t held() const { return held_.load(); }
  std::uint64_t capacity() const { return capacity_; }

 private:
  std::uint64_t capacity_;
  std::atomic<std::uint64_t> held_{0};
};

class Connection;

class FrontServer : public httplib::Server {
 public:
  struct Hooks {
    /// Route-level checks on a parsed head before any body byte is read (e.g. 415 for a media
    /// type POST /seam does not take). nullopt admits the request.
    std::function<std::optional<Refusal>(const RequestHead&)> admit;
    /// Called for every request the front answers itself (head == nullptr when the head could
    /// not be parsed): log it, count it, add X-Request-Id to refusal.headers.
    std::function<void(const RequestHead*, Refusal&, const std::string& remote)> refused;
  };

  FrontServer(FrontConfig config, Hooks hooks);

  /// Binds host:port (0 = ephemeral) with the configured backlog. Returns the port, or -1.
  int bind_with_backlog(const std::string& host, int port);
  /// The backlog in force after the clamp to net.core.somaxconn (0 before binding).
  int effective_backlog() const { return effective_backlog_; }

  /// Starts the drain: idle connections close at once, requests still arriving must be whole
  /// by `deadline`, and every connection is ended by then. Thread-safe, idempotent.
  void begin_drain(std::chrono::steady_clock::time_point deadline);

  /// While a handler runs: true when its client closed its side of the connection (FIN or
  /// reset), i.e. nobody is waiting for the answer. O(1) (one poll).
  bool peer_closed(const httplib::Request& req) const;

  /// The client of `req` is gone: whatever the library writes for it is dropped and the
  /// connection closes after the handler, without an answer. Thread-safe.
  void abandon(const httplib::Request& req);

  /// Inside the library's error handler: why the front stopped the body of `req` (413 past
  /// the limit, 408 too slow, 503 over the bytes-in-flight budget), or nullopt.
  std::optional<Refusal> body_failure(const httplib::Request& req) const;

  /// Inside the library's error handler: true when the library has not read all of `req`'s
  /// body (it refused the chunked framing, or stopped early). The connection then closes after
  /// the answer, since where the next request would start is unknown; the answer should say so.
  bool body_incomplete(const httplib::Request& req) const;

  const ByteBudget& budget() const { return budget_; }
  const FrontConfig& front_config() const { return config_; }

 private:
  bool process_and_close_socket(socket_t sock) override;
  void serve_connection(Connection& conn);
  void refuse(Connection& conn, const RequestHead* head, Refusal refusal);
  Connection* connection_of(const httplib::Request& req) const;

  FrontConfig config_;
  Hooks hooks_;
  ByteBudget budget_;
  int listen_fd_ = -1;
  int effective_backlog_ = 0;
  std::atomic<std::int64_t> drain_deadline_ns_{0};  ///< 0 = not draining (steady clock)

  mutable std::mutex requests_mutex_;
  std::unordered_map<const httplib::Request*, Connection*> requests_;
};

}  // namespace seam::server
