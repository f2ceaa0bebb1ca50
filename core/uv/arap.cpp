#include "core/uv/arap.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/uv/sparse_cholesky.h"

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
  SparseCholesky solver(system);
  if (solver.info() != Eigen::Success) {
    return make_error(ErrorCode::kSolverFailed, "ARAP: the Cholesky factorization of the cotan Laplacian failed");
  }

  std::vector<Eigen::Matrix2d> rotation(nf);
  std::vector<Vec2> direction(n, Vec2::Zero());
  Eigen::MatrixX2d rhs(nfree, 2);
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
    rhs.setZero();
    for (std::size_t t = 0; t < nf; ++t) {
      const Triangle& tri = patch.triangles[t];
      for (int k = 0; k < 3; ++k) {
        const int i = (k + 1) % 3;
        const int j = (k + 2) % 3;
        const Vec2 r = weight[t][k] * (rotation[t] * (frame[t][i] - frame[t][j]));
        if (tri[i] != 0) rhs.row(tri[i] - 1) += r.transpose();
        if (tri[j] != 0) rhs.row(tri[j] - 1) -= r.transpose();
      }
    }
    rhs -= pinned_column * initial[0].transpose();
    const Eigen::MatrixX2d xy = solver.solve(rhs);
    if (!xy.allFinite()) {
      return make_error(ErrorCode::kSolverFailed, "ARAP: the global step produced non-finite values");
    }
    // For fixed rotations the energy is convex in the UVs, so every point on the segment to
    // the global minimiser lowers it; step only as far as no positive triangle reaches zero
    // area (Smith & Schaefer 2015's injective step bound), so ARAP never adds a flip.
    direction[0] = Vec2::Zero();
    for (Eigen::Index v = 0; v < nfree; ++v) {
      direction[static_cast<std::size_t>(v) + 1] = Vec2(xy(v, 0), xy(v, 1)) - initial[static_cast<std::size_t>(v) + 1];
    }
    const double step = std::min(1.0, 0.8 * max_injective_step(patch, initial, direction));
    for (std::size_t v = 0; v < n; ++v) initial[v] += step * direction[v];
    // A tiny step means some triangle wants to fold and the bound has locked the iteration;
    // more steps would only squeeze that triangle towards zero area.
    if (step < 1e-3) break;
  }
  return initial;
}

}  // namespace seam::core
