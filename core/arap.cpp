#include "core/arap.h"

#include <cmath>

#include <Eigen/SparseCholesky>

namespace seam::core {

Result<std::vector<Vec2>> flatten_arap(const DiscPatch& patch, std::vector<Vec2> initial, int iterations,
                                       const CancelToken& cancel) {
  const std::size_t n = patch.num_vertices();
  const std::size_t nf = patch.triangles.size();
  if (initial.size() != n) {
    return make_error(ErrorCode::kInvalidArgument, "ARAP: the initial map has " + std::to_string(initial.size()) +
                                                       " UVs for " + std::to_string(n) + " vertices");
  }
  if (iterations <= 0 || n < 2) return initial;

  // Per triangle: isometric planar corners and the half-cotan edge weights (edge k is the
  // edge opposite corner k).
  std::vector<std::array<Vec2, 3>> frame(nf);
  std::vector<Vec3> weight(nf);
  for (std::size_t t = 0; t < nf; ++t) {
    frame[t] = local_triangle_frame(patch, t);
    weight[t] = 0.5 * corner_cotans(patch, t);
  }

  // Vertex 0 is pinned: the energy is translation invariant, the rest of the Laplacian is
  // positive definite on a connected disc.
  const Eigen::SparseMatrix<double> laplacian = cotan_laplacian(patch);
  const auto nfree = static_cast<Eigen::Index>(n - 1);
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<std::size_t>(laplacian.nonZeros()));
  Eigen::VectorXd pinned_column = Eigen::VectorXd::Zero(nfree);  // L_f0
  for (Eigen::Index c = 0; c < laplacian.outerSize(); ++c) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(laplacian, c); it; ++it) {
      if (it.row() == 0) continue;
      if (c == 0) {
        pinned_column[it.row() - 1] = it.value();
      } else {
        entries.emplace_back(it.row() - 1, c - 1, it.value());
      }
    }
  }
  Eigen::SparseMatrix<double> system(nfree, nfree);
  system.setFromTriplets(entries.begin(), entries.end());
  entries = {};
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>> solver(system);
  if (solver.info() != Eigen::Success) {
    return make_error(ErrorCode::kSolverFailed, "ARAP: the Cholesky factorization of the cotan Laplacian failed");
  }

  std::vector<Eigen::Matrix2d> rotation(nf);
  Eigen::VectorXd rhs_x(nfree);
  Eigen::VectorXd rhs_y(nfree);
  std::uint32_t poll = 0;
  for (int iter = 0; iter < iterations; ++iter) {
    if (cancel.is_cancelled()) return cancelled_error("ARAP");
    // Local step: the rotation R maximising tr(R^T S), S = sum_k w_k du_k dx_k^T, is the
    // rotation by atan2(S10 - S01, S00 + S11).
    for (std::size_t t = 0; t < nf; ++t) {
      if (cancel.poll(poll)) return cancelled_error("ARAP local step");
      const Triangle& tri = patch.triangles[t];
      Eigen::Matrix2d s = Eigen::Matrix2d::Zero();
      for (int k = 0; k < 3; ++k) {
        const int i = (k + 1) % 3;
        const int j = (k + 2) % 3;
        s += weight[t][k] * (initial[tri[i]] - initial[tri[j]]) * (frame[t][i] - frame[t][j]).transpose();
      }
      const double angle = std::atan2(s(1, 0) - s(0, 1), s(0, 0) + s(1, 1));
      const double c = std::cos(angle);
      const double sn = std::sin(angle);
      rotation[t] << c, -sn, sn, c;
    }
    // Global step: L u = sum_t sum_edges w R_t (x_i - x_j), with u_0 fixed.
    rhs_x.setZero();
    rhs_y.setZero();
    for (std::size_t t = 0; t < nf; ++t) {
      const Triangle& tri = patch.triangles[t];
      for (int k = 0; k < 3; ++k) {
        const int i = (k + 1) % 3;
        const int j = (k + 2) % 3;
        const Vec2 r = weight[t][k] * (rotation[t] * (frame[t][i] - frame[t][j]));
        if (tri[i] != 0) {
          rhs_x[tri[i] - 1] += r.x();
          rhs_y[tri[i] - 1] += r.y();
        }
        if (tri[j] != 0) {
          rhs_x[tri[j] - 1] -= r.x();
          rhs_y[tri[j] - 1] -= r.y();
        }
      }
    }
    rhs_x -= pinned_column * initial[0].x();
    rhs_y -= pinned_column * initial[0].y();
    const Eigen::VectorXd x = solver.solve(rhs_x);
    const Eigen::VectorXd y = solver.solve(rhs_y);
    if (!x.allFinite() || !y.allFinite()) {
      return make_error(ErrorCode::kSolverFailed, "ARAP: the global step produced non-finite values");
    }
    for (Eigen::Index v = 0; v < nfree; ++v) initial[static_cast<std::size_t>(v) + 1] = Vec2(x[v], y[v]);
  }
  return initial;
}

}  // namespace seam::core
