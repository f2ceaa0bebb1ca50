// The shared sparse Cholesky (CHOLMOD, simplicial or supernodal by flops per entry of L):
// solves SPD systems to round-off with either kind, reports non-SPD input through info() with
// either kind, reuses a symbolic analysis, orders by nested dissection on request (less fill on
// a grid) from a size on or in an order given (one nested dissection restricted to subsystems),
// keeps BLAS and CHOLMOD's OpenMP loops single-threaded and runs those loops inline, orders
// the same from concurrent threads, and takes springs on its diagonal by a rank update of a
// simplicial factor.
#include "core/uv/sparse_cholesky.h"

#include <dlfcn.h>
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <iterator>
#include <mutex>
#include <numeric>
#include <thread>
#include <vector>

namespace seam_sparse_cholesky_test {

using seam::core::SparseCholesky;

namespace {

// The 1D Dirichlet Laplacian tridiag(-1, 2 + shift, -1) of size n: SPD for shift > -2(1 - cos(pi/(n+1))).
Eigen::SparseMatrix<double> laplacian_1d(int n, double shift) {
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, 2.0 + shift);
    if (i + 1 < n) {
      t.emplace_back(i + 1, i, -1.0);
      t.emplace_back(i, i + 1, -1.0);
    }
  }
  Eigen::SparseMatrix<double> a(n, n);
  a.setFromTriplets(t.begin(), t.end());
  return a;
}

// The 5-point Laplacian of an m x m grid (or 7-point of an m x m x m one) plus `shift` on the
// diagonal: a 2D mesh's structure, or a 3D one's, whose factor does many flops per entry.
Eigen::SparseMatrix<double> grid_laplacian(int m, int dims, double shift) {
  const int n = dims == 2 ? m * m : m * m * m;
  std::vector<Eigen::Triplet<double>> t;
  for (int v = 0; v < n; ++v) {
    t.emplace_back(v, v, 2.0 * dims + shift);
    for (int stride = 1, d = 0; d < dims; ++d, stride *= m) {
      if ((v / stride) % m + 1 >= m) continue;
      t.emplace_back(v + stride, v, -1.0);
      t.emplace_back(v, v + stride, -1.0);
    }
  }
  Eigen::SparseMatrix<double> a(n, n);
  a.setFromTriplets(t.begin(), t.end());
  return a;
}

}  // namespace

TEST_CASE("CHOLMOD solves an SPD system to round-off and refactors with a reused analysis") {
  const int n = 2000;
  Eigen::SparseMatrix<double> a = laplacian_1d(n, 0.0);
  const Eigen::VectorXd x_true = Eigen::VectorXd::LinSpaced(n, -1.0, 3.0);
  SparseCholesky solver(a);
  REQUIRE(solver.info() == Eigen::Success);
  const Eigen::VectorXd x = solver.solve(a * x_true);
  CHECK((x - x_true).norm() / x_true.norm() < 1e-8);

  // Same pattern, new values: factorize() alone.
  Eigen::SparseMatrix<double> b = laplacian_1d(n, 0.5);
  solver.factorize(b);
  REQUIRE(solver.info() == Eigen::Success);
  const Eigen::VectorXd y = solver.solve(b * x_true);
  CHECK((y - x_true).norm() / x_true.norm() < 1e-10);
}

