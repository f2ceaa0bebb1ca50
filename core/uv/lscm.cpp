#include "core/uv/lscm.h"

#include "core/uv/sparse_cholesky.h"

namespace seam::core {

std::array<std::uint32_t, 2> boundary_far_pair(const DiscPatch& patch) {
  // Two sweeps give a pair at least half the true diameter apart at O(boundary) cost; the
  // exact pair is quadratic and buys nothing visible in the map.
  auto farthest_from = [&](std::uint32_t from) {
    std::uint32_t best = from;
    double best_d = -1;
    for (std::uint32_t v : patch.boundary) {
      const double d = (patch.positions[v] - patch.positions[from]).squaredNorm();
      if (d > best_d) {
        best_d = d;
        best = v;
      }
    }
    return best;
  };
  const std::uint32_t a = farthest_from(patch.boundary.front());
  const std::uint32_t b = farthest_from(a);
  return {a, b};
}

namespace {

// The conformal energy minus the signed area as a system over the free coordinates: u_i is
// coordinate i, v_i is n + i, and the pinned pair's four coordinates are known.
struct LscmSystem {
  Eigen::SparseMatrix<double> matrix;
  Eigen::VectorXd rhs;
  Eigen::VectorXd known;                 // every coordinate; only the pinned ones are read
  std::vector<Eigen::Index> free_index;  // coordinate -> unknown, -1 when pinned

  double value(const Eigen::VectorXd& x, std::size_t k) const {
    return free_index[k] >= 0 ? x[free_index[k]] : known[static_cast<Eigen::Index>(k)];
  }
};

// Pins p0 at the origin and p1 on the u axis at their 3D distance, then assembles.
Result<LscmSystem> assemble_lscm(const DiscPatch& patch, std::size_t p0, std::size_t p1, const CancelToken& cancel) {
  const std::size_t n = patch.num_vertices();
  LscmSystem sys;
  const double d = (patch.positions[p1] - patch.positions[p0]).norm();
  sys.known = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(2 * n));
  sys.known[static_cast<Eigen::Index>(p1)] = d > 0 ? d : 1.0;
  sys.free_index.assign(2 * n, -1);
  Eigen::Index num_free = 0;
  for (std::size_t k = 0; k < 2 * n; ++k) {
    const std::size_t vertex = k % n;
    if (vertex == p0 || vertex == p1) continue;
    sys.free_index[k] = num_free++;
  }

  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(patch.triangles.size() * 24 + patch.boundary.size() * 4);
  sys.rhs = Eigen::VectorXd::Zero(num_free);
  auto add = [&](std::size_t r, std::size_t c, double value) {
    const Eigen::Index fr = sys.free_index[r];
    if (fr < 0) return;
    const Eigen::Index fc = sys.free_index[c];
    if (fc >= 0) {
      entries.emplace_back(fr, fc, value);
    } else {
      sys.rhs[fr] -= value * sys.known[static_cast<Eigen::Index>(c)];
    }
  };

  std::uint32_t poll = 0;
  for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
    if (cancel.poll(poll)) return cancelled_error("LSCM assembly");
    const Triangle& tri = patch.triangles[t];
    const Vec3 cot = corner_cotans(patch, t);
    for (int k = 0; k < 3; ++k) {
      const std::size_t i = tri[(k + 1) % 3];
      const std::size_t j = tri[(k + 2) % 3];
      const double w = 0.5 * cot[k];
      for (std::size_t off : {std::size_t{0}, n}) {
        add(i + off, j + off, -w);
        add(j + off, i + off, -w);
        add(i + off, i + off, w);
        add(j + off, j + off, w);
      }
    }
  }
  // Signed area = 1/2 sum over counter-clockwise boundary edges i->j of (u_i v_j - u_j v_i);
  // as 1/2 x^T A x it puts +1/2 at (u_i, v_j) and -1/2 at (u_j, v_i), symmetrised. The energy
  // subtracts it.
  const std::size_t nb = patch.boundary.size();
  for (std::size_t k = 0; k < nb; ++k) {
    const std::size_t i = patch.boundary[k];
    const std::size_t j = patch.boundary[(k + 1) % nb];
    add(i, n + j, -0.5);
    add(n + j, i, -0.5);
    add(j, n + i, 0.5);
    add(n + i, j, 0.5);
  }
  sys.matrix.resize(num_free, num_free);
  sys.matrix.setFromTriplets(entries.begin(), entries.end());
  return sys;
}

}  // namespace

Result<std::vector<Vec2>> flatten_lscm(const DiscPatch& patch, const CancelToken& cancel) {
  const std::size_t n = patch.num_vertices();
  auto [p0, p1] = boundary_far_pair(patch);
  if (p0 == p1) p1 = patch.boundary[(patch.boundary.size() > 1) ? 1 : 0];
  SEAM_ASSERT(p0 != p1);
  SEAM_TRY(LscmSystem sys, assemble_lscm(patch, p0, p1, cancel));
  if (cancel.is_cancelled()) return cancelled_error("LSCM assembly");

  SparseCholesky solver(sys.matrix);
  if (solver.info() != Eigen::Success) {
    return make_error(ErrorCode::kSolverFailed, "LSCM: the sparse Cholesky factorization failed");
  }
  if (cancel.is_cancelled()) return cancelled_error("LSCM solve");
  const Eigen::VectorXd x = solver.solve(sys.rhs);
  if (solver.info() != Eigen::Success || !x.allFinite()) {
    return make_error(ErrorCode::kSolverFailed, "LSCM: the solve produced non-finite coordinates");
  }
  std::vector<Vec2> uv(n);
  for (std::size_t i = 0; i < n; ++i) uv[i] = Vec2(sys.value(x, i), sys.value(x, n + i));
  return uv;
}

}  // namespace seam::core
