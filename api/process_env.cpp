#include "api/process_env.h"

#include <malloc.h>
#include <unistd.h>

#include <cstdlib>
#include <string_view>

namespace seam::api {

namespace {

constexpr std::string_view kHugeTlb = "glibc.malloc.hugetlb";
// Set in the environment of the second start: a process never executes itself twice, even if
// the loader drops a setting (glibc ignores GLIBC_TUNABLES in set-user-ID programs).
constexpr const char* kReexecuted = "SEAMD_REEXECUTED";

// GLIBC_TUNABLES is a colon-separated list of name=value.
bool names_tunable(std::string_view list, std::string_view name) {
  while (!list.empty()) {
    const std::size_t end = list.find(':');
    const std::string_view item = list.substr(0, end);
    if (item.substr(0, item.find('=')) == name) return true;
    if (end == std::string_view::npos) break;
    list.remove_prefix(end + 1);
  }
  return false;
}

}  // namespace

std::optional<std::string> tunables_with_huge_pages(const char* current) {
  const std::string setting = std::string(kHugeTlb) + "=1";
  if (current == nullptr || *current == '\0') return setting;
  if (names_tunable(current, kHugeTlb)) return std::nullopt;
  return std::string(current) + ":" + setting;
}

bool process_env_in_place(const ProcessEnv& wanted) {
  if (wanted.huge_page_malloc && tunables_with_huge_pages(std::getenv("GLIBC_TUNABLES"))) return false;
  if (wanted.single_threaded_blas && std::getenv("OPENBLAS_NUM_THREADS") == nullptr) return false;
  return true;
}

void reexec_with(const ProcessEnv& wanted, char** argv) {
  if (process_env_in_place(wanted) || std::getenv(kReexecuted) != nullptr) return;
  char self[4096];
  const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
  if (n <= 0) return;
  self[n] = '\0';  // the real path, so that ps and top still say "seamd"
  if (wanted.huge_page_malloc) {
    if (auto tunables = tunables_with_huge_pages(std::getenv("GLIBC_TUNABLES"))) {
      setenv("GLIBC_TUNABLES", tunables->c_str(), 1);
    }
  }
  if (wanted.single_threaded_blas && std::getenv("OPENBLAS_NUM_THREADS") == nullptr) {
    setenv("OPENBLAS_NUM_THREADS", "1", 1);
  }
  setenv(kReexecuted, "1", 1);
  execv(self, argv);  // returns only on failure: then go on as we are
}

void keep_freed_memory_for_short_job() {
  constexpr int kMmapThreshold = 32 << 20;  // glibc's largest dynamic threshold
  constexpr int kTrimThreshold = 64 << 20;
  mallopt(M_MMAP_THRESHOLD, kMmapThreshold);
  mallopt(M_TRIM_THRESHOLD, kTrimThreshold);
}

}  // namespace seam::api
