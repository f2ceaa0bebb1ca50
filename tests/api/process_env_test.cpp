// The environment seamd executes itself under (api/process_env.h): when it counts as in place.
// (That the server process really runs with it: tests/server/process_test.cpp.)
#include "api/process_env.h"

#include <doctest/doctest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

namespace seam_process_env_test {

using seam::api::kReleaseBeforeFlatteningFaces;
using seam::api::process_env_in_place;
using seam::api::ProcessEnv;
using seam::api::release_free_memory_before_flattening;

namespace {

// Sets (or, with null, unsets) an environment variable for one scope.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    if (value) {
      setenv(name, value, 1);
    } else {
      unsetenv(name);
    }
  }
  ~ScopedEnv() {
    if (old_) {
      setenv(name_, old_->c_str(), 1);
    } else {
      unsetenv(name_);
    }
  }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* name_;
  std::optional<std::string> old_;
};

}  // namespace

TEST_CASE("process env: in place when every wanted setting is in the environment, and malloc is left alone") {
  const ProcessEnv blas{.single_threaded_blas = true};
  const ProcessEnv none{.single_threaded_blas = false};
  {
    ScopedEnv blas_env("OPENBLAS_NUM_THREADS", nullptr);
    CHECK_FALSE(process_env_in_place(blas));
    CHECK_FALSE(process_env_in_place(ProcessEnv{}));  // single-threaded BLAS by default
    CHECK(process_env_in_place(none));
  }
  {
    ScopedEnv blas_env("OPENBLAS_NUM_THREADS", "4");  // any thread count the caller set stands
    CHECK(process_env_in_place(blas));
  }
  {
    // glibc's tunables are not seamd's to set: none, or the caller's, both count as in place.
    ScopedEnv blas_env("OPENBLAS_NUM_THREADS", "1");
    ScopedEnv tunables("GLIBC_TUNABLES", nullptr);
    CHECK(process_env_in_place(ProcessEnv{}));
    ScopedEnv huge("GLIBC_TUNABLES", "glibc.malloc.hugetlb=1");
    CHECK(process_env_in_place(ProcessEnv{}));
  }
}

#if !defined(__SANITIZE_ADDRESS__)
namespace {

// Resident bytes of this process (/proc/self/statm's second field, in pages).
std::size_t resident_bytes() {
  std::FILE* f = std::fopen("/proc/self/statm", "r");
  REQUIRE(f != nullptr);
  unsigned long size = 0, resident = 0;
  const int read = std::fscanf(f, "%lu %lu", &size, &resident);
  std::fclose(f);
  REQUIRE(read == 2);
  return resident * static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
}

}  // namespace
#endif

TEST_CASE("process env: free heap memory goes back to the system before a large flattening only") {
#if defined(__SANITIZE_ADDRESS__)
  // AddressSanitizer has its own allocator, which glibc's malloc_trim does not reach.
  release_free_memory_before_flattening(kReleaseBeforeFlatteningFaces);
#else
  // 64 MiB in 32 KiB blocks (below every mmap threshold, so in the heap), touched, then freed
  // but for the last one, which keeps the heap's top from being trimmed on its own.
  constexpr std::size_t kBlock = 32 << 10, kBlocks = 2048;
  std::vector<void*> blocks;
  for (std::size_t i = 0; i < kBlocks; ++i) {
    blocks.push_back(std::malloc(kBlock));
    REQUIRE(blocks.back() != nullptr);
    std::memset(blocks.back(), 1, kBlock);
  }
  for (std::size_t i = 0; i + 1 < kBlocks; ++i) std::free(blocks[i]);
  const std::size_t before = resident_bytes();
  release_free_memory_before_flattening(kReleaseBeforeFlatteningFaces - 1);  // a small job: kept
  const std::size_t small = resident_bytes();
  release_free_memory_before_flattening(kReleaseBeforeFlatteningFaces);
  const std::size_t large = resident_bytes();
  std::free(blocks.back());
  CHECK(small + (8 << 20) > before);   // within 8 MiB: nothing given back
  CHECK(large + (32 << 20) < before);  // at least half of the 64 MiB given back
#endif
}

}  // namespace seam_process_env_test
