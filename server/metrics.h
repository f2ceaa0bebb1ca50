// Request metrics in the Prometheus text exposition format (version 0.0.4).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <utility>

namespace seam::server {

/// Gauges sampled at scrape time (owned by the worker pool and the server).
struct GaugeSnapshot {
  std::size_t queue_depth = 0;
  std::size_t busy_workers = 0;
  std::size_t workers = 0;
  std::size_t queue_capacity = 0;
  std::size_t in_flight = 0;  ///< requests being handled now (all routes)
  std::uint64_t inflight_bytes = 0;        ///< bytes held by requests in flight (front budget)
  std::uint64_t inflight_bytes_limit = 0;  ///< --max-inflight-bytes
  bool draining = false;
};

/// Thread-safe counters and a latency histogram per route. One instance per Server.
class Metrics {
 public:
  /// Upper bounds of the latency buckets, in seconds (+Inf is implicit).
  static constexpr std::array<double, 14> kLatencyBuckets = {0.001, 0.005, 0.01, 0.025, 0.05, 0.1, 0.25,
                                                             0.5,   1.0,   2.5,  5.0,   10.0, 30.0, 60.0};

  /// Records one finished request. `route` must come from a fixed set (e.g. "/seam",
  /// "other") so label cardinality stays bounded. O(log routes) under one mutex.
  void record(const std::string& route, int status, double seconds, std::size_t bytes_in,
              std::size_t bytes_out);

  /// Renders every metric with HELP/TYPE lines. O(routes * statuses + buckets).
  std::string render(const GaugeSnapshot& gauges) const;

  /// Requests recorded so far with this route and status (for tests).
  std::uint64_t count(const std::string& route, int status) const;

 private:
  struct Histogram {
    std::array<std::uint64_t, kLatencyBuckets.size()> buckets{};  // non-cumulative counts
    std::uint64_t count = 0;
    double sum = 0;
  };

  mutable std::mutex mutex_;
  std::map<std::pair<std::string, int>, std::uint64_t> requests_;
  std::map<std::string, Histogram> latency_;
  std::uint64_t bytes_in_ = 0;
  std::uint64_t bytes_out_ = 0;
};

}  // namespace seam::server
