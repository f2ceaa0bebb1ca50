#include "core/uv/slim.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <tuple>
#include <utility>

#include "core/uv/collision.h"
#include "core/uv/distortion.h"
#include "core/uv/sparse_cholesky.h"

namespace seam::core {

namespace {

constexpr double kMaxProxyWeight = 1e8;
constexpr int kHoldRounds = 8;  // rounds of contacts and held vertices per step
// A contact-limited step ends the descent when the last kWindow steps together gained less
// than kWindow x kWindowTolerance x the tolerance.
constexpr int kWindow = 3;
constexpr double kWindowTolerance = 0.5;

using Clock = std::chrono::steady_clock;

// Adds the time since `since` to `total` (milliseconds) and restarts the clock.
void lap(double& total, Clock::time_point& since) {
  const Clock::time_point now = Clock::now();
  total += std::chrono::duration<double, std::milli>(now - since).count();
  since = now;
}

// Per triangle: 3D area and the gradients of its three barycentric coordinates in an isometric
// frame of its plane, so that the Jacobian of the map is J = sum_k uv_k g_k^T.
struct TriangleOperator {
  double area = 0;
  std::array<Vec2, 2> grad12;  // of corners 1 and 2; corner 0's is minus their sum (40 B, not 56)

  Vec2 grad(int k) const { return k == 0 ? Vec2(-(grad12[0] + grad12[1])) : grad12[static_cast<std::size_t>(k - 1)]; }
};

std::vector<TriangleOperator> triangle_operators(const DiscPatch& patch) {
  std::vector<TriangleOperator> ops(patch.triangles.size());
  for (std::size_t t = 0; t < ops.size(); ++t) {
    const auto f = local_triangle_frame(patch, t);
    Eigen::Matrix2d edges;
    edges.col(0) = f[1] - f[0];
    edges.col(1) = f[2] - f[0];
    const double det = edges.determinant();
    TriangleOperator& op = ops[t];
    op.area = 0.5 * std::abs(det);
    if (!(std::abs(det) > 0)) continue;  // a sliver of zero area: no gradient, no energy
    const Eigen::Matrix2d inv = edges.inverse();
    op.grad12[0] = inv.row(0).transpose();
    op.grad12[1] = inv.row(1).transpose();
  }
  return ops;
}

Eigen::Matrix2d jacobian(const TriangleOperator& op, const Triangle& tri, const std::vector<Vec2>& uv) {
  Eigen::Matrix2d j = Eigen::Matrix2d::Zero();
  for (int k = 0; k < 3; ++k) j += uv[tri[k]] * op.grad(k).transpose();
  return j;
}

// s1^2 + s2^2 + 1/s1^2 + 1/s2^2 = |J|^2 (1 + 1/det^2): no SVD needed. Infinite when folded.
double symmetric_dirichlet(const Eigen::Matrix2d& j) {
  const double det = j.determinant();
  if (!(det > 0)) return kInf;
  return j.squaredNorm() * (1 + 1 / (det * det));
}

double mean_energy(const DiscPatch& patch, const std::vector<TriangleOperator>& ops, const std::vector<Vec2>& uv) {
  double sum = 0;
  double area = 0;
  for (std::size_t t = 0; t < ops.size(); ++t) {
    if (ops[t].area == 0) continue;
    sum += ops[t].area * symmetric_dirichlet(jacobian(ops[t], patch.triangles[t], uv));
    area += ops[t].area;
  }
  return area > 0 ? sum / area : 4.0;
}

bool has_fold(const DiscPatch& patch, const std::vector<TriangleOperator>& ops, const std::vector<Vec2>& uv) {
  for (std::size_t t = 0; t < ops.size(); ++t) {
    if (ops[t].area > 0 && !(jacobian(ops[t], patch.triangles[t], uv).determinant() > 0)) return true;
  }
  return false;
}

// Tutte's barycentric embedding: boundary on the unit circle spaced by 3D arc length, every
// interior vertex at the mean of its neighbours. Injective for a disc with a strictly convex
// boundary (Floater 2003).
Result<std::vector<Vec2>> tutte_embedding(const DiscPatch& patch) {
  const std::size_t n = patch.num_vertices();
  std::vector<Vec2> uv(n, Vec2::Zero());
  std::vector<std::int64_t> interior_index(n, -1);
  std::vector<char> on_boundary(n, 0);
  for (std::uint32_t v : patch.boundary) on_boundary[v] = 1;
  double perimeter = 0;
  const std::size_t nb = patch.boundary.size();
  for (std::size_t i = 0; i < nb; ++i) {
    perimeter += (patch.positions[patch.boundary[(i + 1) % nb]] - patch.positions[patch.boundary[i]]).norm();
  }
  double walked = 0;
  for (std::size_t i = 0; i < nb; ++i) {
    const double angle = perimeter > 0 ? 2 * std::numbers::pi * walked / perimeter : 2 * std::numbers::pi * i / nb;
    uv[patch.boundary[i]] = Vec2(std::cos(angle), std::sin(angle));
    walked += (patch.positions[patch.boundary[(i + 1) % nb]] - patch.positions[patch.boundary[i]]).norm();
  }
  Eigen::Index ni = 0;
  for (std::size_t v = 0; v < n; ++v) {
    if (!on_boundary[v]) interior_index[v] = ni++;
  }
  if (ni == 0) return uv;
  // Each triangle adds weight 1 to each of its edges: positive, symmetric weights.
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::MatrixX2d rhs = Eigen::MatrixX2d::Zero(ni, 2);
  for (const Triangle& tri : patch.triangles) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = tri[k];
      const std::uint32_t b = tri[(k + 1) % 3];
      for (auto [p, q] : {std::pair{a, b}, std::pair{b, a}}) {
        if (interior_index[p] < 0) continue;
        entries.emplace_back(interior_index[p], interior_index[p], 1.0);
        if (interior_index[q] >= 0) {
          entries.emplace_back(interior_index[p], interior_index[q], -1.0);
        } else {
          rhs.row(interior_index[p]) += uv[q].transpose();
        }
      }
    }
  }
  Eigen::SparseMatrix<double> system(ni, ni);
  system.setFromTriplets(entries.begin(), entries.end());
  SparseCholesky solver(system);
  if (solver.info() != Eigen::Success) {
    return make_error(ErrorCode::kSolverFailed, "SLIM: the Tutte embedding's factorization failed");
  }
  const Eigen::MatrixX2d xy = solver.solve(rhs);
  for (std::size_t v = 0; v < n; ++v) {
    if (interior_index[v] >= 0) uv[v] = xy.row(interior_index[v]).transpose();
  }
  return uv;
}

