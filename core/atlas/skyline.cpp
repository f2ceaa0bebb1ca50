#include "core/atlas/skyline.h"

#include <algorithm>

namespace seam::core::detail {

Skyline::Skyline(double width, double height) : width_(width), height_(height) {
  segments_.push_back({0, 0, width});
}

bool Skyline::find(double w, double h, Vec2& pos, double& top) const {
  const double max_x = width_ * (1 + 1e-12);
  const double max_y = height_ * (1 + 1e-12);
  bool found = false;
  for (std::size_t i = 0; i < segments_.size(); ++i) {
    const double x = segments_[i].x;
    if (x + w > max_x) break;
    // A start to the right of the best so far must give a strictly lower top; the rectangle
    // rests at least at this segment's height, so most starts end here, and the others as
    // soon as a segment under them is too high.
    if (found && !(segments_[i].y + h < top)) continue;
    double y = 0;
    bool lower = true;
    for (std::size_t j = i; j < segments_.size() && segments_[j].x < x + w; ++j) {
      y = std::max(y, segments_[j].y);
      if (found && !(y + h < top)) {
        lower = false;
        break;
      }
    }
    if (!lower || y + h > max_y) continue;
    found = true;
    top = y + h;
    pos = Vec2(x, y);
  }
  return found;
}

void Skyline::add(const Vec2& pos, double w, double h) {
  if (!(w > 0)) return;
  const double x0 = pos.x();
  const double x1 = pos.x() + w;
  // Only the segments under [x0, x1) change; one more on each side may merge with the new
  // one. Everything outside that window stays as it is (adjacent segments differ in height).
  const auto first = std::partition_point(segments_.begin(), segments_.end(),
                                          [&](const SkylineSegment& s) { return s.x + s.w <= x0; });
  const auto last = std::partition_point(first, segments_.end(), [&](const SkylineSegment& s) { return s.x < x1; });
  const auto lo = first == segments_.begin() ? first : first - 1;
  const auto hi = last == segments_.end() ? last : last + 1;

  // The window rebuilt left to right; a piece at the height of the one before it extends it.
  std::vector<SkylineSegment> out;
  out.reserve(static_cast<std::size_t>(hi - lo) + 2);
  auto emit = [&](const SkylineSegment& s) {
    if (!out.empty() && out.back().y == s.y) {
      out.back().w = s.x + s.w - out.back().x;
    } else {
      out.push_back(s);
    }
  };
  bool inserted = false;
  const SkylineSegment raised{x0, pos.y() + h, w};
  for (auto it = lo; it != hi; ++it) {
    const SkylineSegment& s = *it;
    const double s1 = s.x + s.w;
    if (s1 <= x0 || s.x >= x1) {
      if (!inserted && s.x >= x1) {
        emit(raised);
        inserted = true;
      }
      emit(s);
      continue;
    }
    if (s.x < x0) emit({s.x, s.y, x0 - s.x});
    if (!inserted) {
      emit(raised);
      inserted = true;
    }
    if (s1 > x1) emit({x1, s.y, s1 - x1});
  }
  if (!inserted) emit(raised);

  const auto at = segments_.erase(lo, hi);
  segments_.insert(at, out.begin(), out.end());
}

}  // namespace seam::core::detail