TEST_CASE("nested dissection orders a grid Laplacian with less fill and solves it to round-off") {
  // The 2D grid is where nested dissection beats minimum degree.
  const int m = 60;
  const Eigen::SparseMatrix<double> a = grid_laplacian(m, 2, 0.01);
  const Eigen::VectorXd x_true = Eigen::VectorXd::LinSpaced(m * m, -2.0, 5.0);
  SparseCholesky by_default;
  by_default.compute(a);
  SparseCholesky nested;
  nested.prefer_nested_dissection(0);
  nested.compute(a);
  SparseCholesky below_size;  // the default size bound: 3600 unknowns keep AMD
  below_size.prefer_nested_dissection();
  below_size.compute(a);
  REQUIRE(by_default.info() == Eigen::Success);
  REQUIRE(nested.info() == Eigen::Success);
  REQUIRE(below_size.info() == Eigen::Success);
  // Nested dissection is computed by nested_dissection_order and given to CHOLMOD's analysis.
  CHECK(nested.cholmod().method[nested.cholmod().selected].ordering == CHOLMOD_GIVEN);
  CHECK(by_default.cholmod().method[by_default.cholmod().selected].ordering != CHOLMOD_GIVEN);
  CHECK(below_size.cholmod().method[below_size.cholmod().selected].ordering != CHOLMOD_GIVEN);
  CHECK(nested.cholmod().lnz < by_default.cholmod().lnz);
  const Eigen::VectorXd x = nested.solve(a * x_true);
  CHECK((x - x_true).norm() / x_true.norm() < 1e-10);
}

TEST_CASE("the factor is simplicial for a mesh-like system and supernodal where flops per entry are high") {
  // A 2D grid of 3600 unknowns: few flops per entry of L (a small mesh's Laplacian).
  const Eigen::SparseMatrix<double> flat = grid_laplacian(60, 2, 0.01);
  // A 3D grid of 27k unknowns: large separators, dense supernodes.
  const Eigen::SparseMatrix<double> solid = grid_laplacian(30, 3, 0.01);
  for (const Eigen::SparseMatrix<double>* a : {&flat, &solid}) {
    SparseCholesky solver(*a);
    REQUIRE(solver.info() == Eigen::Success);
    const double flops_per_entry = solver.cholmod().fl / solver.cholmod().lnz;
    CAPTURE(flops_per_entry);
    CHECK(solver.supernodal() == (flops_per_entry >= SparseCholesky::kSupernodalSwitch));
    CHECK(solver.supernodal() == (a == &solid));
    const Eigen::VectorXd x_true = Eigen::VectorXd::LinSpaced(a->rows(), 1.0, -4.0);
    const Eigen::VectorXd x = solver.solve(*a * x_true);
    CHECK((x - x_true).norm() / x_true.norm() < 1e-10);
    // Indefinite values on the same pattern are reported by either kind.
    Eigen::SparseMatrix<double> indefinite = *a;
    indefinite.coeffRef(a->rows() / 2, a->rows() / 2) = -1.0;
    solver.factorize(indefinite);
    CHECK(solver.info() != Eigen::Success);
    solver.factorize(*a);
    CHECK(solver.info() == Eigen::Success);
  }
}

TEST_CASE("an indefinite matrix is reported, not solved") {
  SparseCholesky solver(laplacian_1d(50, -3.0));
  CHECK(solver.info() != Eigen::Success);
}

TEST_CASE("OpenBLAS, when it is the BLAS, and CHOLMOD's OpenMP loops run single-threaded") {
  SparseCholesky solver(laplacian_1d(10, 0.0));
  using GetThreads = int (*)();
  if (auto* get = reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"))) {
    CHECK(get() == 1);
    // The pool OpenBLAS started when it was loaded is stopped: no thread of it is left to
    // spin beside the job's own (this suite starts no thread that outlives its test case).
    const auto tasks = std::distance(std::filesystem::directory_iterator("/proc/self/task"),
                                     std::filesystem::directory_iterator());
    CHECK(tasks == 1);
  } else {
    MESSAGE("the BLAS is not OpenBLAS: nothing to limit");
  }
  using GetLevels = int (*)();
  if (auto* get = reinterpret_cast<GetLevels>(dlsym(RTLD_DEFAULT, "omp_get_max_active_levels"))) {
    CHECK(get() == 0);
  } else {
    MESSAGE("CHOLMOD is built without OpenMP: nothing to limit");
  }
}