// Scales the map so that its UV area equals the 3D area: the symmetric Dirichlet optimum is
// near that scale, and SLIM's proxy weights assume it.
void scale_to_surface_area(const DiscPatch& patch, const std::vector<TriangleOperator>& ops, std::vector<Vec2>& uv) {
  double area_3d = 0;
  double area_uv = 0;
  for (std::size_t t = 0; t < ops.size(); ++t) {
    area_3d += ops[t].area;
    area_uv += std::abs(jacobian(ops[t], patch.triangles[t], uv).determinant()) * ops[t].area;
  }
  if (!(area_uv > 0) || !(area_3d > 0)) return;
  const double s = std::sqrt(area_3d / area_uv);
  for (Vec2& p : uv) p *= s;
}

// SLIM's proxy weights for the symmetric Dirichlet energy (the paper's Table 1, after its
// Eq. 6): w_i^2 = (s_i - s_i^-3) / (s_i - 1) = (s_i + 1)(s_i^2 + 1) / s_i^3, with the 2x2 SVD
// J = Rot(phi) diag(s1, s2) Rot(theta) in closed form. Returns M = W^T W = U diag(w^2) U^T
// and the closest rotation R = U V^T. Weights are capped at `cap`. No trigonometry: R's angle
// and 2 phi = (u + v) + (u - v) come from svd_2x2's unit vectors (the assembly's cost was
// mostly atan2/sincos when svd_2x2 returned angles).
void proxy_weights(const Eigen::Matrix2d& j, double cap, Eigen::Matrix2d& m, Eigen::Matrix2d& r) {
  const Svd2 svd = svd_2x2(j);
  const double s1 = svd.s1;
  const double s2 = std::max(svd.s2, 1e-12);  // positive: the line search keeps det > 0
  auto weight2 = [cap](double s) { return std::min((s + 1) * (s * s + 1) / (s * s * s), cap); };
  const double w1 = weight2(s1);
  const double w2 = weight2(s2);
  const Vec2& rot = svd.rotation;
  const Vec2& refl = svd.reflection;
  const double cos_2phi = refl.x() * rot.x() - refl.y() * rot.y();
  const double sin_2phi = refl.y() * rot.x() + refl.x() * rot.y();
  // (cos phi, sin phi) by the half angle, from the side where nothing cancels: the weights can
  // differ by 20 orders of magnitude, so M = c^2 w1 + s^2 w2 ... needs s^2 to relative accuracy.
  Vec2 half = cos_2phi >= 0 ? Vec2(1 + cos_2phi, sin_2phi) : Vec2(sin_2phi, 1 - cos_2phi);
  half /= half.norm();
  const double c = half.x();
  const double s = half.y();
  m << c * c * w1 + s * s * w2, c * s * (w1 - w2), c * s * (w1 - w2), s * s * w1 + c * c * w2;
  r << rot.x(), -rot.y(), rot.y(), rot.x();
}

// SLIM's reweighted proxy as a sparse system over the free unknowns (vertex 0 is pinned: the
// energy is translation invariant). Anisotropic proxy: (u, v) of vertices 1..n-1 interleaved,
// each vertex a 2x2 block. Isotropic proxy: one unknown per vertex and two right-hand sides.
// The pattern is fixed, so the lower triangle's value slots are located once (32-bit, only the
// entries between distinct vertices: 12 MB at 1M faces instead of 288) and the symbolic
// factorization is done once.
class ProxySystem {
 public:
  ProxySystem(const DiscPatch& patch, int block, std::span<const int> vertex_order)
      : patch_(patch), block_(block), per_triangle_(3 * block * block) {
    const auto nfree = static_cast<Eigen::Index>(block * (patch.num_vertices() - 1));
    system_.resize(nfree, nfree);
    std::vector<Eigen::Triplet<double>> pattern;
    pattern.reserve(patch.triangles.size() * (block == 2 ? 21 : 6));
    for_each_lower_entry([&](std::size_t, std::size_t, Eigen::Index row, Eigen::Index col) {
      pattern.emplace_back(row, col, 0.0);
    }, true);
    system_.setFromTriplets(pattern.begin(), pattern.end());
    system_.makeCompressed();
    pattern = {};
    SEAM_ASSERT(system_.nonZeros() < std::numeric_limits<std::int32_t>::max());
    slot_.assign(patch.triangles.size() * per_triangle_, -1);
    for_each_lower_entry([&](std::size_t t, std::size_t entry, Eigen::Index row, Eigen::Index col) {
      const auto* begin = system_.innerIndexPtr() + system_.outerIndexPtr()[col];
      const auto* end = system_.innerIndexPtr() + system_.outerIndexPtr()[col + 1];
      const auto* it = std::lower_bound(begin, end, static_cast<int>(row));
      SEAM_ASSERT(it != end && *it == row);
      slot_[t * per_triangle_ + entry] = static_cast<std::int32_t>(it - system_.innerIndexPtr());
    }, false);
    // The first entry of each lower-triangle column is its diagonal (where holding springs go);
    // with 2x2 blocks, the second entry of a u column is the same vertex's v row.
    for (Eigen::Index col = 0; col < nfree; ++col) {
      const auto first = system_.outerIndexPtr()[col];
      SEAM_ASSERT(system_.innerIndexPtr()[first] == col);
      SEAM_ASSERT(block == 1 || col % 2 == 1 || system_.innerIndexPtr()[first + 1] == col + 1);
    }
    rhs_.resize(nfree, block == 2 ? 1 : 2);
    // One analysis, one factorization per step (and per held-vertex re-solve): nested
    // dissection's cheaper factorizations repay its dearer analysis (sparse_cholesky.h).
    solver_.prefer_nested_dissection();
    if (!vertex_order.empty()) solver_.use_order(unknown_order(vertex_order));
    solver_.analyzePattern(system_);
  }

  // The proxy sum_t A_t |W_t (J_t - R_t)|^2 at `uv`. Its normal equations have block (k, l) =
  // A_t (g_k . g_l) M_t and right-hand side A_t M_t R_t g_k for vertex k, M_t = W_t^T W_t. The
  // isotropic proxy replaces M_t by (tr M_t / 2) I: u and v decouple and share one n x n
  // factorization, about a quarter of the 2n x 2n one's cost. False when cancelled.
  bool assemble(const std::vector<TriangleOperator>& ops, const std::vector<Vec2>& uv, double cap,
                const CancelToken& cancel) {
    std::fill(system_.valuePtr(), system_.valuePtr() + system_.nonZeros(), 0.0);
    rhs_.setZero();
    std::uint32_t poll = 0;
    for (std::size_t t = 0; t < ops.size(); ++t) {
      if (cancel.poll(poll)) return false;
      if (ops[t].area == 0) continue;
      add_triangle(t, ops[t], uv, cap);
    }
    return true;
  }

  // Numeric factorization of the current values. False if not numerically positive definite.
  bool factorize() {
    held_.clear();
    solver_.factorize(system_);
    return solver_.info() == Eigen::Success;
  }

