// The environment a seamd process runs best under. OpenBLAS reads it only while the process
// starts (its thread pool, before main), so seamd gets it by executing itself once more with
// the same arguments.
//
// - Single-threaded BLAS (OPENBLAS_NUM_THREADS=1): seamd runs BLAS on one thread anyway
//   (core::use_single_threaded_solvers, which stops the pool OpenBLAS started when it was
//   loaded), but with the variable set OpenBLAS starts no pool at all, and a pool stopped
//   late leaves more memory behind: peak RSS of the default job at 1.25M faces 956 MiB with
//   the pool stopped, 937 MiB without one. The server needs it for its signal handling too
//   (server/main.cpp). A value the caller's environment already gives stands.
//
// glibc's malloc is left as the caller's environment sets it. From 2026-12-02 to 12-04 seamd
// added glibc.malloc.hugetlb=1 (2 MiB transparent huge pages for the heap), measured then at
// the weld stage of 1.2M faces 337 -> 151 ms and the default job at 312k faces 7.0 -> 5.3 s.
// This virtual machine's balloon has free page reporting (dmesg: "Free page reporting
// enabled"): free 2 MiB blocks go back to the host within seconds, and a huge page is always
// such a block, so it faults in at host speed: touching 400 MiB took 1.6-1.7 s in huge pages
// (even 5 or 20 s after the last run), 36 ms when run again at once, and 225 ms in small pages,
// which the kernel reuses from memory still backed. On 2026-12-04, in paired runs, huge pages
// made every job slower (603 huge-page faults, 8 s of system time in one 1.25M-face job): the
// CLI's default job at 1.25M faces 7.8-9.1 s without, 10.4-15.5 s with; the same through the
// server, repeated, 6.8-7.9 s against 8.3-10.0 s; 20k small parts 1.5-2.2 s against 1.9-2.5 s.
// Only the weld stage repeated in one process, its memory warm, still gained (266 against
// 277 ms). What huge pages are worth depends on the host, and without them the times hold
// steady, so they are the caller's choice: GLIBC_TUNABLES=glibc.malloc.hugetlb=1 turns them on.
#pragma once

#include <cstddef>
#include <cstdint>

namespace seam::api {

struct ProcessEnv {
  bool single_threaded_blas = true;  ///< OPENBLAS_NUM_THREADS=1
};

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
/// should give memory back, and the 1.25M-face job took 9.5-9.8 s with these thresholds
/// against 7.8-8.4 s without (2026-12-04).
void keep_freed_memory_for_short_job();

/// Gives the free memory in malloc's heaps back to the system (glibc's malloc_trim), before a
/// large job's flattening: BFF's factorization is the default job's peak, and what the weld,
/// seam and cut stages freed would otherwise stay resident under it. Does nothing below
/// kReleaseBeforeFlatteningFaces faces, where the next small job would only fault the memory in
/// again. The default job at 1.25M faces (`scripts/memory-bench.py --levels 3`, three pairs):
/// peak 946 -> 921 MiB, the same time (9.2-9.9 s). Thread-safe.
void release_free_memory_before_flattening(std::size_t faces);
inline constexpr std::size_t kReleaseBeforeFlatteningFaces = 200000;

/// The input size from which `seamd seam` executes itself again (without OpenBLAS's thread
/// pool) instead of keeping freed memory for a short job: a second start costs about 20 ms
/// (30 shared libraries), nothing next to a job of ~20k faces and up.
inline constexpr std::uintmax_t kReexecInputBytes = 256 * 1024;

}  // namespace seam::api