namespace {

using Parallel = void (*)(void (*)(void*), void*, unsigned, unsigned);

// A region body that records how many times it ran, on which threads, and the team it saw
// through the OpenMP calls CHOLMOD's static loops make.
struct RegionLog {
  std::mutex mutex;
  std::vector<std::thread::id> threads;
  std::vector<int> team_sizes;
};

void record_region(void* data) {
  auto* log = static_cast<RegionLog*>(data);
  using Query = int (*)();
  const auto num_threads = reinterpret_cast<Query>(dlsym(RTLD_DEFAULT, "omp_get_num_threads"));
  std::lock_guard lock(log->mutex);
  log->threads.push_back(std::this_thread::get_id());
  log->team_sizes.push_back(num_threads != nullptr ? num_threads() : -1);
}

}  // namespace

TEST_CASE("in a solver thread an OpenMP region runs inline once, other threads keep libgomp's teams") {
  // The dynamic linker binds GOMP_parallel to the executable's definition (core/CMakeLists.txt
  // exports it), which CHOLMOD's calls then reach.
  auto* ours = reinterpret_cast<Parallel>(dlsym(RTLD_DEFAULT, "GOMP_parallel"));
  auto* libgomp = reinterpret_cast<Parallel>(dlvsym(RTLD_NEXT, "GOMP_parallel", "GOMP_4.0"));
  REQUIRE(reinterpret_cast<void*>(ours) != nullptr);
  if (libgomp == nullptr) {
    MESSAGE("libgomp is not loaded (CHOLMOD built without OpenMP): nothing to run inline");
    return;
  }
  CHECK(reinterpret_cast<void*>(ours) != reinterpret_cast<void*>(libgomp));

  // A solver thread: one run, on the calling thread, in a team of one.
  seam::core::use_single_threaded_solvers();
  RegionLog inline_log;
  ours(record_region, &inline_log, 4, 0);
  REQUIRE(inline_log.threads.size() == 1);
  CHECK(inline_log.threads[0] == std::this_thread::get_id());
  CHECK(inline_log.team_sizes[0] == 1);

  // A thread that never asked for single-threaded solvers gets a real team of two.
  RegionLog team_log;
  std::thread other([&] { ours(record_region, &team_log, 2, 0); });
  other.join();
  CHECK(team_log.threads.size() == 2);
  CHECK(std::count(team_log.team_sizes.begin(), team_log.team_sizes.end(), 2) == 2);
}

namespace {

// Entries in L of an analysis of `a` in the order `perm` (postordered, as every analysis here).
double fill_in_order(const Eigen::SparseMatrix<double>& a, std::vector<int> perm) {
  SparseCholesky solver;
  solver.use_order(std::move(perm));
  solver.analyzePattern(a);
  REQUIRE(solver.info() == Eigen::Success);
  return solver.cholmod().lnz;
}

}  // namespace

TEST_CASE("nested dissection reads the graph off the lower triangle and fills like CHOLMOD's METIS call") {
  const int m = 90;
  const Eigen::SparseMatrix<double> full = grid_laplacian(m, 2, 0.01);
  const Eigen::SparseMatrix<double> lower = full.triangularView<Eigen::Lower>();
  const Eigen::SparseMatrix<double> strictly_lower = full.triangularView<Eigen::StrictlyLower>();
  const std::vector<int> order = seam::core::nested_dissection_order(lower);
  REQUIRE(order.size() == static_cast<std::size_t>(m * m));
  std::vector<int> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  std::vector<int> identity(sorted.size());
  std::iota(identity.begin(), identity.end(), 0);
  CHECK(sorted == identity);
  // One graph, however it is stored: the same order (METIS is deterministic).
  CHECK(seam::core::nested_dissection_order(strictly_lower) == order);
  CHECK(seam::core::nested_dissection_order(full) == order);

  // The oracle: CHOLMOD's own METIS call (its defaults: ten refinement passes per level).
  cholmod_common common;
  cholmod_start(&common);
  common.print = 0;
  cholmod_sparse view = Eigen::viewAsCholmod(lower.selfadjointView<Eigen::Lower>());
  std::vector<int> reference(static_cast<std::size_t>(m * m));
  REQUIRE(cholmod_metis(&view, nullptr, 0, 1, reference.data(), &common) != 0);
  cholmod_finish(&common);
  const double ours = fill_in_order(full, order);
  const double theirs = fill_in_order(full, reference);
  const double banded = fill_in_order(full, identity);  // row by row: a band of width m
  CAPTURE(ours);
  CAPTURE(theirs);
  // One refinement pass per level instead of ten: 5.3% more fill on this 90 x 90 grid, 0.7%
  // on a 1M-face disc's graph; separators found by other options differ by as much.
  CHECK(ours <= 1.10 * theirs);
  CHECK(ours < 0.35 * banded);

  CHECK(seam::core::nested_dissection_order(Eigen::SparseMatrix<double>(0, 0)).empty());
  CHECK(seam::core::nested_dissection_order(Eigen::SparseMatrix<double>(3, 4)).empty());
}