  // The step towards the minimiser of the factorized proxy, A^-1 (b - A uv) (solved as a
  // residual so that the pinned vertex needs no special case). Empty if not finite.
  std::vector<Vec2> direction(const std::vector<Vec2>& uv) const {
    Eigen::MatrixXd current(rhs_.rows(), rhs_.cols());
    for (std::uint32_t v = 1; v < uv.size(); ++v) {
      for (int c = 0; c < 2; ++c) at(current, v, c) = uv[v][c];
    }
    const Eigen::MatrixXd residual = rhs_ - system_.selfadjointView<Eigen::Lower>() * current;
    const Eigen::MatrixXd x = solver_.solve(residual);
    if (!x.allFinite()) return {};
    std::vector<Vec2> dir(uv.size(), Vec2::Zero());
    for (std::uint32_t v = 1; v < uv.size(); ++v) dir[v] = Vec2(at(x, v, 0), at(x, v, 1));
    return dir;
  }

  // A linearised contact between a boundary vertex and a boundary edge: the direction must
  // satisfy n . (d[v0] + c1 d[v1] + c2 d[v2]) >= h (the vertex's motion relative to its closest
  // point on the edge, along the normal n from the edge to the vertex).
  struct Contact {
    std::array<std::uint32_t, 3> v;
    std::array<Vec2, 3> w;  // the row: sum_k w[k] . d[v[k]] >= h
    double h = 0;
  };

  // How many right-hand sides one solve with the factor costs as much as one numeric
  // factorization (CHOLMOD's flop counts from the analysis: about 4 flops per entry of L and
  // column; deterministic).
  double solves_per_factorization() {
    const double lnz = solver_.cholmod().lnz;
    const double fl = solver_.cholmod().fl;
    return lnz > 0 ? fl / (4 * lnz) : 1;
  }

  // A stiff spring holding vertex v at `where` (in the matrix and the right-hand side); the
  // factor follows at the next refactor_held().
  void hold(std::uint32_t v, const Vec2& where, double spring) {
    if (v == 0) return;
    for (int c = 0; c < block_; ++c) {
      system_.valuePtr()[system_.outerIndexPtr()[unknown(v, c)]] += spring;
      held_.emplace_back(static_cast<int>(unknown(v, c)), spring);
    }
    at(rhs_, v, 0) += spring * where.x();
    at(rhs_, v, 1) += spring * where.y();
  }

  enum class Refactor { kUpdated, kFactored, kFailed };

  // The factor of the system with the springs hold() added since the last call: a low-rank
  // update of the current factor (SparseCholesky::update_diagonal: a simplicial factor, the
  // springs' unknowns' paths in the elimination tree), else a numeric factorization.
  Refactor refactor_held() {
    const bool updated = solver_.update_diagonal(held_);
    held_.clear();
    if (updated) return Refactor::kUpdated;
    return factorize() ? Refactor::kFactored : Refactor::kFailed;
  }

  double max_diagonal() const {
    double d = 0;
    for (Eigen::Index c = 0; c < system_.cols(); ++c) d = std::max(d, std::abs(system_.valuePtr()[system_.outerIndexPtr()[c]]));
    return d;
  }

  // The minimiser of the factorized proxy (as `direction`: `free` = A^-1 r) subject to the
  // contacts as inequalities n . (relative motion) >= h, by their Schur complement
  // S = G A^-1 G^T with the step's own factor: one half-solve on its elimination-tree reach per
  // contact, then one whole solve for the correction, no refactorization. Empty if not finite.
  std::vector<Vec2> constrained(const std::vector<Vec2>& free, const std::vector<Contact>& contacts) {
    const auto m = static_cast<Eigen::Index>(contacts.size());
    Eigen::VectorXd violation(m);
    for (Eigen::Index i = 0; i < m; ++i) {
      const Contact& c = contacts[static_cast<std::size_t>(i)];
      double rel = 0;
      for (int k = 0; k < 3; ++k) rel += c.w[k].dot(free[c.v[k]]);
      violation(i) = rel - c.h;
    }
    const Eigen::VectorXd lambda = active_multipliers(contact_schur(contacts), violation);
    if (!lambda.allFinite()) return {};
    Eigen::MatrixXd g = Eigen::MatrixXd::Zero(rhs_.rows(), rhs_.cols());
    for (Eigen::Index j = 0; j < m; ++j) {
      const Contact& c = contacts[static_cast<std::size_t>(j)];
      add_row(g, 0, c, lambda(j), 0);
      if (block_ == 1) add_row(g, 1, c, lambda(j), 1);  // the isotropic proxy's v column
    }
    const Eigen::MatrixXd y = solver_.solve(g);
    if (!y.allFinite()) return {};
    std::vector<Vec2> dir = free;
    for (std::uint32_t v = 1; v < dir.size(); ++v) dir[v] -= Vec2(at(y, v, 0), at(y, v, 1));
    return dir;
  }

 private:
  Eigen::Index unknown(std::uint32_t v, int c) const { return static_cast<Eigen::Index>(block_ * (v - 1) + c); }

  // An order of the vertices as an order of the unknowns: the pinned vertex dropped, a
  // vertex's u and v (2x2 blocks) adjacent.
  std::vector<int> unknown_order(std::span<const int> vertex_order) const {
    std::vector<int> order;
    order.reserve(static_cast<std::size_t>(block_) * vertex_order.size());
    for (int v : vertex_order) {
      if (v == 0) continue;
      for (int c = 0; c < block_; ++c) order.push_back(static_cast<int>(unknown(static_cast<std::uint32_t>(v), c)));
    }
    return order;
  }
  // Component c of vertex v in a matrix laid out like the right-hand side.
  double& at(Eigen::MatrixXd& m, std::uint32_t v, int c) const {
    return block_ == 2 ? m(unknown(v, c), 0) : m(unknown(v, 0), c);
  }
  double at(const Eigen::MatrixXd& m, std::uint32_t v, int c) const {
    return block_ == 2 ? m(unknown(v, c), 0) : m(unknown(v, 0), c);
  }

  // Calls f(unknown, coefficient) for every entry of the contact's row: with 2x2 blocks w on
  // the u and v unknowns; with the isotropic proxy (u and v in two columns of one system)
  // component `comp` of w alone (vertex 0 is pinned: no unknown).
  template <class F>
  void for_each_entry(const Contact& c, int comp, F&& f) const {
    for (int k = 0; k < 3; ++k) {
      if (c.v[k] == 0) continue;
      if (block_ == 2) {
        for (int a = 0; a < 2; ++a) f(unknown(c.v[k], a), c.w[k][a]);
      } else {
        f(unknown(c.v[k], 0), c.w[k][comp]);
      }
    }
  }

  // Adds scale x (the contact's row) to column `col` of g.
  void add_row(Eigen::MatrixXd& g, Eigen::Index col, const Contact& c, double scale, int comp) const {
    for_each_entry(c, comp, [&](Eigen::Index row, double w) { g(row, col) += scale * w; });
  }

  // The contact's row (component `comp` with the isotropic proxy) as (unknown, coefficient).
  std::vector<std::pair<int, double>> row_entries(const Contact& c, int comp) const {
    std::vector<std::pair<int, double>> entries;
    for_each_entry(c, comp, [&](Eigen::Index row, double w) { entries.emplace_back(static_cast<int>(row), w); });
    return entries;
  }

