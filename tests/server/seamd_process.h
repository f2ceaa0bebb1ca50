// The real seamd binary as a child process on a free loopback port, and a raw-socket client
// that speaks HTTP byte by byte: hostile traffic is tested against the process that ships,
// framed exactly as an attacker frames it (no client library in between to fix it up).
#pragma once

#include <doctest/doctest.h>

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace seam::test_process {

using Clock = std::chrono::steady_clock;

/// A port that was free a moment ago (the kernel does not hand it out again at once).
inline int free_port() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  REQUIRE(fd >= 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  REQUIRE(bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0);
  socklen_t len = sizeof addr;
  REQUIRE(getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) == 0);
  close(fd);
  return ntohs(addr.sin_port);
}

/// A connected TCP socket to 127.0.0.1:port, closed on destruction.
class RawConnection {
 public:
  explicit RawConnection(int port) : fd_(socket(AF_INET, SOCK_STREAM, 0)) {
    REQUIRE(fd_ >= 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<std::uint16_t>(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    connected_ = connect(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0;
  }
  ~RawConnection() {
    if (fd_ >= 0) close(fd_);
  }
  RawConnection(const RawConnection&) = delete;
  RawConnection& operator=(const RawConnection&) = delete;
  RawConnection(RawConnection&& o) noexcept : fd_(o.fd_), connected_(o.connected_) { o.fd_ = -1; }

  bool connected() const { return connected_; }
  int fd() const { return fd_; }

  /// Sends all bytes; false when the peer closed or reset (the server refused early).
  bool send(std::string_view bytes) {
    while (!bytes.empty()) {
      const auto n = ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL);
      if (n <= 0) return false;
      bytes.remove_prefix(static_cast<std::size_t>(n));
    }
    return true;
  }
  void shutdown_write() { ::shutdown(fd_, SHUT_WR); }

  /// Reads until the peer closes or `limit` passes; `reset` is set on ECONNRESET.
  std::string read_all(std::chrono::milliseconds limit, bool* reset = nullptr) {
    std::string out;
    const auto until = Clock::now() + limit;
    char buf[65536];
    while (Clock::now() < until) {
      pollfd p{fd_, POLLIN, 0};
      if (poll(&p, 1, 50) <= 0) continue;
      const auto n = recv(fd_, buf, sizeof buf, 0);
      if (n < 0 && reset && errno == ECONNRESET) *reset = true;
      if (n <= 0) break;
      out.append(buf, static_cast<std::size_t>(n));
    }
    return out;
  }

  /// Reads until `needle` appears in what was read, the peer closes, or `limit` passes.
  std::string read_until(std::string_view needle, std::chrono::milliseconds limit) {
    std::string out;
    const auto until = Clock::now() + limit;
    char buf[65536];
    while (Clock::now() < until && out.find(needle) == std::string::npos) {
      pollfd p{fd_, POLLIN, 0};
      if (poll(&p, 1, 50) <= 0) continue;
      const auto n = recv(fd_, buf, sizeof buf, 0);
      if (n <= 0) break;
      out.append(buf, static_cast<std::size_t>(n));
    }
    return out;
  }

 private:
  int fd_;
  bool connected_ = false;
};

/// The status code of the first response in `raw` (0 when there is none).
inline int status_of(std::string_view raw) {
  if (raw.substr(0, 9) != "HTTP/1.1 " || raw.size() < 12) return 0;
  return std::atoi(std::string(raw.substr(9, 3)).c_str());
}

/// Every response's status in `raw`, in order (pipelined answers; bodies framed by
/// Content-Length, 1xx and 204 without one).
inline std::vector<int> statuses_of(std::string_view raw) {
  std::vector<int> out;
  while (!raw.empty()) {
    const int status = status_of(raw);
    const auto head_end = raw.find("\r\n\r\n");
    if (status == 0 || head_end == std::string_view::npos) break;
    out.push_back(status);
    std::size_t length = 0;
    const auto head = raw.substr(0, head_end);
    if (const auto at = head.find("\r\nContent-Length: "); at != std::string_view::npos) {
      length = std::strtoull(std::string(head.substr(at + 18, 20)).c_str(), nullptr, 10);
    }
    raw.remove_prefix(std::min(raw.size(), head_end + 4 + length));
  }
  return out;
}

/// A header's value in the first response of `raw` (case-sensitive name), or "".
inline std::string header_of(std::string_view raw, std::string_view name) {
  const auto head_end = raw.find("\r\n\r\n");
  const auto head = raw.substr(0, head_end);
  const std::string key = "\r\n" + std::string(name) + ": ";
  const auto at = head.find(key);
  if (at == std::string_view::npos) return "";
  const auto from = at + key.size();
  return std::string(head.substr(from, head.find("\r\n", from) - from));
}

/// The body of the first response of `raw` (after its head).
inline std::string body_of(std::string_view raw) {
  const auto head_end = raw.find("\r\n\r\n");
  return head_end == std::string_view::npos ? std::string() : std::string(raw.substr(head_end + 4));
}

/// The error code of the JSON error body in `raw`'s first response ("" when there is none).
/// (No std::regex in these tests: GCC 12 warns inside <regex> with sanitizers, and warnings
/// are errors in CI.)
inline std::string error_code_in(std::string_view raw) {
  const auto body = body_of(raw);
  constexpr std::string_view key = "\"code\":\"";
  const auto at = body.find(key);
  if (at == std::string::npos) return "";
  const auto from = at + key.size();
  return body.substr(from, body.find('"', from) - from);
}

/// The value of an unlabelled Prometheus sample `name` in `metrics` text (-1 when absent).
inline long long metric_value(std::string_view metrics, std::string_view name) {
  const std::string key = "\n" + std::string(name) + " ";
  const auto at = metrics.find(key);
  if (at == std::string_view::npos) return -1;
  return std::atoll(std::string(metrics.substr(at + key.size(), 24)).c_str());
}

/// One request and its whole answer on a fresh connection (Connection: close is the caller's).
inline std::string exchange(int port, std::string_view request, std::chrono::milliseconds limit = std::chrono::seconds(30)) {
  RawConnection c(port);
  REQUIRE(c.connected());
  c.send(request);
  return c.read_all(limit);
}

/// `n` slow clients of `port`: each sends the start of a request (half a head that never
/// ends, half a POST head declaring a 100,000-byte body) and then one byte a second until
/// stop() or destruction.
class TricklingClients {
 public:
  TricklingClients(int port, int n) {
    for (int i = 0; i < n; ++i) {
      clients_.emplace_back(port);
      REQUIRE(clients_.back().connected());
      REQUIRE(clients_.back().send(i % 2 ? std::string("GET /healthz HTTP/1.1\r\nHost: t\r\nX-Slow: ")
                                         : "POST /seam HTTP/1.1\r\nHost: t\r\nContent-Type: model/gltf-binary\r\n"
                                           "Content-Length: 100000\r\nConnection: close\r\n\r\n"));
    }
    thread_ = std::thread([this] {
      while (!stop_) {
        for (auto& c : clients_) c.send("a");
        for (int i = 0; i < 20 && !stop_; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
    });
  }
  ~TricklingClients() { stop(); }
  TricklingClients(const TricklingClients&) = delete;
  TricklingClients& operator=(const TricklingClients&) = delete;

  void stop() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
  }
  /// The connections, e.g. to read what the server answered them (after stop()).
  std::vector<RawConnection>& connections() { return clients_; }

 private:
  std::vector<RawConnection> clients_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

/// seamd started with `args` (after --bind 127.0.0.1 --port P --log-level off); waits until
/// /healthz answers. Killed on destruction if still running.
class Seamd {
 public:
  /// `env`: NAME=VALUE entries added to (or replacing those of) the test's environment.
  explicit Seamd(std::vector<std::string> args, std::vector<std::string> env = {}) : port_(free_port()) {
    std::vector<std::string> all = {SEAMD_BINARY, "--bind", "127.0.0.1", "--port", std::to_string(port_), "--log-level", "off"};
    all.insert(all.end(), args.begin(), args.end());
    // Built before fork: the child only calls execve.
    for (char** e = environ; *e != nullptr; ++e) {
      const std::string entry = *e;
      const std::string name = entry.substr(0, entry.find('=') + 1);
      const bool replaced = std::any_of(env.begin(), env.end(), [&](const std::string& o) { return o.rfind(name, 0) == 0; });
      if (!replaced) env.push_back(entry);
    }
    std::vector<char*> argv, envp;
    for (auto& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    for (auto& e : env) envp.push_back(e.data());
    envp.push_back(nullptr);
    pid_ = fork();
    REQUIRE(pid_ >= 0);
    if (pid_ == 0) {
      execve(SEAMD_BINARY, argv.data(), envp.data());
      _exit(127);
    }
    bool up = false;
    for (int i = 0; i < 250 && !up && running(); ++i) {  // up to ~10 s under sanitizers
      RawConnection probe(port_);
      up = probe.connected() && probe.send("GET /healthz HTTP/1.1\r\nHost: t\r\nConnection: close\r\n\r\n") &&
           status_of(probe.read_all(std::chrono::milliseconds(500))) == 200;
      if (!up) std::this_thread::sleep_for(std::chrono::milliseconds(40));
    }
    if (!up) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
      FAIL("seamd did not answer /healthz");
    }
  }
  ~Seamd() {
    if (pid_ > 0 && running()) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }
  Seamd(const Seamd&) = delete;
  Seamd& operator=(const Seamd&) = delete;

  int port() const { return port_; }
  pid_t pid() const { return pid_; }

  /// True while the process has not exited (reaps it when it has).
  bool running() {
    if (exited_) return false;
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      exited_ = true;
      status_ = status;
      return false;
    }
    return true;
  }

  /// Waits up to `limit` for the process to exit; its wait status, or nullopt.
  std::optional<int> wait_exit(std::chrono::milliseconds limit) {
    const auto until = Clock::now() + limit;
    while (Clock::now() < until) {
      if (!running()) return status_;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return std::nullopt;
  }

  /// Resident set size in KiB (VmRSS), 0 when unreadable.
  long rss_kib() const {
    std::ifstream in("/proc/" + std::to_string(pid_) + "/status");
    std::string line;
    while (std::getline(in, line)) {
      if (line.rfind("VmRSS:", 0) == 0) return std::atol(line.c_str() + 6);
    }
    return 0;
  }

  /// GET path on a fresh connection; the raw answer.
  std::string get(const std::string& path, std::chrono::milliseconds limit = std::chrono::seconds(10)) const {
    return exchange(port_, "GET " + path + " HTTP/1.1\r\nHost: t\r\nConnection: close\r\n\r\n", limit);
  }

 private:
  int port_;
  pid_t pid_ = -1;
  bool exited_ = false;
  int status_ = 0;
};

/// A POST /seam request head with Content-Length for `body` of `type`.
inline std::string post_head(std::size_t length, std::string_view type = "model/gltf-binary",
                             std::string_view extra = "") {
  return "POST /seam HTTP/1.1\r\nHost: t\r\nContent-Type: " + std::string(type) +
         "\r\nContent-Length: " + std::to_string(length) + "\r\n" + std::string(extra) + "Connection: close\r\n\r\n";
}

}  // namespace seam::test_process
