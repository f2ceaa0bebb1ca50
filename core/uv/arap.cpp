#include "core/uv/arap.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <span>

#include "core/uv/sparse_cholesky.h"

namespace seam::core {

namespace {

// Per triangle: isometric planar corners and the half-cotan edge weights (edge k is the
// edge opposite corner k).
struct ArapTriangles {
  std::vector<std::array<Vec2, 3>> frame;
  std::vector<Vec3> weight;
};

ArapTriangles arap_triangles(const DiscPatch& patch) {
  const std::size_t nf = patch.triangles.size();
  ArapTriangles tris{std::vector<std::array<Vec2, 3>>(nf), std::vector<Vec3>(nf)};
  for (std::size_t t = 0; t < nf; ++t) {
    tris.frame[t] = local_triangle_frame(patch, t);
    tris.weight[t] = 0.5 * corner_cotans(patch, t);
  }
  return tris;
}

// The global step's system with vertex 0 pinned: the energy is translation invariant, the
// rest of the Laplacian is positive definite on a connected disc.
struct PinnedSystem {
  Eigen::SparseMatrix<double> matrix;  // L_ff: the Laplacian without vertex 0's row and column
  Eigen::VectorXd pinned_column;       // L_f0
};

PinnedSystem pinned_laplacian(const DiscPatch& patch) {
  const Eigen::SparseMatrix<double> laplacian = cotan_laplacian(patch);
  const auto nfree = static_cast<Eigen::Index>(patch.num_vertices() - 1);
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<std::size_t>(laplacian.nonZeros()));
  PinnedSystem system{Eigen::SparseMatrix<double>(nfree, nfree), Eigen::VectorXd::Zero(nfree)};
  for (Eigen::Index c = 0; c < laplacian.outerSize(); ++c) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(laplacian, c); it; ++it) {
      if (it.row() == 0) continue;
      if (c == 0) {
        system.pinned_column[it.row() - 1] = it.value();
      } else {
        entries.emplace_back(it.row() - 1, c - 1, it.value());
      }
    }
  }
  system.matrix.setFromTriplets(entries.begin(), entries.end());
  return system;
}

// Local step: the rotation R maximising tr(R^T S), S = sum_k w_k du_k dx_k^T, is the
// rotation by atan2(S10 - S01, S00 + S11). Writes into `rotation` (one per triangle) so the
// iterations reuse one buffer.
Status fit_rotations(const DiscPatch& patch, const ArapTriangles& tris, const std::vector<Vec2>& uv,
                     std::span<Eigen::Matrix2d> rotation, std::uint32_t& poll, const CancelToken& cancel) {
  for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
    if (cancel.poll(poll)) return cancelled_error("ARAP local step");
    const Triangle& tri = patch.triangles[t];
    Eigen::Matrix2d s = Eigen::Matrix2d::Zero();
    for (int k = 0; k < 3; ++k) {
      const int i = (k + 1) % 3;
      const int j = (k + 2) % 3;
      s += tris.weight[t][k] * (uv[tri[i]] - uv[tri[j]]) * (tris.frame[t][i] - tris.frame[t][j]).transpose();
    }
    const double angle = std::atan2(s(1, 0) - s(0, 1), s(0, 0) + s(1, 1));
    const double c = std::cos(angle);
    const double sn = std::sin(angle);
    rotation[t] << c, -sn, sn, c;
  }
  return Ok{};
}

// Global step's right-hand side: L u = sum_t sum_edges w R_t (x_i - x_j), with u_0 = `pinned_uv`
// fixed, over the free vertices. Overwrites `rhs` (n - 1 by 2) so the iterations reuse one
// buffer.
void global_rhs(const DiscPatch& patch, const ArapTriangles& tris, std::span<const Eigen::Matrix2d> rotation,
                const PinnedSystem& system, const Vec2& pinned_uv, Eigen::MatrixX2d& rhs) {
  rhs.setZero();
  for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
    const Triangle& tri = patch.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const int i = (k + 1) % 3;
      const int j = (k + 2) % 3;
      const Vec2 r = tris.weight[t][k] * (rotation[t] * (tris.frame[t][i] - tris.frame[t][j]));
      if (tri[i] != 0) rhs.row(tri[i] - 1) += r.transpose();
      if (tri[j] != 0) rhs.row(tri[j] - 1) -= r.transpose();
    }
  }
  rhs -= system.pinned_column * pinned_uv.transpose();
}

}  // namespace

Result<std::vector<Vec2>> flatten_arap(const DiscPatch& patch, std::vector<Vec2> initial, int iterations,
                                       const CancelToken& cancel) {
  const std::size_t n = patch.num_vertices();
  const std::size_t nf = patch.triangles.size();
  if (initial.size() != n) {
    return make_error(ErrorCode::kInvalidArgument, "ARAP: the initial map has " + std::to_string(initial.size()) +
                                                       " UVs for " + std::to_string(n) + " vertices");
  }
  if (iterations <= 0 || n < 2) return initial;

  const ArapTriangles tris = arap_triangles(patch);
  const PinnedSystem system = pinned_laplacian(patch);
  const auto nfree = static_cast<Eigen::Index>(n - 1);
  SparseCholesky solver(system.matrix);
  if (solver.info() != Eigen::Success) {
    return make_error(ErrorCode::kSolverFailed, "ARAP: the Cholesky factorization of the cotan Laplacian failed");
  }

  std::vector<Eigen::Matrix2d> rotation(nf);
  std::vector<Vec2> direction(n, Vec2::Zero());
  Eigen::MatrixX2d rhs(nfree, 2);
  std::uint32_t poll = 0;
  for (int iter = 0; iter < iterations; ++iter) {
    if (cancel.is_cancelled()) return cancelled_error("ARAP");
    if (Status fitted = fit_rotations(patch, tris, initial, rotation, poll, cancel); !fitted.ok()) {
      return fitted.take_error();
    }
    global_rhs(patch, tris, rotation, system, initial[0], rhs);
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
