#include "core/uv/slim.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "core/uv/collision.h"
#include "core/uv/distortion.h"
#include "core/uv/sparse_cholesky.h"

namespace seam::core {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kMaxProxyWeight = 1e8;
constexpr int kHoldRounds = 8;     // rounds of holding colliding vertices per step
constexpr int kResolveRounds = 1;  // of those, rounds that re-solve the proxy with them pinned

// Per triangle: 3D area and the gradients of its three barycentric coordinates in an isometric
// frame of its plane, so that the Jacobian of the map is J = sum_k uv_k g_k^T.
struct TriangleOperator {
  double area = 0;
  std::array<Vec2, 3> grad;
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
    op.grad[1] = inv.row(0).transpose();
    op.grad[2] = inv.row(1).transpose();
    op.grad[0] = -(op.grad[1] + op.grad[2]);
  }
  return ops;
}

Eigen::Matrix2d jacobian(const TriangleOperator& op, const Triangle& tri, const std::vector<Vec2>& uv) {
  Eigen::Matrix2d j = Eigen::Matrix2d::Zero();
  for (int k = 0; k < 3; ++k) j += uv[tri[k]] * op.grad[k].transpose();
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
// and the closest rotation R = U V^T. Weights are capped at `cap`.
void proxy_weights(const Eigen::Matrix2d& j, double cap, Eigen::Matrix2d& m, Eigen::Matrix2d& r) {
  const Svd2 svd = svd_2x2(j);
  const double s1 = svd.s1;
  const double s2 = std::max(svd.s2, 1e-12);  // positive: the line search keeps det > 0
  const double phi = svd.u_angle;
  const double rotation = svd.u_angle + svd.v_angle;
  auto weight2 = [cap](double s) { return std::min((s + 1) * (s * s + 1) / (s * s * s), cap); };
  const double w1 = weight2(s1);
  const double w2 = weight2(s2);
  const double c = std::cos(phi);
  const double s = std::sin(phi);
  m << c * c * w1 + s * s * w2, c * s * (w1 - w2), c * s * (w1 - w2), s * s * w1 + c * c * w2;
  r << std::cos(rotation), -std::sin(rotation), std::sin(rotation), std::cos(rotation);
}

}  // namespace