TEST_CASE("nested dissections from concurrent threads come out as they do one at a time") {
  // METIS's random generator is process-wide: unserialized, two threads ordering at once
  // changed both orders (a data race).
  const Eigen::SparseMatrix<double> first = grid_laplacian(70, 2, 0.01).triangularView<Eigen::Lower>();
  const Eigen::SparseMatrix<double> third = grid_laplacian(20, 3, 0.01).triangularView<Eigen::Lower>();
  const std::vector<int> alone_first = seam::core::nested_dissection_order(first);
  const std::vector<int> alone_third = seam::core::nested_dissection_order(third);
  REQUIRE(!alone_first.empty());
  REQUIRE(!alone_third.empty());
  constexpr int kRounds = 12;
  int same_first = 0;
  int same_third = 0;
  std::thread other([&] {
    for (int i = 0; i < kRounds; ++i) same_first += seam::core::nested_dissection_order(first) == alone_first;
  });
  for (int i = 0; i < kRounds; ++i) same_third += seam::core::nested_dissection_order(third) == alone_third;
  other.join();
  CHECK(same_first == kRounds);
  CHECK(same_third == kRounds);
}

TEST_CASE("one nested dissection, restricted to subsets of the unknowns, orders each system") {
  const int m = 80;  // large enough for nested dissection to beat minimum degree
  const Eigen::SparseMatrix<double> whole = grid_laplacian(m, 2, 0.01);
  Eigen::SparseMatrix<double> lower = whole.triangularView<Eigen::Lower>();
  const std::vector<int> order = seam::core::nested_dissection_order(lower);
  REQUIRE(order.size() == static_cast<std::size_t>(m * m));
  std::vector<int> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (int i = 0; i < m * m; ++i) REQUIRE(sorted[static_cast<std::size_t>(i)] == i);

  // The interior of the grid (the boundary ring dropped), numbered row by row: BFF's A_II.
  std::vector<Eigen::Index> unknown_of(static_cast<std::size_t>(m * m), -1);
  Eigen::Index interior = 0;
  for (int v = 0; v < m * m; ++v) {
    const int row = v / m, col = v % m;
    if (row > 0 && row + 1 < m && col > 0 && col + 1 < m) unknown_of[static_cast<std::size_t>(v)] = interior++;
  }
  const std::vector<int> restricted = seam::core::restrict_order(order, unknown_of);
  REQUIRE(static_cast<Eigen::Index>(restricted.size()) == interior);
  // Relative order kept: the unknowns appear as their vertices do in `order`.
  std::vector<Eigen::Index> expected;
  for (int v : order) {
    if (unknown_of[static_cast<std::size_t>(v)] >= 0) expected.push_back(unknown_of[static_cast<std::size_t>(v)]);
  }
  CHECK(std::equal(restricted.begin(), restricted.end(), expected.begin(), expected.end()));

  const Eigen::SparseMatrix<double> a_ii = grid_laplacian(m - 2, 2, 0.01);
  SparseCholesky given;
  given.use_order(restricted);
  given.compute(a_ii);
  SparseCholesky nested;  // METIS on the subsystem itself
  nested.prefer_nested_dissection(0);
  nested.compute(a_ii);
  std::vector<int> identity(static_cast<std::size_t>(a_ii.rows()));
  std::iota(identity.begin(), identity.end(), 0);
  SparseCholesky banded;  // the row-by-row numbering: a band of width m
  banded.use_order(identity);
  banded.compute(a_ii);
  REQUIRE(given.info() == Eigen::Success);
  REQUIRE(nested.info() == Eigen::Success);
  REQUIRE(banded.info() == Eigen::Success);
  CHECK(given.cholmod().method[given.cholmod().selected].ordering == CHOLMOD_GIVEN);
  // Within 10% of METIS's own fill (7.7% more here; the restriction costs the separators their
  // refinement on the smaller graph), a quarter of the band's.
  CHECK(given.cholmod().lnz < 1.1 * nested.cholmod().lnz);
  CHECK(given.cholmod().lnz < 0.25 * banded.cholmod().lnz);
  const Eigen::VectorXd x_true = Eigen::VectorXd::LinSpaced(a_ii.rows(), -1.0, 3.0);
  const Eigen::VectorXd x = given.solve(a_ii * x_true);
  CHECK((x - x_true).norm() / x_true.norm() < 1e-10);
  // Refactoring new values on the same pattern keeps the given order.
  given.factorize(a_ii * 2.0);
  CHECK(((given.solve(a_ii * x_true) * 2.0) - x_true).norm() / x_true.norm() < 1e-10);

  // An order of the wrong size is ignored: CHOLMOD orders the system itself.
  SparseCholesky wrong;
  wrong.use_order(order);
  wrong.compute(a_ii);
  REQUIRE(wrong.info() == Eigen::Success);
  CHECK(wrong.cholmod().method[wrong.cholmod().selected].ordering == CHOLMOD_AMD);

  // The solver that factored in the given order, analysing a system the order does not fit:
  // AMD again, not the method the given order left behind.
  given.compute(whole);
  REQUIRE(given.info() == Eigen::Success);
  CHECK(given.cholmod().method[given.cholmod().selected].ordering == CHOLMOD_AMD);
  const Eigen::VectorXd w_true = Eigen::VectorXd::LinSpaced(whole.rows(), 2.0, -1.0);
  CHECK((given.solve(whole * w_true) - w_true).norm() / w_true.norm() < 1e-10);
}

