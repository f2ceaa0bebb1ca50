#include "core/uv/sparse_cholesky.h"

#include <dlfcn.h>
#include <metis.h>

#include <algorithm>
#include <cmath>
#include <mutex>

#include "core/error.h"

namespace seam::core {
namespace {

// METIS's refinement passes per uncoarsening level (METIS_OPTION_NITER, default 10): one pass
// orders a 533k-vertex mesh graph about 11% faster for 1% more factorization flops
// (nested_dissection_order).
constexpr idx_t kMetisRefinementPasses = 1;

// Set by use_single_threaded_solvers() in each thread that runs solvers: OpenMP regions that
// thread starts are inactive (max-active-levels 0), so GOMP_parallel below runs them inline.
thread_local bool serial_openmp_regions = false;

}  // namespace
}  // namespace seam::core

// libgomp runs an inactive parallel region (max-active-levels 0, as every solver thread here
// sets) on the calling thread, yet still builds a team of one for it and ends it with a futex
// wake-up, a system call. CHOLMOD's supernodal factorization opens a region per supernode
// update: 1.3M of them for two factorizations of a 533k-unknown Laplacian, which on this
// service's VMs (system calls trap to the hypervisor) took half their time (3.0-4.1 s against
// 1.5-1.6 s each; docs/uv.md). The executable defines the symbol (exported by
// core/CMakeLists.txt), so the dynamic linker binds CHOLMOD's calls here: in a solver thread
// the region's body runs directly, as one thread would run it (CHOLMOD's regions are static
// loops: omp_get_num_threads() = 1, omp_get_thread_num() = 0 give the whole range); any other
// thread gets libgomp's own GOMP_parallel, so OpenMP parallelism elsewhere is untouched.
extern "C" __attribute__((visibility("default"))) void GOMP_parallel(void (*fn)(void*), void* data,
                                                                     unsigned num_threads, unsigned flags) {
  if (seam::core::serial_openmp_regions) {
    fn(data);
    return;
  }
  using Parallel = void (*)(void (*)(void*), void*, unsigned, unsigned);
  static const auto next = reinterpret_cast<Parallel>(dlvsym(RTLD_NEXT, "GOMP_parallel", "GOMP_4.0"));
  SEAM_ASSERT(next != nullptr);  // only OpenMP code calls this, and libgomp defines it
  next(fn, data, num_threads, flags);
}

