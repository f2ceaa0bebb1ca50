// The real seamd binary as a process: it serves, and SIGTERM or SIGINT make it drain and exit
// 0. (Once it blocked the signals and took them with sigwait; OpenBLAS's thread, started before
// main, did not block them, so SIGTERM killed the process with 143, or, as PID 1 in a
// container, was dropped until podman's SIGKILL.)
#include <doctest/doctest.h>

#include "api/gltf_writer.h"
#include "test_data.h"

#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <future>
#include <string>
#include <thread>

#include <httplib.h>

namespace {

// A port that was free a moment ago (the kernel does not hand it out again at once).
int free_port() {
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

// Waits up to `limit` for the child; returns its wait status, or -1 if it is still running.
int wait_for_exit(pid_t pid, std::chrono::milliseconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < deadline) {
    int status = 0;
    if (waitpid(pid, &status, WNOHANG) == pid) return status;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return -1;
}

// Starts seamd on a free loopback port and waits until /healthz answers.
struct Seamd {
  pid_t pid = -1;
  int port = 0;
};

Seamd start_seamd(const char* workers) {
  Seamd s;
  s.port = free_port();
  const std::string port_arg = std::to_string(s.port);
  s.pid = fork();
  REQUIRE(s.pid >= 0);
  if (s.pid == 0) {
    execl(SEAMD_BINARY, SEAMD_BINARY, "--bind", "127.0.0.1", "--port", port_arg.c_str(), "--workers", workers,
          "--log-level", "off", static_cast<char*>(nullptr));
    _exit(127);
  }
  httplib::Client client("127.0.0.1", s.port);
  client.set_connection_timeout(std::chrono::milliseconds(200));
  bool up = false;
  for (int i = 0; i < 250 && !up; ++i) {  // up to ~10 s under sanitizers
    auto res = client.Get("/healthz");
    up = res && res->status == 200;
    if (!up) std::this_thread::sleep_for(std::chrono::milliseconds(40));
  }
  CHECK(up);
  return s;
}

// Signals seamd and returns its wait status (-1 and a failure if it does not exit in 60 s).
int stop_seamd(const Seamd& s, int sig) {
  REQUIRE(kill(s.pid, sig) == 0);
  const int status = wait_for_exit(s.pid, std::chrono::seconds(60));
  if (status == -1) {
    kill(s.pid, SIGKILL);
    waitpid(s.pid, nullptr, 0);
    FAIL("seamd did not exit within 60 s of the signal");
  }
  return status;
}

}  // namespace

TEST_CASE("seamd as a process: SIGTERM and SIGINT drain it and it exits 0") {
  for (int sig : {SIGTERM, SIGINT}) {
    CAPTURE(sig);
    const Seamd seamd = start_seamd("1");
    const int status = stop_seamd(seamd, sig);
    CHECK(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 0);
  }
}

TEST_CASE("seamd as a process: a request in flight at SIGTERM is answered, then it exits 0") {
  // The camel with automatic extrema, skeleton seam and SLIM UVs: a few hundred ms of work.
  auto glb = seam::api::write_plain_glb(seam::test_data::load_cgal("camel"));
  REQUIRE(glb.ok());
  const Seamd seamd = start_seamd("1");
  auto answer = std::async(std::launch::async, [&] {
    httplib::Client client("127.0.0.1", seamd.port);
    client.set_read_timeout(std::chrono::seconds(60));
    auto res = client.Post("/seam", *glb, "model/gltf-binary");
    return res ? res->status : -1;
  });
  // Signal once the request is on its way (it may also have finished: then this is the plain
  // case above).
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  const int status = stop_seamd(seamd, SIGTERM);
  CHECK(answer.get() == 200);
  CHECK(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 0);
}
