// The environment a seamd process runs best under. The libraries concerned read it only
// while the process starts (glibc's malloc tunables, OpenBLAS's thread pool, both before
// main), so seamd gets it by executing itself once more with the same arguments.
//
// - Huge-page malloc (GLIBC_TUNABLES gains glibc.malloc.hugetlb=1): glibc's malloc advises
//   the kernel to back its heap and its large blocks with 2 MiB transparent huge pages
//   (madvise, which is the setting of Debian and most distributions: `always` needs no
//   advice, `never` ignores it). A job's memory is mostly fresh blocks of megabytes (meshes,
//   sparse matrices, factors) that are touched once: with 4 KiB pages every page is a fault,
//   and faults are the dearest thing a virtual machine does. Measured on the 2-core test
//   machine (`bench/mesh_bench --job`, docs/uv.md): the weld stage at 1.2M faces 337 -> 151 ms,
//   the whole default job at 312k faces 7.0 -> 5.3 s; peak RSS the same (935/937 MiB at 1.25M
//   faces).
// - Single-threaded BLAS (OPENBLAS_NUM_THREADS=1): seamd runs BLAS on one thread anyway
//   (core::use_single_threaded_solvers, which stops the pool OpenBLAS started when it was
//   loaded), but with the variable set OpenBLAS starts no pool at all, and a pool stopped
//   late leaves more memory behind: peak RSS of the default job at 1.25M faces 956 MiB with
//   the pool stopped, 937 MiB without one. The server needs it for its signal handling too
//   (server/main.cpp).
//
// A value the caller's environment already gives (any glibc.malloc.hugetlb, any
// OPENBLAS_NUM_THREADS) is left as it is: setting `GLIBC_TUNABLES=glibc.malloc.hugetlb=0`
// turns huge pages off.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace seam::api {

struct ProcessEnv {
  bool huge_page_malloc = true;      ///< GLIBC_TUNABLES: glibc.malloc.hugetlb=1
  bool single_threaded_blas = true;  ///< OPENBLAS_NUM_THREADS=1
};

/// The GLIBC_TUNABLES value that adds glibc.malloc.hugetlb=1 to `current` (null: unset), or
/// nullopt when `current` already sets glibc.malloc.hugetlb (to anything).
std::optional<std::string> tunables_with_huge_pages(const char* current);

/// True when this process's environment already has everything `wanted` asks for.
bool process_env_in_place(const ProcessEnv& wanted);

/// Executes this program again (/proc/self/exe, the same argv) with the settings of `wanted`
/// that its environment lacks, and SEAMD_REEXECUTED=1. Returns only when nothing is missing,
/// when SEAMD_REEXECUTED is set (a process is executed again at most once, so a loader that
/// drops a setting cannot make a loop), or when the program cannot be executed again (no
/// /proc, a failed execv): the process then goes on as it is, which is correct, only slower.
/// Call it before starting any thread or reading any input.
void reexec_with(const ProcessEnv& wanted, char** argv);

/// For a short job in a process of its own (`seamd seam` on a small input, which is not worth
/// a second start): glibc keeps the memory the job frees for its next blocks instead of
/// unmapping it and taking it back page by page (mmap threshold 32 MiB, trim threshold
/// 64 MiB, both fixed). Homer (10k faces) as a whole process: 157 -> 148 ms (fewer page
/// faults: 3,014 -> 2,373). Not for the server or large jobs: a long-lived or large process
/// should give memory back.
void keep_freed_memory_for_short_job();

/// The input size from which `seamd seam` executes itself again for huge-page malloc: a
/// second start costs about 20 ms (30 shared libraries), which the huge pages repay from
/// about 20k faces (a 350 KB GLB: 40 ms saved; 10k faces: 15 ms, less than the start).
inline constexpr std::uintmax_t kHugePageInputBytes = 256 * 1024;

}  // namespace seam::api