  // S = G A^-1 G^T, S_ij = sum over the parts of (L^-1 P g_i) . (L^-1 P g_j) (with the
  // isotropic proxy a contact's row is G_u on u and G_v on v: two parts), each half-solve on
  // the reach of the contact's few unknowns in the elimination tree only
  // (SparseCholesky::half_solve_sparse). Whole solves, two per contact, took 24 of the 36 s of
  // SLIM on camel x64's 1.25M-face chart (every step there is contact-limited). NaN where
  // CHOLMOD fails.
  Eigen::MatrixXd contact_schur(const std::vector<Contact>& contacts) {
    const auto m = static_cast<Eigen::Index>(contacts.size());
    const int parts = block_ == 1 ? 2 : 1;
    std::vector<std::vector<std::pair<int, double>>> half(static_cast<std::size_t>(m * parts));
    for (Eigen::Index i = 0; i < m; ++i) {
      for (int comp = 0; comp < parts; ++comp) {
        const auto entries = row_entries(contacts[static_cast<std::size_t>(i)], comp);
        auto& y = half[static_cast<std::size_t>(i * parts + comp)];
        y = solver_.half_solve_sparse(entries);
        if (y.empty() && !entries.empty()) return Eigen::MatrixXd::Constant(m, m, std::numeric_limits<double>::quiet_NaN());
      }
    }
    auto dot = [](const std::vector<std::pair<int, double>>& a, const std::vector<std::pair<int, double>>& b) {
      double sum = 0;
      for (std::size_t p = 0, q = 0; p < a.size() && q < b.size();) {
        if (a[p].first < b[q].first) {
          ++p;
        } else if (b[q].first < a[p].first) {
          ++q;
        } else {
          sum += a[p++].second * b[q++].second;
        }
      }
      return sum;
    };
    Eigen::MatrixXd s(m, m);
    for (Eigen::Index i = 0; i < m; ++i) {
      for (Eigen::Index j = i; j < m; ++j) {
        double e = 0;
        for (int comp = 0; comp < parts; ++comp) {
          e += dot(half[static_cast<std::size_t>(i * parts + comp)], half[static_cast<std::size_t>(j * parts + comp)]);
        }
        s(i, j) = s(j, i) = e;
      }
    }
    return s;
  }

  // Multipliers of S lambda = violation on the active contacts, the others 0. Contacts are
  // inequalities (a vertex may leave its edge): one whose multiplier pulls (positive here) is
  // released, the largest first, and the rest re-solved. Redundant contacts (a vertex against
  // both edges of a corner) make S singular: a ridge of 1e-10 of its diagonal.
  static Eigen::VectorXd active_multipliers(Eigen::MatrixXd s, const Eigen::VectorXd& violation) {
    const Eigen::Index m = s.rows();
    Eigen::VectorXd lambda = Eigen::VectorXd::Zero(m);
    if (m == 0) return lambda;
    s.diagonal().array() += 1e-10 * std::max(s.diagonal().cwiseAbs().maxCoeff(), 1e-300);
    std::vector<Eigen::Index> active(static_cast<std::size_t>(m));
    for (Eigen::Index i = 0; i < m; ++i) active[static_cast<std::size_t>(i)] = i;
    while (!active.empty()) {
      const auto k = static_cast<Eigen::Index>(active.size());
      Eigen::MatrixXd sa(k, k);
      Eigen::VectorXd va(k);
      for (Eigen::Index i = 0; i < k; ++i) {
        const Eigen::Index ai = active[static_cast<std::size_t>(i)];
        va(i) = violation(ai);
        for (Eigen::Index j = 0; j < k; ++j) sa(i, j) = s(ai, active[static_cast<std::size_t>(j)]);
      }
      const Eigen::VectorXd la = sa.ldlt().solve(va);
      lambda.setZero();
      for (Eigen::Index i = 0; i < k; ++i) lambda(active[static_cast<std::size_t>(i)]) = la(i);
      Eigen::Index worst = 0;
      if (!la.allFinite() || la.maxCoeff(&worst) <= 0) break;
      active.erase(active.begin() + worst);
    }
    return lambda;
  }

  // The slot entry of corners k != l and components a, b: the corner pair (k + l - 1), then
  // the components.
  std::size_t entry(int k, int l, int a, int b) const {
    return static_cast<std::size_t>((k + l - 1) * block_ * block_ + block_ * a + b);
  }

  // Calls f(t, entry, row, col) for every lower-triangle entry triangle t touches between two
  // of its corners (and, with `same_vertex`, within one corner's block too; entry is then
  // meaningless).
  template <class F>
  void for_each_lower_entry(F&& f, bool same_vertex) const {
    for (std::size_t t = 0; t < patch_.triangles.size(); ++t) {
      const Triangle& tri = patch_.triangles[t];
      for (int k = 0; k < 3; ++k) {
        for (int l = 0; l < 3; ++l) {
          if (tri[k] == 0 || tri[l] == 0 || (k == l && !same_vertex)) continue;
          for (int a = 0; a < block_; ++a) {
            for (int b = 0; b < block_; ++b) {
              const Eigen::Index row = unknown(tri[k], a);
              const Eigen::Index col = unknown(tri[l], b);
              if (row >= col) f(t, k == l ? 0 : entry(k, l, a, b), row, col);
            }
          }
        }
      }
    }
  }

  // Index into the values of the entry (corner k, component a; corner l, component c) of
  // triangle t, or -1 in the upper triangle. Within a vertex's own block the entries sit at
  // fixed places of its columns (see the constructor); the others come from the slots.
  std::int64_t value_index(std::size_t t, int k, int l, int a, int c) const {
    const Triangle& tri = patch_.triangles[t];
    const Eigen::Index row = unknown(tri[k], a);
    const Eigen::Index col = unknown(tri[l], c);
    if (row < col) return -1;
    if (k == l) return system_.outerIndexPtr()[col] + (row - col);
    return slot_[t * per_triangle_ + entry(k, l, a, c)];
  }

  void add_triangle(std::size_t t, const TriangleOperator& op, const std::vector<Vec2>& uv, double cap) {
    const Triangle& tri = patch_.triangles[t];
    Eigen::Matrix2d m;
    Eigen::Matrix2d r;
    proxy_weights(jacobian(op, tri, uv), cap, m, r);
    if (block_ == 1) {
      add_isotropic_triangle(t, op, uv, 0.5 * m.trace(), r);
      return;
    }
    const Eigen::Matrix2d mr = m * r;
    for (int k = 0; k < 3; ++k) {
      if (tri[k] == 0) continue;
      const Vec2 b = op.area * (mr * op.grad(k));
      for (int l = 0; l < 3; ++l) {
        const Eigen::Matrix2d coefficient = (op.area * op.grad(k).dot(op.grad(l))) * m;
        if (tri[l] == 0) {
          // The pinned vertex moves to the right-hand side.
          const Vec2 pinned = coefficient * uv[0];
          at(rhs_, tri[k], 0) -= pinned.x();
          at(rhs_, tri[k], 1) -= pinned.y();
          continue;
        }
        for (int a = 0; a < block_; ++a) {
          for (int c = 0; c < block_; ++c) {
            const std::int64_t s = value_index(t, k, l, a, c);
            if (s >= 0) system_.valuePtr()[s] += coefficient(a, c);
          }
        }
      }
      at(rhs_, tri[k], 0) += b.x();
      at(rhs_, tri[k], 1) += b.y();
    }
  }

