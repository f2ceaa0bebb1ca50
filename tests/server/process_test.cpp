// The real seamd binary as a process: it serves, and SIGTERM or SIGINT make it drain and exit
// 0. (Once it blocked the signals and took them with sigwait; OpenBLAS's thread, started before
// main, did not block them, so SIGTERM killed the process with 143, or, as PID 1 in a
// container, was dropped until podman's SIGKILL.)
#include <doctest/doctest.h>

#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
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

}  // namespace

TEST_CASE("seamd as a process: SIGTERM and SIGINT drain it and it exits 0") {
  for (int sig : {SIGTERM, SIGINT}) {
    CAPTURE(sig);
    const int port = free_port();
    const std::string port_arg = std::to_string(port);
    const pid_t pid = fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
      execl(SEAMD_BINARY, SEAMD_BINARY, "--bind", "127.0.0.1", "--port", port_arg.c_str(), "--workers", "1",
            "--log-level", "off", static_cast<char*>(nullptr));
      _exit(127);
    }
    httplib::Client client("127.0.0.1", port);
    client.set_connection_timeout(std::chrono::milliseconds(200));
    bool up = false;
    for (int i = 0; i < 250 && !up; ++i) {  // up to ~10 s under sanitizers
      auto res = client.Get("/healthz");
      up = res && res->status == 200;
      if (!up) std::this_thread::sleep_for(std::chrono::milliseconds(40));
    }
    CHECK(up);
    REQUIRE(kill(pid, sig) == 0);
    const int status = wait_for_exit(pid, std::chrono::seconds(15));
    if (status == -1) {
      kill(pid, SIGKILL);
      waitpid(pid, nullptr, 0);
      FAIL("seamd did not exit within 15 s of the signal");
    }
    CHECK(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 0);
  }
}
