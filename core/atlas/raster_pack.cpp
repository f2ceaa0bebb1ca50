#include "core/atlas/raster_pack.h"

#include <algorithm>
#include <array>
#include <bit>
#include <climits>
#include <cmath>
#include <cstdint>
#include <tuple>

#include "core/atlas/predicates.h"

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

constexpr double kEps = 1e-9;

// Widens [x_lo, x_hi] by the x-extent of segment a-b within row j's slab [j, j + 1] (grown by
// kEps); leaves it when the segment misses the slab.
void clip_to_row(const Vec2& a, const Vec2& b, int j, double& x_lo, double& x_hi) {
  const double y0 = std::max(std::min(a.y(), b.y()), j - kEps);
  const double y1 = std::min(std::max(a.y(), b.y()), j + 1 + kEps);
  if (y0 > y1) return;
  for (double y : {y0, y1}) {
    const double x =
        a.y() == b.y() ? a.x() : a.x() + (b.x() - a.x()) * std::clamp((y - a.y()) / (b.y() - a.y()), 0.0, 1.0);
    x_lo = std::min({x_lo, x, a.y() == b.y() ? b.x() : x});
    x_hi = std::max({x_hi, x, a.y() == b.y() ? b.x() : x});
  }
}

// Sets cells i0..i1 (inclusive) of row j.
void set_cells(ChartCells::Cells& c, int j, int i0, int i1) {
  std::uint64_t* row = &c.bits[static_cast<std::size_t>(j) * c.words];
  const int k0 = i0 / 64;
  const int k1 = i1 / 64;
  const std::uint64_t first = ~std::uint64_t{0} << (i0 % 64);
  const std::uint64_t last = ~std::uint64_t{0} >> (63 - i1 % 64);
  if (k0 == k1) {
    row[k0] |= first & last;
    return;
  }
  row[k0] |= first;
  for (int k = k0 + 1; k < k1; ++k) row[k] = ~std::uint64_t{0};
  row[k1] |= last;
}

// Marks the cells of grid `c` (unit cells) that the closed polygon `p` (a triangle,
// or a segment as two points) touches. Row by row: its part within the row's slab is convex,
// so it touches exactly the cells its x-extent meets; the extent comes from the edges clipped
// to the slab. Degenerate triangles (segments) are handled alike.
template <std::size_t N>
void mark_polygon(const std::array<Vec2, N>& p, ChartCells::Cells& c) {
  const int w = c.w;
  const int h = c.h;
  Vec2 lo = p[0];
  Vec2 hi = p[0];
  for (const Vec2& v : p) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const int j0 = std::clamp(static_cast<int>(std::floor(lo.y() - kEps)), 0, h - 1);
  const int j1 = std::clamp(static_cast<int>(std::floor(hi.y() + kEps)), 0, h - 1);
  for (int j = j0; j <= j1; ++j) {
    double x_lo = std::numeric_limits<double>::infinity();
    double x_hi = -x_lo;
    for (std::size_t k = 0; k < (N == 2 ? 1 : N); ++k) clip_to_row(p[k], p[(k + 1) % N], j, x_lo, x_hi);
    if (x_lo > x_hi) continue;
    const int i0 = std::clamp(static_cast<int>(std::floor(x_lo - kEps)), 0, w - 1);
    const int i1 = std::clamp(static_cast<int>(std::floor(x_hi + kEps)), 0, w - 1);
    set_cells(c, j, i0, i1);
  }
}

