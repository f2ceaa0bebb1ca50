// The shared sparse Cholesky (CHOLMOD supernodal): solves SPD systems to round-off, reports
// non-SPD input through info(), reuses a symbolic analysis, orders by nested dissection on
// request (less fill on a grid), and keeps BLAS single-threaded.
#include <doctest/doctest.h>

#include <dlfcn.h>

#include <vector>

#include "core/uv/sparse_cholesky.h"

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
  // The 5-point Laplacian of an m x m grid (plus a small shift): the 2D structure where
  // nested dissection beats minimum degree.
  const int m = 60;
  std::vector<Eigen::Triplet<double>> t;
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < m; ++i) {
      const int v = j * m + i;
      t.emplace_back(v, v, 4.01);
      for (int w : {i + 1 < m ? v + 1 : -1, j + 1 < m ? v + m : -1}) {
        if (w < 0) continue;
        t.emplace_back(w, v, -1.0);
        t.emplace_back(v, w, -1.0);
      }
    }
  }
  Eigen::SparseMatrix<double> a(m * m, m * m);
  a.setFromTriplets(t.begin(), t.end());
  const Eigen::VectorXd x_true = Eigen::VectorXd::LinSpaced(m * m, -2.0, 5.0);
  SparseCholesky by_default;
  by_default.compute(a);
  SparseCholesky nested;
  nested.prefer_nested_dissection();
  nested.compute(a);
  REQUIRE(by_default.info() == Eigen::Success);
  REQUIRE(nested.info() == Eigen::Success);
  CHECK(nested.cholmod().method[nested.cholmod().selected].ordering == CHOLMOD_METIS);
  CHECK(by_default.cholmod().method[by_default.cholmod().selected].ordering != CHOLMOD_METIS);
  CHECK(nested.cholmod().lnz < by_default.cholmod().lnz);
  const Eigen::VectorXd x = nested.solve(a * x_true);
  CHECK((x - x_true).norm() / x_true.norm() < 1e-10);
}

TEST_CASE("an indefinite matrix is reported, not solved") {
  SparseCholesky solver(laplacian_1d(50, -3.0));
  CHECK(solver.info() != Eigen::Success);
}

TEST_CASE("OpenBLAS, when it is the BLAS, runs single-threaded") {
  SparseCholesky solver(laplacian_1d(10, 0.0));
  using GetThreads = int (*)();
  if (auto* get = reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"))) {
    CHECK(get() == 1);
  } else {
    MESSAGE("the BLAS is not OpenBLAS: nothing to limit");
  }
}
