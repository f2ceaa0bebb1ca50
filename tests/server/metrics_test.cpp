// Prometheus text rendering: counters by route and status, a cumulative histogram, gauges.
#include "server/metrics.h"

#include <doctest/doctest.h>

namespace seam_metrics_test {

TEST_CASE("metrics render cumulative histograms and labelled counters") {
  seam::server::Metrics m;
  m.record("/seam", 200, 0.003, 100, 2000);
  m.record("/seam", 200, 0.2, 50, 10);
  m.record("/seam", 503, 0.0001, 10, 5);
  m.record("/healthz", 200, 0.0001, 0, 15);
  CHECK(m.count("/seam", 200) == 2);
  CHECK(m.count("/seam", 503) == 1);
  CHECK(m.count("/seam", 404) == 0);
  const auto text = m.render({.queue_depth = 3, .busy_workers = 2, .workers = 4, .queue_capacity = 8});
  CHECK(text.find("seamd_requests_total{route=\"/seam\",status=\"200\"} 2\n") != std::string::npos);
  CHECK(text.find("seamd_requests_total{route=\"/seam\",status=\"503\"} 1\n") != std::string::npos);
  CHECK(text.find("seamd_request_duration_seconds_bucket{route=\"/seam\",le=\"0.001\"} 1\n") != std::string::npos);
  CHECK(text.find("seamd_request_duration_seconds_bucket{route=\"/seam\",le=\"0.005\"} 2\n") != std::string::npos);
  CHECK(text.find("seamd_request_duration_seconds_bucket{route=\"/seam\",le=\"0.25\"} 3\n") != std::string::npos);
  CHECK(text.find("seamd_request_duration_seconds_bucket{route=\"/seam\",le=\"+Inf\"} 3\n") != std::string::npos);
  CHECK(text.find("seamd_request_duration_seconds_count{route=\"/seam\"} 3\n") != std::string::npos);
  CHECK(text.find("seamd_request_bytes_total 160\n") != std::string::npos);
  CHECK(text.find("seamd_response_bytes_total 2030\n") != std::string::npos);
  CHECK(text.find("seamd_queue_depth 3\n") != std::string::npos);
  CHECK(text.find("seamd_busy_workers 2\n") != std::string::npos);
  CHECK(text.find("# TYPE seamd_request_duration_seconds histogram") != std::string::npos);
  // Every sample line belongs to a declared metric family.
  std::size_t pos = 0;
  while ((pos = text.find('\n', pos)) != std::string::npos && pos + 1 < text.size()) {
    ++pos;
    if (text[pos] == '#') continue;
    CHECK(text.compare(pos, 6, "seamd_") == 0);
  }
}

}  // namespace seam_metrics_test
