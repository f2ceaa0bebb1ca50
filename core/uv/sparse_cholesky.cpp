#include "core/uv/sparse_cholesky.h"

#include <dlfcn.h>

#include <mutex>

namespace seam::core {

void use_single_threaded_blas() {
  static std::once_flag once;
  std::call_once(once, [] {
    // CHOLMOD reaches BLAS through Debian's libblas.so.3 alternative, which may be OpenBLAS
    // (threaded by default), the reference BLAS or another; only OpenBLAS has this hook.
    using SetThreads = void (*)(int);
    if (auto* set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"))) set(1);
  });
}

}  // namespace seam::core
