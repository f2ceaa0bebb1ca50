#include "core/uv/uv_patch.h"

#include <algorithm>
#include <cmath>
#include <limits>
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
  return cot;
}

Eigen::SparseMatrix<double> vertex_graph_lower(const DiscPatch& patch) {
  const auto n = static_cast<Eigen::Index>(patch.num_vertices());
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(3 * patch.triangles.size() + patch.num_vertices());
  for (Eigen::Index v = 0; v < n; ++v) entries.emplace_back(v, v, 1.0);
  for (const Triangle& tri : patch.triangles) {
    for (int k = 0; k < 3; ++k) {
      const auto a = static_cast<Eigen::Index>(tri[k]);
      const auto b = static_cast<Eigen::Index>(tri[(k + 1) % 3]);
      entries.emplace_back(std::max(a, b), std::min(a, b), 1.0);
    }
  }
  Eigen::SparseMatrix<double> lower(n, n);
  // An edge of two triangles is listed twice: one entry, still 1.
  lower.setFromTriplets(entries.begin(), entries.end(), [](double, double) { return 1.0; });
  return lower;
}

Eigen::SparseMatrix<double> cotan_laplacian(const DiscPatch& patch) {
  const auto n = static_cast<Eigen::Index>(patch.num_vertices());
  // Off-diagonal triplets only; the diagonal is summed here in the same triangle order as
  // setFromTriplets would sum it (the same doubles), at half the triplets to sort.
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(patch.triangles.size() * 6 + static_cast<std::size_t>(n));
  std::vector<double> diagonal(static_cast<std::size_t>(n), 0.0);
  for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
    const Triangle& tri = patch.triangles[t];
    const Vec3 cot = corner_cotans(patch, t);
    for (int k = 0; k < 3; ++k) {
      // The corner k is opposite edge (k+1, k+2).
      const auto i = static_cast<Eigen::Index>(tri[(k + 1) % 3]);
      const auto j = static_cast<Eigen::Index>(tri[(k + 2) % 3]);
      const double w = 0.5 * cot[k];
      entries.emplace_back(i, j, -w);
      entries.emplace_back(j, i, -w);
      diagonal[static_cast<std::size_t>(i)] += w;
      diagonal[static_cast<std::size_t>(j)] += w;
    }
  }
  for (Eigen::Index v = 0; v < n; ++v) entries.emplace_back(v, v, diagonal[static_cast<std::size_t>(v)]);
  Eigen::SparseMatrix<double> laplacian(n, n);
  laplacian.setFromTriplets(entries.begin(), entries.end());
  return laplacian;
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

}  // namespace seam::core

namespace seam::core {

namespace {

double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

double signed_area_2x(const Vec2& a, const Vec2& b, const Vec2& c) { return cross2(b - a, c - a); }

// Vertex -> incident triangles, CSR: the triangles of vertex v are
// triangles[offset[v] .. offset[v + 1]).
struct VertexStars {
  std::vector<std::uint32_t> offset;
  std::vector<std::uint32_t> triangles;
};

VertexStars vertex_stars(const DiscPatch& patch) {
  const std::size_t n = patch.num_vertices();
  VertexStars s;
  s.offset.assign(n + 1, 0);
  for (const Triangle& t : patch.triangles) {
    for (std::uint32_t v : t) ++s.offset[v + 1];
  }
  for (std::size_t v = 0; v < n; ++v) s.offset[v + 1] += s.offset[v];
  s.triangles.resize(s.offset[n]);
  std::vector<std::uint32_t> fill(s.offset.begin(), s.offset.end() - 1);
  for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
    for (std::uint32_t v : patch.triangles[t]) s.triangles[fill[v]++] = static_cast<std::uint32_t>(t);
  }
  return s;
}

}  // namespace

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
    if (!(signed_area_2x(uv[t[0]], uv[t[1]], uv[t[2]]) > 0)) ++flipped;
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
      if (!(signed_area_2x(uv[t[0]], uv[t[1]], uv[t[2]]) > 0)) ++bad;
    }
    return bad;
  };

  std::vector<std::uint8_t> mark(n, 0);
  std::vector<std::uint32_t> candidates;
  for (const Triangle& t : patch.triangles) {
    if (signed_area_2x(uv[t[0]], uv[t[1]], uv[t[2]]) > 0) continue;
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

}  // namespace seam::core

#include <cmath>

namespace seam::core {

Float32Rounding round_to_float32(const DiscPatch& patch, std::vector<Vec2>& uv) {
  std::vector<double> before(patch.triangles.size());
  for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
    const Triangle& tri = patch.triangles[t];
    before[t] = signed_area_2x(uv[tri[0]], uv[tri[1]], uv[tri[2]]);
  }
  // Through float storage: with GCC 12 at -O3 a direct double->float->double cast in a loop
  // was observed to leave the doubles unrounded (the tests check every value is a float).
  std::vector<float> stored(2 * uv.size());
  for (std::size_t v = 0; v < uv.size(); ++v) {
    stored[2 * v] = static_cast<float>(uv[v].x());
    stored[2 * v + 1] = static_cast<float>(uv[v].y());
  }
  for (std::size_t v = 0; v < uv.size(); ++v) uv[v] = Vec2(double{stored[2 * v]}, double{stored[2 * v + 1]});

  Float32Rounding out;
  std::vector<std::uint32_t> bad;
  for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
    const Triangle& tri = patch.triangles[t];
    if (before[t] > 0 && !(signed_area_2x(uv[tri[0]], uv[tri[1]], uv[tri[2]]) > 0)) {
      bad.push_back(static_cast<std::uint32_t>(t));
    }
  }
  out.degenerate = bad.size();
  if (bad.empty()) return out;

  const VertexStars stars = vertex_stars(patch);
  const std::vector<std::uint32_t>& offset = stars.offset;
  const std::vector<std::uint32_t>& star = stars.triangles;
  auto star_ok = [&](std::uint32_t v) {
    for (std::uint32_t k = offset[v]; k < offset[v + 1]; ++k) {
      const Triangle& t = patch.triangles[star[k]];
      if (before[star[k]] > 0 && !(signed_area_2x(uv[t[0]], uv[t[1]], uv[t[2]]) > 0)) return false;
    }
    return true;
  };
  auto step = [](double x, int dir) {
    if (dir == 0) return x;
    const float f = std::nextafter(static_cast<float>(x), dir > 0 ? 2.0f : -1.0f);
    return static_cast<double>(std::clamp(f, 0.0f, 1.0f));
  };
  for (std::uint32_t t : bad) {
    const Triangle& tri = patch.triangles[t];
    if (signed_area_2x(uv[tri[0]], uv[tri[1]], uv[tri[2]]) > 0) continue;  // fixed by a neighbour's nudge
    bool fixed = false;
    for (int corner = 0; corner < 3 && !fixed; ++corner) {
      const std::uint32_t v = tri[corner];
      const Vec2 old = uv[v];
      for (int dx = -1; dx <= 1 && !fixed; ++dx) {
        for (int dy = -1; dy <= 1 && !fixed; ++dy) {
          if (dx == 0 && dy == 0) continue;
          uv[v] = Vec2(step(old.x(), dx), step(old.y(), dy));
          fixed = star_ok(v);
          if (!fixed) uv[v] = old;
        }
      }
    }
    if (!fixed) ++out.remaining;
  }
  return out;
}

}  // namespace seam::core