// Marks the cells of grid `c` whose centre has a non-zero winding number with
// respect to the closed chain of directed segments `edges` over points `p` (in cell units).
// A crossing counts where the segment's half-open y-range [min, max) holds the row's centre
// line; cells whose centres lie on the chain are marked or not (the chain's own cells are
// marked apart). Returns false, marking nothing, when the chain crosses the rows' centre lines
// more than `budget` times (a comb of long thin teeth), which would hold that many crossings.
bool fill_inside(std::span<const std::array<std::uint32_t, 2>> edges, std::span<const Vec2> p, std::size_t budget,
                 ChartCells::Cells& c) {
  const int w = c.w;
  const int h = c.h;
  struct Crossing {
    double x;
    int row;
    int delta;
  };
  // Rows j with y_lo <= j + 0.5 < y_hi, of the segment's y-range [y_lo, y_hi].
  const auto rows = [h](double y_lo, double y_hi) {
    return std::pair{std::max(0, static_cast<int>(std::ceil(y_lo - 0.5))),
                     std::min(h - 1, static_cast<int>(std::ceil(y_hi - 0.5)) - 1)};
  };
  std::size_t count = 0;
  for (const auto& [s, e] : edges) {
    const auto [j0, j1] = rows(std::min(p[s].y(), p[e].y()), std::max(p[s].y(), p[e].y()));
    count += static_cast<std::size_t>(std::max(0, j1 - j0 + 1));
  }
  if (count > budget) return false;
  std::vector<Crossing> crossings;
  crossings.reserve(count);
  for (const auto& [s, e] : edges) {
    const Vec2& a = p[s];
    const Vec2& b = p[e];
    if (a.y() == b.y()) continue;
    const auto [j0, j1] = rows(std::min(a.y(), b.y()), std::max(a.y(), b.y()));
    const double slope = (b.x() - a.x()) / (b.y() - a.y());
    for (int j = j0; j <= j1; ++j) {
      const double x = std::clamp(a.x() + (j + 0.5 - a.y()) * slope, std::min(a.x(), b.x()), std::max(a.x(), b.x()));
      crossings.push_back({x, j, b.y() > a.y() ? 1 : -1});
    }
  }
  std::sort(crossings.begin(), crossings.end(),
            [](const Crossing& u, const Crossing& v) { return u.row != v.row ? u.row < v.row : u.x < v.x; });
  int winding = 0;
  for (std::size_t k = 0; k < crossings.size(); ++k) {
    const Crossing& here = crossings[k];
    winding += here.delta;
    if (winding == 0 || k + 1 == crossings.size() || crossings[k + 1].row != here.row) continue;
    // Centres i + 0.5 in [here.x, next.x].
    const int i0 = std::max(0, static_cast<int>(std::ceil(here.x - 0.5)));
    const int i1 = std::min(w - 1, static_cast<int>(std::floor(crossings[k + 1].x - 0.5)));
    if (i0 <= i1) set_cells(c, here.row, i0, i1);
  }
  return true;
}

// row |= row << k over `words` words (towards higher x; bits beyond the row are dropped).
// In place from the highest word down, so every word reads words not yet changed.
void or_shifted(std::uint64_t* row, int words, int k) {
  const int ws = k / 64;
  const int bs = k % 64;
  for (int i = words - 1; i >= ws; --i) {
    std::uint64_t v = row[i - ws] << bs;
    if (bs != 0 && i - ws >= 1) v |= row[i - ws - 1] >> (64 - bs);
    row[i] |= v;
  }
}

// The set bit of `row` with `rank` set bits before it (rank < the row's set bits).
int nth_set(const std::uint64_t* row, int words, std::size_t rank) {
  for (int i = 0; i < words; ++i) {
    std::uint64_t word = row[i];
    const auto count = static_cast<std::size_t>(std::popcount(word));
    if (rank >= count) {
      rank -= count;
      continue;
    }
    for (; rank > 0; --rank) word &= word - 1;  // drop the lowest set bits
    return i * 64 + std::countr_zero(word);
  }
  return -1;
}

