#include "core/uv/sparse_cholesky.h"

#include <dlfcn.h>

#include <mutex>

namespace seam::core {

void use_single_threaded_solvers() {
  static std::once_flag once;
  std::call_once(once, [] {
    // CHOLMOD reaches BLAS through Debian's libblas.so.3 alternative, which may be OpenBLAS
    // (threaded by default), the reference BLAS or another; only OpenBLAS has this hook.
    using SetThreads = void (*)(int);
    if (auto* set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"))) set(1);
  });
  // OpenMP's max-active-levels is an attribute of the calling thread's data environment: each
  // worker thread sets it once. With 0 levels every parallel region runs on one thread.
  thread_local bool done = false;
  if (done) return;
  done = true;
  using SetLevels = void (*)(int);
  if (auto* set = reinterpret_cast<SetLevels>(dlsym(RTLD_DEFAULT, "omp_set_max_active_levels"))) set(0);
}

bool SparseCholesky::supernodal() const { return m_cholmodFactor != nullptr && m_cholmodFactor->is_super != 0; }

}  // namespace seam::core
