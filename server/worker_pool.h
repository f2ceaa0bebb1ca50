// The compute pool: a fixed set of worker threads with a bounded admission count, separate
// from the HTTP connection threads. A full pool refuses at once (the caller answers 503)
// instead of queueing without bound.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace seam::server {

class WorkerPool {
 public:
  /// Starts `workers` threads (>= 1). At most `workers + queue_capacity` tasks are admitted
  /// at a time (running plus waiting); try_submit refuses beyond that.
  WorkerPool(unsigned workers, std::size_t queue_capacity);
  /// Runs every admitted task to completion, then joins (see shutdown()).
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  /// Admits `task` if the pool is below its bound and not shut down; never blocks.
  /// Returns false when full or shut down (the task is dropped, not run).
  /// The task must not throw (exceptions are caught and ignored as a last resort).
  bool try_submit(std::function<void()> task);

  /// Stops admitting, lets every admitted task finish, joins the threads. Idempotent.
  void shutdown();

  std::size_t queue_depth() const;  ///< admitted tasks not yet started
  std::size_t busy() const;         ///< tasks running now
  bool full() const;                ///< the next try_submit would be refused
  unsigned workers() const { return static_cast<unsigned>(threads_.size()); }
  std::size_t queue_capacity() const { return capacity_; }

 private:
  void run();

  const std::size_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<std::function<void()>> pending_;
  std::size_t busy_ = 0;
  bool stopping_ = false;
  std::vector<std::thread> threads_;
};

}  // namespace seam::server
