#include "core/mesh/split_pinched.h"

#include <algorithm>

#include "core/mesh/small_sort.h"
#include "core/seam/tree_util.h"

namespace seam::core {

PinchSplit split_pinched_vertices(std::span<const Vec3> positions, std::span<const Triangle> triangles) {
  const std::size_t n = positions.size();
  const std::size_t nf = triangles.size();
  PinchSplit out;
  out.positions.assign(positions.begin(), positions.end());
  out.triangles.assign(triangles.begin(), triangles.end());
  out.source.resize(n);
  for (std::uint32_t v = 0; v < n; ++v) out.source[v] = v;

  auto valid = [&](const Triangle& t) {
    return t[0] < n && t[1] < n && t[2] < n && t[0] != t[1] && t[1] != t[2] && t[0] != t[2];
  };
  // Corners 3t + k. Triangles sharing edge {a, b} join their corners at a and at b.
  struct EdgeUse {
    std::uint64_t key;
    std::uint32_t corner_low;   // the corner at min(a, b)
    std::uint32_t corner_high;  // the corner at max(a, b)
  };
  std::vector<EdgeUse> uses;
  uses.reserve(3 * nf);
  for (std::uint32_t t = 0; t < nf; ++t) {
    const Triangle& tri = triangles[t];
    if (!valid(tri)) continue;
    for (std::uint32_t k = 0; k < 3; ++k) {
      const std::uint32_t j = (k + 1) % 3;
      std::uint32_t ca = 3 * t + k, cb = 3 * t + j;
      std::uint32_t a = tri[k], b = tri[j];
      if (a > b) std::swap(a, b), std::swap(ca, cb);
      uses.push_back({(std::uint64_t{a} << 32) | b, ca, cb});
    }
  }
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) {
    return std::tie(x.key, x.corner_low) < std::tie(y.key, y.corner_low);
  });
  detail::UnionFind fans(3 * nf);
  for (std::size_t i = 1; i < uses.size(); ++i) {
    if (uses[i].key != uses[i - 1].key) continue;
    fans.unite(uses[i].corner_low, uses[i - 1].corner_low);
    fans.unite(uses[i].corner_high, uses[i - 1].corner_high);
  }

  std::vector<std::uint32_t> roots(3 * nf, kNoFan);
  for (std::uint32_t t = 0; t < nf; ++t) {
    if (!valid(triangles[t])) continue;
    for (std::uint32_t k = 0; k < 3; ++k) roots[3 * t + k] = fans.find(3 * t + k);
  }
  out.pinched_vertices = split_corner_fans(out.positions, out.source, out.triangles, roots).size();
  return out;
}

namespace {

// A corner at some vertex, tagged with its fan.
struct FanCorner {
  std::uint32_t root;    // the fan (its lowest corner)
  std::uint32_t corner;  // 3 * triangle + k
};

// Per vertex v, corners[start[v], start[v + 1]) are v's corners sorted by (fan root, corner):
// a counting sort by vertex, which keeps the corners in order, then a stable sort by root
// inside each vertex's few corners.
struct CornersByVertex {
  std::vector<std::uint32_t> start;
  std::vector<FanCorner> corners;
};

CornersByVertex corners_by_vertex(std::size_t nv, std::span<const Triangle> triangles,
                                  std::span<const std::uint32_t> fan_root) {
  CornersByVertex g;
  g.start.assign(nv + 1, 0);
  for (std::uint32_t c = 0; c < fan_root.size(); ++c) {
    if (fan_root[c] != kNoFan) ++g.start[triangles[c / 3][c % 3] + 1];
  }
  for (std::size_t v = 0; v < nv; ++v) g.start[v + 1] += g.start[v];
  g.corners.resize(g.start[nv]);
  std::vector<std::uint32_t> fill(g.start.begin(), g.start.end() - 1);
  for (std::uint32_t c = 0; c < fan_root.size(); ++c) {
    if (fan_root[c] != kNoFan) g.corners[fill[triangles[c / 3][c % 3]]++] = {fan_root[c], c};
  }
  const auto by_root = [](const FanCorner& x, const FanCorner& y) { return x.root < y.root; };
  for (std::size_t v = 0; v < nv; ++v) {
    stable_sort_small(g.corners.begin() + g.start[v], g.corners.begin() + g.start[v + 1], by_root);
  }
  return g;
}

}  // namespace

std::vector<std::uint32_t> split_corner_fans(std::vector<Vec3>& positions, std::vector<std::uint32_t>& source,
                                             std::vector<Triangle>& triangles, std::span<const std::uint32_t> fan_root) {
  const std::size_t nv = positions.size();
  const CornersByVertex g = corners_by_vertex(nv, triangles, fan_root);
  std::vector<std::uint32_t> split;
  for (std::uint32_t v = 0; v < nv; ++v) {
    if (g.start[v] == g.start[v + 1]) continue;
    const std::uint32_t first_fan = g.corners[g.start[v]].root;
    std::uint32_t fan = first_fan;
    std::uint32_t copy = v;
    for (std::uint32_t i = g.start[v]; i < g.start[v + 1]; ++i) {
      const auto [root, corner] = g.corners[i];
      if (root != fan) {
        fan = root;
        copy = static_cast<std::uint32_t>(positions.size());
        positions.push_back(positions[v]);
        source.push_back(source[v]);
      }
      if (fan != first_fan) triangles[corner / 3][corner % 3] = copy;
    }
    if (copy != v) split.push_back(v);
  }
  return split;
}

}  // namespace seam::core