// The chart's cells grown by g in every direction (a square neighbourhood), as the mask's
// words: cell (x, y) of the (w + 2g) x (h + 2g) mask is set when some cell (x', y') of `c`
// with x - 2g <= x' <= x and y - 2g <= y' <= y is. Rows are packed into words, then grown
// along x by shifted ORs (windows doubling to 2g + 1 bits) and along y alike over rows;
// then the row spans and the probes. m.words >= c.words: the grown rows are wider.
void grow_into(const ChartCells::Cells& c, int g, Mask& m) {
  m.w = c.w + 2 * g;
  m.h = c.h + 2 * g;
  m.words = (m.w + 63) / 64;
  m.bits.assign(static_cast<std::size_t>(m.h) * m.words, 0);
  for (int y = 0; y < c.h; ++y) {
    std::copy_n(&c.bits[static_cast<std::size_t>(y) * c.words], c.words,
                &m.bits[static_cast<std::size_t>(y) * m.words]);
  }
  const int window = 2 * g + 1;
  int len = 1;
  for (; 2 * len <= window; len *= 2) {
    for (int y = 0; y < c.h; ++y) or_shifted(&m.bits[static_cast<std::size_t>(y) * m.words], m.words, len);
  }
  if (len < window) {
    for (int y = 0; y < c.h; ++y) or_shifted(&m.bits[static_cast<std::size_t>(y) * m.words], m.words, window - len);
  }
  const auto or_rows_below = [&](int k) {  // row y |= row y - k, rows from the top down
    for (int y = m.h - 1; y >= k; --y) {
      std::uint64_t* to = &m.bits[static_cast<std::size_t>(y) * m.words];
      const std::uint64_t* from = &m.bits[static_cast<std::size_t>(y - k) * m.words];
      for (int i = 0; i < m.words; ++i) to[i] |= from[i];
    }
  };
  for (len = 1; 2 * len <= window; len *= 2) or_rows_below(len);
  if (len < window) or_rows_below(window - len);

  m.span.assign(m.h, {INT_MAX, -1});
  for (int y = 0; y < m.h; ++y) {
    const std::uint64_t* row = &m.bits[static_cast<std::size_t>(y) * m.words];
    for (int i = 0; i < m.words; ++i) {
      if (row[i] != 0) m.span[y] = {std::min(m.span[y][0], i), i};
    }
  }
  // Probes: set cells spread over the mask (of rows at eighths of the height, the set cells
  // at 1/4, 1/2 and 3/4 of the row), so that most colliding positions fail on one of them.
  for (int k = 0; k < 8; ++k) {
    const int y = (2 * k + 1) * m.h / 16;
    const std::uint64_t* row = &m.bits[static_cast<std::size_t>(y) * m.words];
    std::size_t set = 0;
    for (int i = 0; i < m.words; ++i) set += static_cast<std::size_t>(std::popcount(row[i]));
    for (std::size_t f : {set / 2, set / 4, 3 * set / 4}) {
      if (f < set) m.probes.push_back({nth_set(row, m.words, f), y});
    }
  }
}

Mask rasterize(const ChartCells& chart, double angle, double cell, int grow) {
  ChartCells::Cells c = chart.cells(angle, cell);
  Mask m;
  m.lo = c.lo;
  m.hi = c.hi;
  m.origin = m.lo - Vec2::Constant(grow * cell);
  grow_into(c, grow, m);
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

// The vertices (< nv) that the triangles use, ascending.
std::vector<std::uint32_t> vertices_in_use(std::size_t nv, std::span<const Triangle> triangles) {
  std::vector<char> in_use(nv, 0);
  for (const Triangle& t : triangles) in_use[t[0]] = in_use[t[1]] = in_use[t[2]] = 1;
  std::vector<std::uint32_t> used;
  for (std::uint32_t v = 0; v < nv; ++v) {
    if (in_use[v]) used.push_back(v);
  }
  return used;
}

}  // namespace

int strict_turn(std::span<const Vec2> uv, const Triangle& t) {
  const Vec2 ab = uv[t[1]] - uv[t[0]];
  const Vec2 ac = uv[t[2]] - uv[t[0]];
  const double cross = cross2(ab, ac);
  const double clear = 1e-12 * ab.norm() * ac.norm();
  return cross > clear ? 1 : cross < -clear ? -1 : 0;
}

