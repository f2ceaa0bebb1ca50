// Cooperative cancellation: long loops poll a token so the server can enforce a time budget.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>

#include "core/error.h"

namespace seam::core {

/// A cancellation flag with an optional deadline. Thread-safe: one thread may cancel()
/// while workers poll. Not copyable; pass by const reference.
class CancelToken {
 public:
  using Clock = std::chrono::steady_clock;

  CancelToken() = default;
  explicit CancelToken(Clock::time_point deadline) : deadline_(deadline), has_deadline_(true) {}
  CancelToken(const CancelToken&) = delete;
  CancelToken& operator=(const CancelToken&) = delete;

  /// A token that fires `budget` after now.
  static Clock::time_point deadline_after(std::chrono::milliseconds budget) {
    return Clock::now() + budget;
  }

  void cancel() const { cancelled_.store(true, std::memory_order_relaxed); }

  /// True once cancel() was called or the deadline passed. Costs one clock read.
  bool is_cancelled() const {
    if (cancelled_.load(std::memory_order_relaxed)) return true;
    if (has_deadline_ && Clock::now() >= deadline_) {
      cancelled_.store(true, std::memory_order_relaxed);
      return true;
    }
    return false;
  }

  /// Cheap poll for hot loops: reads the clock only every 4096 calls per `counter`.
  bool poll(std::uint32_t& counter) const {
    return (++counter & 4095u) == 0 ? is_cancelled() : cancelled_.load(std::memory_order_relaxed);
  }

  /// A token that never fires, for callers without a budget.
  static const CancelToken& none() {
    static const CancelToken token;
    return token;
  }

 private:
  mutable std::atomic<bool> cancelled_{false};
  Clock::time_point deadline_{};
  bool has_deadline_ = false;
};

inline Error cancelled_error(const char* stage) {
  return make_error(ErrorCode::kCancelled, std::string("cancelled during ") + stage +
                                               ": the time budget was exceeded");
}

}  // namespace seam::core
