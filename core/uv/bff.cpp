#include "core/uv/bff.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/uv/sparse_cholesky.h"

namespace seam::core {

namespace {

std::size_t count_inverted(const DiscPatch& patch, const std::vector<Vec2>& uv) {
  std::size_t count = 0;
  for (const Triangle& t : patch.triangles) {
    const Vec2 a = uv[t[1]] - uv[t[0]];
    const Vec2 b = uv[t[2]] - uv[t[0]];
    if (!(cross2(a, b) > 0)) ++count;
  }
  return count;
}

// Dirichlet extension of the boundary values in `uv` with edge weights max(w_ij, floor),
// floor a small fraction of the mean positive weight, so every weight is positive.
Result<std::vector<Vec2>> extend_positive(const DiscPatch& patch, const std::vector<Eigen::Index>& interior_index,
                                          std::vector<Vec2> uv, const CancelToken& cancel) {
  const Eigen::SparseMatrix<double> laplacian = cotan_laplacian(patch);
  double positive_sum = 0;
  std::size_t positive_count = 0;
  for (Eigen::Index c = 0; c < laplacian.outerSize(); ++c) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(laplacian, c); it; ++it) {
      if (it.row() != c && -it.value() > 0) {
        positive_sum += -it.value();
        ++positive_count;
      }
    }
  }
  const double floor = positive_count > 0 ? 1e-3 * positive_sum / static_cast<double>(positive_count) : 1.0;
  Eigen::Index num_interior = 0;
  for (Eigen::Index i : interior_index) num_interior += i >= 0 ? 1 : 0;
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::VectorXd diagonal = Eigen::VectorXd::Zero(num_interior);
  Eigen::MatrixX2d rhs = Eigen::MatrixX2d::Zero(num_interior, 2);
  for (Eigen::Index c = 0; c < laplacian.outerSize(); ++c) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(laplacian, c); it; ++it) {
      const Eigen::Index r = it.row();
      if (r == c || interior_index[r] < 0) continue;
      const double w = std::max(-it.value(), floor);
      diagonal[interior_index[r]] += w;
      if (interior_index[c] >= 0) {
        entries.emplace_back(interior_index[r], interior_index[c], -w);
      } else {
        rhs.row(interior_index[r]) += w * uv[static_cast<std::size_t>(c)].transpose();
      }
    }
  }
  for (Eigen::Index i = 0; i < num_interior; ++i) entries.emplace_back(i, i, diagonal[i]);
  Eigen::SparseMatrix<double> system(num_interior, num_interior);
  system.setFromTriplets(entries.begin(), entries.end());
  if (cancel.is_cancelled()) return cancelled_error("BFF extension");
  SparseCholesky solver(system);
  if (solver.info() != Eigen::Success) {
    return make_error(ErrorCode::kSolverFailed, "BFF: the positive-weight extension failed to factor");
  }
  const Eigen::MatrixX2d xy = solver.solve(rhs);
  if (!xy.allFinite()) return make_error(ErrorCode::kSolverFailed, "BFF: the positive-weight extension diverged");
  for (std::size_t v = 0; v < uv.size(); ++v) {
    if (interior_index[v] >= 0) uv[v] = Vec2(xy(interior_index[v], 0), xy(interior_index[v], 1));
  }
  return uv;
}

// Interior vertices get indices 0..nI-1 in the reduced system; boundary vertices keep their
// position in the counter-clockwise loop.
struct BffIndex {
  std::vector<Eigen::Index> interior;  // -1 on the boundary
  std::vector<Eigen::Index> boundary;  // -1 inside
  Eigen::Index num_interior = 0;
};

BffIndex index_vertices(const DiscPatch& patch) {
  BffIndex index;
  const std::size_t n = patch.num_vertices();
  index.interior.assign(n, -1);
  index.boundary.assign(n, -1);
  for (std::size_t k = 0; k < patch.boundary.size(); ++k) {
    index.boundary[patch.boundary[k]] = static_cast<Eigen::Index>(k);
  }
  for (std::size_t v = 0; v < n; ++v) {
    if (index.boundary[v] < 0) index.interior[v] = index.num_interior++;
  }
  return index;
}

// Angle sums give the curvatures: K = 2 pi - sum (interior), k = pi - sum (boundary).
Result<std::vector<double>> angle_sums(const DiscPatch& patch, const CancelToken& cancel) {
  std::vector<double> angle_sum(patch.num_vertices(), 0.0);
  std::uint32_t poll = 0;
  for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
    if (cancel.poll(poll)) return cancelled_error("BFF curvature");
    const Vec3 a = corner_angles(patch, t);
    for (int k = 0; k < 3; ++k) angle_sum[patch.triangles[t][k]] += a[k];
  }
  return angle_sum;
}

// The cotan Laplacian's interior rows, split into A_II and A_IB.
struct SplitLaplacian {
  Eigen::SparseMatrix<double> a_ii;  // its lower triangle: all that the factorization reads
  Eigen::SparseMatrix<double> a_ib;
};

