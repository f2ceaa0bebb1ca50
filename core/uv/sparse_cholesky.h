// The sparse Cholesky factorization every flattening method uses.
#pragma once

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>

namespace seam::core {

/// Makes the solvers run single-threaded in the calling thread: an optimized BLAS
/// (OpenBLAS's openblas_set_num_threads(1), process-wide) and CHOLMOD's own OpenMP loops
/// (omp_set_max_active_levels(0), a per-thread setting; Debian's CHOLMOD asks for 4 OpenMP
/// threads per supernode whatever the machine has). Both hooks are looked up at run time and
/// are no-ops where the BLAS or CHOLMOD is built without them. The server already runs one
/// request per core; solver threads on top would oversubscribe them (on 2 cores the OpenMP
/// wake-ups alone cost 17-25% of a supernodal factorization). Idempotent and thread-safe.
void use_single_threaded_solvers();

/// CHOLMOD's LL^T (SuiteSparse; Chen, Davis, Hager, Rajamanickam 2008) reading the lower
/// triangle, simplicial or supernodal as the analysis finds cheaper: supernodal (dense BLAS
/// kernels per supernode) only when the factorization does at least kSupernodalSwitch flops
/// per entry of L. Measured on SLIM's proxy (bench/flatten_bench, docs/uv.md): the simplicial
/// factorization is 5x faster on 5k-26k unknowns (about 25-50 flops per entry), 1.7x on 40k
/// (73), and the supernodal one 1.5x faster on 157k (131) and above. Same interface as
/// Eigen::SimplicialLLT (compute / analyzePattern / factorize / solve / info); a matrix that
/// is not numerically positive definite is reported by info() with either kind. Each instance
/// owns its cholmod_common, so concurrent requests share nothing.
class SparseCholesky : public Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower> {
 public:
  static constexpr double kSupernodalSwitch = 100;
  /// prefer_nested_dissection()'s default: nested dissection from this many unknowns on.
  static constexpr Eigen::Index kNestedDissectionMin = 200000;

  SparseCholesky() { configure(); }
  explicit SparseCholesky(const Eigen::SparseMatrix<double>& matrix) {
    configure();
    compute(matrix);
  }

  /// For systems of at least `min_unknowns` unknowns, orders by METIS nested dissection
  /// instead of the AMD that CHOLMOD picks by default for mesh Laplacians (it tries METIS only
  /// at fill ratios meshes do not reach). On a 490k-vertex triangulated grid: 20% less fill
  /// (24.0M vs 30.2M entries in L) and 39% fewer flops per factorization (6.6 vs 10.7 GFlop);
  /// on SLIM's proxy at 534k unknowns analysis + 5 factorizations take 13.3 s against AMD's
  /// 14.7 s. Below 200k AMD wins: its analysis is 3-4x cheaper and, at 40k unknowns, its
  /// simplicial factorization no slower. Call before analyzePattern / compute.
  void prefer_nested_dissection(Eigen::Index min_unknowns = kNestedDissectionMin) {
    nested_dissection_min_ = min_unknowns;
  }

  void analyzePattern(const Eigen::SparseMatrix<double>& matrix) {
    if (nested_dissection_min_ >= 0 && matrix.rows() >= nested_dissection_min_) {
      cholmod().nmethods = 1;
      cholmod().method[0].ordering = CHOLMOD_METIS;
      cholmod().postorder = 1;
    }
    Base::analyzePattern(matrix);
  }

  SparseCholesky& compute(const Eigen::SparseMatrix<double>& matrix) {
    analyzePattern(matrix);
    factorize(matrix);
    return *this;
  }

  /// After the analysis: whether the factor is supernodal.
  bool supernodal() const;

 private:
  using Base = Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower>;

  // Failures reach the caller through info(); CHOLMOD must not also print them to stderr (the
  // server's log is structured JSON). LL^T in either kind (final_ll), chosen by flops per
  // entry of L at the analysis (CHOLMOD_AUTO).
  void configure() {
    use_single_threaded_solvers();
    cholmod().print = 0;
    cholmod().supernodal = CHOLMOD_AUTO;
    cholmod().supernodal_switch = kSupernodalSwitch;
    cholmod().final_asis = 0;
    cholmod().final_ll = 1;
  }

  Eigen::Index nested_dissection_min_ = -1;  // -1: never
};

}  // namespace seam::core
