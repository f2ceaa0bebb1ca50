#include "core/uv/uv_patch.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <string>

namespace seam::core {

Result<std::vector<DiscPatch>> extract_disc_patches(const HalfedgeMesh& mesh, const Topology& topology) {
  const std::size_t num_components = topology.components.size();
  for (std::size_t c = 0; c < num_components; ++c) {
    const ComponentInfo& info = topology.components[c];
    if (info.euler_characteristic != 1 || info.boundary_loops != 1) {
      // Name one face so the caller can find the component.
      std::uint32_t face = 0;
      for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
        if (topology.face_component[FaceId(f)] == c) {
          face = static_cast<std::uint32_t>(f);
          break;
        }
      }
      return make_error(ErrorCode::kTopologyViolation,
                        "component " + std::to_string(c) + " (containing face " + std::to_string(face) +
                            ") is not a disc: Euler characteristic " + std::to_string(info.euler_characteristic) +
                            ", " + std::to_string(info.boundary_loops) +
                            " boundary loops; cut it open first (expected 1 and 1)",
                        {face});
    }
  }

  std::vector<DiscPatch> patches(num_components);
  std::vector<std::uint32_t> local(mesh.num_vertices(), VertexId::kInvalidValue);
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
    const std::uint32_t c = topology.vertex_component[VertexId(v)];
    if (c == VertexId::kInvalidValue) continue;  // isolated vertex: in no chart
    DiscPatch& p = patches[c];
    local[v] = static_cast<std::uint32_t>(p.positions.size());
    p.to_mesh.push_back(VertexId(v));
    p.positions.push_back(mesh.position(VertexId(v)));
  }
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    DiscPatch& p = patches[topology.face_component[FaceId(f)]];
    const auto vs = mesh.face_vertices(FaceId(f));
    p.triangles.push_back({local[vs[0].index()], local[vs[1].index()], local[vs[2].index()]});
    p.to_mesh_face.push_back(FaceId(f));
  }
  for (std::size_t l = 0; l < topology.boundary_loops.size(); ++l) {
    DiscPatch& p = patches[topology.boundary_loop_component[l]];
    // Boundary half-edges run clockwise around the disc (their twins belong to the
    // counter-clockwise faces), so the tails in reverse order are the counter-clockwise loop.
    const auto& loop = topology.boundary_loops[l];
    p.boundary.reserve(loop.size());
    for (auto it = loop.rbegin(); it != loop.rend(); ++it) p.boundary.push_back(local[mesh.tail(*it).index()]);
  }
  return patches;
}

Vec3 corner_angles(const DiscPatch& patch, std::size_t t) {
  const Triangle& tri = patch.triangles[t];
  Vec3 angles;
  for (int k = 0; k < 3; ++k) {
    const Vec3& p = patch.positions[tri[k]];
    const Vec3 a = patch.positions[tri[(k + 1) % 3]] - p;
    const Vec3 b = patch.positions[tri[(k + 2) % 3]] - p;
    // atan2 of |cross| and dot is accurate for angles near 0 and pi, unlike acos.
    angles[k] = std::atan2(a.cross(b).norm(), a.dot(b));
  }
  return angles;
}

Vec3 corner_cotans(const DiscPatch& patch, std::size_t t) {
  const Triangle& tri = patch.triangles[t];
  Vec3 cot;
  for (int k = 0; k < 3; ++k) {
    const Vec3& p = patch.positions[tri[k]];
    const Vec3 a = patch.positions[tri[(k + 1) % 3]] - p;
    const Vec3 b = patch.positions[tri[(k + 2) % 3]] - p;
    const double s = a.cross(b).norm();
    const double c = a.dot(b);
    double value = s > 0 ? c / s : (c >= 0 ? kCotanClamp : -kCotanClamp);
    cot[k] = std::clamp(value, -kCotanClamp, kCotanClamp);
  }
  return semi_definite_cotans(cot);
}