namespace seam::core {

void use_single_threaded_solvers() {
  static std::once_flag once;
  std::call_once(once, [] {
    // CHOLMOD reaches BLAS through Debian's libblas.so.3 alternative, which may be OpenBLAS
    // (threaded by default), the reference BLAS or another; only OpenBLAS has this hook.
    using SetThreads = void (*)(int);
    if (auto* set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"))) set(1);
    // OpenBLAS started its pool when it was loaded (unless OPENBLAS_NUM_THREADS=1). With one
    // thread the pool is never used, but its threads spin (sched_yield) for about 0.1 s after
    // any start first, taking the second core from the job's own threads: the extrema's
    // geodesic passes on homer took 15.7 instead of 12.4 ms. Stopped as OpenBLAS stops it
    // before a fork; a threaded BLAS call would start it again.
    using Shutdown = int (*)();
    if (auto* stop = reinterpret_cast<Shutdown>(dlsym(RTLD_DEFAULT, "blas_thread_shutdown_"))) stop();
  });
  // OpenMP's max-active-levels is an attribute of the calling thread's data environment: each
  // worker thread sets it once. With 0 levels every parallel region runs on one thread.
  if (serial_openmp_regions) return;
  serial_openmp_regions = true;
  using SetLevels = void (*)(int);
  if (auto* set = reinterpret_cast<SetLevels>(dlsym(RTLD_DEFAULT, "omp_set_max_active_levels"))) set(0);
}

SparseCholesky::~SparseCholesky() {
  cholmod_free_dense(&b_, &cholmod());
  cholmod_free_sparse(&b_set_, &cholmod());
  cholmod_free_dense(&x_, &cholmod());
  cholmod_free_sparse(&x_set_, &cholmod());
  cholmod_free_dense(&y_, &cholmod());
  cholmod_free_dense(&e_, &cholmod());
}

void SparseCholesky::cache_positions() {
  if (!position_.empty()) return;
  const auto n = static_cast<int>(m_cholmodFactor->n);
  position_.assign(static_cast<std::size_t>(n), 0);
  const int* perm = static_cast<const int*>(m_cholmodFactor->Perm);
  for (int i = 0; i < n; ++i) position_[static_cast<std::size_t>(perm ? perm[i] : i)] = i;
}

std::vector<std::pair<int, double>> SparseCholesky::half_solve_sparse(std::span<const std::pair<int, double>> b) {
  SEAM_ASSERT(m_cholmodFactor != nullptr && m_factorizationIsOk && m_cholmodFactor->is_ll != 0);
  cache_positions();
  return m_cholmodFactor->is_super != 0 ? half_solve_supernodal(b) : half_solve_simplicial(b);
}

// Column-oriented forward substitution restricted to the supernodes that y can reach: those
// holding b's rows and their ancestors (every row below a supernode's columns belongs to an
// ancestor's). Each supernode is a dense column-major block of nsrow x nscol, its first
// nscol rows the lower triangle of its own columns. Reach supernodes in increasing order are
// a topological order (a parent's columns come after its children's).
std::vector<std::pair<int, double>> SparseCholesky::half_solve_supernodal(std::span<const std::pair<int, double>> b) {
  const cholmod_factor& f = *m_cholmodFactor;
  const auto nsuper = static_cast<int>(f.nsuper);
  const int* super = static_cast<const int*>(f.super);
  const int* pi = static_cast<const int*>(f.pi);
  const int* px = static_cast<const int*>(f.px);
  const int* rows = static_cast<const int*>(f.s);
  const auto* x = static_cast<const double*>(f.x);
  if (supernode_of_.empty()) {
    supernode_of_.assign(f.n, 0);
    parent_.assign(static_cast<std::size_t>(nsuper), -1);
    for (int sn = 0; sn < nsuper; ++sn) {
      for (int k = super[sn]; k < super[sn + 1]; ++k) supernode_of_[static_cast<std::size_t>(k)] = sn;
    }
    for (int sn = 0; sn < nsuper; ++sn) {
      const int nscol = super[sn + 1] - super[sn];
      if (pi[sn] + nscol < pi[sn + 1]) {
        parent_[static_cast<std::size_t>(sn)] = supernode_of_[static_cast<std::size_t>(rows[pi[sn] + nscol])];
      }
    }
    work_.assign(f.n, 0.0);
    in_reach_.assign(static_cast<std::size_t>(nsuper), 0);
  }
  std::vector<int> reach;
  for (const auto& [unknown, value] : b) {
    const int row = position_[static_cast<std::size_t>(unknown)];
    work_[static_cast<std::size_t>(row)] = value;
    for (int sn = supernode_of_[static_cast<std::size_t>(row)]; sn >= 0 && !in_reach_[static_cast<std::size_t>(sn)];
         sn = parent_[static_cast<std::size_t>(sn)]) {
      in_reach_[static_cast<std::size_t>(sn)] = 1;
      reach.push_back(sn);
    }
  }
  std::sort(reach.begin(), reach.end());
  std::vector<std::pair<int, double>> y;
  for (int sn : reach) {
    in_reach_[static_cast<std::size_t>(sn)] = 0;
    const int k1 = super[sn];
    const int nscol = super[sn + 1] - k1;
    const int nsrow = pi[sn + 1] - pi[sn];
    const int* sn_rows = rows + pi[sn];
    const double* block = x + px[sn];
    for (int j = 0; j < nscol; ++j) {
      const double* column = block + static_cast<std::ptrdiff_t>(j) * nsrow;
      double& yj = work_[static_cast<std::size_t>(k1 + j)];
      yj /= column[j];
      if (yj == 0.0) continue;
      for (int r = j + 1; r < nsrow; ++r) work_[static_cast<std::size_t>(sn_rows[r])] -= column[r] * yj;
    }
    for (int j = 0; j < nscol; ++j) {
      double& yj = work_[static_cast<std::size_t>(k1 + j)];
      y.emplace_back(k1 + j, yj);
      yj = 0.0;  // work_ is all zero between calls
    }
  }
  return y;
}

std::vector<std::pair<int, double>> SparseCholesky::half_solve_simplicial(std::span<const std::pair<int, double>> b) {
  const auto n = static_cast<int>(m_cholmodFactor->n);
  if (b_ != nullptr && b_->nrow != static_cast<std::size_t>(n)) {  // analysed anew at another size
    cholmod_free_dense(&b_, &cholmod());
    cholmod_free_sparse(&b_set_, &cholmod());
  }
  if (b_ == nullptr) {
    b_ = cholmod_zeros(static_cast<std::size_t>(n), 1, CHOLMOD_REAL, &cholmod());
    b_set_ = cholmod_allocate_sparse(static_cast<std::size_t>(n), 1, static_cast<std::size_t>(n), 1, 1, 0,
                                     CHOLMOD_PATTERN, &cholmod());
  }
  if (b_ == nullptr || b_set_ == nullptr) return {};
  auto* bx = static_cast<double*>(b_->x);
  auto* bp = static_cast<int*>(b_set_->p);
  auto* bi = static_cast<int*>(b_set_->i);
  bp[0] = 0;
  bp[1] = static_cast<int>(b.size());
  for (std::size_t k = 0; k < b.size(); ++k) {
    const int row = position_[static_cast<std::size_t>(b[k].first)];  // (P b)[row] = b[unknown]
    bi[k] = row;
    bx[row] = b[k].second;
  }
  const int ok = cholmod_solve2(CHOLMOD_L, m_cholmodFactor, b_, b_set_, &x_, &x_set_, &y_, &e_, &cholmod());
  for (std::size_t k = 0; k < b.size(); ++k) bx[bi[k]] = 0;  // b_ is all zero between calls
  if (!ok || x_ == nullptr || x_set_ == nullptr) return {};
  const int* xp = static_cast<const int*>(x_set_->p);
  const int* xi = static_cast<const int*>(x_set_->i);
  const auto* xx = static_cast<const double*>(x_->x);
  std::vector<std::pair<int, double>> y;
  y.reserve(static_cast<std::size_t>(xp[1] - xp[0]));
  for (int p = xp[0]; p < xp[1]; ++p) y.emplace_back(xi[p], xx[xi[p]]);
  std::sort(y.begin(), y.end());
  return y;
}

void SparseCholesky::analyze_with_order(const Eigen::SparseMatrix<double>& matrix, std::span<const int> order) {
  if (m_cholmodFactor != nullptr) {
    cholmod_free_factor(&m_cholmodFactor, &cholmod());
    m_cholmodFactor = nullptr;
  }
  cholmod().nmethods = 1;
  cholmod().method[0].ordering = CHOLMOD_GIVEN;
  cholmod().postorder = 1;
  cholmod_sparse a = Eigen::viewAsCholmod(matrix.selfadjointView<Eigen::Lower>());
  // CHOLMOD reads the permutation only.
  m_cholmodFactor = cholmod_analyze_p(&a, const_cast<int*>(order.data()), nullptr, 0, &cholmod());
  m_isInitialized = true;
  m_info = m_cholmodFactor != nullptr ? Eigen::Success : Eigen::NumericalIssue;
  m_analysisIsOk = m_cholmodFactor != nullptr;
  m_factorizationIsOk = false;
}

std::vector<int> nested_dissection_order(const Eigen::SparseMatrix<double>& lower) {
  if (lower.rows() == 0 || lower.rows() != lower.cols()) return {};
  static_assert(sizeof(idx_t) >= sizeof(int), "METIS's indices must hold the matrix's");
  // METIS reads the graph as adjacency lists (CSR) without self-loops: each off-diagonal
  // entry (i, j) of the lower triangle is the edges i-j and j-i.
  const auto n = static_cast<std::size_t>(lower.rows());
  std::vector<idx_t> start(n + 1, 0);
  for (Eigen::Index j = 0; j < lower.outerSize(); ++j) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(lower, j); it; ++it) {
      if (it.row() <= j) continue;  // the diagonal, or the upper triangle of a full matrix
      ++start[static_cast<std::size_t>(it.row()) + 1];
      ++start[static_cast<std::size_t>(j) + 1];
    }
  }
  for (std::size_t v = 0; v < n; ++v) start[v + 1] += start[v];
  std::vector<idx_t> adjacent(static_cast<std::size_t>(start[n]));
  std::vector<idx_t> fill(start.begin(), start.end() - 1);
  for (Eigen::Index j = 0; j < lower.outerSize(); ++j) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(lower, j); it; ++it) {
      if (it.row() <= j) continue;  // the diagonal, or the upper triangle of a full matrix
      const auto i = static_cast<std::size_t>(it.row());
      adjacent[static_cast<std::size_t>(fill[i]++)] = static_cast<idx_t>(j);
      adjacent[static_cast<std::size_t>(fill[static_cast<std::size_t>(j)]++)] = static_cast<idx_t>(i);
    }
  }
  fill = {};
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_NITER] = kMetisRefinementPasses;
  auto vertices = static_cast<idx_t>(n);
  std::vector<idx_t> perm(n), inverse(n);
  // METIS draws its random choices from one generator per process (GKlib's, not per thread):
  // two calls at once race on it and order differently than either alone (measured: both
  // orders of a 246k-vertex graph changed). One call at a time keeps every order the same.
  static std::mutex metis;
  const std::lock_guard<std::mutex> one_at_a_time(metis);
  if (METIS_NodeND(&vertices, start.data(), adjacent.data(), nullptr, options, perm.data(), inverse.data()) !=
      METIS_OK) {
    return {};
  }
  return std::vector<int>(perm.begin(), perm.end());
}

