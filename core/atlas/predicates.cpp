#include "core/atlas/predicates.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

namespace seam::core {

namespace {

struct Pair {
  double hi;
  double lo;
};

// Knuth's two-sum: hi + lo == a + b exactly.
Pair two_sum(double a, double b) {
  const double x = a + b;
  const double bv = x - a;
  const double av = x - bv;
  return {x, (a - av) + (b - bv)};
}

// hi + lo == a * b exactly (the FMA recovers the rounding error).
Pair two_product(double a, double b) {
  const double x = a * b;
  return {x, std::fma(a, b, -x)};
}

// Shewchuk's Grow-Expansion: adds b to the nonoverlapping expansion e[0..n) (increasing
// magnitude), keeping it nonoverlapping; zero components are dropped.
int grow(std::array<double, 32>& e, int n, double b) {
  double q = b;
  int out = 0;
  for (int i = 0; i < n; ++i) {
    const Pair s = two_sum(q, e[i]);
    q = s.hi;
    if (s.lo != 0) e[out++] = s.lo;
  }
  if (q != 0) e[out++] = q;
  return out;
}

int exact_orient(const Vec2& a, const Vec2& b, const Vec2& c) {
  // (bx - ax)(cy - ay) - (by - ay)(cx - ax), each difference an exact two-term expansion.
  const Pair d[4] = {two_sum(b.x(), -a.x()), two_sum(c.y(), -a.y()), two_sum(b.y(), -a.y()),
                     two_sum(c.x(), -a.x())};
  std::array<double, 32> e{};
  int n = 0;
  for (int sign : {1, -1}) {
    const Pair& p = sign > 0 ? d[0] : d[2];
    const Pair& q = sign > 0 ? d[1] : d[3];
    for (double x : {p.hi, p.lo}) {
      for (double y : {q.hi, q.lo}) {
        const Pair pr = two_product(x, y);
        n = grow(e, n, sign * pr.lo);
        n = grow(e, n, sign * pr.hi);
      }
    }
  }
  // The largest-magnitude component of a nonoverlapping expansion carries its sign.
  if (n == 0) return 0;
  return e[n - 1] > 0 ? 1 : -1;
}

}  // namespace

int orient2d(const Vec2& a, const Vec2& b, const Vec2& c) {
  const double left = (b.x() - a.x()) * (c.y() - a.y());
  const double right = (b.y() - a.y()) * (c.x() - a.x());
  const double det = left - right;
  const double bound = 3.3306690738754716e-16 * (std::abs(left) + std::abs(right));
  if (det > bound) return 1;
  if (-det > bound) return -1;
  return exact_orient(a, b, c);
}

std::vector<std::uint32_t> same_point_representatives(std::span<const Vec2> uv,
                                                      std::span<const std::uint32_t> vertices) {
  std::vector<std::uint32_t> out(uv.size());
  std::iota(out.begin(), out.end(), std::uint32_t{0});
  std::vector<std::uint32_t> order(vertices.begin(), vertices.end());
  const auto before = [&](std::uint32_t a, std::uint32_t b) {
    return uv[a].x() != uv[b].x() ? uv[a].x() < uv[b].x() : uv[a].y() < uv[b].y();
  };
  std::sort(order.begin(), order.end(),
            [&](std::uint32_t a, std::uint32_t b) { return before(a, b) || (!before(b, a) && a < b); });
  for (std::size_t i = 1; i < order.size(); ++i) {
    if (uv[order[i]] == uv[order[i - 1]]) out[order[i]] = out[order[i - 1]];
  }
  return out;
}

}  // namespace seam::core