Vec3 semi_definite_cotans(Vec3 cot) {
  // The triangle's Dirichlet energy sum_k cot_k (u_{k+1} - u_{k+2})^2 / 2 is positive
  // semi-definite exactly when every pairwise sum and cot_0 cot_1 + cot_1 cot_2 + cot_2 cot_0
  // are >= 0; a triangle's true cotangents make the latter 1. Clamping a cap's (one angle
  // near pi, two near 0) or rounding a collinear triangle's breaks it: (-1e5, 1e5, 1e5) gives
  // -1e10, and one such triangle made the whole Laplacian indefinite (CGAL's triceratops).
  // The one negative weight is raised to -b c / (b + c), the least that keeps the energy
  // semi-definite; true cotangents lie above that bound by 1 / (b + c), so a triangle whose
  // cotangents were not clamped keeps them. Two negative weights (no real triangle has two
  // obtuse angles) are set to 0.
  int negative = 0;
  int at = 0;
  for (int k = 0; k < 3; ++k) {
    if (cot[k] < 0) {
      ++negative;
      at = k;
    }
  }
  if (negative == 1) {
    const double b = cot[(at + 1) % 3];
    const double c = cot[(at + 2) % 3];
    cot[at] = b + c > 0 ? std::max(cot[at], -b * c / (b + c)) : 0.0;
  } else if (negative > 1) {
    for (int k = 0; k < 3; ++k) cot[k] = std::max(cot[k], 0.0);
  }
  return cot;
}

namespace {

// An n x n compressed matrix built column by column into its own arrays (no triplets: at 1M
// faces triplets and setFromTriplets' transposed copy were ~250 MB of fresh memory, whose
// first touch costs more than the work on it in this VM). `column(c, entries)` lists column
// c's (row, value) pairs, a row possibly more than once; they are ordered by row with a
// stable insertion sort (columns are short), and a repeated row's values are folded in
// listed order by `merge`. `expected` entries are reserved.
template <class Column, class Merge>
Eigen::SparseMatrix<double> by_columns(std::size_t n, std::size_t expected, Column&& column, Merge&& merge) {
  Eigen::SparseMatrix<double> matrix(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  auto& data = matrix.data();
  data.reserve(static_cast<Eigen::Index>(expected));
  int* outer = matrix.outerIndexPtr();
  outer[0] = 0;
  std::vector<std::pair<std::uint32_t, double>> entries;
  for (std::uint32_t c = 0; c < n; ++c) {
    entries.clear();
    column(c, entries);
    for (std::size_t i = 1; i < entries.size(); ++i) {
      const auto x = entries[i];
      std::size_t j = i;
      for (; j > 0 && entries[j - 1].first > x.first; --j) entries[j] = entries[j - 1];
      entries[j] = x;
    }
    for (std::size_t i = 0; i < entries.size(); ++i) {
      if (i > 0 && entries[i - 1].first == entries[i].first) {
        data.value(data.size() - 1) = merge(data.value(data.size() - 1), entries[i].second);
      } else {
        data.append(entries[i].second, entries[i].first);
      }
    }
    outer[c + 1] = static_cast<int>(data.size());
  }
  return matrix;
}

// The position (0, 1, 2) of vertex v in triangle t, which holds it.
int corner_of(const Triangle& t, std::uint32_t v) {
  return t[0] == v ? 0 : t[1] == v ? 1 : 2;
}

// A disc's entries in the lower triangle with the diagonal: n + E, E = (3F + boundary) / 2.
std::size_t disc_lower_entries(const DiscPatch& patch) {
  return patch.num_vertices() + (3 * patch.triangles.size() + patch.boundary.size()) / 2;
}

}  // namespace

Eigen::SparseMatrix<double> vertex_graph_lower(const DiscPatch& patch) {
  const VertexStars stars = vertex_stars(patch);
  // An edge of two triangles is listed twice: one entry, still 1.
  return by_columns(
      patch.num_vertices(), disc_lower_entries(patch),
      [&](std::uint32_t c, std::vector<std::pair<std::uint32_t, double>>& entries) {
        entries.emplace_back(c, 1.0);
        for (std::uint32_t k = stars.offset[c]; k < stars.offset[c + 1]; ++k) {
          for (std::uint32_t u : patch.triangles[stars.triangles[k]]) {
            if (u > c) entries.emplace_back(u, 1.0);
          }
        }
      },
      [](double, double) { return 1.0; });
}

Eigen::SparseMatrix<double> cotan_laplacian(const DiscPatch& patch) {
  const std::size_t n = patch.num_vertices();
  const std::size_t nt = patch.triangles.size();
  // Each corner's weight, and the diagonal summed in triangle order as before.
  std::vector<Vec3> weight(nt);
  std::vector<double> diagonal(n, 0.0);
  for (std::size_t t = 0; t < nt; ++t) {
    const Triangle& tri = patch.triangles[t];
    weight[t] = 0.5 * corner_cotans(patch, t);
    for (int k = 0; k < 3; ++k) {
      // The corner k is opposite edge (k+1, k+2).
      diagonal[tri[(k + 1) % 3]] += weight[t][k];
      diagonal[tri[(k + 2) % 3]] += weight[t][k];
    }
  }
  // Column c: its diagonal, and two off-diagonal entries per triangle of its star, which
  // lists the triangles in index order, so an interior edge's two values are summed in
  // triangle order: the doubles setFromTriplets gave (uv_patch_test compares bit for bit).
  const VertexStars stars = vertex_stars(patch);
  return by_columns(
      n, 2 * disc_lower_entries(patch) - n,
      [&](std::uint32_t c, std::vector<std::pair<std::uint32_t, double>>& entries) {
        entries.emplace_back(c, diagonal[c]);
        for (std::uint32_t k = stars.offset[c]; k < stars.offset[c + 1]; ++k) {
          const std::uint32_t t = stars.triangles[k];
          const Triangle& tri = patch.triangles[t];
          // Edge (m, m+2) is opposite corner m+1, edge (m, m+1) opposite corner m+2.
          const int m = corner_of(tri, c);
          const int k1 = (m + 1) % 3, k2 = (m + 2) % 3;
          entries.emplace_back(tri[k2], -weight[t][k1]);
          entries.emplace_back(tri[k1], -weight[t][k2]);
        }
      },
      [](double sum, double value) { return sum + value; });
}

std::array<Vec2, 3> local_triangle_frame(const DiscPatch& patch, std::size_t t) {
  const Triangle& tri = patch.triangles[t];
  const Vec3 e1 = patch.positions[tri[1]] - patch.positions[tri[0]];
  const Vec3 e2 = patch.positions[tri[2]] - patch.positions[tri[0]];
  const double l1 = e1.norm();
  const Vec3 x = l1 > 0 ? Vec3(e1 / l1) : Vec3(1, 0, 0);
  const double ex = e2.dot(x);
  const double ey = (e2 - ex * x).norm();
  return {Vec2(0, 0), Vec2(l1, 0), Vec2(ex, ey)};
}

VertexStars vertex_stars(std::span<const Triangle> triangles, std::size_t num_vertices) {
  VertexStars s;
  s.offset.assign(num_vertices + 1, 0);
  for (const Triangle& t : triangles) {
    for (std::uint32_t v : t) ++s.offset[v + 1];
  }
  for (std::size_t v = 0; v < num_vertices; ++v) s.offset[v + 1] += s.offset[v];
  s.triangles.resize(s.offset[num_vertices]);
  std::vector<std::uint32_t> fill(s.offset.begin(), s.offset.end() - 1);
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (std::uint32_t v : triangles[t]) s.triangles[fill[v]++] = static_cast<std::uint32_t>(t);
  }
  return s;
}

