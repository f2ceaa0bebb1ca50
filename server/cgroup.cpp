#include "server/cgroup.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <thread>

namespace seam::server {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

template <class T>
std::optional<T> number(std::string_view s) {
  s = trim(s);
  T v{};
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || ptr != s.data() + s.size() || s.empty()) return std::nullopt;
  return v;
}

std::optional<std::string> slurp(const char* path) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

}  // namespace

std::optional<double> parse_cpu_max(std::string_view text) {
  text = trim(text);
  const auto space = text.find(' ');
  if (space == std::string_view::npos) return std::nullopt;
  const auto quota = number<long long>(text.substr(0, space));  // "max" is no number
  const auto period = number<long long>(text.substr(space + 1));
  if (!quota || !period || *quota <= 0 || *period <= 0) return std::nullopt;
  return static_cast<double>(*quota) / static_cast<double>(*period);
}

std::optional<double> parse_cfs_quota(std::string_view quota_us, std::string_view period_us) {
  const auto quota = number<long long>(quota_us);
  const auto period = number<long long>(period_us);
  if (!quota || !period || *quota <= 0 || *period <= 0) return std::nullopt;
  return static_cast<double>(*quota) / static_cast<double>(*period);
}

std::optional<std::uint64_t> parse_memory_limit(std::string_view text) {
  const auto bytes = number<std::uint64_t>(text);
  // v1 reports "no limit" as LONG_MAX rounded down to a page: anything above 2^62 is none.
  if (!bytes || *bytes == 0 || *bytes >= (1ull << 62)) return std::nullopt;
  return bytes;
}

std::optional<double> cgroup_cpu_quota() {
  if (const auto v2 = slurp("/sys/fs/cgroup/cpu.max")) return parse_cpu_max(*v2);
  for (const char* dir : {"/sys/fs/cgroup/cpu,cpuacct", "/sys/fs/cgroup/cpu"}) {
    const auto quota = slurp((std::string(dir) + "/cpu.cfs_quota_us").c_str());
    const auto period = slurp((std::string(dir) + "/cpu.cfs_period_us").c_str());
    if (quota && period) return parse_cfs_quota(*quota, *period);
  }
  return std::nullopt;
}

std::optional<std::uint64_t> cgroup_memory_limit() {
  if (const auto v2 = slurp("/sys/fs/cgroup/memory.max")) return parse_memory_limit(*v2);
  if (const auto v1 = slurp("/sys/fs/cgroup/memory/memory.limit_in_bytes")) return parse_memory_limit(*v1);
  return std::nullopt;
}

unsigned available_cpus() {
  unsigned cpus = std::max(1u, std::thread::hardware_concurrency());
  if (const auto quota = cgroup_cpu_quota()) {
    cpus = std::min(cpus, std::max(1u, static_cast<unsigned>(std::ceil(*quota - 1e-9))));
  }
  return cpus;
}

}  // namespace seam::server