  // add_triangle with the isotropic proxy M_t = w I, w = tr M_t / 2: each pair of corners adds
  // the scalar A_t (g_k . g_l) w, and the same arithmetic as the 2x2 path in the same order, so
  // the system is the same to the bit (uv_bench's 164 rows unchanged) in half the 2x2 path's
  // time (armadillo's 17 assemblies: 103-123 -> 52-62 ms, flatten_bench).
  void add_isotropic_triangle(std::size_t t, const TriangleOperator& op, const std::vector<Vec2>& uv, double w,
                              const Eigen::Matrix2d& r) {
    const Triangle& tri = patch_.triangles[t];
    const std::array<Vec2, 3> grad = {op.grad(0), op.grad(1), op.grad(2)};
    const Eigen::Matrix2d wr = w * r;
    double* values = system_.valuePtr();
    const std::int32_t* slots = slot_.data() + t * per_triangle_;
    const auto rows = rhs_.rows();
    double* rhs_u = rhs_.data();
    double* rhs_v = rhs_.data() + rows;
    for (int k = 0; k < 3; ++k) {
      if (tri[k] == 0) continue;
      const auto row = static_cast<Eigen::Index>(tri[k] - 1);
      const Vec2& grad_k = grad[static_cast<std::size_t>(k)];
      const Vec2 b = op.area * (wr * grad_k);
      for (int l = 0; l < 3; ++l) {
        const double coefficient = (op.area * grad_k.dot(grad[static_cast<std::size_t>(l)])) * w;
        if (tri[l] == 0) {
          rhs_u[row] -= coefficient * uv[0].x();  // the pinned vertex moves to the right-hand side
          rhs_v[row] -= coefficient * uv[0].y();
          continue;
        }
        if (k == l) {
          values[system_.outerIndexPtr()[row]] += coefficient;  // each column's first entry: its diagonal
        } else if (tri[k] >= tri[l]) {
          values[slots[k + l - 1]] += coefficient;  // lower triangle only
        }
      }
      rhs_u[row] += b.x();
      rhs_v[row] += b.y();
    }
  }

  const DiscPatch& patch_;
  int block_;
  std::size_t per_triangle_;
  Eigen::SparseMatrix<double> system_;  // lower triangle
  std::vector<std::int32_t> slot_;      // per triangle and entry: index into the values, or -1
  std::vector<std::pair<int, double>> held_;  // springs hold() added since the last factor: (unknown, stiffness)
  Eigen::MatrixXd rhs_;
  SparseCholesky solver_;
};

// One SLIM run between its steps: the chart, the current map and its energy, the proxy.
struct Descent {
  const DiscPatch& patch;
  const std::vector<TriangleOperator>* ops;  // the chart's, or a progressive reference's
  const SlimOptions& options;
  bool injective;  // options.injective, until a squeezed chart is given up to the pack step
  double gap;  // boundary vertices keep this far from the boundary edges they face
  SlimResult& result;
  double energy;
  ProxySystem proxy;
  std::vector<Vec2> trial;
};

// Backtracking on the true energy from `step` (no larger than the largest step that keeps every
// triangle positive, with a margin since the energy is infinite at the bound itself). Leaves
// the last trial map in d.trial and returns its energy.
double line_search(Descent& d, const std::vector<Vec2>& dir, double step) {
  const std::vector<Vec2>& uv = d.result.uv;
  double trial_energy = kInf;
  for (int halving = 0; halving < 30 && step > 1e-12; ++halving, step *= 0.5) {
    for (std::size_t v = 0; v < uv.size(); ++v) d.trial[v] = uv[v] + step * dir[v];
    trial_energy = mean_energy(d.patch, *d.ops, d.trial);
    if (trial_energy < d.energy) break;
  }
  return trial_energy;
}

struct HeldSearch {
  double energy = kInf;  // of d.trial
  bool descended = false;
};

// The contact between boundary vertex c.vertex and edge (c.a, c.b) linearised at `uv` as the
// collision test sees it (collision.h): the rate of cross(b - a, p - a) = |e| x the vertex's
// distance from the edge's line, d/dt = cross(e, d_p - d_a) + cross(d_b - d_a, p - a), scaled
// by 1/|e| and signed towards the vertex's side, must be at least h: a vertex within 2 gaps of
// the line moves out to them, any other keeps at least a tenth of a gap per step clear of an
// approach (so that no linearised pair collides at t = 0). The vertex may slide along the edge.
ProxySystem::Contact linearised_contact(const std::vector<Vec2>& uv, const CollisionStep::Contact& c, double gap) {
  const Vec2 e = uv[c.b] - uv[c.a];
  const Vec2 q = uv[c.vertex] - uv[c.a];
  const double len = std::max(e.norm(), 1e-300);
  const double cross0 = e.x() * q.y() - e.y() * q.x();
  const double side = cross0 >= 0 ? 1.0 : -1.0;
  const Vec2 e_perp = Vec2(-e.y(), e.x()) * (side / len);  // cross(e, d) = e_perp . d
  const Vec2 q_perp = Vec2(q.y(), -q.x()) * (side / len);  // cross(d, q) = q_perp . d
  const double dist = std::abs(cross0) / len;
  return {.v = {c.vertex, c.a, c.b},
          .w = {e_perp, Vec2(-(e_perp + q_perp)), q_perp},
          .h = std::max(2 * gap - dist, 0.1 * gap)};
}

// What contact_search keeps between its rounds.
struct ContactRound {
  std::vector<Vec2> free;   // the proxy's step (solved again in each round that adds springs)
  std::vector<Vec2> held;   // the step with the contacts and held vertices
  std::vector<char> pinned; // vertices held still
  std::vector<ProxySystem::Contact> contacts;
  int budget = 0;           // solves one factorization is worth
  int spent = 0;            // solves so far
};