VertexStars vertex_stars(const DiscPatch& patch) {
  return vertex_stars(patch.triangles, patch.num_vertices());
}

double max_injective_step(const DiscPatch& patch, const std::vector<Vec2>& uv, const std::vector<Vec2>& direction) {
  double best = std::numeric_limits<double>::infinity();
  for (const Triangle& t : patch.triangles) {
    const Vec2 a = uv[t[1]] - uv[t[0]];
    const Vec2 c = uv[t[2]] - uv[t[0]];
    const double a0 = cross2(a, c);
    if (!(a0 > 0)) continue;  // already folded: it may unfold, it cannot fold further
    const Vec2 b = direction[t[1]] - direction[t[0]];
    const Vec2 e = direction[t[2]] - direction[t[0]];
    const double b1 = cross2(a, e) + cross2(b, c);
    const double c2 = cross2(b, e);
    // Smallest positive root of c2 t^2 + b1 t + a0.
    double root = std::numeric_limits<double>::infinity();
    if (std::abs(c2) < 1e-300) {
      if (b1 < 0) root = -a0 / b1;
    } else {
      const double disc = b1 * b1 - 4 * c2 * a0;
      if (disc >= 0) {
        const double sq = std::sqrt(disc);
        // Numerically stable pair of roots.
        const double q = -0.5 * (b1 + std::copysign(sq, b1));
        for (double r : {q / c2, q != 0 ? a0 / q : std::numeric_limits<double>::infinity()}) {
          if (r > 0) root = std::min(root, r);
        }
      }
    }
    best = std::min(best, root);
  }
  return best;
}

