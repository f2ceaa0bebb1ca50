#include "core/mesh/vertex_order.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <utility>

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

// Sorts `order` (initially 0..n-1) stably by code[order[i]]: an LSD radix sort on (code, index)
// pairs, 8 passes of 8 bits, skipping passes whose digit is the same for every vertex (the top
// bits of a 63-bit code, say). O(n) time against std::sort's O(n log n) indirect comparisons.
void radix_sort_by_code(std::vector<std::uint32_t>& order, const std::vector<std::uint64_t>& code) {
  struct Item {
    std::uint64_t code;
    std::uint32_t index;
  };
  const std::size_t n = order.size();
  std::vector<Item> items(n), scratch(n);
  std::vector<std::array<std::uint32_t, 256>> count(8);
  for (auto& c : count) c.fill(0);
  for (std::size_t i = 0; i < n; ++i) {
    items[i] = {code[order[i]], order[i]};
    for (unsigned d = 0; d < 8; ++d) ++count[d][(items[i].code >> (8 * d)) & 0xffu];
  }
  for (unsigned d = 0; d < 8; ++d) {
    if (count[d][(items[0].code >> (8 * d)) & 0xffu] == n) continue;
    std::uint32_t sum = 0;
    for (std::uint32_t& c : count[d]) sum += std::exchange(c, sum);
    for (const Item& item : items) scratch[count[d][(item.code >> (8 * d)) & 0xffu]++] = item;
    items.swap(scratch);
  }
  for (std::size_t i = 0; i < n; ++i) order[i] = items[i].index;
}

}  // namespace

std::vector<std::uint32_t> spatial_order(std::span<const Vec3> positions) {
  const std::size_t n = positions.size();
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  if (n == 0) return order;
  Vec3 lo = positions[0];
  Vec3 hi = positions[0];
  for (const Vec3& p : positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double extent = std::max((hi - lo).maxCoeff(), 1e-300);
  const double scale = static_cast<double>((1u << 21) - 1) / extent;
  std::vector<std::uint64_t> code(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 q = (positions[i] - lo) * scale;
    code[i] = spread_bits(static_cast<std::uint64_t>(q.x())) | spread_bits(static_cast<std::uint64_t>(q.y())) << 1 |
              spread_bits(static_cast<std::uint64_t>(q.z())) << 2;
  }
  // A stable radix sort by code leaves equal codes in index order; only those runs (vertices
  // closer than one grid step) need the (x, y, z, index) tie-break, which sorts them alike.
  radix_sort_by_code(order, code);
  for (std::size_t begin = 0; begin < n;) {
    std::size_t end = begin + 1;
    while (end < n && code[order[end]] == code[order[begin]]) ++end;
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

}  // namespace seam::core