// One round's new colliding pairs: within the solve budget they become contacts. A pair that
// already is one and still collides (linearised at the closest point, it misses what the edge's
// turn and stretch do: at 1.25M faces such pairs sit within the gap and collide at t = 0), or
// one beyond the budget (solving it would cost more than a factorization), has its vertices
// tied by stiff springs (1e6 x the largest diagonal): issue 12's way, only where the contacts
// do not suffice. The springs go into the step's factor by a rank update of their unknowns
// (refactor_held; a second factorization for a supernodal factor): camel x64's coarse chart
// (52k vertices, 7 of 12 steps with springs) 19 -> 12 factorizations, the same steps and
// energy. Every round that holds new vertices adds their springs and solves the step again:
// a held vertex whose motion is merely zeroed lets its tiny neighbours degenerate within a
// fraction of the step, and the descent stalls. Holding only the first round's vertices by
// springs and zeroing later ones stalled camel x64's coarse chart, triangles numbered as the
// service numbers them, at energy 5.99 after 5 steps (its fine chart's optimum is 4.35) or
// at BFF's map after none, depending on the coarse size.
void add_contacts(Descent& d, CollisionStep& collision, ContactRound& state) {
  const std::vector<Vec2>& uv = d.result.uv;
  std::sort(collision.contacts.begin(), collision.contacts.end(), [](const auto& x, const auto& y) {
    return std::tie(x.time, x.vertex, x.a) < std::tie(y.time, y.vertex, y.a);
  });
  bool added = false;
  std::vector<std::uint32_t> spring;
  for (const CollisionStep::Contact& c : collision.contacts) {
    const std::array<std::uint32_t, 3> key = {c.vertex, c.a, c.b};
    const bool known = std::any_of(state.contacts.begin(), state.contacts.end(),
                                   [&](const ProxySystem::Contact& k) { return k.v == key; });
    if (!known && state.spent + static_cast<int>(state.contacts.size()) + 2 <= state.budget) {
      state.contacts.push_back(linearised_contact(uv, c, d.gap));
      added = true;
      continue;
    }
    for (std::uint32_t v : key) {
      if (!state.pinned[v]) spring.push_back(v);
      state.pinned[v] = 1;
    }
  }
  if (!spring.empty()) {
    const double stiffness = 1e6 * d.proxy.max_diagonal();
    for (std::uint32_t v : spring) d.proxy.hold(v, uv[v], stiffness);
    ++d.result.spring_rounds;
    const ProxySystem::Refactor refactor = d.proxy.refactor_held();
    if (refactor != ProxySystem::Refactor::kFailed) {
      ++(refactor == ProxySystem::Refactor::kUpdated ? d.result.factor_updates : d.result.factorizations);
      std::vector<Vec2> resolved = d.proxy.direction(uv);
      if (!resolved.empty()) state.free = std::move(resolved);
    }
    state.held = state.free;
    added = true;
  }
  if (added && !state.contacts.empty()) {
    state.spent += static_cast<int>(state.contacts.size()) + 1;
    d.result.contact_solves += static_cast<int>(state.contacts.size()) + 1;
    std::vector<Vec2> solved = d.proxy.constrained(state.free, state.contacts);
    if (!solved.empty()) state.held = std::move(solved);
  }
}

// Truncating the whole step at the first boundary contact would stall every vertex for the
// sake of a few. Instead the colliding vertex-edge pairs become linearised contacts and the
// proxy is minimised subject to them with the step's own factor (ProxySystem::constrained):
// the touching vertices may still slide along their edges or leave them, and the rest of the
// chart moves as well as it can. The bounds are recomputed for that direction (so the
// guarantees hold) for a few rounds, since the new direction may meet other contacts
// (add_contacts). Before issue 14 every colliding vertex was pinned by a stiff spring and the
// proxy factored again: one more factorization per contact-limited step, and the vertices
// could not slide; now that happens only for the contacts beyond the solve budget.
// With `springs_only` every colliding pair's vertices are held by springs from the first round
// (issue 12's way, the budget 0).
HeldSearch contact_search(Descent& d, const std::vector<Vec2>& direction, CollisionStep collision, bool springs_only) {
  const std::vector<Vec2>& uv = d.result.uv;
  HeldSearch out;
  ContactRound state{.free = direction, .held = direction, .pinned = std::vector<char>(uv.size(), 0)};
  state.budget =
      springs_only ? 0 : std::max(d.options.contact_solves, static_cast<int>(d.proxy.solves_per_factorization()));
  for (int round = 0; round < kHoldRounds && collision.limited; ++round) {
    add_contacts(d, collision, state);
    for (std::uint32_t v = 0; v < uv.size(); ++v) {
      if (state.pinned[v]) state.held[v] = Vec2::Zero();
    }
    const double held_step = std::min(1.0, 0.9 * max_injective_step(d.patch, uv, state.held));
    collision = max_collision_free_step(d.patch, uv, state.held, held_step, d.gap);
    if (!collision.limited || round == kHoldRounds - 1) {
      const double bound = collision.limited ? 0.9 * collision.step : held_step;
      out.energy = line_search(d, state.held, bound);
      out.descended = out.energy < d.energy;
    }
  }
  return out;
}

struct StepOutcome {
  double energy = kInf;   // of d.trial
  bool collided = false;  // a boundary contact limited the step
};

// The bounded step along the proxy's direction: no triangle degenerates and (with
// options.injective) no boundary vertex reaches a boundary edge.
StepOutcome bounded_step(Descent& d, const std::vector<Vec2>& direction) {
  SlimTimings& timings = d.result.timings;
  Clock::time_point clock = Clock::now();
  double step = std::min(1.0, 0.9 * max_injective_step(d.patch, d.result.uv, direction));
  lap(timings.line_search_ms, clock);
  StepOutcome out;
  if (d.injective) {
    const CollisionStep collision = max_collision_free_step(d.patch, d.result.uv, direction, step, d.gap);
    if (collision.limited) {
      ++d.result.collision_limited_steps;
      out.collided = true;
      // Sliding contacts can bend the step until a small triangle degenerates almost at once
      // (camel x64's coarse chart with 96 contact solves: held steps of 0.5% and no descent,
      // so the descent stopped at energy 4.50 instead of 4.37); then the colliding vertices
      // are held by springs instead, which moves the rest of the chart (4.367). The first
      // search's springs stay in the step's factor.
      HeldSearch held = contact_search(d, direction, collision, false);
      if (!held.descended) {
        ++d.result.spring_fallbacks;
        held = contact_search(d, direction, collision, true);
      }
      if (held.descended) {
        out.energy = held.energy;
        lap(timings.collision_ms, clock);
        return out;
      }
      step = 0.9 * collision.step;  // the bound above: neither search moved the map
    }
    lap(timings.collision_ms, clock);
  }
  out.energy = line_search(d, direction, step);
  lap(timings.line_search_ms, clock);
  return out;
}

// The start: the given map, or Tutte's embedding when it folds or (injective) its boundary
// crosses itself; scaled to the 3D area.
Result<std::vector<Vec2>> slim_start(const DiscPatch& patch, const std::vector<TriangleOperator>& ops,
                                     std::vector<Vec2> initial, bool injective, SlimResult& result) {
  if (has_fold(patch, ops, initial)) {
    SEAM_TRY(initial, tutte_embedding(patch));
    result.tutte_start = true;
  } else if (injective && !boundary_is_simple(patch, initial)) {
    // Fold-free but overlapping (a boundary that winds over itself): Tutte's map on a convex
    // boundary is bijective, and the bounded steps keep it so.
    SEAM_TRY(initial, tutte_embedding(patch));
    result.tutte_start = true;
    result.overlapping_start = true;
  }
  scale_to_surface_area(patch, ops, initial);
  return initial;
}

