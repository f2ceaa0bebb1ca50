// The real seamd binary as a process: it serves, and SIGTERM or SIGINT make it drain and exit
// 0. (Once it blocked the signals and took them with sigwait; OpenBLAS's thread, started before
// main, did not block them, so SIGTERM killed the process with 143, or, as PID 1 in a
// container, was dropped until podman's SIGKILL.)
#include <doctest/doctest.h>

#include "api/gltf_writer.h"
#include "api/process_env.h"
#include "test_data.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <future>

#include "seamd_process.h"

#include <httplib.h>
#include <nlohmann/json.hpp>

namespace seam_process_test {

using namespace seam::test_process;

namespace {

// Signals seamd and returns its wait status (a failure if it does not exit in 60 s).
int stop_seamd(Seamd& s, int sig) {
  REQUIRE(kill(s.pid(), sig) == 0);
  const auto status = s.wait_exit(std::chrono::seconds(60));
  REQUIRE_MESSAGE(status.has_value(), "seamd did not exit within 60 s of the signal");
  return *status;
}

}  // namespace

TEST_CASE("seamd as a process: SIGTERM and SIGINT drain it and it exits 0") {
  for (int sig : {SIGTERM, SIGINT}) {
    CAPTURE(sig);
    Seamd seamd({"--workers", "1"});
    const int status = stop_seamd(seamd, sig);
    CHECK(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 0);
  }
}

TEST_CASE("seamd as a process: a request in flight at SIGTERM is answered, then it exits 0") {
  // The camel with automatic extrema, skeleton seam and SLIM UVs: a few hundred ms of work.
  auto glb = seam::api::write_plain_glb(seam::test_data::load_cgal("camel"));
  REQUIRE(glb.ok());
  Seamd seamd({"--workers", "1"});
  auto answer = std::async(std::launch::async, [&] {
    httplib::Client client("127.0.0.1", seamd.port());
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

TEST_CASE("seamd as a process: SIGTERM while several jobs are in METIS and OpenBLAS drains, never crashes") {
  // METIS (CHOLMOD's nested-dissection ordering of the flattening) installs a SIGTERM handler
  // that longjmps for the length of each call: a SIGTERM handled while jobs were in it crashed
  // seamd with SIGSEGV. Now no thread of seamd's runs a handler for it (see server/main.cpp).
  auto glb = seam::api::write_plain_glb(seam::test_data::load_cgal("elephant"));
  REQUIRE(glb.ok());
  for (int delay_ms : {150, 300, 450}) {
    CAPTURE(delay_ms);
    Seamd seamd({"--workers", "2", "--queue", "8"});
    std::vector<std::future<int>> answers;
    for (int c = 0; c < 6; ++c) {
      answers.push_back(std::async(std::launch::async, [&] {
        httplib::Client client("127.0.0.1", seamd.port());
        client.set_read_timeout(std::chrono::seconds(60));
        auto res = client.Post("/seam", *glb, "model/gltf-binary");
        return res ? res->status : -1;
      }));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
    const int status = stop_seamd(seamd, SIGTERM);
    CHECK_MESSAGE(WIFEXITED(status), "seamd ended by signal " << (WIFSIGNALED(status) ? WTERMSIG(status) : 0));
    CHECK(WEXITSTATUS(status) == 0);
    for (auto& a : answers) {
      const int code = a.get();
      CHECK((code == 200 || code == 503 || code == -1));  // answered, refused while draining, or closed
    }
  }
}

TEST_CASE("seamd as a process: slow clients at SIGTERM do not outlast the drain timeout") {
  Seamd seamd({"--workers", "1", "--drain-timeout-s", "2", "--request-timeout-s", "60"});
  // One client trickling its head, one idle keep-alive connection, one that sent nothing.
  RawConnection trickling(seamd.port()), idle(seamd.port()), silent(seamd.port());
  REQUIRE(trickling.send("GET /healthz HTTP/1.1\r\nHo"));
  REQUIRE(idle.send("GET /healthz HTTP/1.1\r\nHost: t\r\n\r\n"));
  CHECK(status_of(idle.read_until("\r\n\r\n", std::chrono::seconds(5))) == 200);
  std::atomic<bool> stop{false};
  std::thread trickle([&] {
    while (!stop && trickling.send("x")) std::this_thread::sleep_for(std::chrono::milliseconds(500));
  });
  const auto signalled = Clock::now();
  const int status = stop_seamd(seamd, SIGTERM);
  const double seconds = std::chrono::duration<double>(Clock::now() - signalled).count();
  stop = true;
  trickle.join();
  MESSAGE("exit " << seconds << " s after SIGTERM with a trickling, an idle and a silent client");
  CHECK(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 0);
  CHECK(seconds < 2.0 + 3.0);  // the drain timeout plus the poll slices and process exit
}

namespace {

// The process's environment, as the kernel holds it: NAME=VALUE entries.
std::vector<std::string> environment_of(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/environ", std::ios::binary);
  std::vector<std::string> entries;
  std::string entry;
  while (std::getline(in, entry, '\0')) entries.push_back(entry);
  return entries;
}

bool has_entry(const std::vector<std::string>& env, const std::string& entry) {
  return std::find(env.begin(), env.end(), entry) != env.end();
}

bool has_name(const std::vector<std::string>& env, const std::string& name) {
  return std::any_of(env.begin(), env.end(), [&](const std::string& e) { return e.rfind(name + "=", 0) == 0; });
}

}  // namespace

TEST_CASE("seamd as a process: it executes itself once, with single-threaded BLAS and malloc as it found it") {
  // An empty GLIBC_TUNABLES, as a shell script may export: seamd adds nothing to it
  // (api/process_env.h: huge pages are the caller's choice).
  Seamd seamd({"--workers", "1"}, {"GLIBC_TUNABLES="});
  const auto env = environment_of(seamd.pid());
  REQUIRE_FALSE(env.empty());
  CHECK(has_entry(env, "GLIBC_TUNABLES="));
  if (std::getenv("OPENBLAS_NUM_THREADS") == nullptr) {
    CHECK(has_entry(env, "SEAMD_REEXECUTED=1"));
    CHECK(has_entry(env, "OPENBLAS_NUM_THREADS=1"));
  }
  // It still serves a job.
  auto glb = seam::api::write_plain_glb(seam::test_data::load_cgal("camel"));
  REQUIRE(glb.ok());
  httplib::Client client("127.0.0.1", seamd.port());
  client.set_read_timeout(std::chrono::seconds(60));
  auto res = client.Post("/seam", *glb, "model/gltf-binary");
  REQUIRE(res);
  CHECK(res->status == 200);
}

TEST_CASE("seamd as a process: settings the caller gives are kept, and then it starts only once") {
  Seamd seamd({"--workers", "1"}, {"GLIBC_TUNABLES=glibc.malloc.hugetlb=1", "OPENBLAS_NUM_THREADS=1"});
  const auto env = environment_of(seamd.pid());
  REQUIRE_FALSE(env.empty());
  CHECK(has_entry(env, "GLIBC_TUNABLES=glibc.malloc.hugetlb=1"));
  CHECK_FALSE(has_name(env, "SEAMD_REEXECUTED"));
}

TEST_CASE("seamd seam executed again for a large input still reads --params from a pipe") {
  // The armadillo as a GLB (~630 KB) is over api::kReexecInputBytes, so `seamd seam` starts a second
  // time; the parameters on stdin must reach that start unread (the first one read them and
  // the second found the pipe empty before the fix).
  auto glb = seam::api::write_plain_glb(seam::test_data::load_cgal("armadillo"));
  REQUIRE(glb.ok());
  REQUIRE(glb->size() >= seam::api::kReexecInputBytes);
  const std::string dir = (std::filesystem::temp_directory_path() /
                           ("seamd_reexec_" + std::to_string(getpid()))).string();
  std::filesystem::create_directories(dir);
  const std::string in = dir + "/armadillo.glb";
  const std::string out = dir + "/out.glb";
  std::ofstream(in, std::ios::binary).write(glb->data(), static_cast<std::streamsize>(glb->size()));
  // Without the settings in the environment, so that the second start happens.
  const std::string command = "printf '{\"uv\": \"bff\"}' | env -u GLIBC_TUNABLES -u OPENBLAS_NUM_THREADS -u "
                              "SEAMD_REEXECUTED " SEAMD_BINARY " seam " + in + " " + out + " --params @/dev/stdin";
  std::FILE* pipe = popen(command.c_str(), "r");
  REQUIRE(pipe != nullptr);
  std::string summary;
  char buffer[4096];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) summary.append(buffer, n);
  const int status = pclose(pipe);
  CAPTURE(summary);
  CHECK(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 0);
  const auto json = nlohmann::json::parse(summary, nullptr, false);
  REQUIRE_FALSE(json.is_discarded());
  CHECK(json["uv"]["method"] == "bff");
  CHECK(std::filesystem::file_size(out) > 0);
  std::filesystem::remove_all(dir);
}

}  // namespace seam_process_test
