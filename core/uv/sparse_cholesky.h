// The sparse Cholesky factorization every flattening method uses.
#pragma once

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>

#include <span>
#include <utility>
#include <vector>

namespace seam::core {

/// Makes the solvers run single-threaded in the calling thread: an optimized BLAS
/// (OpenBLAS's openblas_set_num_threads(1), process-wide, and its thread pool stopped) and
/// CHOLMOD's own OpenMP loops
/// (omp_set_max_active_levels(0), a per-thread setting; Debian's CHOLMOD asks for 4 OpenMP
/// threads per supernode whatever the machine has). Both hooks are looked up at run time and
/// are no-ops where the BLAS or CHOLMOD is built without them. The server already runs one
/// request per core; solver threads on top would oversubscribe them (on 2 cores the OpenMP
/// wake-ups alone cost 17-25% of a supernodal factorization). In a thread that called this,
/// CHOLMOD's OpenMP regions then run inline, without libgomp's team of one and the system call
/// that ends each (sparse_cholesky.cpp, GOMP_parallel: supernodal factorizations at 533k
/// unknowns 3.0-4.1 -> 1.5-1.6 s). Idempotent and thread-safe.
void use_single_threaded_solvers();

/// METIS nested dissection (METIS_NodeND, Karypis & Kumar 1998) of the symmetric pattern whose
/// lower triangle is `lower` (the diagonal and any entry above it are ignored): order[k] is the
/// unknown eliminated k-th. What SparseCholesky::prefer_nested_dissection() analyses with, for
/// a caller with several systems on one graph: METIS is most of a large analysis, and an order
/// restricted to a subset of the unknowns (restrict_order) is still a nested dissection of the
/// subgraph they induce, since removing vertices keeps every separator a separator. METIS
/// refines each level's separator with one pass instead of its default ten: on the 533k-vertex
/// graph of a 1M-face disc 2.39 s against 2.84 s through CHOLMOD's cholmod_metis (METIS's
/// defaults), for 0.7% more entries in L and 0.9% more flops per factorization
/// (bench/flatten_bench, median of 3 pairs).
/// CHOLMOD postorders the order in its analysis. Empty if METIS fails (out of memory) or
/// `lower` is not square. Deterministic (METIS's fixed seed) and thread-safe: METIS keeps its
/// random generator in process-wide state, so calls from concurrent requests take turns.
/// Complexity: METIS's, about O(nnz log n).
std::vector<int> nested_dissection_order(const Eigen::SparseMatrix<double>& lower);

/// `order` (over n items) restricted to the items that are unknowns of a smaller system:
/// unknown_of[item] is the item's unknown, or negative for none. The unknowns keep their
/// relative order. Precondition: unknown_of.size() == order.size(), the non-negative entries a
/// permutation of 0..m-1. O(n).
std::vector<int> restrict_order(std::span<const int> order, std::span<const Eigen::Index> unknown_of);

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
  /// (nested_dissection_order; CHOLMOD's analysis then reports CHOLMOD_GIVEN) instead of AMD,
  /// which every other analysis uses (also if METIS fails). On a 490k-vertex triangulated
  /// grid: 20% less fill (24.0M vs 30.2M entries in L) and 39% fewer flops per factorization
  /// (6.6 vs 10.7 GFlop); on SLIM's proxy at 534k unknowns analysis + 5 factorizations take
  /// 13.3 s against AMD's 14.7 s. Below 200k AMD wins: its analysis is 3-4x cheaper and, at
  /// 40k unknowns, its simplicial factorization no slower. Call before analyzePattern / compute.
  void prefer_nested_dissection(Eigen::Index min_unknowns = kNestedDissectionMin) {
    nested_dissection_min_ = min_unknowns;
  }

  /// Eliminates the unknowns in this order (perm[k]: the unknown eliminated k-th, a permutation
  /// of 0..n-1 for the next analysis's n unknowns) instead of computing one: for a system whose
  /// nested dissection another solver has already computed (nested_dissection_order,
  /// restrict_order). CHOLMOD still postorders it. Takes precedence over
  /// prefer_nested_dissection(); an empty order, or one of the wrong size, is ignored.
  void use_order(std::vector<int> perm) { order_ = std::move(perm); }

