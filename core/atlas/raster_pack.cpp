#include "core/atlas/raster_pack.h"

#include <algorithm>
#include <array>
#include <bit>
#include <climits>
#include <cmath>
#include <cstdint>
#include <tuple>

namespace seam::core::detail {

namespace {

// A chart's cells at one angle, grown by the half margin: rows of 64-bit words, bit x of row
// y is cell (x, y). Cell (0, 0)'s lower-left corner is `origin` in the rotated chart's frame.
struct Mask {
  int w = 0;
  int h = 0;
  int words = 0;
  std::vector<std::uint64_t> bits;
  std::vector<std::array<int, 2>> span;    // per row: first and last non-zero word (first > last: none)
  std::vector<std::array<int, 2>> probes;  // a few set cells, tested before the rows
  Vec2 origin = Vec2::Zero();
  Vec2 lo = Vec2::Zero();  // the rotated chart's bounding box
  Vec2 hi = Vec2::Zero();
};

// Marks the cells of a w x h byte grid (unit cells) that the closed triangle touches. Row by
// row: the triangle's part within the row's slab is convex, so it touches exactly the cells
// its x-extent meets; the extent comes from the edges clipped to the slab. Degenerate
// triangles (segments) are handled alike.
void mark_triangle(const std::array<Vec2, 3>& t, int w, int h, std::vector<std::uint8_t>& cells) {
  constexpr double kEps = 1e-9;
  const Vec2 lo = t[0].cwiseMin(t[1]).cwiseMin(t[2]);
  const Vec2 hi = t[0].cwiseMax(t[1]).cwiseMax(t[2]);
  const int j0 = std::clamp(static_cast<int>(std::floor(lo.y() - kEps)), 0, h - 1);
  const int j1 = std::clamp(static_cast<int>(std::floor(hi.y() + kEps)), 0, h - 1);
  for (int j = j0; j <= j1; ++j) {
    double x_lo = std::numeric_limits<double>::infinity();
    double x_hi = -x_lo;
    for (int k = 0; k < 3; ++k) {
      const Vec2& a = t[k];
      const Vec2& b = t[(k + 1) % 3];
      const double y0 = std::max(std::min(a.y(), b.y()), j - kEps);
      const double y1 = std::min(std::max(a.y(), b.y()), j + 1 + kEps);
      if (y0 > y1) continue;
      for (double y : {y0, y1}) {
        const double x = a.y() == b.y() ? a.x() : a.x() + (b.x() - a.x()) * std::clamp((y - a.y()) / (b.y() - a.y()), 0.0, 1.0);
        x_lo = std::min({x_lo, x, a.y() == b.y() ? b.x() : x});
        x_hi = std::max({x_hi, x, a.y() == b.y() ? b.x() : x});
      }
    }
    if (x_lo > x_hi) continue;
    const int i0 = std::clamp(static_cast<int>(std::floor(x_lo - kEps)), 0, w - 1);
    const int i1 = std::clamp(static_cast<int>(std::floor(x_hi + kEps)), 0, w - 1);
    std::fill_n(cells.begin() + static_cast<std::ptrdiff_t>(j) * w + i0, i1 - i0 + 1, 1);
  }
}

// One line grown by g: out[k * out_step] (k < n + 2g) is set when some in[k' * in_step] with
// k - 2g <= k' <= k (k' < n) is.
void grow_line(const std::uint8_t* in, std::size_t in_step, int n, std::uint8_t* out, std::size_t out_step, int g) {
  int last = INT_MIN / 2;
  for (int k = 0; k < n + 2 * g; ++k) {
    if (k < n && in[k * in_step]) last = k;
    out[k * out_step] = last >= k - 2 * g;
  }
}

// Cells grown by g in every direction (square neighbourhood): out is (w + 2g) x (h + 2g) and
// out(x, y) is set when some in(x', y') has x - 2g <= x' <= x and y - 2g <= y' <= y.
std::vector<std::uint8_t> grow_cells(const std::vector<std::uint8_t>& in, int w, int h, int g) {
  const std::size_t ow = w + 2 * g;
  std::vector<std::uint8_t> rows(h * ow, 0);
  for (int y = 0; y < h; ++y) grow_line(&in[y * std::size_t(w)], 1, w, &rows[y * ow], 1, g);
  std::vector<std::uint8_t> out((h + 2 * g) * ow, 0);
  for (std::size_t x = 0; x < ow; ++x) grow_line(&rows[x], ow, h, &out[x], ow, g);
  return out;
}

// The words, row spans and probes of a grown byte grid.
void fill_words(const std::vector<std::uint8_t>& cells, Mask& m) {
  m.words = (m.w + 63) / 64;
  m.bits.assign(static_cast<std::size_t>(m.h) * m.words, 0);
  m.span.assign(m.h, {INT_MAX, -1});
  for (int y = 0; y < m.h; ++y) {
    for (int x = 0; x < m.w; ++x) {
      if (!cells[static_cast<std::size_t>(y) * m.w + x]) continue;
      m.bits[static_cast<std::size_t>(y) * m.words + x / 64] |= std::uint64_t{1} << (x % 64);
      m.span[y] = {std::min(m.span[y][0], x / 64), x / 64};
    }
  }
  // Probes: set cells spread over the mask (of rows at eighths of the height, the set cells
  // at 1/4, 1/2 and 3/4 of the row), so that most colliding positions fail on one of them.
  for (int k = 0; k < 8; ++k) {
    const int y = (2 * k + 1) * m.h / 16;
    std::vector<int> set;
    for (int x = 0; x < m.w; ++x) {
      if (cells[static_cast<std::size_t>(y) * m.w + x]) set.push_back(x);
    }
    for (std::size_t f : {set.size() / 2, set.size() / 4, 3 * set.size() / 4}) {
      if (f < set.size()) m.probes.push_back({set[f], y});
    }
  }
}

Mask rasterize(const RasterChart& chart, double angle, double cell, int grow) {
  const double c = std::cos(angle);
  const double s = std::sin(angle);
  std::vector<Vec2> q(chart.uv.size());
  Mask m;
  m.lo = Vec2::Constant(std::numeric_limits<double>::infinity());
  m.hi = -m.lo;
  for (const Triangle& t : chart.triangles) {
    for (std::uint32_t v : t) {
      const Vec2 p = chart.scale * chart.uv[v];
      q[v] = Vec2(c * p.x() - s * p.y(), s * p.x() + c * p.y());
      m.lo = m.lo.cwiseMin(q[v]);
      m.hi = m.hi.cwiseMax(q[v]);
    }
  }
  const int w = static_cast<int>(std::floor((m.hi.x() - m.lo.x()) / cell)) + 1;
  const int h = static_cast<int>(std::floor((m.hi.y() - m.lo.y()) / cell)) + 1;
  std::vector<std::uint8_t> cells(static_cast<std::size_t>(w) * h, 0);
  for (const Triangle& t : chart.triangles) {
    mark_triangle({(q[t[0]] - m.lo) / cell, (q[t[1]] - m.lo) / cell, (q[t[2]] - m.lo) / cell}, w, h, cells);
  }
  m.w = w + 2 * grow;
  m.h = h + 2 * grow;
  m.origin = m.lo - Vec2::Constant(grow * cell);
  fill_words(grow_cells(cells, w, h, grow), m);
  return m;
}

// The square of grid x grid cells being filled.
class Grid {
 public:
  explicit Grid(int n) : n_(n), words_(n / 64 + 2), bits_(static_cast<std::size_t>(n) * words_, 0) {}

