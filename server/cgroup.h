// What the container may use: the cgroup's CPU quota and memory limit (v2 and v1), so that
// worker and thread defaults follow the quota rather than the node's core count (a 2-CPU pod
// on a 64-core node must not start 64 threads per request), and the face limit follows the
// memory limit (a job that would not fit is a 422, not an OOM kill of the pod).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace seam::server {

/// v2 `cpu.max` ("max 100000" or "200000 100000"): the quota in CPUs, nullopt when unlimited
/// or unreadable. O(1).
std::optional<double> parse_cpu_max(std::string_view text);
/// v1 `cpu.cfs_quota_us` and `cpu.cfs_period_us`: the quota in CPUs, nullopt for -1. O(1).
std::optional<double> parse_cfs_quota(std::string_view quota_us, std::string_view period_us);
/// v2 `memory.max` ("max" or bytes) or v1 `memory.limit_in_bytes` (a page-rounded 2^63 when
/// unlimited): the limit in bytes, nullopt when unlimited or unreadable. O(1).
std::optional<std::uint64_t> parse_memory_limit(std::string_view text);

/// The CPU quota of this process's cgroup (v2 first, then v1), nullopt when none.
std::optional<double> cgroup_cpu_quota();
/// The memory limit of this process's cgroup (v2 first, then v1), nullopt when none.
std::optional<std::uint64_t> cgroup_memory_limit();

/// The CPUs this process may use: the hardware concurrency, capped by the cgroup quota
/// (rounded up: a 1.5-CPU quota gives 2), at least 1.
unsigned available_cpus();

}  // namespace seam::server