Status validate(std::size_t n, const std::vector<Vec2>& initial, const SlimOptions& options) {
  if (initial.size() != n) {
    return make_error(ErrorCode::kInvalidArgument, "SLIM: the initial map has " + std::to_string(initial.size()) +
                                                       " UVs for " + std::to_string(n) + " vertices");
  }
  if (options.iterations < 0 || options.iterations > 1000) {
    return make_error(ErrorCode::kInvalidArgument,
                      "SLIM: iterations must be in 0..1000, got " + std::to_string(options.iterations));
  }
  if (!(options.tolerance >= 0 && options.tolerance <= 1)) {
    return make_error(ErrorCode::kInvalidArgument, "SLIM: tolerance must be in 0..1");
  }
  if (options.contact_solves < 0 || options.contact_solves > 100000) {
    return make_error(ErrorCode::kInvalidArgument,
                      "SLIM: contact_solves must be in 0..100000, got " + std::to_string(options.contact_solves));
  }
  if (!options.vertex_order.empty() && options.vertex_order.size() != n) {
    return make_error(ErrorCode::kInvalidArgument, "SLIM: the vertex order has " +
                                                       std::to_string(options.vertex_order.size()) + " entries for " +
                                                       std::to_string(n) + " vertices");
  }
  return Ok{};
}

// The descent loop, at most `steps` steps: returns false when cancelled.
bool descend(Descent& d, int steps, double tolerance, const CancelToken& cancel) {
  SlimResult& result = d.result;
  SlimTimings& timings = result.timings;
  // Uncapped first. Triangles squeezed to 1e-4 of their size (a long limb that no seam
  // reaches) give weights near 1e12 and a system too ill-conditioned for Cholesky in double
  // precision; then the weights are capped and the step retried. The line search on the true
  // energy keeps every step a descent step either way.
  double weight_cap = kInf;
  int taken = 0;
  std::array<double, kWindow> gains{};  // relative decrease of the last kWindow steps, cyclic
  while (taken < steps) {
    if (cancel.is_cancelled()) return false;
    Clock::time_point clock = Clock::now();
    if (!d.proxy.assemble(*d.ops, result.uv, weight_cap, cancel)) return false;
    lap(timings.assemble_ms, clock);
    // Every iterate is a valid (fold-free) map, so a numerical failure of the proxy stops the
    // descent where it is instead of failing the request.
    if (!d.proxy.factorize()) {
      if (weight_cap == kInf) {
        weight_cap = kMaxProxyWeight;
        continue;
      }
      result.numerical_stop = true;
      break;
    }
    ++result.factorizations;
    const std::vector<Vec2> direction = d.proxy.direction(result.uv);
    lap(timings.factor_ms, clock);
    if (direction.empty()) {
      result.numerical_stop = true;
      break;
    }
    const StepOutcome step = bounded_step(d, direction);
    if (!(step.energy < d.energy)) break;  // no descent along the proxy's step: converged
    result.uv.swap(d.trial);
    const double decrease = (d.energy - step.energy) / d.energy;
    d.energy = step.energy;
    gains[static_cast<std::size_t>(taken % kWindow)] = decrease;
    ++taken;
    ++result.iterations;
    if (!step.collided) {
      if (decrease < tolerance) break;
      continue;
    }
    // A contact-limited step gains unevenly (a contact released, then another met), so one
    // small gain does not mean convergence: the window's mean gain is measured instead.
    double window_gain = 0;
    for (double g : gains) window_gain += g;
    if (taken >= kWindow && window_gain < kWindow * kWindowTolerance * tolerance) break;
  }
  return true;
}

// Progressive references (after Liu et al. 2018, "Progressive parameterizations"). A start
// that squeezes part of the chart by many orders of magnitude (BFF's conformal map of
// protrusions no seam reaches: singular values of 1e-8 on a camel cut through three random
// points; Tutte's map of a chart whose boundary squeezes it) is beyond SLIM in double
// precision: the proxy's weights span 1e12, after a step or two no direction lowers the
// energy, and the map shipped squeezed below the UV grid (thousands of degenerate triangles).
// Instead, every triangle gets a reference shape between its current UV shape and its 3D
// shape, J_ref = U S^(1 - t) V^T for the current Jacobian J = U S V^T, with one t for the
// chart chosen so that the map's singular values against the references (J J_ref^-1 =
// U S^t U^T) stay within [1/kProgressiveStretch, kProgressiveStretch]; a few SLIM steps on
// the references (the same proxy, line search and injectivity bounds, the energy still
// infinite at a degenerate triangle), then new references, until the chart's own shapes are
// within reach; then SLIM again. Only where SLIM on the chart's own shapes ended stretched
// beyond kProgressiveStart somewhere, so every other chart keeps its map (of CGAL's 138
// meshes with automatic extrema: cheese, femur, mpi and mpi_triang). SLIM alone does recover
// some squeezed starts (a cup 20 radii deep, slim_test), so it runs first.
constexpr double kProgressiveStretch = 300;
constexpr double kProgressiveStart = 1e4;
constexpr int kProgressiveRounds = 24;
constexpr int kProgressiveSteps = 4;

// s1 >= s2 > 0 of a fold-free triangle's Jacobian; s2 = det / s1, since svd_2x2's q - r
// cancels for a squeezed triangle.
std::pair<double, double> singular_values(const Eigen::Matrix2d& j, const Svd2& svd) {
  return {svd.s1, j.determinant() / svd.s1};
}

// The largest |log s| over the chart's triangles: how far the map is from isometric anywhere.
double largest_log_stretch(const DiscPatch& patch, const std::vector<TriangleOperator>& ops,
                           const std::vector<Vec2>& uv) {
  double largest = 0;
  for (std::size_t t = 0; t < ops.size(); ++t) {
    if (ops[t].area == 0) continue;
    const Eigen::Matrix2d j = jacobian(ops[t], patch.triangles[t], uv);
    const auto [s1, s2] = singular_values(j, svd_2x2(j));
    largest = std::max({largest, std::abs(std::log(s1)), std::abs(std::log(s2))});
  }
  return largest;
}

