// The rectangle packer's skyline (core/atlas/skyline.h), indexed by height, against the
// plain scan it replaced (every segment start tried, the whole skyline rebuilt per rectangle):
// the same positions and the same segments, bit for bit, on random sequences with exact ties
// (widths and heights from a few values) and without; and the placed rectangles never overlap
// and stay inside the square.
#include "core/atlas/skyline.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <random>
#include <vector>

namespace seam_skyline_test {

using namespace seam::core;
using seam::core::detail::Skyline;
using seam::core::detail::SkylineSegment;

namespace {

// The oracle: every segment start is a candidate; the skyline is rebuilt after each rectangle.
class PlainSkyline {
 public:
  PlainSkyline(double width, double height) : width_(width), height_(height) { segments_.push_back({0, 0, width}); }

  bool find(double w, double h, Vec2& pos, double& top) const {
    bool found = false;
    for (std::size_t i = 0; i < segments_.size(); ++i) {
      const double x = segments_[i].x;
      if (x + w > width_ * (1 + 1e-12)) break;
      double y = 0;
      for (std::size_t j = i; j < segments_.size() && segments_[j].x < x + w; ++j) y = std::max(y, segments_[j].y);
      if (y + h > height_ * (1 + 1e-12)) continue;
      if (!found || y + h < top || (y + h == top && x < pos.x())) {
        found = true;
        top = y + h;
        pos = Vec2(x, y);
      }
    }
    return found;
  }

  void add(const Vec2& pos, double w, double h) {
    const double x0 = pos.x();
    const double x1 = pos.x() + w;
    std::vector<SkylineSegment> out;
    bool inserted = false;
    for (const SkylineSegment& s : segments_) {
      const double s1 = s.x + s.w;
      if (s1 <= x0 || s.x >= x1) {
        if (!inserted && s.x >= x1) {
          out.push_back({x0, pos.y() + h, w});
          inserted = true;
        }
        out.push_back(s);
        continue;
      }
      if (s.x < x0) out.push_back({s.x, s.y, x0 - s.x});
      if (!inserted) {
        out.push_back({x0, pos.y() + h, w});
        inserted = true;
      }
      if (s1 > x1) out.push_back({x1, s.y, s1 - x1});
    }
    if (!inserted) out.push_back({x0, pos.y() + h, w});
    segments_.clear();
    for (const SkylineSegment& s : out) {
      if (!segments_.empty() && segments_.back().y == s.y) {
        segments_.back().w = s.x + s.w - segments_.back().x;
      } else {
        segments_.push_back(s);
      }
    }
  }

  const std::vector<SkylineSegment>& segments() const { return segments_; }

 private:
  double width_;
  double height_;
  std::vector<SkylineSegment> segments_;
};

struct Rect {
  double x0, y0, x1, y1;
};

bool same_segments(const std::vector<SkylineSegment>& a, const std::vector<SkylineSegment>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].x != b[i].x || a[i].y != b[i].y || a[i].w != b[i].w) return false;
  }
  return true;
}

// Packs `count` rectangles drawn by `draw` into both skylines (each also tried turned, as the
// packer does) and checks that they agree at every step; returns the rectangles placed.
template <class Draw>
std::vector<Rect> pack_both(double side, int count, std::mt19937& rng, Draw&& draw) {
  Skyline fast(side, side);
  PlainSkyline plain(side, side);
  std::vector<Rect> placed;
  for (int i = 0; i < count; ++i) {
    const auto [w, h] = draw(rng);
    for (const auto& [a, b] : {std::pair{w, h}, std::pair{h, w}}) {
      Vec2 p1 = Vec2::Zero(), p2 = Vec2::Zero();
      double t1 = 0, t2 = 0;
      const bool f1 = fast.find(a, b, p1, t1);
      const bool f2 = plain.find(a, b, p2, t2);
      REQUIRE(f1 == f2);
      if (f1) {
        REQUIRE(p1.x() == p2.x());
        REQUIRE(p1.y() == p2.y());
        REQUIRE(t1 == t2);
      }
    }
    Vec2 pos = Vec2::Zero();
    double top = 0;
    if (!fast.find(w, h, pos, top)) continue;
    fast.add(pos, w, h);
    plain.add(pos, w, h);
    REQUIRE(same_segments(fast.segments(), plain.segments()));
    placed.push_back({pos.x(), pos.y(), pos.x() + w, pos.y() + h});
  }
  return placed;
}