TEST_CASE("half solves on the reach of a sparse right-hand side give b^T A^-1 c exactly as whole solves do") {
  // A 2D grid (a simplicial factor: CHOLMOD's partial solve) and a 3D one (a supernodal
  // factor: the reach's supernodes).
  const Eigen::SparseMatrix<double> flat = grid_laplacian(40, 2, 0.01);
  const Eigen::SparseMatrix<double> solid = grid_laplacian(30, 3, 0.01);
  for (const Eigen::SparseMatrix<double>* a : {&flat, &solid}) {
    SparseCholesky solver(*a);
    REQUIRE(solver.info() == Eigen::Success);
    REQUIRE(solver.supernodal() == (a == &solid));
    CAPTURE(solver.supernodal());
    // Right-hand sides with three nonzeros each, as a boundary contact's row: a vertex and an edge.
    const std::vector<std::vector<std::pair<int, double>>> rows = {{{5, 1.0}, {6, -0.5}, {45, -0.5}},
                                                                   {{820, 0.3}, {821, 0.7}, {861, -1.0}},
                                                                   {{1599, 2.0}, {0, -1.0}, {799, 0.25}}};
    // Twice: the values of a second factorization on the same analysis are used.
    for (double scale : {1.0, 3.0}) {
      CAPTURE(scale);
      solver.factorize(*a * scale);
      REQUIRE(solver.info() == Eigen::Success);
      std::vector<std::vector<std::pair<int, double>>> half;
      for (const auto& row : rows) {
        half.push_back(solver.half_solve_sparse(row));
        REQUIRE_FALSE(half.back().empty());
        CHECK(std::is_sorted(half.back().begin(), half.back().end()));
        CHECK(half.back().size() < static_cast<std::size_t>(a->rows()));  // the reach, not the whole
      }
      for (std::size_t i = 0; i < rows.size(); ++i) {
        Eigen::VectorXd b = Eigen::VectorXd::Zero(a->rows());
        for (const auto& [k, v] : rows[i]) b[k] = v;
        const Eigen::VectorXd x = solver.solve(b);
        for (std::size_t j = 0; j < rows.size(); ++j) {
          double expected = 0;
          for (const auto& [k, v] : rows[j]) expected += v * x[k];
          double got = 0;
          for (const auto& [r, v] : half[i]) {
            for (const auto& [q, w] : half[j]) got += r == q ? v * w : 0.0;
          }
          CAPTURE(i);
          CAPTURE(j);
          CHECK(got == doctest::Approx(expected).epsilon(1e-12));
        }
      }
    }
  }
}