std::size_t count_flipped(const DiscPatch& patch, const std::vector<Vec2>& uv) {
  std::size_t flipped = 0;
  for (const Triangle& t : patch.triangles) {
    if (!(cross2(uv[t[0]], uv[t[1]], uv[t[2]]) > 0)) ++flipped;
  }
  return flipped;
}

std::size_t repair_flips(const DiscPatch& patch, std::vector<Vec2>& uv, int rounds) {
  std::size_t flipped = count_flipped(patch, uv);
  if (flipped == 0) return 0;
  const std::size_t n = patch.num_vertices();
  const VertexStars stars = vertex_stars(patch);
  const std::vector<std::uint32_t>& offset = stars.offset;
  const std::vector<std::uint32_t>& star = stars.triangles;
  auto bad_in_star = [&](std::uint32_t v) {
    std::size_t bad = 0;
    for (std::uint32_t k = offset[v]; k < offset[v + 1]; ++k) {
      const Triangle& t = patch.triangles[star[k]];
      if (!(cross2(uv[t[0]], uv[t[1]], uv[t[2]]) > 0)) ++bad;
    }
    return bad;
  };

  std::vector<std::uint8_t> mark(n, 0);
  std::vector<std::uint32_t> candidates;
  for (const Triangle& t : patch.triangles) {
    if (cross2(uv[t[0]], uv[t[1]], uv[t[2]]) > 0) continue;
    for (std::uint32_t v : t) {
      if (!mark[v]) {
        mark[v] = 1;
        candidates.push_back(v);
      }
    }
  }
  for (int round = 0; round < rounds && flipped > 0; ++round) {
    for (std::uint32_t v : candidates) {
      const std::size_t before = bad_in_star(v);
      if (before == 0) continue;
      Vec2 average = Vec2::Zero();
      std::size_t count = 0;
      for (std::uint32_t k = offset[v]; k < offset[v + 1]; ++k) {
        for (std::uint32_t w : patch.triangles[star[k]]) {
          if (w != v) {
            average += uv[w];
            ++count;
          }
        }
      }
      if (count == 0) continue;
      average /= static_cast<double>(count);
      const Vec2 old = uv[v];
      for (const Vec2& candidate : {average, Vec2(0.5 * (old + average)), Vec2(0.75 * old + 0.25 * average)}) {
        uv[v] = candidate;
        if (bad_in_star(v) < before) break;
        uv[v] = old;
      }
    }
    flipped = count_flipped(patch, uv);
    // Grow the region by one ring: a fold can need its neighbours to make room.
    const std::size_t current = candidates.size();
    for (std::size_t i = 0; i < current; ++i) {
      const std::uint32_t v = candidates[i];
      for (std::uint32_t k = offset[v]; k < offset[v + 1]; ++k) {
        for (std::uint32_t w : patch.triangles[star[k]]) {
          if (!mark[w]) {
            mark[w] = 1;
            candidates.push_back(w);
          }
        }
      }
    }
  }
  return flipped;
}

