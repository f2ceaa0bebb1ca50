#include "api/process_env.h"

#include <malloc.h>
#include <unistd.h>

#include <cstdlib>

namespace seam::api {

namespace {

// Set in the environment of the second start: a process never executes itself twice, even if
// the loader drops a setting.
constexpr const char* kReexecuted = "SEAMD_REEXECUTED";

}  // namespace

bool process_env_in_place(const ProcessEnv& wanted) {
  return !wanted.single_threaded_blas || std::getenv("OPENBLAS_NUM_THREADS") != nullptr;
}

void reexec_with(const ProcessEnv& wanted, char** argv) {
  if (process_env_in_place(wanted) || std::getenv(kReexecuted) != nullptr) return;
  char self[4096];
  const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
  if (n <= 0) return;
  self[n] = '\0';  // the real path, so that ps and top still say "seamd"
  if (wanted.single_threaded_blas) setenv("OPENBLAS_NUM_THREADS", "1", 1);
  setenv(kReexecuted, "1", 1);
  execv(self, argv);  // returns only on failure: then go on as we are
}

void keep_freed_memory_for_short_job() {
  constexpr int kMmapThreshold = 32 << 20;  // glibc's largest dynamic threshold
  constexpr int kTrimThreshold = 64 << 20;
  mallopt(M_MMAP_THRESHOLD, kMmapThreshold);
  mallopt(M_TRIM_THRESHOLD, kTrimThreshold);
}

void release_free_memory_before_flattening(std::size_t faces) {
  if (faces >= kReleaseBeforeFlatteningFaces) malloc_trim(0);
}

}  // namespace seam::api
