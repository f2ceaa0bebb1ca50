// A real seam server on 127.0.0.1 with an ephemeral port, run on its own thread, for the
// end-to-end tests. Include after any header that pulls in Eigen (httplib's <resolv.h>).
#pragma once

#include <doctest/doctest.h>

#include <chrono>
#include <memory>
#include <string>
#include <thread>

#include "server/server.h"

#include <httplib.h>

namespace seam::test_server {

/// Test defaults: loopback only, ephemeral port, quiet, small pool, short keep-alive so a
/// shutdown does not wait on idle connections.
inline server::ServerConfig test_config() {
  server::ServerConfig c;
  c.bind = "127.0.0.1";
  c.port = 0;
  c.workers = 2;
  c.queue = 2;
  c.log_level = "off";
  c.keep_alive_timeout_s = 1;
  c.drain_timeout_s = 20;
  c.time_budget = std::chrono::milliseconds(30'000);
  return c;
}

class RunningServer {
 public:
  explicit RunningServer(server::ServerConfig config, server::SeamJob job = {})
      : server_(std::make_unique<server::Server>(std::move(config), std::move(job))) {
    auto port = server_->bind();
    REQUIRE_MESSAGE(port.ok(), (port.ok() ? "" : port.error().message));
    thread_ = std::thread([this] { server_->run(); });
    // httplib 0.11 has no wait_until_ready(): poll is_running() (shared/notes/stack.md).
    for (int i = 0; i < 5000 && !server_->is_running(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    REQUIRE(server_->is_running());
  }
  ~RunningServer() { stop(); }

  /// Sends the shutdown and waits for run() to return (every in-flight request answered).
  void stop() {
    if (!thread_.joinable()) return;
    server_->shutdown();
    thread_.join();
  }

  std::unique_ptr<httplib::Client> client(int read_timeout_s = 60) const {
    auto c = std::make_unique<httplib::Client>("127.0.0.1", server_->port());
    c->set_read_timeout(read_timeout_s, 0);
    c->set_write_timeout(30, 0);
    c->set_connection_timeout(5, 0);
    return c;
  }

  server::Server& server() { return *server_; }
  int port() const { return server_->port(); }

 private:
  std::unique_ptr<server::Server> server_;
  std::thread thread_;
};

/// The parsed error code of a JSON error body ("" when the body is not one).
inline std::string error_code_of(const std::string& body) {
  auto j = nlohmann::json::parse(body, nullptr, false);
  if (j.is_discarded() || !j.contains("error") || !j["error"].contains("code")) return "";
  return j["error"]["code"].get<std::string>();
}

}  // namespace seam::test_server
