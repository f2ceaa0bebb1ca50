// Fixture meshes built in code, with known topology. Header-only so every suite can use them.
#pragma once

#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <tuple>
#include <vector>

#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/icosphere.h"
#include "core/mesh/types.h"

namespace seam::fixtures {

using core::Triangle;
using core::Vec3;

struct Soup {
  std::vector<Vec3> positions;
  std::vector<Triangle> triangles;
};

inline Soup tetrahedron() {
  return {{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)},
          {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}};
}

/// Icosahedron subdivided `levels` times, projected to the unit sphere (core::icosphere).
/// Genus 0, closed.
inline Soup icosphere(int levels) {
  core::IndexedMesh m = core::icosphere(levels);
  return {std::move(m.positions), std::move(m.triangles)};
}

/// A (nu x nv) grid on a torus of radii R > r. Genus 1, closed.
inline Soup torus(int nu = 24, int nv = 12, double R = 2.0, double r = 0.6) {
  Soup s;
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * std::numbers::pi * i / nu;
      const double v = 2 * std::numbers::pi * j / nv;
      s.positions.emplace_back((R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u),
                               r * std::sin(v));
    }
  }
  auto id = [&](int i, int j) { return static_cast<std::uint32_t>(((i + nu) % nu) * nv + (j + nv) % nv); };
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      s.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      s.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return s;
}

/// An open cylinder of radius 1 and height h: genus 0 with two boundary loops.
inline Soup open_cylinder(int around = 16, int rows = 6, double h = 2.0) {
  Soup s;
  for (int j = 0; j <= rows; ++j) {
    for (int i = 0; i < around; ++i) {
      const double a = 2 * std::numbers::pi * i / around;
      s.positions.emplace_back(std::cos(a), std::sin(a), h * j / rows);
    }
  }
  auto id = [&](int i, int j) { return static_cast<std::uint32_t>(j * around + (i + around) % around); };
  for (int j = 0; j < rows; ++j) {
    for (int i = 0; i < around; ++i) {
      s.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      s.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return s;
}

/// A flat unit disc in the z = 0 plane: `rings` concentric rings, one boundary loop.
inline Soup disc(int rings = 6, int sectors = 16) {
  Soup s;
  s.positions.emplace_back(0, 0, 0);
  for (int r = 1; r <= rings; ++r) {
    for (int k = 0; k < sectors; ++k) {
      const double a = 2 * std::numbers::pi * k / sectors;
      s.positions.emplace_back(r * std::cos(a) / rings, r * std::sin(a) / rings, 0.0);
    }
  }
  auto id = [&](int r, int k) {
    return r == 0 ? 0u : static_cast<std::uint32_t>(1 + (r - 1) * sectors + (k + sectors) % sectors);
  };
  for (int k = 0; k < sectors; ++k) s.triangles.push_back({0, id(1, k), id(1, k + 1)});
  for (int r = 1; r < rings; ++r) {
    for (int k = 0; k < sectors; ++k) {
      s.triangles.push_back({id(r, k), id(r + 1, k), id(r + 1, k + 1)});
      s.triangles.push_back({id(r, k), id(r + 1, k + 1), id(r, k + 1)});
    }
  }
  return s;
}

/// The closed boundary surface of a union of unit voxels, oriented outward. With `filled`
/// free of diagonal-only contacts it is a manifold; a slab with g holes has genus g.
inline Soup voxel_surface(const std::set<std::tuple<int, int, int>>& filled) {
  Soup s;
  std::map<std::tuple<int, int, int>, std::uint32_t> index;
  auto vertex = [&](int x, int y, int z) {
    auto [it, inserted] = index.try_emplace({x, y, z}, static_cast<std::uint32_t>(s.positions.size()));
    if (inserted) s.positions.emplace_back(x, y, z);
    return it->second;
  };
  for (const auto& [x, y, z] : filled) {
    for (int axis = 0; axis < 3; ++axis) {
      for (int dir = -1; dir <= 1; dir += 2) {
        int n[3] = {x, y, z};
        n[axis] += dir;
        if (filled.count({n[0], n[1], n[2]})) continue;
        // Corners of the face in the plane axis = c, counter-clockwise seen from outside.
        const int c = (dir > 0) ? (axis == 0 ? x : axis == 1 ? y : z) + 1 : (axis == 0 ? x : axis == 1 ? y : z);
        const int u = (axis + 1) % 3;
        const int w = (axis + 2) % 3;
        int base[3] = {x, y, z};
        base[axis] = c;
        std::uint32_t q[4];
        const int du[4] = {0, 1, 1, 0};
        const int dw[4] = {0, 0, 1, 1};
        for (int k = 0; k < 4; ++k) {
          int p[3] = {base[0], base[1], base[2]};
          p[u] += du[k];
          p[w] += dw[k];
          q[k] = vertex(p[0], p[1], p[2]);
        }
        if (dir > 0) {
          s.triangles.push_back({q[0], q[1], q[2]});
          s.triangles.push_back({q[0], q[2], q[3]});
        } else {
          s.triangles.push_back({q[0], q[2], q[1]});
          s.triangles.push_back({q[0], q[3], q[2]});
        }
      }
    }
  }
  return s;
}

/// A 3 x (2g+1) slab of voxels with g square holes: a closed surface of genus g.
inline Soup holed_slab(int genus) {
  std::set<std::tuple<int, int, int>> cells;
  for (int x = 0; x < 3; ++x) {
    for (int y = 0; y < 2 * genus + 1; ++y) {
      if (x == 1 && y % 2 == 1) continue;
      cells.insert({x, y, 0});
    }
  }
  return voxel_surface(cells);
}

/// Concatenation of two soups (two connected components).
inline Soup join(const Soup& a, const Soup& b) {
  Soup s = a;
  const auto offset = static_cast<std::uint32_t>(a.positions.size());
  s.positions.insert(s.positions.end(), b.positions.begin(), b.positions.end());
  for (auto t : b.triangles) s.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  return s;
}

/// Translates every position by d.
inline Soup translated(Soup s, const Vec3& d) {
  for (auto& p : s.positions) p += d;
  return s;
}

/// Two triangles sharing only vertex 0: a bowtie (non-manifold vertex).
inline Soup bowtie() {
  return {{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(-1, 0, 0), Vec3(-1, -1, 0)}, {{0, 1, 2}, {0, 3, 4}}};
}

/// Three triangles on edge (0, 1): a fin (non-manifold edge).
inline Soup fin() {
  return {{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, 1)},
          {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}}};
}

