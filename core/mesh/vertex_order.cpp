#include "core/mesh/vertex_order.h"

#include <algorithm>
#include <cmath>
#include <numeric>

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
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    if (code[a] != code[b]) return code[a] < code[b];
    const Vec3& p = positions[a];
    const Vec3& q = positions[b];
    if (p.x() != q.x()) return p.x() < q.x();
    if (p.y() != q.y()) return p.y() < q.y();
    if (p.z() != q.z()) return p.z() < q.z();
    return a < b;
  });
  return order;
}

}  // namespace seam::core