Result<SlimResult> flatten_slim(const DiscPatch& patch, std::vector<Vec2> initial, const SlimOptions& options,
                                const CancelToken& cancel) {
  const std::size_t n = patch.num_vertices();
  const std::size_t nf = patch.triangles.size();
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

  const std::vector<TriangleOperator> ops = triangle_operators(patch);
  SlimResult result;
  if (has_fold(patch, ops, initial)) {
    SEAM_TRY(initial, tutte_embedding(patch));
    result.tutte_start = true;
  } else if (options.injective && !boundary_is_simple(patch, initial)) {
    // Fold-free but overlapping (a boundary that winds over itself): Tutte's map on a convex
    // boundary is bijective, and the bounded steps below keep it so.
    SEAM_TRY(initial, tutte_embedding(patch));
    result.tutte_start = true;
    result.overlapping_start = true;
  }
  scale_to_surface_area(patch, ops, initial);
  result.energy_start = mean_energy(patch, ops, initial);
  result.energy_end = result.energy_start;
  result.uv = std::move(initial);
  std::vector<Vec2>& uv = result.uv;
  if (options.iterations == 0 || n < 2) {
    result.injective = !has_fold(patch, ops, result.uv) && boundary_is_simple(patch, result.uv);
    return result;
  }

  // Vertex 0 is pinned (the energy is translation invariant). Anisotropic proxy: unknowns
  // (u, v) of vertices 1..n-1 interleaved, each vertex a 2x2 block. Isotropic proxy: one
  // unknown per vertex and two right-hand sides. The pattern is fixed, so the lower triangle's
  // value slots are located once and the symbolic factorization is done once.
  const int block = options.proxy == SlimProxy::kAnisotropic ? 2 : 1;
  const auto nfree = static_cast<Eigen::Index>(block * (n - 1));
  auto unknown = [block](std::uint32_t v, int c) { return static_cast<Eigen::Index>(block * (v - 1) + c); };
  // Calls f(t, slot index, row, col) for every lower-triangle entry triangle t touches.
  auto for_each_lower_entry = [&](auto&& f) {
    for (std::size_t t = 0; t < nf; ++t) {
      const Triangle& tri = patch.triangles[t];
      for (int k = 0; k < 3; ++k) {
        for (int l = 0; l < 3; ++l) {
          if (tri[k] == 0 || tri[l] == 0) continue;
          for (int a = 0; a < block; ++a) {
            for (int b = 0; b < block; ++b) {
              const Eigen::Index row = unknown(tri[k], a);
              const Eigen::Index col = unknown(tri[l], b);
              if (row >= col) f(t, static_cast<std::size_t>((3 * k + l) * 4 + 2 * a + b), row, col);
            }
          }
        }
      }
    }
  };
  Eigen::SparseMatrix<double> system(nfree, nfree);
  {
    std::vector<Eigen::Triplet<double>> pattern;
    pattern.reserve(nf * (block == 2 ? 21 : 6));
    for_each_lower_entry([&](std::size_t, std::size_t, Eigen::Index row, Eigen::Index col) {
      pattern.emplace_back(row, col, 0.0);
    });
    system.setFromTriplets(pattern.begin(), pattern.end());
    system.makeCompressed();
  }
  // slot[t][(3k + l) * 4 + 2a + b]: index into system's values, or -1 if pinned or upper.
  std::vector<std::array<std::int64_t, 36>> slot(nf);
  for (auto& s : slot) s.fill(-1);
  for_each_lower_entry([&](std::size_t t, std::size_t entry, Eigen::Index row, Eigen::Index col) {
    const auto* begin = system.innerIndexPtr() + system.outerIndexPtr()[col];
    const auto* end = system.innerIndexPtr() + system.outerIndexPtr()[col + 1];
    const auto* it = std::lower_bound(begin, end, static_cast<int>(row));
    SEAM_ASSERT(it != end && *it == row);
    slot[t][entry] = it - system.innerIndexPtr();
  });
  // The diagonal entry of each unknown (the first entry of its lower-triangle column), where a
  // stiff spring pins a vertex that collides (see the line search).
  std::vector<std::int64_t> diag_slot(static_cast<std::size_t>(nfree));
  for (Eigen::Index col = 0; col < nfree; ++col) {
    const std::int64_t first = system.outerIndexPtr()[col];
    SEAM_ASSERT(system.innerIndexPtr()[first] == col);
    diag_slot[static_cast<std::size_t>(col)] = first;
  }
  SparseCholesky solver;
  solver.analyzePattern(system);

  // One column of interleaved (u, v) for the 2x2-block system, two columns otherwise.
  Eigen::MatrixXd rhs(nfree, block == 2 ? 1 : 2);
  auto rhs_at = [&](std::uint32_t v, int c) -> double& {
    return block == 2 ? rhs(unknown(v, c), 0) : rhs(unknown(v, 0), c);
  };
  std::vector<Vec2> direction(n, Vec2::Zero());
  std::vector<Vec2> trial(n);
  std::uint32_t poll = 0;
  double energy = result.energy_start;
  // Uncapped first. Triangles squeezed to 1e-4 of their size (a long limb that no seam
  // reaches) give weights near 1e12 and a system too ill-conditioned for Cholesky in double
  // precision; then the weights are capped and the step retried. The line search on the true
  // energy keeps every step a descent step either way.
  double weight_cap = kInf;
  // Boundary vertices keep 1e-4 of the chart's size from the boundary edges they face: far
  // below a texel, far above float32's resolution wherever the chart is packed.
  double area_3d = 0;
  for (const TriangleOperator& op : ops) area_3d += op.area;
  const double gap = 1e-4 * std::sqrt(area_3d);
  // A Tutte start is far from the optimum (its convex boundary squeezes whole regions), so it
  // gets three times the step budget.
  int max_iterations = result.tutte_start ? 3 * options.iterations : options.iterations;
  bool extended = false;
  for (int iter = 0; iter < max_iterations; ++iter) {
    if (cancel.is_cancelled()) return cancelled_error("SLIM");
    // Proxy: sum_t A_t |W_t (J_t - R_t)|^2. Its normal equations have block (k, l) =
    // A_t (g_k . g_l) M_t and right-hand side A_t M_t R_t g_k for vertex k, M_t = W_t^T W_t.
    // The isotropic proxy replaces M_t by (tr M_t / 2) I: u and v decouple and share one
    // n x n factorization, about a quarter of the 2n x 2n one's cost, for somewhat slower
    // convergence per step.
    std::fill(system.valuePtr(), system.valuePtr() + system.nonZeros(), 0.0);
    rhs.setZero();
    for (std::size_t t = 0; t < nf; ++t) {
      if (cancel.poll(poll)) return cancelled_error("SLIM assembly");
      const TriangleOperator& op = ops[t];
      if (op.area == 0) continue;
      const Triangle& tri = patch.triangles[t];
      Eigen::Matrix2d m;
      Eigen::Matrix2d r;
      proxy_weights(jacobian(op, tri, uv), weight_cap, m, r);
      if (block == 1) m = 0.5 * m.trace() * Eigen::Matrix2d::Identity();
      const Eigen::Matrix2d mr = m * r;
      for (int k = 0; k < 3; ++k) {
        if (tri[k] == 0) continue;
        const Vec2 b = op.area * (mr * op.grad[k]);
        for (int l = 0; l < 3; ++l) {
          const Eigen::Matrix2d coefficient = (op.area * op.grad[k].dot(op.grad[l])) * m;
          if (tri[l] == 0) {
            // The pinned vertex moves to the right-hand side.
            const Vec2 pinned = coefficient * uv[0];
            rhs_at(tri[k], 0) -= pinned.x();
            rhs_at(tri[k], 1) -= pinned.y();
            continue;
          }
          for (int a = 0; a < block; ++a) {
            for (int c = 0; c < block; ++c) {
              const std::int64_t s = slot[t][static_cast<std::size_t>((3 * k + l) * 4 + 2 * a + c)];
              if (s >= 0) system.valuePtr()[s] += coefficient(a, c);
            }
          }
        }
        rhs_at(tri[k], 0) += b.x();
        rhs_at(tri[k], 1) += b.y();
      }
    }
    // Every iterate is a valid (fold-free) map, so a numerical failure of the proxy stops the
    // descent where it is instead of failing the request.
    solver.factorize(system);
    if (solver.info() != Eigen::Success && weight_cap == kInf) {
      weight_cap = kMaxProxyWeight;
      --iter;
      continue;
    }
    if (solver.info() != Eigen::Success) {
      result.numerical_stop = true;
      break;
    }
    const Eigen::MatrixXd x = solver.solve(rhs);
    if (!x.allFinite()) {
      result.numerical_stop = true;
      break;
    }
    for (std::uint32_t v = 1; v < n; ++v) {
      const Vec2 target = block == 2 ? Vec2(x(unknown(v, 0), 0), x(unknown(v, 1), 0))
                                     : Vec2(x(unknown(v, 0), 0), x(unknown(v, 0), 1));
      direction[v] = target - uv[v];
    }

    // Backtracking on the true energy, from the largest step that keeps every triangle
    // positive (with a margin, since the energy is infinite at the bound itself).
    auto line_search = [&](const std::vector<Vec2>& dir, double step) {
      double trial_energy = kInf;
      for (int halving = 0; halving < 30 && step > 1e-12; ++halving, step *= 0.5) {
        for (std::size_t v = 0; v < n; ++v) trial[v] = uv[v] + step * dir[v];
        trial_energy = mean_energy(patch, ops, trial);
        if (trial_energy < energy) break;
      }
      return trial_energy;
    };
    double step = std::min(1.0, 0.9 * max_injective_step(patch, uv, direction));
    double trial_energy = kInf;
    bool searched = false;
    bool collided = false;
    if (options.injective) {
      CollisionStep collision = max_collision_free_step(patch, uv, direction, step, gap);
      if (collision.limited) {
        ++result.collision_limited_steps;
        collided = true;
        // Contacts slow the descent: allow them the Tutte start's budget.
        if (!extended) {
          max_iterations = std::max(max_iterations, 3 * options.iterations);
          extended = true;
        }
        // Truncating the whole step at the first contact would stall every vertex for the
        // sake of a few. Instead hold the vertices of the colliding pairs where they are and
        // let the rest move (bounds recomputed for that direction, so the guarantees hold);
        // a few rounds, since holding some may expose other contacts.
        std::vector<Vec2> held = direction;
        std::vector<char> pinned(n, 0);
        double spring = 0;
        for (Eigen::Index k = 0; k < nfree; ++k) {
          spring = std::max(spring, std::abs(system.valuePtr()[diag_slot[static_cast<std::size_t>(k)]]));
        }
        spring *= 1e6;
        for (int round = 0; round < kHoldRounds && collision.limited; ++round) {
          for (std::uint32_t v : collision.colliding) {
            if (pinned[v]) continue;
            pinned[v] = 1;
            if (v == 0 || round >= kResolveRounds) continue;
            // A stiff spring to its place: the re-solved proxy step then moves the free
            // vertices as well as it can with these held (zeroing them alone may ascend).
            for (int c = 0; c < block; ++c) system.valuePtr()[diag_slot[unknown(v, c)]] += spring;
            rhs_at(v, 0) += spring * uv[v].x();
            rhs_at(v, 1) += spring * uv[v].y();
          }
          if (round < kResolveRounds) {
            solver.factorize(system);
            if (solver.info() == Eigen::Success) {
              const Eigen::MatrixXd xp = solver.solve(rhs);
              if (xp.allFinite()) {
                for (std::uint32_t v = 1; v < n; ++v) {
                  held[v] = (block == 2 ? Vec2(xp(unknown(v, 0), 0), xp(unknown(v, 1), 0))
                                        : Vec2(xp(unknown(v, 0), 0), xp(unknown(v, 0), 1))) -
                            uv[v];
                }
              }
            }
          }
          for (std::uint32_t v = 0; v < n; ++v) {
            if (pinned[v]) held[v] = Vec2::Zero();
          }
          const double held_step = std::min(1.0, 0.9 * max_injective_step(patch, uv, held));
          collision = max_collision_free_step(patch, uv, held, held_step, gap);
          if (!collision.limited || round == kHoldRounds - 1) {
            const double bound = collision.limited ? 0.9 * collision.step : held_step;
            trial_energy = line_search(held, bound);
            searched = trial_energy < energy;
          }
        }
        if (!searched) {
          step = 0.9 * max_collision_free_step(patch, uv, direction, step, gap).step;
        }
      }
    }
    if (!searched) trial_energy = line_search(direction, step);
    if (!(trial_energy < energy)) break;  // no descent along the proxy's step: converged
    uv.swap(trial);
    const double decrease = (energy - trial_energy) / energy;
    energy = trial_energy;
    ++result.iterations;
    // A step held back by a contact gains little without being converged: go on.
    if (decrease < options.tolerance && !collided) break;
  }
  result.energy_end = energy;
  result.injective = !has_fold(patch, ops, uv) && boundary_is_simple(patch, uv);
  return result;
}

}  // namespace seam::core