  int size() const { return n_; }

  bool get(int x, int y) const { return (bits_[static_cast<std::size_t>(y) * words_ + x / 64] >> (x % 64)) & 1; }

  // The first probe of m with its cell (0, 0) at (x, y) on a set cell, or -1.
  int probe_hit(const Mask& m, int x, int y) const {
    for (std::size_t k = 0; k < m.probes.size(); ++k) {
      if (get(x + m.probes[k][0], y + m.probes[k][1])) return static_cast<int>(k);
    }
    return -1;
  }

  // The first free cell of row y at or after x (n if none).
  int next_free(int y, int x) const {
    const std::uint64_t* row = &bits_[static_cast<std::size_t>(y) * words_];
    for (int k = x / 64; k * 64 < n_; ++k) {
      std::uint64_t free = ~row[k];
      if (k == x / 64) free &= ~std::uint64_t{0} << (x % 64);
      if (free != 0) return std::min(n_, k * 64 + std::countr_zero(free));
    }
    return n_;
  }

  // Whether mask m with its cell (0, 0) at (x, y) meets a set cell; m must lie in the grid.
  bool collides(const Mask& m, int x, int y) const {
    bool hit = false;
    visit(bits_.data(), m, x, y, [&](std::uint64_t word, std::uint64_t cell) { return !(hit = (word & cell) != 0); });
    return hit;
  }

  void add(const Mask& m, int x, int y) {
    visit(bits_.data(), m, x, y, [](std::uint64_t word, std::uint64_t& cell) { cell |= word; return true; });
  }

