#include "core/mesh/vertex_order.h"

#include <algorithm>
#include <cmath>

#include "core/mesh/radix_sort.h"
#include "core/mesh/small_sort.h"

namespace seam::core {

namespace {

// Spreads the low 21 bits of x so that bit i lands on bit 3i.
std::uint64_t spread_bits(std::uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffull;
  x = (x | x << 16) & 0x1f0000ff0000ffull;
  x = (x | x << 8) & 0x100f00f00f00f00full;
  x = (x | x << 4) & 0x10c30c30c30c30c3ull;
  x = (x | x << 2) & 0x1249249249249249ull;
  return x;
}

}  // namespace

std::vector<std::uint32_t> spatial_order(std::span<const Vec3> positions) {
  const std::size_t n = positions.size();
  if (n == 0) return {};
  Vec3 lo = positions[0];
  Vec3 hi = positions[0];
  for (const Vec3& p : positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double extent = std::max((hi - lo).maxCoeff(), 1e-300);
  const double scale = static_cast<double>((1u << 21) - 1) / extent;
  struct Coded {
    std::uint64_t code;
    std::uint32_t index;
  };
  std::vector<Coded> coded(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    const Vec3 q = (positions[i] - lo) * scale;
    coded[i] = {spread_bits(static_cast<std::uint64_t>(q.x())) | spread_bits(static_cast<std::uint64_t>(q.y())) << 1 |
                    spread_bits(static_cast<std::uint64_t>(q.z())) << 2,
                i};
  }
  // A stable radix sort by code leaves equal codes in index order; only those runs (vertices
  // closer than one grid step) need the (x, y, z, index) tie-break, which sorts them alike.
  detail::radix_sort(coded, 63, [](const Coded& c) { return c.code; });
  std::vector<std::uint32_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = coded[i].index;
  for (std::size_t begin = 0; begin < n;) {
    std::size_t end = begin + 1;
    while (end < n && coded[end].code == coded[begin].code) ++end;
    if (end - begin > 1) {
      std::sort(order.begin() + static_cast<std::ptrdiff_t>(begin), order.begin() + static_cast<std::ptrdiff_t>(end),
                [&](std::uint32_t a, std::uint32_t b) {
                  const Vec3& p = positions[a];
                  const Vec3& q = positions[b];
                  if (p.x() != q.x()) return p.x() < q.x();
                  if (p.y() != q.y()) return p.y() < q.y();
                  if (p.z() != q.z()) return p.z() < q.z();
                  return a < b;
                });
    }
    begin = end;
  }
  return order;
}

std::vector<std::uint32_t> sort_triangles(std::vector<Triangle>& triangles, std::size_t num_vertices) {
  // Buckets by t[0]: stable, so each bucket holds its triangles in index order, and only the
  // (t[1], t[2]) order inside a bucket (a few triangles per vertex) is left to sort. The
  // bucketed records carry their triangle, so the sorts and the write-back read memory in
  // order instead of gathering triangles by index.
  struct Item {
    std::uint32_t b, c, index;
  };
  const auto less = [](const Item& x, const Item& y) { return x.b != y.b ? x.b < y.b : x.c < y.c; };
  std::vector<std::uint32_t> start(num_vertices + 1, 0);
  for (const Triangle& t : triangles) ++start[t[0] + 1];
  for (std::size_t v = 0; v < num_vertices; ++v) start[v + 1] += start[v];
  std::vector<Item> items(triangles.size());
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::uint32_t f = 0; f < triangles.size(); ++f) items[fill[triangles[f][0]]++] = {triangles[f][1], triangles[f][2], f};
  }
  std::vector<std::uint32_t> order(triangles.size());
  for (std::uint32_t v = 0; v < num_vertices; ++v) {
    stable_sort_small(items.begin() + start[v], items.begin() + start[v + 1], less);
    for (std::uint32_t i = start[v]; i < start[v + 1]; ++i) {
      triangles[i] = {v, items[i].b, items[i].c};
      order[i] = items[i].index;
    }
  }
  return order;
}

}  // namespace seam::core
