// The column-profile packer (core/atlas/profile_pack.h) on its own: quarter turns map a
// chart's rectangle onto the turned rectangle; a chart drops into another's notch (where the
// rectangles could not share the square); and on random star-shaped charts every placed
// chart stays inside the square with half a margin to spare, no two charts' sampled boundary
// points come closer than the margin along both x and y, and no boundaries cross. The oracle
// is the placed geometry itself, sampled, not the packer's columns.
#include "core/atlas/profile_pack.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <numeric>
#include <random>
#include <vector>

namespace seam_profile_pack_test {

using namespace seam::core;
using seam::core::detail::profile_pack_square;
using seam::core::detail::ProfileChart;
using seam::core::detail::ProfileSlot;
using seam::core::detail::turn_point;

namespace {

// A closed polygon as a chart in its own frame: moved so its bounding box starts at 0.
ProfileChart chart_of(std::vector<Vec2> polygon) {
  Vec2 lo = polygon.front();
  Vec2 hi = polygon.front();
  for (const Vec2& p : polygon) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  ProfileChart chart;
  chart.size = hi - lo;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    chart.boundary.push_back({polygon[i] - lo, polygon[(i + 1) % polygon.size()] - lo});
  }
  return chart;
}

// A star-shaped polygon around the origin: `n` vertices at random radii in [0.3, 1] x scale.
ProfileChart random_star(std::mt19937& rng, int n, double scale) {
  std::uniform_real_distribution<double> radius(0.3, 1.0);
  std::vector<Vec2> polygon;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * std::numbers::pi * i / n;
    const double r = scale * radius(rng);
    polygon.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  return chart_of(polygon);
}

// The chart's boundary where the slot puts it.
std::vector<std::array<Vec2, 2>> placed(const ProfileChart& chart, const ProfileSlot& slot) {
  std::vector<std::array<Vec2, 2>> out;
  for (const auto& s : chart.boundary) {
    out.push_back(
        {turn_point(s[0], slot.turn, chart.size) + slot.shift, turn_point(s[1], slot.turn, chart.size) + slot.shift});
  }
  return out;
}

double cross(const Vec2& o, const Vec2& a, const Vec2& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

// Proper crossing or touching of two segments.
bool segments_meet(const std::array<Vec2, 2>& s, const std::array<Vec2, 2>& t) {
  const double d1 = cross(t[0], t[1], s[0]);
  const double d2 = cross(t[0], t[1], s[1]);
  const double d3 = cross(s[0], s[1], t[0]);
  const double d4 = cross(s[0], s[1], t[1]);
  return ((d1 > 0) != (d2 > 0) || d1 == 0 || d2 == 0) && ((d3 > 0) != (d4 > 0) || d3 == 0 || d4 == 0);
}

std::vector<Vec2> samples(const std::vector<std::array<Vec2, 2>>& boundary, int per_segment) {
  std::vector<Vec2> out;
  for (const auto& s : boundary) {
    for (int i = 0; i < per_segment; ++i) out.push_back(s[0] + (s[1] - s[0]) * (static_cast<double>(i) / per_segment));
  }
  return out;
}

}  // namespace

TEST_CASE("turn_point: a quarter turn maps the chart's rectangle onto the turned one, four turns are none") {
  const Vec2 size(3, 1);
  CHECK(turn_point(Vec2(0, 0), 1, size) == Vec2(1, 0));
  CHECK(turn_point(Vec2(3, 0), 1, size) == Vec2(1, 3));
  CHECK(turn_point(Vec2(3, 1), 2, size) == Vec2(0, 0));
  CHECK(turn_point(Vec2(0, 1), 3, size) == Vec2(1, 3));
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  for (int trial = 0; trial < 100; ++trial) {
    const Vec2 p(3 * u(rng), u(rng));
    Vec2 q = p;
    Vec2 s = size;
    for (int k = 1; k <= 4; ++k) {
      q = turn_point(q, 1, s);
      s = Vec2(s.y(), s.x());
      // In the turned rectangle, and the same as k quarter turns at once.
      CHECK(q.x() >= 0);
      CHECK(q.y() >= 0);
      CHECK(q.x() <= s.x());
      CHECK(q.y() <= s.y());
      CHECK((q - turn_point(p, k, size)).norm() < 1e-12);
    }
    CHECK((q - p).norm() < 1e-12);
  }
}

TEST_CASE("profile packing: a block drops into a U's notch, where their rectangles could not share the square") {
  // A 3 x 3 U with a 1 x 2 notch open at the top, and a 0.8 x 1.5 block: the rectangles' areas
  // (9 + 1.2) exceed the 3 x 3.1 square's, so only nesting fits them.
  const ProfileChart u = chart_of({{0, 0}, {3, 0}, {3, 3}, {2, 3}, {2, 1}, {1, 1}, {1, 3}, {0, 3}});
  const ProfileChart block = chart_of({{0, 0}, {0.8, 0}, {0.8, 1.5}, {0, 1.5}});
  const std::vector<ProfileChart> charts{u, block};
  std::vector<ProfileSlot> slots;
  const double margin = 0.05;
  REQUIRE(profile_pack_square(charts, {0, 1}, 3.1, margin, false, 124, slots));
  // The block sits in the notch: x within [1, 2], resting on the notch's floor plus the margin.
  CHECK(slots[1].shift.x() >= slots[0].shift.x() + 1 + margin - 1e-9);
  CHECK(slots[1].shift.x() + 0.8 <= slots[0].shift.x() + 2 - margin + 1e-9);
  CHECK(slots[1].shift.y() == doctest::Approx(slots[0].shift.y() + 1 + margin));
  // Too small a square for the U itself: refused.
  CHECK_FALSE(profile_pack_square(charts, {0, 1}, 2.9, margin, false, 124, slots));
}

TEST_CASE("profile packing: random charts stay inside the square, a margin apart, and never cross") {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 12; ++trial) {
    CAPTURE(trial);
    std::vector<ProfileChart> charts;
    double area = 0;
    const int n = 3 + trial % 6;
    for (int c = 0; c < n; ++c) {
      charts.push_back(random_star(rng, 5 + c % 7, 0.5 + 0.1 * c));
      area += charts.back().size.prod();
    }
    const bool rotate = trial % 2 == 1;
    const double margin = 0.02 + 0.01 * (trial % 3);
    std::vector<std::size_t> order(charts.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    // Grow the square from the area until everything fits.
    double side = std::sqrt(area);
    std::vector<ProfileSlot> slots;
    while (!profile_pack_square(charts, order, side, margin, rotate, 256, slots)) side *= 1.05;
    std::vector<std::vector<std::array<Vec2, 2>>> boundary;
    for (std::size_t c = 0; c < charts.size(); ++c) {
      boundary.push_back(placed(charts[c], slots[c]));
      if (!rotate) CHECK(slots[c].turn == 0);
      for (const auto& s : boundary.back()) {
        for (const Vec2& p : s) {
          CHECK(p.x() >= 0.5 * margin - 1e-9);
          CHECK(p.y() >= 0.5 * margin - 1e-9);
          CHECK(p.x() <= side - 0.5 * margin + 1e-9);
          CHECK(p.y() <= side - 0.5 * margin + 1e-9);
        }
      }
    }
    for (std::size_t a = 0; a < charts.size(); ++a) {
      const std::vector<Vec2> pa = samples(boundary[a], 16);
      for (std::size_t b = a + 1; b < charts.size(); ++b) {
        const std::vector<Vec2> pb = samples(boundary[b], 16);
        double closest = kInf;  // the least L-infinity distance between sampled points
        for (const Vec2& p : pa) {
          for (const Vec2& q : pb) closest = std::min(closest, (p - q).cwiseAbs().maxCoeff());
        }
        CHECK(closest >= margin - 1e-9);
        bool meet = false;
        for (const auto& s : boundary[a]) {
          for (const auto& t : boundary[b]) meet = meet || segments_meet(s, t);
        }
        CHECK_FALSE(meet);
      }
    }
    // Deterministic.
    std::vector<ProfileSlot> again;
    REQUIRE(profile_pack_square(charts, order, side, margin, rotate, 256, again));
    for (std::size_t c = 0; c < charts.size(); ++c) {
      CHECK(again[c].turn == slots[c].turn);
      CHECK(again[c].shift == slots[c].shift);
    }
  }
}

}  // namespace seam_profile_pack_test