TEST_CASE("a diagonal update of a simplicial factor solves as the factorization of the updated matrix") {
  // Stiff springs on a few unknowns, as SLIM's held vertices: the updated factor's solves and
  // half solves match a factorization of A + D; a supernodal factor is refused.
  const Eigen::SparseMatrix<double> flat = grid_laplacian(40, 2, 0.01);
  const std::vector<std::pair<int, double>> springs = {{5, 1e6}, {820, 2.5e6}, {1599, 1e6}, {821, 0.5}};
  SparseCholesky solver(flat);
  REQUIRE(solver.info() == Eigen::Success);
  REQUIRE_FALSE(solver.supernodal());
  (void)solver.half_solve_sparse(std::vector<std::pair<int, double>>{{7, 1.0}});  // caches the permutation first
  REQUIRE(solver.update_diagonal(springs));
  REQUIRE(solver.info() == Eigen::Success);
  Eigen::SparseMatrix<double> updated = flat;
  for (const auto& [k, v] : springs) updated.coeffRef(k, k) += v;
  const SparseCholesky reference(updated);
  REQUIRE(reference.info() == Eigen::Success);
  Eigen::VectorXd b(flat.rows());
  for (Eigen::Index i = 0; i < b.size(); ++i) b[i] = std::sin(0.37 * static_cast<double>(i)) + 0.1;
  const Eigen::VectorXd x = solver.solve(b);
  const Eigen::VectorXd expected = reference.solve(b);
  CHECK((x - expected).norm() <= 1e-9 * expected.norm());
  CHECK((updated * x - b).norm() <= 1e-8 * b.norm());
  // Half solves stay valid: y . y = e_k^T (A + D)^-1 e_k.
  for (int k : {5, 6, 900}) {
    const auto half = solver.half_solve_sparse(std::vector<std::pair<int, double>>{{k, 1.0}});
    REQUIRE_FALSE(half.empty());
    double got = 0;
    for (const auto& [r, v] : half) got += v * v;
    Eigen::VectorXd e = Eigen::VectorXd::Zero(flat.rows());
    e[k] = 1.0;
    CAPTURE(k);
    CHECK(got == doctest::Approx(reference.solve(e)[k]).epsilon(1e-9));
  }
  // Nothing to add changes nothing; the next factorization starts from the matrix again.
  CHECK(solver.update_diagonal({}));
  solver.factorize(flat);
  REQUIRE(solver.info() == Eigen::Success);
  CHECK((flat * solver.solve(b) - b).norm() <= 1e-8 * b.norm());

  SparseCholesky dense_factor(grid_laplacian(30, 3, 0.01));
  REQUIRE(dense_factor.supernodal());
  CHECK_FALSE(dense_factor.update_diagonal(springs));
}

}  // namespace seam_sparse_cholesky_test
