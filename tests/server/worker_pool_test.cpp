// The bounded compute pool: admission bound, no lost work, drain on shutdown.
#include "server/worker_pool.h"

#include <doctest/doctest.h>

#include <atomic>
#include <chrono>
#include <future>

namespace seam_worker_pool_test {

using namespace std::chrono_literals;

TEST_CASE("worker pool admits workers + queue tasks and refuses the rest at once") {
  seam::server::WorkerPool pool(2, 3);
  std::promise<void> gate;
  std::shared_future<void> open = gate.get_future().share();
  std::atomic<int> ran{0};
  int admitted = 0;
  for (int i = 0; i < 10; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    if (pool.try_submit([open, &ran] {
          open.wait();
          ++ran;
        })) {
      ++admitted;
    }
    CHECK(std::chrono::steady_clock::now() - t0 < 100ms);  // never blocks
  }
  CHECK(admitted == 5);
  CHECK(pool.full());
  for (int i = 0; i < 200 && pool.busy() < 2; ++i) std::this_thread::sleep_for(1ms);
  CHECK(pool.busy() == 2);
  CHECK(pool.queue_depth() == 3);
  gate.set_value();
  pool.shutdown();
  CHECK(ran == 5);
  CHECK(!pool.try_submit([] {}));  // shut down: refused, not run
}

TEST_CASE("worker pool: a zero-length queue still uses idle workers, and a throwing task does not kill a worker") {
  seam::server::WorkerPool pool(1, 0);
  std::atomic<int> ran{0};
  REQUIRE(pool.try_submit([] { throw std::runtime_error("bug"); }));
  for (int i = 0; i < 200 && pool.full(); ++i) std::this_thread::sleep_for(1ms);
  REQUIRE(pool.try_submit([&] { ++ran; }));
  pool.shutdown();
  CHECK(ran == 1);
}

}  // namespace seam_worker_pool_test
