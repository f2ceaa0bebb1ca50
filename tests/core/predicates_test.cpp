// The exact 2D predicates of the atlas checks: orient2d against 128-bit integer arithmetic
// where the naive formula fails, and which UV vertices are one point.
#include "core/atlas/predicates.h"

#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace seam_predicates_test {

using namespace seam::core;

namespace {

__extension__ typedef __int128 Int128;  // exact products of 50-bit integers

}  // namespace

TEST_CASE("orient2d agrees with exact integer arithmetic where the naive formula fails") {
  // Integer coordinates below 2^50 are exact doubles, and their determinant fits in 128 bits.
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<std::int64_t> coord(-(std::int64_t{1} << 49), std::int64_t{1} << 49);
  std::uniform_int_distribution<std::int64_t> small(-3, 3);
  int naive_wrong = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    // Nearly collinear: c = a + k (b - a) + tiny offset.
    const std::int64_t ax = coord(rng) / 4, ay = coord(rng) / 4;
    const std::int64_t dx = coord(rng) / 8, dy = coord(rng) / 8;
    const std::int64_t cx = ax + 2 * dx + small(rng), cy = ay + 2 * dy + small(rng);
    const std::int64_t bx = ax + dx, by = ay + dy;
    const Int128 det = static_cast<Int128>(bx - ax) * (cy - ay) - static_cast<Int128>(by - ay) * (cx - ax);
    const int expected = det > 0 ? 1 : (det < 0 ? -1 : 0);
    const Vec2 a(static_cast<double>(ax), static_cast<double>(ay));
    const Vec2 b(static_cast<double>(bx), static_cast<double>(by));
    const Vec2 c(static_cast<double>(cx), static_cast<double>(cy));
    CHECK(orient2d(a, b, c) == expected);
    const double naive = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
    if ((naive > 0 ? 1 : (naive < 0 ? -1 : 0)) != expected) ++naive_wrong;
  }
  CHECK(naive_wrong > 0);  // the test reaches the exact path
  // Shewchuk's classic: points on the line y = x near (0.5, 0.5).
  CHECK(orient2d(Vec2(0.5, 0.5), Vec2(12, 12), Vec2(24, 24)) == 0);
  CHECK(orient2d(Vec2(0.5, 0.5), Vec2(12, 12), Vec2(24, std::nextafter(24.0, 25.0))) == 1);
  CHECK(orient2d(Vec2(0.5, 0.5), Vec2(12, 12), Vec2(std::nextafter(24.0, 25.0), 24)) == -1);
}

TEST_CASE("same_point_representatives: the lowest listed index at each exact point") {
  const std::vector<Vec2> uv = {Vec2(1, 2), Vec2(0, 0), Vec2(1, 2), Vec2(-0.0, 0), Vec2(1, 2 + 1e-15), Vec2(1, 2)};
  const std::vector<std::uint32_t> every = {0, 1, 2, 3, 4, 5};
  CHECK(same_point_representatives(uv, every) ==
        std::vector<std::uint32_t>{0, 1, 0, 1, 4, 0});  // -0 is 0; 1e-15 apart is apart
  CHECK(same_point_representatives(uv, {}) == every);   // nothing listed, nothing merged
  // Only the listed vertices take part; the others map to themselves.
  const std::vector<std::uint32_t> listed = {5, 2, 3};
  CHECK(same_point_representatives(uv, listed) == std::vector<std::uint32_t>{0, 1, 2, 3, 4, 2});
}

}  // namespace seam_predicates_test
