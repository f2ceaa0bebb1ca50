// Independent oracles for the atlas tests: rasterize a UV layout at pixel centres and count
// how often each sample is covered (plain double barycentric tests, no shared code with
// core/atlas).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "core/mesh/types.h"

namespace seam::atlas_test {

struct RasterCount {
  double sample_area = 0;       ///< area of one sample cell
  std::size_t covered = 0;      ///< samples inside at least one triangle
  std::size_t twice = 0;        ///< samples inside two or more triangles
  double pair_weighted = 0;     ///< sum over samples of k(k-1)/2 (k = covering triangles)
};

/// Samples the bounding box of `uv` on a res x res grid of cell centres; a sample counts for a
/// triangle when it is strictly inside (all three edge functions of one sign, none zero).
inline RasterCount rasterize(std::span<const core::Vec2> uv, std::span<const core::Triangle> triangles, int res) {
  core::Vec2 lo(1e300, 1e300);
  core::Vec2 hi(-1e300, -1e300);
  for (const core::Triangle& t : triangles) {
    for (std::uint32_t v : t) {
      lo = lo.cwiseMin(uv[v]);
      hi = hi.cwiseMax(uv[v]);
    }
  }
  const double w = (hi.x() - lo.x()) / res;
  const double h = (hi.y() - lo.y()) / res;
  std::vector<std::uint16_t> count(static_cast<std::size_t>(res) * res, 0);
  for (const core::Triangle& t : triangles) {
    const core::Vec2 a = uv[t[0]];
    const core::Vec2 b = uv[t[1]];
    const core::Vec2 c = uv[t[2]];
    const double orient = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
    if (orient == 0) continue;
    const int x0 = std::max(0, static_cast<int>((std::min({a.x(), b.x(), c.x()}) - lo.x()) / w) - 1);
    const int x1 = std::min(res - 1, static_cast<int>((std::max({a.x(), b.x(), c.x()}) - lo.x()) / w) + 1);
    const int y0 = std::max(0, static_cast<int>((std::min({a.y(), b.y(), c.y()}) - lo.y()) / h) - 1);
    const int y1 = std::min(res - 1, static_cast<int>((std::max({a.y(), b.y(), c.y()}) - lo.y()) / h) + 1);
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const core::Vec2 p(lo.x() + (x + 0.5) * w, lo.y() + (y + 0.5) * h);
        auto edge = [&](const core::Vec2& s, const core::Vec2& e) {
          return (e.x() - s.x()) * (p.y() - s.y()) - (e.y() - s.y()) * (p.x() - s.x());
        };
        const double e0 = edge(a, b);
        const double e1 = edge(b, c);
        const double e2 = edge(c, a);
        const bool inside = orient > 0 ? (e0 > 0 && e1 > 0 && e2 > 0) : (e0 < 0 && e1 < 0 && e2 < 0);
        if (inside) ++count[static_cast<std::size_t>(y) * res + x];
      }
    }
  }
  RasterCount r;
  r.sample_area = w * h;
  for (std::uint16_t k : count) {
    if (k >= 1) ++r.covered;
    if (k >= 2) ++r.twice;
    r.pair_weighted += 0.5 * k * (k - 1);
  }
  return r;
}

}  // namespace seam::atlas_test
