// Stage timings: the milliseconds that result structs and a response's `timings_ms` report.
#pragma once

#include <chrono>

namespace seam::core {

using StageClock = std::chrono::steady_clock;

/// Milliseconds from `start` to now, on the monotonic clock.
inline double ms_since(StageClock::time_point start) {
  return std::chrono::duration<double, std::milli>(StageClock::now() - start).count();
}

}  // namespace seam::core
