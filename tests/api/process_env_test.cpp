// The environment seamd executes itself under (api/process_env.h): when it counts as in place.
// (That the server process really runs with it: tests/server/process_test.cpp.)
#include <doctest/doctest.h>

#include <cstdlib>
#include <optional>
#include <string>

#include "api/process_env.h"

namespace seam_process_env_test {

using seam::api::process_env_in_place;
using seam::api::ProcessEnv;

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

}  // namespace seam_process_env_test