// Copied column by column (no triplets: at 1M faces they were ~120 MB of fresh memory). The
// interior numbering follows the vertex order, so each column's rows stay sorted; A_II's
// columns come in order, A_IB's in boundary-loop order, so those are counted first. Of A_II
// only the lower triangle is kept: SparseCholesky reads no more (Eigen::Lower), and the upper
// half was ~26 MB held through the factorization, the default job's peak, at 1.25M faces.
SplitLaplacian split_laplacian(const DiscPatch& patch, const BffIndex& index) {
  const Eigen::SparseMatrix<double> laplacian = cotan_laplacian(patch);
  const auto nb = static_cast<Eigen::Index>(patch.boundary.size());
  SplitLaplacian out{Eigen::SparseMatrix<double>(index.num_interior, index.num_interior),
                     Eigen::SparseMatrix<double>(index.num_interior, nb)};
  std::vector<int> ib_count(static_cast<std::size_t>(nb) + 1, 0);
  Eigen::Index ii_entries = 0;
  for (Eigen::Index c = 0; c < laplacian.outerSize(); ++c) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(laplacian, c); it; ++it) {
      if (index.interior[it.row()] < 0) continue;
      if (index.interior[c] >= 0) {
        ii_entries += index.interior[it.row()] >= index.interior[c] ? 1 : 0;
      } else {
        ++ib_count[index.boundary[c] + 1];
      }
    }
  }
  for (Eigen::Index b = 0; b < nb; ++b) ib_count[b + 1] += ib_count[b];
  out.a_ii.resizeNonZeros(ii_entries);
  out.a_ib.resizeNonZeros(ib_count[nb]);
  std::copy(ib_count.begin(), ib_count.end(), out.a_ib.outerIndexPtr());
  int* ii_outer = out.a_ii.outerIndexPtr();
  ii_outer[0] = 0;
  int ii_next = 0;
  for (Eigen::Index c = 0; c < laplacian.outerSize(); ++c) {
    const bool interior_column = index.interior[c] >= 0;
    for (Eigen::SparseMatrix<double>::InnerIterator it(laplacian, c); it; ++it) {
      const Eigen::Index r = index.interior[it.row()];
      if (r < 0 || (interior_column && r < index.interior[c])) continue;
      const int at = interior_column ? ii_next++ : ib_count[index.boundary[c]]++;
      Eigen::SparseMatrix<double>& block = interior_column ? out.a_ii : out.a_ib;
      block.innerIndexPtr()[at] = static_cast<int>(r);
      block.valuePtr()[at] = it.value();
    }
    if (interior_column) ii_outer[index.interior[c] + 1] = ii_next;
  }
  return out;
}

// The target exterior angles k~_B = k_B + (A_BI u_I) (A_BI = A_IB^T), u_I solving
// A_II u_I = -K_I with the factorization `solver` keeps for the extension.
Result<Eigen::VectorXd> target_exterior_angles(const DiscPatch& patch, const BffIndex& index, const SplitLaplacian& a,
                                               const std::vector<double>& angle_sum, SparseCholesky& solver,
                                               const CancelToken& cancel) {
  constexpr double kPi = std::numbers::pi;
  const std::size_t nb = patch.boundary.size();
  Eigen::VectorXd target_k(static_cast<Eigen::Index>(nb));
  for (std::size_t k = 0; k < nb; ++k) target_k[static_cast<Eigen::Index>(k)] = kPi - angle_sum[patch.boundary[k]];
  if (index.num_interior == 0) return target_k;
  solver.compute(a.a_ii);
  if (solver.info() != Eigen::Success) {
    return make_error(ErrorCode::kSolverFailed, "BFF: the Cholesky factorization of the interior cotan Laplacian failed");
  }
  if (cancel.is_cancelled()) return cancelled_error("BFF factorization");
  Eigen::VectorXd minus_k(index.num_interior);
  for (std::size_t v = 0; v < patch.num_vertices(); ++v) {
    if (index.interior[v] >= 0) minus_k[index.interior[v]] = -(2 * kPi - angle_sum[v]);
  }
  const Eigen::VectorXd u_interior = solver.solve(minus_k);
  if (!u_interior.allFinite()) {
    return make_error(ErrorCode::kSolverFailed, "BFF: the scale factor solve produced non-finite values");
  }
  target_k += a.a_ib.transpose() * u_interior;
  return target_k;
}