  void analyzePattern(const Eigen::SparseMatrix<double>& matrix) {
    position_.clear();  // a new analysis: a new permutation and new supernodes
    supernode_of_.clear();
    if (static_cast<Eigen::Index>(order_.size()) == matrix.rows() && matrix.rows() > 0) {
      analyze_with_order(matrix, order_);
      return;
    }
    if (nested_dissection_min_ >= 0 && matrix.rows() >= nested_dissection_min_) {
      if (const std::vector<int> nested = nested_dissection_order(matrix); !nested.empty()) {
        analyze_with_order(matrix, nested);
        return;
      }
    }
    // AMD alone: by default CHOLMOD also tries METIS when AMD's factor is dense enough, and
    // METIS must not run beside another call (nested_dissection_order serializes its own). Set
    // here because an earlier analysis in a given order changed the method.
    cholmod().nmethods = 1;
    cholmod().method[0].ordering = CHOLMOD_AMD;
    Base::analyzePattern(matrix);
  }

  SparseCholesky& compute(const Eigen::SparseMatrix<double>& matrix) {
    analyzePattern(matrix);
    factorize(matrix);
    return *this;
  }

  SparseCholesky(const SparseCholesky&) = delete;
  SparseCholesky& operator=(const SparseCholesky&) = delete;
  ~SparseCholesky();

  /// After the analysis: whether the factor is supernodal.
  bool supernodal() const;

  /// y = L^-1 P b, half of a solve (A = P^T L L^T P), so that b^T A^-1 c = y_b . y_c: for a
  /// right-hand side with few nonzeros, computed on the reach of their pattern in the
  /// elimination tree only, typically a small part of the n unknowns: CHOLMOD's partial solve
  /// (cholmod_solve2 with Bset) for a simplicial factor, a forward substitution over the reach's
  /// supernodes for a supernodal one (CHOLMOD would convert the factor). `b` lists (unknown,
  /// value) with distinct unknowns. Returns y's nonzeros as (row in the factor's order, value),
  /// rows increasing. Precondition (SEAM_ASSERT): a successful factorize(). Empty when CHOLMOD
  /// fails. Keeps its workspace (up to four vectors of n doubles) between calls; the reach is
  /// cached per analysis.
  std::vector<std::pair<int, double>> half_solve_sparse(std::span<const std::pair<int, double>> b);

  /// The factor of the factored matrix plus `additions` on its diagonal ((unknown, value),
  /// values >= 0; an unknown listed twice gets both), by a rank-k update of a simplicial factor
  /// (cholmod_updown; Davis & Hager 2001): each unknown costs about the entries of L on its
  /// path to the root of the elimination tree, far less than a numeric factorization when k is
  /// small. The factor stays LL^T, so solves and half_solve_sparse go on as before. The caller
  /// updates its own copy of the matrix. Returns false when the factor is supernodal (CHOLMOD
  /// would convert it to a simplicial one the size of L; the factor is left as it was) or
  /// CHOLMOD fails (the factor is then unusable); either way the caller factorizes the updated
  /// matrix instead. Precondition (SEAM_ASSERT): a successful factorize(). Not bit-identical to
  /// factorizing the updated matrix: the same factor up to rounding.
  bool update_diagonal(std::span<const std::pair<int, double>> additions);

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

  // Base::analyzePattern with cholmod_analyze_p and the given order (Eigen has no such call).
  void analyze_with_order(const Eigen::SparseMatrix<double>& matrix, std::span<const int> order);
  // position_ from the factor's permutation, once per analysis.
  void cache_positions();
  // half_solve_sparse's two kinds; position_ filled.
  std::vector<std::pair<int, double>> half_solve_simplicial(std::span<const std::pair<int, double>> b);
  std::vector<std::pair<int, double>> half_solve_supernodal(std::span<const std::pair<int, double>> b);

  Eigen::Index nested_dissection_min_ = -1;  // -1: never
  std::vector<int> order_;                   // use_order(); empty: CHOLMOD orders
  // half_solve_sparse's right-hand side, its pattern and CHOLMOD's reusable outputs.
  cholmod_dense* b_ = nullptr;
  cholmod_sparse* b_set_ = nullptr;
  cholmod_dense* x_ = nullptr;
  cholmod_sparse* x_set_ = nullptr;
  cholmod_dense* y_ = nullptr;
  cholmod_dense* e_ = nullptr;
  std::vector<int> position_;  // unknown -> row in the factor's order
  // Supernodal factors: the supernode of each row, each supernode's parent in the supernodal
  // elimination tree (-1 at a root), the dense work vector and a mark per supernode.
  std::vector<int> supernode_of_;
  std::vector<int> parent_;
  std::vector<double> work_;
  std::vector<char> in_reach_;
};

}  // namespace seam::core