/// A tetrahedron with face 3 reversed (inconsistent orientation).
inline Soup flipped_tetrahedron() {
  Soup s = tetrahedron();
  std::swap(s.triangles[3][1], s.triangles[3][2]);
  return s;
}

/// An icosphere with every face whose centroid has z > `z_min` reversed: a flipped patch
/// (inconsistent orientation) on a closed surface, as a bad export leaves it.
inline Soup sphere_with_flipped_patch(int levels = 2, double z_min = 0.7) {
  Soup s = icosphere(levels);
  for (auto& t : s.triangles) {
    const double z = (s.positions[t[0]].z() + s.positions[t[1]].z() + s.positions[t[2]].z()) / 3;
    if (z > z_min) std::swap(t[1], t[2]);
  }
  return s;
}

/// An icosphere with a fin: one extra triangle on the existing edge of face 0's first two
/// corners, its apex pushed outwards (three faces on one edge).
inline Soup sphere_with_fin(int levels = 1) {
  Soup s = icosphere(levels);
  const Triangle t = s.triangles[0];
  const Vec3 mid = (s.positions[t[0]] + s.positions[t[1]]) / 2;
  s.positions.push_back(mid * 1.8);
  s.triangles.push_back({t[0], t[1], static_cast<std::uint32_t>(s.positions.size() - 1)});
  return s;
}

