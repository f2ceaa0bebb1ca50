// The environment seamd executes itself under (api/process_env.h): the GLIBC_TUNABLES value it
// computes, and when the environment counts as in place. (That the server process really runs
// with it: tests/server/process_test.cpp.)
#include <doctest/doctest.h>

#include <cstdlib>
#include <optional>
#include <string>

#include "api/process_env.h"

namespace seam_process_env_test {

using seam::api::ProcessEnv;
using seam::api::process_env_in_place;
using seam::api::tunables_with_huge_pages;

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

TEST_CASE("process env: huge pages are added to GLIBC_TUNABLES unless it names them") {
  CHECK(tunables_with_huge_pages(nullptr) == "glibc.malloc.hugetlb=1");
  CHECK(tunables_with_huge_pages("") == "glibc.malloc.hugetlb=1");
  CHECK(tunables_with_huge_pages("glibc.malloc.arena_max=2") == "glibc.malloc.arena_max=2:glibc.malloc.hugetlb=1");
  // Any value the caller chose stands, wherever it is in the list.
  CHECK_FALSE(tunables_with_huge_pages("glibc.malloc.hugetlb=0").has_value());
  CHECK_FALSE(tunables_with_huge_pages("glibc.malloc.hugetlb=2").has_value());
  CHECK_FALSE(tunables_with_huge_pages("glibc.malloc.arena_max=2:glibc.malloc.hugetlb=0").has_value());
  // A name that only starts like it is another tunable.
  CHECK(tunables_with_huge_pages("glibc.malloc.hugetlbx=1") == "glibc.malloc.hugetlbx=1:glibc.malloc.hugetlb=1");
  CHECK(tunables_with_huge_pages("x.glibc.malloc.hugetlb=1") == "x.glibc.malloc.hugetlb=1:glibc.malloc.hugetlb=1");
}

TEST_CASE("process env: in place when every wanted setting is in the environment") {
  const ProcessEnv both{.huge_page_malloc = true, .single_threaded_blas = true};
  const ProcessEnv none{.huge_page_malloc = false, .single_threaded_blas = false};
  {
    ScopedEnv tunables("GLIBC_TUNABLES", nullptr);
    ScopedEnv blas("OPENBLAS_NUM_THREADS", nullptr);
    CHECK_FALSE(process_env_in_place(both));
    CHECK_FALSE(process_env_in_place(ProcessEnv{}));  // both by default
    CHECK(process_env_in_place(none));
  }
  {
    ScopedEnv tunables("GLIBC_TUNABLES", "glibc.malloc.hugetlb=0");  // the caller turned them off
    ScopedEnv blas("OPENBLAS_NUM_THREADS", nullptr);
    CHECK(process_env_in_place({.huge_page_malloc = true, .single_threaded_blas = false}));
    CHECK_FALSE(process_env_in_place(both));
  }
  {
    ScopedEnv tunables("GLIBC_TUNABLES", "glibc.malloc.hugetlb=1");
    ScopedEnv blas("OPENBLAS_NUM_THREADS", "4");  // any thread count the caller set stands
    CHECK(process_env_in_place(both));
  }
}

}  // namespace seam_process_env_test