 private:
  // Calls f(mask word shifted to the grid's word boundaries, grid word) over the mask's rows
  // until f returns false. Bits is std::uint64_t or const std::uint64_t.
  template <class Bits, class F>
  void visit(Bits* bits, const Mask& m, int x, int y, F&& f) const {
    const int shift = x % 64;
    const int base = x / 64;
    for (int r = 0; r < m.h; ++r) {
      const auto [first, last] = m.span[r];
      if (first > last) continue;
      const std::uint64_t* row = &m.bits[static_cast<std::size_t>(r) * m.words];
      Bits* cells = bits + static_cast<std::size_t>(y + r) * words_ + base;
      for (int k = first; k <= last + (shift != 0); ++k) {
        std::uint64_t word = k <= last ? row[k] << shift : 0;
        if (shift != 0 && k > first) word |= row[k - 1] >> (64 - shift);
        if (word != 0 && !f(word, cells[k])) return;
      }
    }
  }

  int n_;
  int words_;
  std::vector<std::uint64_t> bits_;
};

// A position for a mask, ordered by the side of the square around all placed cells, the
// area of their bounding box, then lowest, leftmost, first angle.
struct Pick {
  int side = INT_MAX;
  long long area = 0;
  int y = 0;
  int x = 0;
  int angle = -1;
  bool operator<(const Pick& o) const { return std::tie(side, area, y, x) < std::tie(o.side, o.area, o.y, o.x); }
};

// Improves `best` with the positions (x0..x1, y) of mask m: keys grow with x, so the first
// free one is the row's best. Positions whose probe lands on a set cell skip to the next free
// cell under that probe.
void scan_row(const Grid& grid, const Mask& m, int angle, int ex, int ey, int side, int y, int x0, int x1,
              Pick& best) {
  for (int x = x0; x <= x1;) {
    const Pick pick{side, static_cast<long long>(std::max(ex, x + m.w)) * std::max(ey, y + m.h), y, x, angle};
    if (!(pick < best)) return;
    if (const int k = grid.probe_hit(m, x, y); k >= 0) {
      x = grid.next_free(y + m.probes[k][1], x + m.probes[k][0] + 1) - m.probes[k][0];
    } else if (grid.collides(m, x, y)) {
      ++x;
    } else {
      best = pick;
      return;
    }
  }
}

// Improves `best` with the best free position of mask m (angle `angle`): the square grows
// from the placed cells' extent (ex, ey) one cell at a time until m fits.
void search(const Grid& grid, const Mask& m, int angle, int ex, int ey, Pick& best) {
  const int first = std::max({ex, ey, m.w, m.h});
  for (int side = first; side <= grid.size() && side <= best.side; ++side) {
    if (side == first) {
      // Positions inside the extent first: they keep its area, so the first free one prunes
      // most of the rest.
      for (int y = 0; y + m.h <= ey; ++y) scan_row(grid, m, angle, ex, ey, side, y, 0, ex - m.w, best);
      for (int y = 0; y + m.h <= side; ++y) scan_row(grid, m, angle, ex, ey, side, y, 0, side - m.w, best);
    } else {  // the band the square gains: its top row and right column of positions
      scan_row(grid, m, angle, ex, ey, side, side - m.h, 0, side - m.w, best);
      for (int y = 0; y + m.h < side; ++y) scan_row(grid, m, angle, ex, ey, side, y, side - m.w, side - m.w, best);
    }
    if (best.side == side) break;
  }
}

}  // namespace

RasterLayout raster_pack(std::span<const RasterChart> charts, std::span<const std::size_t> order, double bound,
                         double margin_fraction, int grid) {
  const double cell = bound / grid;
  // d cells between charts hold the margin for any side up to the bound; each chart grows by
  // half of it.
  const int d = std::max(1, static_cast<int>(std::ceil(margin_fraction * grid)));
  const int grow = (d + 1) / 2;
  Grid atlas(grid);
  int ex = 0;
  int ey = 0;
  RasterLayout layout;
  layout.slots.resize(charts.size());
  double reach = 0;
  for (std::size_t idx : order) {
    const RasterChart& chart = charts[idx];
    std::vector<Mask> masks;
    Pick best;
    for (std::size_t a = 0; a < chart.angles.size(); ++a) {
      masks.push_back(rasterize(chart, chart.angles[a], cell, grow));
      if (masks.back().w <= grid && masks.back().h <= grid) search(atlas, masks.back(), static_cast<int>(a), ex, ey, best);
    }
    if (best.angle < 0) return {};
    const Mask& m = masks[best.angle];
    atlas.add(m, best.x, best.y);
    ex = std::max(ex, best.x + m.w);
    ey = std::max(ey, best.y + m.h);
    PlacedChart& slot = layout.slots[idx];
    slot.angle = chart.angles[best.angle];
    slot.offset = Vec2(best.x, best.y) * cell - m.origin;
    slot.lo = m.lo + slot.offset;
    slot.hi = m.hi + slot.offset;
    reach = std::max(reach, slot.hi.maxCoeff());
  }
  // The tight square: the charts' reach plus half a margin of border.
  layout.side = reach / (1 - 0.5 * margin_fraction);
  if (layout.side > bound) return {};
  return layout;
}

}  // namespace seam::core::detail