/// `pages` triangles on edge (0, 1), directions alternating: `pages` sheets on one edge.
inline Soup book(int pages) {
  Soup s{{Vec3(0, 0, 0), Vec3(1, 0, 0)}, {}};
  for (int p = 0; p < pages; ++p) {
    const double a = 2 * std::numbers::pi * p / pages;
    s.positions.emplace_back(0.5, std::cos(a), std::sin(a));
    const auto apex = static_cast<std::uint32_t>(s.positions.size() - 1);
    s.triangles.push_back(p % 2 == 0 ? Triangle{0, 1, apex} : Triangle{1, 0, apex});
  }
  return s;
}

/// Two tetrahedra sharing one edge (four faces on it): two closed sheets.
inline Soup tetrahedra_on_one_edge() {
  Soup s = tetrahedron();  // edge (0, 1) is shared
  s.positions.push_back(Vec3(0.5, -1, -0.5));
  s.positions.push_back(Vec3(0.5, -0.5, -1));
  // A second tetrahedron 0, 1, 4, 5, wound outwards.
  const std::uint32_t a = 0, b = 1, c = 4, d = 5;
  const Vec3 centre = (s.positions[a] + s.positions[b] + s.positions[c] + s.positions[d]) / 4;
  for (Triangle t : {Triangle{a, b, c}, Triangle{a, b, d}, Triangle{a, c, d}, Triangle{b, c, d}}) {
    const Vec3 n = (s.positions[t[1]] - s.positions[t[0]]).cross(s.positions[t[2]] - s.positions[t[0]]);
    if (n.dot(s.positions[t[0]] - centre) < 0) std::swap(t[1], t[2]);
    s.triangles.push_back(t);
  }
  return s;
}

/// A Moebius strip of `segments` quads: non-orientable, every edge manifold.
inline Soup moebius(int segments = 12) {
  Soup s;
  for (int i = 0; i < segments; ++i) {
    const double u = 2 * std::numbers::pi * i / segments;
    for (int side : {-1, 1}) {
      const double w = 0.3 * side;
      s.positions.emplace_back((1 + w * std::cos(u / 2)) * std::cos(u), (1 + w * std::cos(u / 2)) * std::sin(u),
                               w * std::sin(u / 2));
    }
  }
  const auto n = static_cast<std::uint32_t>(segments);
  for (std::uint32_t i = 0; i < n; ++i) {
    std::uint32_t a = 2 * i, b = 2 * i + 1, c = 2 * ((i + 1) % n), d = 2 * ((i + 1) % n) + 1;
    if (i + 1 == n) std::swap(c, d);  // the half twist
    s.triangles.push_back({a, c, b});
    s.triangles.push_back({b, c, d});
  }
  return s;
}

/// A latitude-longitude sphere as exporters write it at a UV seam: the first meridian's
/// vertices are stored twice (columns 0 and `around`, same positions). Unwelded it is a disc
/// (one boundary loop); welded it is the closed sphere. `split` = false stores them once.
inline Soup uv_sphere(int around = 16, int rows = 8, bool split = true) {
  Soup s;
  s.positions.emplace_back(0, 0, 1);   // north pole
  s.positions.emplace_back(0, 0, -1);  // south pole
  const int columns = split ? around + 1 : around;
  for (int j = 1; j < rows; ++j) {
    const double theta = std::numbers::pi * j / rows;
    for (int i = 0; i < columns; ++i) {
      const double phi = 2 * std::numbers::pi * (i % around) / around;
      s.positions.emplace_back(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
    }
  }
  auto id = [&](int j, int i) {  // ring j in 1..rows-1, column i in 0..around
    return static_cast<std::uint32_t>(2 + (j - 1) * columns + (split ? i : i % around));
  };
  for (int i = 0; i < around; ++i) {
    s.triangles.push_back({0, id(1, i), id(1, i + 1)});
    s.triangles.push_back({1, id(rows - 1, i + 1), id(rows - 1, i)});
    for (int j = 1; j + 1 < rows; ++j) {
      s.triangles.push_back({id(j, i), id(j + 1, i), id(j + 1, i + 1)});
      s.triangles.push_back({id(j, i), id(j + 1, i + 1), id(j, i + 1)});
    }
  }
  return s;
}

}  // namespace seam::fixtures
