#include "server/metrics.h"

#include <sstream>

namespace seam::server {

void Metrics::record(const std::string& route, int status, double seconds, std::size_t bytes_in,
                     std::size_t bytes_out) {
  std::lock_guard lock(mutex_);
  ++requests_[{route, status}];
  auto& h = latency_[route];
  std::size_t b = 0;
  while (b < kLatencyBuckets.size() && seconds > kLatencyBuckets[b]) ++b;
  if (b < kLatencyBuckets.size()) ++h.buckets[b];
  ++h.count;
  h.sum += seconds;
  bytes_in_ += bytes_in;
  bytes_out_ += bytes_out;
}

std::uint64_t Metrics::count(const std::string& route, int status) const {
  std::lock_guard lock(mutex_);
  const auto it = requests_.find({route, status});
  return it == requests_.end() ? 0 : it->second;
}

std::string Metrics::render(const GaugeSnapshot& g) const {
  std::ostringstream os;
  os.precision(10);
  std::lock_guard lock(mutex_);
  os << "# HELP seamd_requests_total HTTP requests by route and status.\n"
     << "# TYPE seamd_requests_total counter\n";
  for (const auto& [key, n] : requests_) {
    os << "seamd_requests_total{route=\"" << key.first << "\",status=\"" << key.second << "\"} " << n << "\n";
  }
  os << "# HELP seamd_request_duration_seconds Request latency from headers read to response built.\n"
     << "# TYPE seamd_request_duration_seconds histogram\n";
  for (const auto& [route, h] : latency_) {
    std::uint64_t cumulative = 0;
    for (std::size_t b = 0; b < kLatencyBuckets.size(); ++b) {
      cumulative += h.buckets[b];
      os << "seamd_request_duration_seconds_bucket{route=\"" << route << "\",le=\"" << kLatencyBuckets[b]
         << "\"} " << cumulative << "\n";
    }
    os << "seamd_request_duration_seconds_bucket{route=\"" << route << "\",le=\"+Inf\"} " << h.count << "\n"
       << "seamd_request_duration_seconds_sum{route=\"" << route << "\"} " << h.sum << "\n"
       << "seamd_request_duration_seconds_count{route=\"" << route << "\"} " << h.count << "\n";
  }
  os << "# HELP seamd_request_bytes_total Request body bytes received.\n"
     << "# TYPE seamd_request_bytes_total counter\n"
     << "seamd_request_bytes_total " << bytes_in_ << "\n"
     << "# HELP seamd_response_bytes_total Response body bytes sent.\n"
     << "# TYPE seamd_response_bytes_total counter\n"
     << "seamd_response_bytes_total " << bytes_out_ << "\n"
     << "# HELP seamd_queue_depth Seam jobs admitted and waiting for a worker.\n"
     << "# TYPE seamd_queue_depth gauge\n"
     << "seamd_queue_depth " << g.queue_depth << "\n"
     << "# HELP seamd_queue_capacity Seam jobs allowed to wait beyond the busy workers.\n"
     << "# TYPE seamd_queue_capacity gauge\n"
     << "seamd_queue_capacity " << g.queue_capacity << "\n"
     << "# HELP seamd_busy_workers Workers computing a seam now.\n"
     << "# TYPE seamd_busy_workers gauge\n"
     << "seamd_busy_workers " << g.busy_workers << "\n"
     << "# HELP seamd_workers Size of the compute pool.\n"
     << "# TYPE seamd_workers gauge\n"
     << "seamd_workers " << g.workers << "\n"
     << "# HELP seamd_in_flight_requests Requests being handled now.\n"
     << "# TYPE seamd_in_flight_requests gauge\n"
     << "seamd_in_flight_requests " << g.in_flight << "\n"
     << "# HELP seamd_inflight_bytes Bytes held by requests in flight (4 x body each), for admission.\n"
     << "# TYPE seamd_inflight_bytes gauge\n"
     << "seamd_inflight_bytes " << g.inflight_bytes << "\n"
     << "# HELP seamd_inflight_bytes_limit Requests beyond this many bytes in flight get 503.\n"
     << "# TYPE seamd_inflight_bytes_limit gauge\n"
     << "seamd_inflight_bytes_limit " << g.inflight_bytes_limit << "\n"
     << "# HELP seamd_draining 1 after SIGTERM while in-flight work finishes.\n"
     << "# TYPE seamd_draining gauge\n"
     << "seamd_draining " << (g.draining ? 1 : 0) << "\n";
  return os.str();
}

}  // namespace seam::server