namespace {

// The point p maximising the smallest doubled signed area of the triangles (p, a_i, b_i), and
// that area: a linear program in (p, t) solved by its vertices (three active constraints).
// `ring` holds the pairs (a_i, b_i). Returns t = -infinity for no solution (parallel rows).
std::pair<Vec2, double> max_min_area_point(const std::vector<std::pair<Vec2, Vec2>>& ring) {
  // Doubled area of (p, a, b) = cross(a, b) + p . (a.y - b.y, b.x - a.x): c_i + g_i . p.
  std::vector<Vec2> g;
  std::vector<double> c;
  for (const auto& [a, b] : ring) {
    g.emplace_back(a.y() - b.y(), b.x() - a.x());
    c.push_back(cross2(a, b));
  }
  Vec2 best_p = Vec2::Zero();
  double best_t = -std::numeric_limits<double>::infinity();
  const std::size_t d = ring.size();
  for (std::size_t i = 0; i < d; ++i) {
    for (std::size_t j = i + 1; j < d; ++j) {
      for (std::size_t k = j + 1; k < d; ++k) {
        // c + g . p = t for i, j, k: subtracting row i leaves a 2x2 system in p.
        const Vec2 r1 = g[j] - g[i];
        const Vec2 r2 = g[k] - g[i];
        const double det = r1.x() * r2.y() - r1.y() * r2.x();
        if (std::abs(det) < 1e-300) continue;
        const double b1 = c[i] - c[j];
        const double b2 = c[i] - c[k];
        const Vec2 p((b1 * r2.y() - b2 * r1.y()) / det, (r1.x() * b2 - r2.x() * b1) / det);
        double t = std::numeric_limits<double>::infinity();
        for (std::size_t m = 0; m < d; ++m) t = std::min(t, c[m] + g[m].dot(p));
        if (t > best_t) {
          best_t = t;
          best_p = p;
        }
      }
    }
  }
  return {best_p, best_t};
}

// Whether moving a star's centre from `from` to `to` (where its smallest doubled area is t) is
// taken: it must unfold some of the star's folded triangles and fold none that was not, or,
// for a star with nothing folded, make its thinnest triangle fatter. So the fold count never
// rises. `relaxed`: any move that raises the star's smallest area. "Folded": a doubled signed
// area at most `floor`.
bool moves_well(const std::vector<std::pair<Vec2, Vec2>>& ring, const Vec2& from, const Vec2& to, double t,
                bool relaxed, double floor) {
  std::size_t folded_before = 0;
  std::size_t folded_after = 0;
  double worst_before = std::numeric_limits<double>::infinity();
  if (relaxed) {
    for (const auto& [a, b] : ring) worst_before = std::min(worst_before, cross2(from, a, b));
    return t > worst_before;
  }
  for (const auto& [a, b] : ring) {
    const double before = cross2(from, a, b);
    const bool now_folded = !(cross2(to, a, b) > floor);
    worst_before = std::min(worst_before, before);
    if (!(before > floor)) {
      ++folded_before;
    } else if (now_folded) {
      return false;  // would fold a triangle that was not
    }
    if (now_folded) ++folded_after;
  }
  return folded_before > 0 ? folded_after < folded_before : t > worst_before;
}

}  // namespace

std::size_t untangle(const DiscPatch& patch, std::vector<Vec2>& uv, int rounds, double min_area_2x) {
  auto thin = [&](std::uint32_t t) {
    const Triangle& tri = patch.triangles[t];
    return !(cross2(uv[tri[0]], uv[tri[1]], uv[tri[2]]) > min_area_2x);
  };
  // The thin triangles in index order, kept up to date from the stars of the vertices each
  // round moves (a triangle changes only when a corner moves): the rounds see what a scan of
  // every triangle would give, without one (at 1.25M faces 40 scans were ~0.1 s).
  std::vector<std::uint32_t> thin_set;
  for (std::uint32_t t = 0; t < patch.triangles.size(); ++t) {
    if (thin(t)) thin_set.push_back(t);
  }
  if (thin_set.empty()) return 0;
  const VertexStars stars = vertex_stars(patch);
  std::vector<std::uint8_t> boundary(patch.num_vertices(), 0);
  for (std::uint32_t v : patch.boundary) boundary[v] = 1;
  std::vector<std::uint8_t> mark(patch.num_vertices(), 0);
  std::vector<std::uint32_t> candidates, moved;
  std::vector<std::pair<Vec2, Vec2>> ring;
  for (int round = 0; round < rounds && !thin_set.empty(); ++round) {
    // The interior corners of folded triangles and, from the second round, their neighbours.
    candidates.clear();
    for (std::uint32_t t : thin_set) {
      for (std::uint32_t v : patch.triangles[t]) {
        if (mark[v]) continue;
        mark[v] = 1;
        candidates.push_back(v);
      }
    }
    for (std::size_t i = 0, folded = candidates.size(); round > 0 && i < folded; ++i) {
      for (std::uint32_t k = stars.offset[candidates[i]]; k < stars.offset[candidates[i] + 1]; ++k) {
        for (std::uint32_t w : patch.triangles[stars.triangles[k]]) {
          if (!mark[w]) {
            mark[w] = 1;
            candidates.push_back(w);
          }
        }
      }
    }
    moved.clear();
    for (std::uint32_t v : candidates) {
      mark[v] = 0;
      const std::uint32_t degree = stars.offset[v + 1] - stars.offset[v];
      if (boundary[v] || degree < 3 || degree > kUntangleMaxDegree) continue;
      ring.clear();
      for (std::uint32_t k = stars.offset[v]; k < stars.offset[v + 1]; ++k) {
        const Triangle& t = patch.triangles[stars.triangles[k]];
        const int at = corner_of(t, v);
        ring.emplace_back(uv[t[(at + 1) % 3]], uv[t[(at + 2) % 3]]);
      }
      const auto [p, t] = max_min_area_point(ring);
      if (moves_well(ring, uv[v], p, t, round >= rounds / 2, min_area_2x)) {
        uv[v] = p;
        moved.push_back(v);
      }
    }
    for (std::uint32_t v : moved) {
      for (std::uint32_t k = stars.offset[v]; k < stars.offset[v + 1]; ++k) thin_set.push_back(stars.triangles[k]);
    }
    std::sort(thin_set.begin(), thin_set.end());
    thin_set.erase(std::unique(thin_set.begin(), thin_set.end()), thin_set.end());
    std::erase_if(thin_set, [&](std::uint32_t t) { return !thin(t); });
  }
  return thin_set.size();
}

}  // namespace seam::core