std::optional<std::vector<std::array<std::uint32_t, 2>>> chart_outline(std::span<const Vec2> uv,
                                                                       std::span<const Triangle> triangles) {
  for (int sign = 0; const Triangle& t : triangles) {
    const int s = strict_turn(uv, t);
    if (s == 0 || (sign != 0 && s != sign)) return std::nullopt;
    sign = s;
  }
  const std::vector<std::uint32_t> used = vertices_in_use(uv.size(), triangles);
  const std::vector<std::uint32_t> point = same_point_representatives(uv, used);
  // Directed edges bucketed by their lower end (a counting sort), each bucket sorted by the
  // higher end; each segment's two directions cancel.
  std::vector<std::uint32_t> offset(uv.size() + 1, 0);
  const auto for_each_edge = [&](auto&& f) {
    for (const Triangle& t : triangles) {
      for (int k = 0; k < 3; ++k) f(point[t[k]], point[t[(k + 1) % 3]]);
    }
  };
  for_each_edge([&](std::uint32_t a, std::uint32_t b) { ++offset[std::min(a, b) + 1]; });
  for (std::size_t v = 0; v < uv.size(); ++v) offset[v + 1] += offset[v];
  std::vector<std::pair<std::uint32_t, int>> upper(offset.back());  // (higher end, +1 if a < b)
  std::vector<std::uint32_t> cursor(offset.begin(), offset.end() - 1);
  for_each_edge([&](std::uint32_t a, std::uint32_t b) {
    upper[cursor[std::min(a, b)]++] = {std::max(a, b), a < b ? 1 : -1};
  });
  std::vector<std::array<std::uint32_t, 2>> outline;
  for (const std::uint32_t lo : used) {
    const auto first = upper.begin() + offset[lo];
    const auto last = upper.begin() + offset[lo + 1];
    std::sort(first, last);
    for (auto it = first; it != last;) {
      const std::uint32_t hi = it->first;
      int net = 0;
      for (; it != last && it->first == hi; ++it) net += it->second;
      for (int k = 0; k < std::abs(net); ++k) outline.push_back(net > 0 ? std::array{lo, hi} : std::array{hi, lo});
    }
  }
  return outline;
}

ChartCells::ChartCells(const RasterChart& chart)
    : uv_(chart.uv),
      triangles_(chart.triangles),
      scale_(chart.scale),
      used_(vertices_in_use(chart.uv.size(), chart.triangles)) {
  // An outline longer than the triangles are many (a soup of unshared edges) costs more to
  // draw than the triangles themselves.
  auto outline = chart_outline(uv_, triangles_);
  by_outline_ = outline && outline->size() <= triangles_.size();
  if (by_outline_) outline_ = std::move(*outline);
}

ChartCells::Cells ChartCells::cells(double angle, double cell) const {
  const double c = std::cos(angle);
  const double s = std::sin(angle);
  std::vector<Vec2> p(uv_.size());
  Cells out;
  out.lo = Vec2::Constant(std::numeric_limits<double>::infinity());
  out.hi = -out.lo;
  for (std::uint32_t v : used_) {
    const Vec2 q = scale_ * uv_[v];
    p[v] = Vec2(c * q.x() - s * q.y(), s * q.x() + c * q.y());
    out.lo = out.lo.cwiseMin(p[v]);
    out.hi = out.hi.cwiseMax(p[v]);
  }
  out.w = static_cast<int>(std::floor((out.hi.x() - out.lo.x()) / cell)) + 1;
  out.h = static_cast<int>(std::floor((out.hi.y() - out.lo.y()) / cell)) + 1;
  for (std::uint32_t v : used_) p[v] = (p[v] - out.lo) / cell;
  out.words = (out.w + 63) / 64;
  out.bits.assign(static_cast<std::size_t>(out.h) * out.words, 0);
  // The crossings of the rows' centre lines are held at once: a few per cell at most, else
  // (an outline zigzagging across many rows) the triangles are drawn.
  const std::size_t budget = 4 * static_cast<std::size_t>(out.w) * out.h + 64;
  if (by_outline_ && fill_inside(outline_, p, budget, out)) {
    for (const auto& [a, b] : outline_) mark_polygon(std::array{p[a], p[b]}, out);
  } else {
    for (const Triangle& t : triangles_) mark_polygon(std::array{p[t[0]], p[t[1]], p[t[2]]}, out);
  }
  return out;
}

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
    const ChartCells chart_cells(chart);
    std::vector<Mask> masks;
    Pick best;
    for (std::size_t a = 0; a < chart.angles.size(); ++a) {
      masks.push_back(rasterize(chart_cells, chart.angles[a], cell, grow));
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