// The references for fraction t: grad_ref = J_ref^-T grad and area_ref = det(J_ref) area (the
// reference triangle is J_ref applied to the 3D triangle's local frame). Weighting by the
// reference's own area keeps the proxy's entries (area x |grad|^2) of one magnitude: with the
// 3D areas, a squeezed triangle's were 1e16 times its neighbours' and Cholesky failed.
void progressive_references(const DiscPatch& patch, const std::vector<TriangleOperator>& ops,
                            const std::vector<Vec2>& uv, double t, std::vector<TriangleOperator>& reference) {
  for (std::size_t k = 0; k < ops.size(); ++k) {
    reference[k] = ops[k];
    if (ops[k].area == 0) continue;
    const Eigen::Matrix2d j = jacobian(ops[k], patch.triangles[k], uv);
    const Svd2 svd = svd_2x2(j);
    const auto [s1, s2] = singular_values(j, svd);
    // J_ref^-T = U S^-(1 - t) V^T = (p1 + p2) / 2 U V^T + (p1 - p2) / 2 U diag(1, -1) V^T, the
    // two being svd_2x2's rotation and reflection (J = q rotation + r reflection).
    const double p1 = std::pow(s1, t - 1);
    const double p2 = std::pow(s2, t - 1);
    const Vec2& rot = svd.rotation;
    const Vec2& refl = svd.reflection;
    Eigen::Matrix2d rotation;
    rotation << rot.x(), -rot.y(), rot.y(), rot.x();
    Eigen::Matrix2d reflection;
    reflection << refl.x(), refl.y(), refl.y(), -refl.x();
    const Eigen::Matrix2d inverse_transpose = 0.5 * (p1 + p2) * rotation + 0.5 * (p1 - p2) * reflection;
    reference[k].grad12[0] = inverse_transpose * ops[k].grad12[0];
    reference[k].grad12[1] = inverse_transpose * ops[k].grad12[1];
    reference[k].area = ops[k].area / (p1 * p2);
  }
}

// The progressive rounds: returns false when cancelled. Leaves d on the chart's own operators.
bool descend_progressively(Descent& d, const std::vector<TriangleOperator>& ops, const CancelToken& cancel) {
  const double reach = std::log(kProgressiveStretch);
  double stretch = largest_log_stretch(d.patch, ops, d.result.uv);
  std::vector<TriangleOperator> reference(ops.size());
  for (int round = 0; round < kProgressiveRounds && std::isfinite(stretch) && stretch > reach; ++round) {
    if (cancel.is_cancelled()) return false;
    progressive_references(d.patch, ops, d.result.uv, reach / stretch, reference);
    d.ops = &reference;
    d.energy = mean_energy(d.patch, reference, d.result.uv);
    // A fixed number of steps: against references within reach the energy sits near 4, and
    // the relative tolerance would stop a descent that still gains.
    if (!descend(d, kProgressiveSteps, 0.0, cancel)) return false;
    ++d.result.progressive_rounds;
    const double next = largest_log_stretch(d.patch, ops, d.result.uv);
    // With the boundary's collision bounds, a round that took the largest stretch down by less
    // than half its reach (a factor of 17) ends them, and SLIM goes on from here on the chart's
    // own shapes: a genus-133 chart (cheese) gained a few percent of its reach per round at
    // 0.3 s each. Without them, rounds go on while they gain (cheese: 8 rounds to energy 4.7).
    if (!(next < stretch - (d.injective ? 0.5 * reach : 0.0))) break;
    stretch = next;
  }
  d.ops = &ops;
  d.energy = mean_energy(d.patch, ops, d.result.uv);
  return true;
}

bool squeezed(const Descent& d, const std::vector<TriangleOperator>& ops) {
  return largest_log_stretch(d.patch, ops, d.result.uv) > std::log(kProgressiveStart);
}

// From `start` again on progressive references, then SLIM for `steps`; the map of lower energy
// (this one or the one before) is kept. Returns false when cancelled.
bool retry_progressively(Descent& d, const std::vector<TriangleOperator>& ops, const std::vector<Vec2>& start,
                         int steps, const CancelToken& cancel) {
  std::vector<Vec2> before = std::move(d.result.uv);
  const double before_energy = d.energy;
  d.result.uv = start;
  if (!descend_progressively(d, ops, cancel) || !descend(d, steps, d.options.tolerance, cancel)) return false;
  if (!(d.energy < before_energy)) {
    d.result.uv = std::move(before);
    d.energy = before_energy;
  }
  return true;
}

// Where SLIM stalled on a squeezed map (a triangle still stretched beyond kProgressiveStart),
// it starts again from its start on progressive references (from the stalled map instead, dino
// and cow cut through three random points kept 1,283 and 136 triangles below the UV grid).
// Where the boundary's collision bounds stop that too (a chart its own boundary squeezes:
// cheese, genus 133, whose cut graph through 133 handles holds 9,888 of its 13,838 vertices,
// stayed at energy 1.7e13), once more without them: cheese then reaches 4.7, its boundary
// overlaps itself (SlimResult::injective false), and the pack step cuts the chart into
// overlap-free pieces (untangle.h), as it does lscm's and bff's maps. Returns false when
// cancelled.
bool recover_squeezed(Descent& d, const std::vector<TriangleOperator>& ops, const std::vector<Vec2>& start, int steps,
                      const CancelToken& cancel) {
  if (!squeezed(d, ops)) return true;
  if (!retry_progressively(d, ops, start, steps, cancel)) return false;
  if (!d.injective || !squeezed(d, ops)) return true;
  d.injective = false;
  return retry_progressively(d, ops, start, steps, cancel);
}

}  // namespace

Result<SlimResult> flatten_slim(const DiscPatch& patch, std::vector<Vec2> initial, const SlimOptions& options,
                                const CancelToken& cancel) {
  const std::size_t n = patch.num_vertices();
  if (Status valid = validate(n, initial, options); !valid.ok()) return valid.take_error();
  Clock::time_point clock = Clock::now();
  const std::vector<TriangleOperator> ops = triangle_operators(patch);
  SlimResult result;
  SEAM_TRY(result.uv, slim_start(patch, ops, std::move(initial), options.injective, result));
  result.energy_start = mean_energy(patch, ops, result.uv);
  result.energy_end = result.energy_start;
  lap(result.timings.start_ms, clock);
  if (options.iterations > 0 && n >= 2) {
    double area_3d = 0;
    for (const TriangleOperator& op : ops) area_3d += op.area;
    // Boundary vertices keep 1e-4 of the chart's size from the boundary edges they face: far
    // below a texel, far above float32's resolution wherever the chart is packed.
    Descent d{.patch = patch,
              .ops = &ops,
              .options = options,
              .injective = options.injective,
              .gap = 1e-4 * std::sqrt(area_3d),
              .result = result,
              .energy = result.energy_start,
              .proxy = ProxySystem(patch, options.proxy == SlimProxy::kAnisotropic ? 2 : 1, options.vertex_order),
              .trial = std::vector<Vec2>(n)};
    lap(result.timings.analyze_ms, clock);
    // A Tutte start is far from the optimum (its convex boundary squeezes whole regions), so it
    // gets three times the step budget. Contact-limited steps get no more: they cost one
    // factorization each, like the others (contact_search), and they are the budget.
    const int steps = result.tutte_start ? 3 * options.iterations : options.iterations;
    std::vector<Vec2> start;
    if (options.progressive) start = result.uv;
    if (!descend(d, steps, options.tolerance, cancel)) return cancelled_error("SLIM");
    if (options.progressive && !recover_squeezed(d, ops, start, steps, cancel)) return cancelled_error("SLIM");
    result.energy_end = d.energy;
  }
  result.injective = !has_fold(patch, ops, result.uv) && boundary_is_simple(patch, result.uv);
  return result;
}

}  // namespace seam::core
