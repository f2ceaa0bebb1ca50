// seamd's configuration: flags over environment over defaults, every value range-checked.
#include "server/config.h"
#include "server/cgroup.h"

#include <doctest/doctest.h>

#include <map>
#include <string>
#include <vector>

namespace seam_config_test {

namespace {

using seam::server::parse_config;

struct Args {
  std::vector<std::string> words;
  std::vector<const char*> ptrs;
  explicit Args(std::vector<std::string> w) : words(std::move(w)) {
    words.insert(words.begin(), "seamd");
    for (auto& s : words) ptrs.push_back(s.c_str());
  }
  int argc() const { return static_cast<int>(ptrs.size()); }
  const char* const* argv() const { return ptrs.data(); }
};

seam::server::EnvLookup env_of(std::map<std::string, std::string> vars) {
  return [vars = std::move(vars)](const char* name) -> const char* {
    const auto it = vars.find(name);
    return it == vars.end() ? nullptr : it->second.c_str();
  };
}

}  // namespace

TEST_CASE("config: defaults, environment, flags, precedence") {
  const Args none({});
  auto d = parse_config(none.argc(), none.argv(), env_of({}));
  REQUIRE(d.ok());
  CHECK(d->config.port == 8080);
  CHECK(d->config.bind == "0.0.0.0");
  CHECK(!d->help);
  CHECK(seam::server::effective_workers(d->config) >= 1);
  CHECK(seam::server::effective_http_threads(d->config) >= 64);

  const Args flags({"--port", "9000", "--workers=3", "--queue", "5", "--time-budget-ms", "1500", "--log-level=warn",
                    "--max-body-bytes", "1048576", "--max-faces", "1000", "--bind", "127.0.0.1"});
  auto env = env_of({{"SEAMD_PORT", "7000"}, {"SEAMD_QUEUE", "9"}, {"SEAMD_READ_TIMEOUT_S", "7"}});
  auto c = parse_config(flags.argc(), flags.argv(), env);
  REQUIRE(c.ok());
  CHECK(c->config.port == 9000);         // flag beats environment
  CHECK(c->config.queue == 5);           // flag beats environment
  CHECK(c->config.read_timeout_s == 7);  // environment beats default
  CHECK(c->config.workers == 3);
  CHECK(c->config.time_budget.count() == 1500);
  CHECK(c->config.log_level == "warn");
  CHECK(c->config.max_body_bytes == 1048576);
  CHECK(c->config.max_faces == 1000);
  CHECK(c->config.bind == "127.0.0.1");
  CHECK(seam::server::effective_workers(c->config) == 3);
}

TEST_CASE("config: bad values name the flag or variable and the range") {
  struct Bad {
    std::vector<std::string> args;
    std::map<std::string, std::string> env;
    std::string mentions;
  };
  const std::vector<Bad> cases = {
      {{"--port", "70000"}, {}, "--port"},
      {{"--port", "80a"}, {}, "[0, 65535]"},
      {{"--workers"}, {}, "needs a value"},
      {{"--frobnicate", "1"}, {}, "unknown flag --frobnicate"},
      {{"serve"}, {}, "unexpected argument"},
      {{"--log-level", "loud"}, {}, "trace|debug"},
      {{"--time-budget-ms", "0"}, {}, "--time-budget-ms"},
      {{}, {{"SEAMD_WORKERS", "-1"}}, "SEAMD_WORKERS"},
  };
  for (const auto& b : cases) {
    const Args a(b.args);
    auto r = parse_config(a.argc(), a.argv(), env_of(b.env));
    CAPTURE(b.mentions);
    REQUIRE(!r.ok());
    CHECK(r.error().code == seam::api::ApiErrorCode::kInvalidParameter);
    CHECK(r.error().message.find(b.mentions) != std::string::npos);
  }
}

TEST_CASE("config: --help lists every flag with its environment variable") {
  const Args a({"--help"});
  auto r = parse_config(a.argc(), a.argv(), env_of({}));
  REQUIRE(r.ok());
  CHECK(r->help);
  const auto text = seam::server::help_text();
  for (const char* pair : {"--port", "SEAMD_PORT", "--bind", "SEAMD_BIND", "--workers", "SEAMD_WORKERS", "--queue",
                           "SEAMD_QUEUE", "--max-body-bytes", "--time-budget-ms", "--max-faces", "--log-level",
                           "--read-timeout-s", "--write-timeout-s", "--drain-timeout-s", "seamd seam", "seamd sample"}) {
    CAPTURE(pair);
    CHECK(text.find(pair) != std::string::npos);
  }
}

TEST_CASE("config: cgroup quota and memory limit parsing (v2 and v1)") {
  using namespace seam::server;
  CHECK(parse_cpu_max("max 100000\n") == std::nullopt);
  CHECK(parse_cpu_max("200000 100000\n") == std::optional<double>(2.0));
  CHECK(parse_cpu_max("150000 100000") == std::optional<double>(1.5));
  CHECK(parse_cpu_max("garbage") == std::nullopt);
  CHECK(parse_cfs_quota("-1\n", "100000\n") == std::nullopt);
  CHECK(parse_cfs_quota("50000\n", "100000\n") == std::optional<double>(0.5));
  CHECK(parse_memory_limit("max\n") == std::nullopt);
  CHECK(parse_memory_limit("9223372036854771712\n") == std::nullopt);  // v1's "no limit"
  CHECK(parse_memory_limit("4294967296\n") == std::optional<std::uint64_t>(4294967296ull));
  CHECK(available_cpus() >= 1);
}

TEST_CASE("config: the face limit follows the memory limit, and the drain covers the budget") {
  using namespace seam::server;
  ServerConfig c;
  c.workers = 2;
  c.memory_limit_bytes = 0;
  c.max_faces = 5'000'000;
  if (!cgroup_memory_limit()) CHECK(effective_max_faces(c) == 5'000'000);  // no limit: as configured
  c.memory_limit_bytes = 4ull << 30;
  const auto fit = effective_max_faces(c);
  // Two jobs of `fit` faces plus the bases fit in 4 GiB, two of fit + 1% do not.
  CHECK(effective_inflight_bytes(c) == 1ull << 30);  // a quarter of the limit, below the 4 GiB default
  const auto need = [&](std::size_t faces) {
    return kServerBaseBytes + effective_inflight_bytes(c) + 2 * (kJobBaseBytes + faces * kJobBytesPerFace);
  };
  CHECK(need(fit) <= c.memory_limit_bytes);
  CHECK(need(fit + fit / 100 + 1) > c.memory_limit_bytes);
  c.memory_limit_bytes = 64ull << 40;
  CHECK(effective_max_faces(c) == 5'000'000);  // never above --max-faces
  c.memory_limit_bytes = 1;
  CHECK(effective_max_faces(c) == 1);          // nothing fits: every mesh is a 422, never an OOM

  c.drain_timeout_s = 0;
  c.time_budget = std::chrono::milliseconds(60'000);
  CHECK(effective_drain_timeout_s(c) == 65);
  c.time_budget = std::chrono::milliseconds(1'500);
  CHECK(effective_drain_timeout_s(c) == 7);
  c.drain_timeout_s = 3;
  CHECK(effective_drain_timeout_s(c) == 3);
}

}  // namespace seam_config_test
