#include "core/atlas/profile_pack.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace seam::core::detail {

namespace {

// y-range of segment [a, b] within the vertical slab x0 <= x <= x1; false if it misses it.
bool segment_in_slab(const Vec2& a, const Vec2& b, double x0, double x1, double& lo, double& hi) {
  double t0 = 0;
  double t1 = 1;
  const double dx = b.x() - a.x();
  if (dx == 0) {
    if (a.x() < x0 || a.x() > x1) return false;
  } else {
    double ta = (x0 - a.x()) / dx;
    double tb = (x1 - a.x()) / dx;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  const double y0 = a.y() + t0 * (b.y() - a.y());
  const double y1 = a.y() + t1 * (b.y() - a.y());
  lo = std::min(y0, y1);
  hi = std::max(y0, y1);
  return true;
}

struct Profile {
  std::vector<double> bottom;  // per column: lowest chart point within reach, +inf if none
  std::vector<double> top;
};

// Column j of a chart placed with its left edge at margin/2 covers chart x in
// [j c - margin/2, (j+1) c - margin/2]; grown by margin/2 on each side for the horizontal margin.
Profile profile_of(const ProfileChart& chart, int k, double cell, double margin, int width) {
  Profile p{std::vector<double>(width, kInf), std::vector<double>(width, -kInf)};
  for (const auto& seg : chart.boundary) {
    const Vec2 a = turn_point(seg[0], k, chart.size);
    const Vec2 b = turn_point(seg[1], k, chart.size);
    const double xmin = std::min(a.x(), b.x());
    const double xmax = std::max(a.x(), b.x());
    const int j0 = std::max(0, static_cast<int>(std::floor(xmin / cell)) - 1);
    const int j1 = std::min(width - 1, static_cast<int>(std::floor((xmax + margin) / cell)) + 1);
    for (int j = j0; j <= j1; ++j) {
      double lo = 0;
      double hi = 0;
      if (!segment_in_slab(a, b, j * cell - margin, (j + 1) * cell, lo, hi)) continue;
      p.bottom[j] = std::min(p.bottom[j], lo);
      p.top[j] = std::max(p.top[j], hi);
    }
  }
  return p;
}

}  // namespace

Vec2 turn_point(const Vec2& p, int k, const Vec2& size) {
  switch (k & 3) {
    case 0:
      return p;
    case 1:
      return Vec2(size.y() - p.y(), p.x());
    case 2:
      return Vec2(size.x() - p.x(), size.y() - p.y());
    default:
      return Vec2(p.y(), size.x() - p.x());
  }
}

bool profile_pack_square(const std::vector<ProfileChart>& charts, const std::vector<std::size_t>& order,
                         double side, double margin, bool rotate, int columns, std::vector<ProfileSlot>& slots) {
  const double cell = side / columns;
  std::vector<double> sky(columns, 0.0);
  slots.assign(charts.size(), ProfileSlot{});
  for (std::size_t idx : order) {
    const ProfileChart& chart = charts[idx];
    double best_top = kInf;
    int best_col = -1;
    int best_turn = 0;
    double best_y = 0;
    Profile best_profile;
    for (int k = 0; k < (rotate ? 4 : 1); ++k) {
      const double w = (k & 1) ? chart.size.y() : chart.size.x();
      const int width = static_cast<int>(std::ceil((w + margin) / cell));
      if (width > columns) continue;
      Profile p = profile_of(chart, k, cell, margin, width);
      for (int col = 0; col + width <= columns; ++col) {
        double y = 0;  // the chart's lowest point rests at y + bottom >= margin/2 above the floor
        for (int j = 0; j < width; ++j) {
          if (p.bottom[j] < kInf) y = std::max(y, sky[col + j] + 0.5 * margin - p.bottom[j]);
        }
        double top = -kInf;
        for (int j = 0; j < width; ++j) top = std::max(top, p.top[j] + y);
        top += 0.5 * margin;
        if (top > side * (1 + 1e-12)) continue;
        if (top < best_top) {
          best_top = top;
          best_col = col;
          best_turn = k;
          best_y = y;
        }
      }
      if (best_turn == k && best_col >= 0) best_profile = std::move(p);
    }
    if (best_col < 0) return false;
    for (std::size_t j = 0; j < best_profile.top.size(); ++j) {
      if (best_profile.top[j] > -kInf) {
        sky[best_col + j] = std::max(sky[best_col + j], best_profile.top[j] + best_y + 0.5 * margin);
      }
    }
    slots[idx] = {best_turn, Vec2(best_col * cell + 0.5 * margin, best_y)};
  }
  return true;
}

}  // namespace seam::core::detail