// The boundary curve: the tangent integrated with turns target_k (edge k runs from
// boundary[k] to boundary[k+1] and turns by k~ at boundary[k] relative to edge k-1), closed
// with the least change of lengths, sum (l*-l)^2 / l, subject to sum l* T = 0 (§4.1.2):
// l* = l - diag(l) T^T (T diag(l) T^T)^-1 T l. Returns the boundary vertices' positions in
// loop order.
Result<std::vector<Vec2>> boundary_curve(const DiscPatch& patch, const Eigen::VectorXd& target_k) {
  const std::size_t nb = patch.boundary.size();
  Eigen::VectorXd length(static_cast<Eigen::Index>(nb));
  Eigen::Matrix2Xd tangent(2, static_cast<Eigen::Index>(nb));
  double phi = 0;
  for (std::size_t k = 0; k < nb; ++k) {
    const auto kk = static_cast<Eigen::Index>(k);
    if (k > 0) phi += target_k[kk];
    length[kk] = (patch.positions[patch.boundary[(k + 1) % nb]] - patch.positions[patch.boundary[k]]).norm();
    tangent(0, kk) = std::cos(phi);
    tangent(1, kk) = std::sin(phi);
  }
  const Eigen::Matrix2d gram = tangent * length.asDiagonal() * tangent.transpose();
  const Eigen::Vector2d gap = tangent * length;
  const Eigen::Vector2d lambda = gram.ldlt().solve(gap);
  const Eigen::VectorXd closed_length = length - length.asDiagonal() * (tangent.transpose() * lambda);
  if (!closed_length.allFinite()) {
    return make_error(ErrorCode::kSolverFailed, "BFF: closing the boundary curve failed");
  }
  std::vector<Vec2> curve(nb);
  Vec2 p(0, 0);
  for (std::size_t k = 0; k < nb; ++k) {
    curve[k] = p;
    p += closed_length[static_cast<Eigen::Index>(k)] * tangent.col(static_cast<Eigen::Index>(k));
  }
  return curve;
}

// The interior by the harmonic extension of the boundary curve (with `solver`'s A_II); where
// it folds, the positive-weight extension if that folds less.
Result<std::vector<Vec2>> extend_inside(const DiscPatch& patch, const BffIndex& index, const SplitLaplacian& a,
                                        const std::vector<Vec2>& curve, const SparseCholesky& solver,
                                        const CancelToken& cancel) {
  const std::size_t nb = patch.boundary.size();
  std::vector<Vec2> uv(patch.num_vertices(), Vec2::Zero());
  Eigen::VectorXd bx(static_cast<Eigen::Index>(nb));
  Eigen::VectorXd by(static_cast<Eigen::Index>(nb));
  for (std::size_t k = 0; k < nb; ++k) {
    uv[patch.boundary[k]] = curve[k];
    bx[static_cast<Eigen::Index>(k)] = curve[k].x();
    by[static_cast<Eigen::Index>(k)] = curve[k].y();
  }
  if (index.num_interior == 0) return uv;
  if (cancel.is_cancelled()) return cancelled_error("BFF extension");
  const Eigen::VectorXd x = solver.solve(-(a.a_ib * bx));
  const Eigen::VectorXd y = solver.solve(-(a.a_ib * by));
  if (!x.allFinite() || !y.allFinite()) {
    return make_error(ErrorCode::kSolverFailed, "BFF: the harmonic extension produced non-finite values");
  }
  for (std::size_t v = 0; v < patch.num_vertices(); ++v) {
    if (index.interior[v] >= 0) uv[v] = Vec2(x[index.interior[v]], y[index.interior[v]]);
  }
  if (count_inverted(patch, uv) > 0) {
    // Cotan weights are negative across non-Delaunay edges, and then the discrete harmonic
    // extension has no maximum principle and can fold. Retry with the weights clamped to be
    // positive (a convex-combination map in the sense of Floater): one more factorization,
    // paid only by meshes that need it; kept only if it folds less.
    SEAM_TRY(std::vector<Vec2> positive, extend_positive(patch, index.interior, uv, cancel));
    if (count_inverted(patch, positive) < count_inverted(patch, uv)) uv = std::move(positive);
  }
  return uv;
}

}  // namespace

Result<std::vector<Vec2>> flatten_bff(const DiscPatch& patch, const CancelToken& cancel,
                                      std::span<const int> vertex_order) {
  if (!vertex_order.empty() && vertex_order.size() != patch.num_vertices()) {
    return make_error(ErrorCode::kInvalidArgument, "BFF: the vertex order has " + std::to_string(vertex_order.size()) +
                                                       " entries for " + std::to_string(patch.num_vertices()) +
                                                       " vertices");
  }
  const BffIndex index = index_vertices(patch);
  SEAM_TRY(const std::vector<double> angle_sum, angle_sums(patch, cancel));
  const SplitLaplacian a = split_laplacian(patch, index);
  if (cancel.is_cancelled()) return cancelled_error("BFF assembly");
  // A_II is the Dirichlet Laplacian of a connected disc: positive definite, so LL^T applies.
  // In the order given (SLIM's, whose nested dissection keeps the default job's peak memory in
  // bounds), else CHOLMOD's own (AMD): for one factorization METIS's analysis costs more than
  // its smaller factor saves, since CHOLMOD's regions run inline (uv: bff at 1.07M faces 4.5 ->
  // 2.2 s; at 1.25M faces the job 9.1 -> 6.5 s, peak 872 -> 920 MiB, below the default job's).
  SparseCholesky solver;
  if (!vertex_order.empty()) solver.use_order(restrict_order(vertex_order, index.interior));
  SEAM_TRY(const Eigen::VectorXd target_k, target_exterior_angles(patch, index, a, angle_sum, solver, cancel));
  SEAM_TRY(const std::vector<Vec2> curve, boundary_curve(patch, target_k));
  return extend_inside(patch, index, a, curve, solver, cancel);
}

}  // namespace seam::core