std::vector<int> restrict_order(std::span<const int> order, std::span<const Eigen::Index> unknown_of) {
  SEAM_ASSERT(unknown_of.size() == order.size());
  std::vector<int> restricted;
  restricted.reserve(order.size());
  for (int item : order) {
    const Eigen::Index unknown = unknown_of[static_cast<std::size_t>(item)];
    if (unknown >= 0) restricted.push_back(static_cast<int>(unknown));
  }
  return restricted;
}

bool SparseCholesky::update_diagonal(std::span<const std::pair<int, double>> additions) {
  SEAM_ASSERT(m_cholmodFactor != nullptr && m_factorizationIsOk);
  if (additions.empty()) return true;
  if (m_cholmodFactor->is_super != 0) return false;
  const auto n = static_cast<int>(m_cholmodFactor->n);
  cache_positions();
  // C: one column sqrt(value) e_row per addition, rows in the factor's order (CHOLMOD updates
  // the factor of P A P^T, so C is P C); A + C C^T adds the values to the diagonal.
  const auto k = additions.size();
  cholmod_sparse* c = cholmod_allocate_sparse(static_cast<std::size_t>(n), k, k, 1, 1, 0, CHOLMOD_REAL, &cholmod());
  if (c == nullptr) return false;
  auto* cp = static_cast<int*>(c->p);
  auto* ci = static_cast<int*>(c->i);
  auto* cx = static_cast<double*>(c->x);
  for (std::size_t j = 0; j < k; ++j) {
    SEAM_ASSERT(additions[j].second >= 0);
    cp[j] = static_cast<int>(j);
    ci[j] = position_[static_cast<std::size_t>(additions[j].first)];
    cx[j] = std::sqrt(additions[j].second);
  }
  cp[k] = static_cast<int>(k);
  // cholmod_updown works on LDL^T (converting the LL^T factor in place, same pattern: C adds
  // no fill, every row of C is a column of L); then back to LL^T for half_solve_sparse.
  const bool ok = cholmod_updown(1, c, m_cholmodFactor, &cholmod()) != 0 &&
                  cholmod_change_factor(CHOLMOD_REAL, 1, 0, 1, 1, m_cholmodFactor, &cholmod()) != 0 &&
                  cholmod().status == CHOLMOD_OK;
  cholmod_free_sparse(&c, &cholmod());
  if (!ok) {
    m_factorizationIsOk = false;
    m_info = Eigen::NumericalIssue;
  }
  return ok;
}

bool SparseCholesky::supernodal() const { return m_cholmodFactor != nullptr && m_cholmodFactor->is_super != 0; }

}  // namespace seam::core