void check_layout(const std::vector<Rect>& placed, double side) {
  for (std::size_t i = 0; i < placed.size(); ++i) {
    const Rect& a = placed[i];
    CHECK(a.x0 >= 0);
    CHECK(a.y0 >= 0);
    CHECK(a.x1 <= side * (1 + 1e-9));
    CHECK(a.y1 <= side * (1 + 1e-9));
    for (std::size_t j = i + 1; j < placed.size(); ++j) {
      const Rect& b = placed[j];
      const bool apart = a.x1 <= b.x0 || b.x1 <= a.x0 || a.y1 <= b.y0 || b.y1 <= a.y0;
      if (!apart) FAIL_CHECK("rectangles " << i << " and " << j << " overlap");
    }
  }
}

}  // namespace

TEST_CASE("skyline: an empty square takes a rectangle at its lower left corner") {
  Skyline sky(10, 10);
  Vec2 pos = Vec2::Constant(-1);
  double top = 0;
  REQUIRE(sky.find(4, 3, pos, top));
  CHECK(pos == Vec2(0, 0));
  CHECK(top == 3);
  sky.add(pos, 4, 3);
  REQUIRE(sky.segments().size() == 2);
  CHECK(sky.segments()[0].y == 3);
  CHECK(sky.segments()[1].x == 4);
  // The next one goes beside it (lower top), a too-wide one on top, a too-tall one nowhere.
  REQUIRE(sky.find(6, 5, pos, top));
  CHECK(pos == Vec2(4, 0));
  CHECK_FALSE(sky.find(11, 1, pos, top));
  CHECK_FALSE(sky.find(1, 11, pos, top));
  sky.add(pos, 6, 5);
  REQUIRE(sky.find(10, 2, pos, top));
  CHECK(pos == Vec2(0, 5));
  // Filling a step level with its neighbour merges the two segments.
  REQUIRE(sky.find(4, 2, pos, top));
  CHECK(pos == Vec2(0, 3));
  sky.add(pos, 4, 2);
  REQUIRE(sky.segments().size() == 1);
  CHECK(sky.segments()[0].y == 5);
  CHECK(sky.segments()[0].w == 10);
}

TEST_CASE("skyline: a rectangle without width changes nothing") {
  Skyline sky(4, 4);
  sky.add(Vec2(1, 0), 0, 2);
  REQUIRE(sky.segments().size() == 1);
  CHECK(sky.segments()[0].y == 0);
}

TEST_CASE("skyline: the same positions and segments as the plain scan, with exact ties") {
  std::mt19937 rng(7);
  for (int round = 0; round < 40; ++round) {
    const double side = 20 + round;
    // Few distinct sizes: equal heights merge, equal tops tie, and the leftmost must win.
    const std::vector<double> sizes = {0.5, 1, 1.5, 2, 3, 4.25};
    std::uniform_int_distribution<std::size_t> pick(0, sizes.size() - 1);
    const auto placed = pack_both(side, 400, rng, [&](std::mt19937& r) {
      return std::pair{sizes[pick(r)], sizes[pick(r)]};
    });
    CHECK(placed.size() > 20);
    check_layout(placed, side);
  }
}

TEST_CASE("skyline: the same positions and segments as the plain scan, real-valued sizes") {
  std::mt19937 rng(11);
  for (int round = 0; round < 40; ++round) {
    const double side = 1.0 + 0.01 * round;
    std::uniform_real_distribution<double> size(0.001, 0.2);
    std::uniform_real_distribution<double> tall(0.001, 0.6);
    const auto placed = pack_both(side, 300, rng, [&](std::mt19937& r) {
      const double a = size(r);
      return std::pair{a, round % 3 == 0 ? tall(r) : a * size(r) * 10};
    });
    CHECK(placed.size() > 10);
    check_layout(placed, side);
  }
}

TEST_CASE("skyline: thousands of equal squares fill the square without overlap") {
  std::mt19937 rng(3);
  const auto placed = pack_both(64, 4096, rng, [](std::mt19937&) { return std::pair{1.0, 1.0}; });
  CHECK(placed.size() == 4096);  // 64 x 64 unit squares tile it exactly
  check_layout(placed, 64);
}

}  // namespace seam_skyline_test
