#include "server/worker_pool.h"

#include <algorithm>

namespace seam::server {

WorkerPool::WorkerPool(unsigned workers, std::size_t queue_capacity) : capacity_(queue_capacity) {
  workers = std::max(1u, workers);
  threads_.reserve(workers);
  for (unsigned i = 0; i < workers; ++i) threads_.emplace_back([this] { run(); });
}

WorkerPool::~WorkerPool() { shutdown(); }

bool WorkerPool::try_submit(std::function<void()> task) {
  {
    std::lock_guard lock(mutex_);
    // The bound counts running tasks too: an idle worker takes a job even with a zero-length
    // queue, and a busy pool refuses at once rather than letting latency grow unbounded.
    if (stopping_ || pending_.size() + busy_ >= threads_.size() + capacity_) return false;
    pending_.push_back(std::move(task));
  }
  ready_.notify_one();
  return true;
}

void WorkerPool::shutdown() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  ready_.notify_all();
  for (auto& t : threads_) {
    if (t.joinable()) t.join();
  }
}

std::size_t WorkerPool::queue_depth() const {
  std::lock_guard lock(mutex_);
  return pending_.size();
}

std::size_t WorkerPool::busy() const {
  std::lock_guard lock(mutex_);
  return busy_;
}

bool WorkerPool::full() const {
  std::lock_guard lock(mutex_);
  return stopping_ || pending_.size() + busy_ >= threads_.size() + capacity_;
}

void WorkerPool::run() {
  for (;;) {
    std::function<void()> task;
    {
      std::unique_lock lock(mutex_);
      ready_.wait(lock, [this] { return stopping_ || !pending_.empty(); });
      // Admitted work is a promise to a waiting client: drain the queue even when stopping.
      if (pending_.empty()) return;
      task = std::move(pending_.front());
      pending_.pop_front();
      ++busy_;
    }
    try {
      task();
    } catch (...) {
      // Tasks report their own failures; this only keeps a worker alive after a bug.
    }
    std::lock_guard lock(mutex_);
    --busy_;
  }
}

}  // namespace seam::server