#include <cmath>

namespace seam::core {

double to_uv_grid(double x) {
  // Scaling by powers of two and rounding to an integer below 2^24 are exact in double.
  return std::round(std::clamp(x, 0.0, 1.0) * (1.0 / kUvGrid)) * kUvGrid;
}

Float32Rounding round_to_float32(const DiscPatch& patch, std::vector<Vec2>& uv) {
  // The wanted turn: counter-clockwise where the double map had it, free elsewhere.
  std::vector<double> want(patch.triangles.size());
  for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
    const Triangle& tri = patch.triangles[t];
    want[t] = cross2(uv[tri[0]], uv[tri[1]], uv[tri[2]]) > 0 ? 1.0 : 0.0;
  }
  for (Vec2& p : uv) p = Vec2(to_uv_grid(p.x()), to_uv_grid(p.y()));
  return restore_turns(patch.triangles, want, uv);
}

Float32Rounding restore_turns(std::span<const Triangle> triangles, std::span<const double> want,
                              std::vector<Vec2>& uv) {
  constexpr int kRestoreReach = 4;
  auto turns_right = [&](std::uint32_t t) {
    const Triangle& tri = triangles[t];
    const double area = cross2(uv[tri[0]], uv[tri[1]], uv[tri[2]]);
    return want[t] == 0 || (want[t] > 0 ? area > 0 : area < 0);
  };
  Float32Rounding out;
  std::vector<std::uint32_t> bad;
  for (std::uint32_t t = 0; t < triangles.size(); ++t) {
    if (!turns_right(t)) bad.push_back(t);
  }
  out.degenerate = bad.size();
  if (bad.empty()) return out;

  const VertexStars stars = vertex_stars(triangles, uv.size());
  auto star_ok = [&](std::uint32_t v) {
    for (std::uint32_t k = stars.offset[v]; k < stars.offset[v + 1]; ++k) {
      if (!turns_right(stars.triangles[k])) return false;
    }
    return true;
  };
  auto step = [](double x, int dir) { return std::clamp(x + dir * kUvGrid, 0.0, 1.0); };
  for (std::uint32_t t : bad) {
    if (turns_right(t)) continue;  // fixed by a neighbour's nudge
    bool fixed = false;
    // Rings of growing radius: the nearest grid points first (one step, as a rounding
    // error is), then up to kRestoreReach steps for a sliver thinner than the grid.
    for (int reach = 1; reach <= kRestoreReach && !fixed; ++reach) {
      for (int corner = 0; corner < 3 && !fixed; ++corner) {
        const std::uint32_t v = triangles[t][corner];
        const Vec2 old = uv[v];
        for (int dx = -reach; dx <= reach && !fixed; ++dx) {
          for (int dy = -reach; dy <= reach && !fixed; ++dy) {
            if (std::max(std::abs(dx), std::abs(dy)) != reach) continue;  // on this ring only
            uv[v] = Vec2(step(old.x(), dx), step(old.y(), dy));
            fixed = star_ok(v);
            if (!fixed) uv[v] = old;
          }
        }
      }
    }
    if (!fixed) ++out.remaining;
  }
  return out;
}

}  // namespace seam::core
