// The production front as shipped: docker/nginx.conf (upstream and listen lines rewritten to
// loopback ports) run by Debian's nginx in front of the real seamd. Slow clients are held by
// nginx, which buffers requests whole; seamd never sees them (issue 10, item 4).
#include <doctest/doctest.h>

#include "api/sample_mesh.h"

#include <filesystem>

#include "seamd_process.h"

namespace seam_nginx_front_test {

using namespace seam::test_process;
using namespace std::chrono_literals;

namespace {

constexpr const char* kNginx = "/usr/sbin/nginx";

std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// nginx with docker/nginx.conf in a scratch prefix, proxying to 127.0.0.1:upstream.
class NginxFront {
 public:
  explicit NginxFront(int upstream) : port_(free_port()) {
    char dir_template[] = "/tmp/seam-nginx-XXXXXX";
    REQUIRE(mkdtemp(dir_template) != nullptr);
    dir_ = dir_template;
    std::string conf = read_file(std::filesystem::path(SEAM_SOURCE_DIR) / "docker" / "nginx.conf");
    REQUIRE_FALSE(conf.empty());
    auto replace = [&](const std::string& from, const std::string& to) {
      const auto at = conf.find(from);
      REQUIRE_MESSAGE(at != std::string::npos, from);
      conf.replace(at, from.size(), to);
    };
    replace("server seamd:8080", "server 127.0.0.1:" + std::to_string(upstream));
    replace("listen 8080", "listen 127.0.0.1:" + std::to_string(port_));
    replace("pid /tmp/nginx.pid", "pid " + (dir_ / "nginx.pid").string());
    replace("/var/log/nginx/access.log", (dir_ / "access.log").string());
    std::ofstream(dir_ / "nginx.conf") << conf;
    const std::string globals = "daemon off; master_process on; error_log " + (dir_ / "error.log").string() + ";";
    pid_ = fork();
    REQUIRE(pid_ >= 0);
    if (pid_ == 0) {
      const std::string conf_path = (dir_ / "nginx.conf").string(), prefix = dir_.string();
      execl(kNginx, kNginx, "-p", prefix.c_str(), "-c", conf_path.c_str(), "-g", globals.c_str(), static_cast<char*>(nullptr));
      _exit(127);
    }
    bool up = false;
    for (int i = 0; i < 100 && !up; ++i) {
      RawConnection probe(port_);
      up = probe.connected() && probe.send("GET /healthz HTTP/1.1\r\nHost: t\r\nConnection: close\r\n\r\n") &&
           status_of(probe.read_all(500ms)) == 200;
      if (!up) std::this_thread::sleep_for(50ms);
    }
    if (!up) MESSAGE("nginx error log: " << read_file(dir_ / "error.log"));
    REQUIRE(up);
  }
  ~NginxFront() {
    kill(pid_, SIGTERM);
    waitpid(pid_, nullptr, 0);
    std::filesystem::remove_all(dir_);
  }
  int port() const { return port_; }

 private:
  int port_;
  pid_t pid_ = -1;
  std::filesystem::path dir_;
};

long long in_flight(Seamd& seamd) {
  return metric_value(body_of(seamd.get("/metrics")), "seamd_in_flight_requests");
}

}  // namespace

TEST_CASE("nginx front (docker/nginx.conf): slow clients stay in nginx, honest requests pass, limits hold") {
  if (!std::filesystem::exists(kNginx)) {
    MESSAGE("skipped: " << kNginx << " is missing (scripts/install-deps.sh --test installs it)");
    return;
  }
  auto glb = seam::api::sample_glb();
  REQUIRE(glb.ok());
  Seamd seamd({"--workers", "2"});
  NginxFront nginx(seamd.port());

  TricklingClients slow(nginx.port(), 80);
  int probes = 0, healthy = 0;
  long long most_in_seamd = 0;
  for (const auto until = Clock::now() + 3s; Clock::now() < until; ++probes) {
    healthy += status_of(exchange(nginx.port(), "GET /healthz HTTP/1.1\r\nHost: t\r\nConnection: close\r\n\r\n", 2s)) == 200;
    most_in_seamd = std::max(most_in_seamd, in_flight(seamd));
    std::this_thread::sleep_for(100ms);
  }
  const auto seam = exchange(nginx.port(), post_head(glb->size()) + *glb, 60s);
  slow.stop();
  MESSAGE("through nginx with 80 slow clients: /healthz " << healthy << "/" << probes
                                                           << ", at most " << most_in_seamd << " seam request(s) in flight in seamd");
  CHECK(healthy == probes);
  CHECK(status_of(seam) == 200);
  CHECK(most_in_seamd == 0);  // the slow POSTs never reach seamd: nginx holds them

  const auto too_large = exchange(nginx.port(), post_head(300'000'000), 10s);
  CHECK(status_of(too_large) == 413);
  CHECK(body_of(too_large).find("\"payload_too_large\"") != std::string::npos);
  std::string ranges = "bytes=0-";
  for (int i = 0; i < 500; ++i) ranges += ",0-";
  const auto ranged = exchange(nginx.port(), "GET /version HTTP/1.1\r\nHost: t\r\nRange: " + ranges + "\r\nConnection: close\r\n\r\n");
  CHECK(status_of(ranged) == 200);
  CHECK(body_of(ranged) == body_of(seamd.get("/version")));
}

}  // namespace seam_nginx_front_test
