#include "core/atlas/pack.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <numeric>
#include <optional>
#include <string>

#include "core/atlas/profile_pack.h"
#include "core/atlas/raster_pack.h"
#include "core/atlas/skyline.h"
#include "core/timing.h"

namespace seam::core {

namespace {

Vec2 rotate(const Vec2& p, double angle) {
  const double c = std::cos(angle);
  const double s = std::sin(angle);
  return Vec2(c * p.x() - s * p.y(), s * p.x() + c * p.y());
}

constexpr std::size_t kMaxProfileCharts = 256;
// The shape packer: at most this many charts, on a grid of this many cells per side (at the
// default texture, a cell is two texels).
constexpr std::size_t kMaxRasterCharts = 256;
constexpr int kRasterGrid = 512;

struct Slot {
  Vec2 pos = Vec2::Zero();
  bool turned = false;
};

// Packs rectangles (sizes at unit density) into an L x L square with margins of
// margin_fraction * L; false if they do not all fit.
bool pack_square(const std::vector<Vec2>& sizes, const std::vector<std::size_t>& order, double side,
                 double margin_fraction, bool rotate, std::vector<Slot>& slots) {
  const double m = margin_fraction * side;
  detail::Skyline sky(side, side);
  slots.assign(sizes.size(), Slot{});
  for (std::size_t idx : order) {
    const double w = sizes[idx].x() + m;
    const double h = sizes[idx].y() + m;
    Vec2 pos;
    double top = 0;
    bool found = sky.find(w, h, pos, top);
    bool turned = false;
    if (rotate && w != h) {
      Vec2 pos90;
      double top90 = 0;
      if (sky.find(h, w, pos90, top90) && (!found || top90 < top)) {
        found = true;
        pos = pos90;
        turned = true;
      }
    }
    if (!found) return false;
    sky.add(pos, turned ? h : w, turned ? w : h);
    slots[idx] = {pos, turned};
  }
  return true;
}

// The smallest side L that could hold the rectangles with their margins: n cells of
// (w + fL) x (h + fL) cover at most L^2, so L^2 (1 - n f^2) - L f sum(w + h) - sum(w h) >= 0,
// and the longest side fits: longest + fL <= L. Needs n f^2 < 1 (margins_fit).
double side_lower_bound(const std::vector<Vec2>& sizes, double margin_fraction) {
  const double f = margin_fraction;
  double area = 0;
  double perimeter = 0;
  double longest = 0;
  for (const Vec2& s : sizes) {
    area += s.x() * s.y();
    perimeter += s.x() + s.y();
    longest = std::max(longest, s.maxCoeff());  // a square fits a rectangle only by its long side
  }
  const double a = 1 - static_cast<double>(sizes.size()) * f * f;
  const double b = f * perimeter;
  return std::max((b + std::sqrt(b * b + 4 * a * area)) / (2 * a), longest / (1 - f));
}

// Bisects the square side in (lo, hi], `fits(hi)` known true, for the smallest side `fits`
// accepts: at most `steps` halvings, stopping within `tolerance` of the side. Returns the last
// side that fit; `fits` keeps what it packed there.
template <class Fits>
double bisect_side(double lo, double hi, int steps, double tolerance, Fits&& fits) {
  for (int it = 0; it < steps && hi - lo > tolerance * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (fits(mid)) {
      hi = mid;
    } else {
      lo = mid;
    }
  }
  return hi;
}

// The smallest square side (by bisection, to 1e-4 of the side) that the order packs into, and
// its slots. `beat`, the best side of another order: first tried 1e-4 below it, and if the
// order does not pack there it is not bisected (nullopt), so a losing order costs one pass.
// Also nullopt if no square up to 1.1^200 times the lower bound holds the charts (margins_fit
// rules that out).
std::optional<double> smallest_square(const std::vector<Vec2>& sizes, const std::vector<std::size_t>& order,
                                      double margin_fraction, bool rotate, double beat, std::vector<Slot>& slots) {
  double lo = side_lower_bound(sizes, margin_fraction);
  double hi = std::isfinite(beat) ? std::max(lo, beat * (1 - 1e-4)) : lo;
  std::vector<Slot> trial;
  int grow = 0;
  while (!pack_square(sizes, order, hi, margin_fraction, rotate, trial)) {
    if (std::isfinite(beat) || ++grow > 200) return std::nullopt;
    lo = hi;
    hi *= 1.1;
  }
  slots = trial;
  return bisect_side(lo, hi, 24, 1e-4, [&](double side) {
    if (!pack_square(sizes, order, side, margin_fraction, rotate, trial)) return false;
    slots = trial;
    return true;
  });
}

}  // namespace

bool margins_fit(std::size_t charts, const PackOptions& options) {
  const double f = std::max(options.margin_px / options.texture_size, 1e-6);
  return static_cast<double>(charts) * f * f < 1;
}

std::string margins_message(std::size_t charts, const PackOptions& options) {
  const double root = std::sqrt(static_cast<double>(charts));
  char text[320];
  std::snprintf(text, sizeof text,
                "pack: %zu charts %g px apart do not fit a %d px texture: their margins alone would cover it "
                "(%zu x %g^2 texels >= %d^2); use texture_size above %.0f or margin_px below %.3g",
                charts, options.margin_px, options.texture_size, charts, options.margin_px, options.texture_size,
                std::floor(options.margin_px * root), options.texture_size / root);
  return text;
}

namespace {

Status validate(std::span<const PackChart> charts, const PackOptions& options) {
  if (options.texture_size < 16 || options.texture_size > 65536) {
    return make_error(ErrorCode::kInvalidArgument,
                      "pack: texture_size must be in 16..65536, got " + std::to_string(options.texture_size));
  }
  if (!(options.margin_px >= 0 && options.margin_px <= options.texture_size / 8.0)) {
    return make_error(ErrorCode::kInvalidArgument, "pack: margin_px must be in 0..texture_size/8");
  }
  if (!margins_fit(charts.size(), options)) {
    return make_error(ErrorCode::kInvalidArgument, margins_message(charts.size(), options));
  }
  return validate_pack_charts(charts);
}

double uv_area(const PackChart& chart) {
  double area = 0;
  for (const Triangle& t : chart.triangles) area += 0.5 * std::abs(cross2(chart.uv[t[0]], chart.uv[t[1]], chart.uv[t[2]]));
  return area;
}

// The rectangle turned a quarter where needed so it is wider than tall: (x, y) -> (y, -x).
MinAreaRect landscape(MinAreaRect r) {
  if (r.size.y() <= r.size.x()) return r;
  r.angle -= 0.5 * std::numbers::pi;
  r.min = Vec2(r.min.y(), -(r.min.x() + r.size.x()));
  r.size = Vec2(r.size.y(), r.size.x());
  return r;
}

// The segments that bound a chart, as point pairs through `map`: its outline where all its
// triangles turn one way (detail::chart_outline). Otherwise (a fold can reach past the edges
// used by one triangle) the outline of the triangles that turn the way most do, and every
// edge of the others once: the union of the triangles ends on those too. Either way the
// chart's lowest and highest points in any column lie on them, and a few flipped triangles
// add a few segments, not all of the chart's edges.
template <class F>
std::vector<std::array<Vec2, 2>> boundary_segments(const PackChart& chart, F&& map) {
  std::vector<std::array<Vec2, 2>> out;
  const auto add = [&](const std::vector<std::array<std::uint32_t, 2>>& outline) {
    for (const auto& [a, b] : outline) out.push_back({map(chart.uv[a]), map(chart.uv[b])});
  };
  if (const auto outline = detail::chart_outline(chart.uv, chart.triangles)) {
    add(*outline);
    return out;
  }
  std::vector<int> turn(chart.triangles.size());
  for (std::size_t i = 0; i < turn.size(); ++i) turn[i] = detail::strict_turn(chart.uv, chart.triangles[i]);
  const int most = std::accumulate(turn.begin(), turn.end(), 0) >= 0 ? 1 : -1;  // ccw minus cw
  std::vector<Triangle> majority;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;  // of the other triangles
  for (std::size_t i = 0; i < turn.size(); ++i) {
    const Triangle& t = chart.triangles[i];
    if (turn[i] == most) {
      majority.push_back(t);
      continue;
    }
    for (int k = 0; k < 3; ++k) edges.emplace_back(std::minmax(t[k], t[(k + 1) % 3]));
  }
  if (const auto outline = detail::chart_outline(chart.uv, majority)) add(*outline);
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  for (const auto& [a, b] : edges) out.push_back({map(chart.uv[a]), map(chart.uv[b])});
  return out;
}

// Profile packing into the smallest square found by bisection; infinity if it never fits.
double smallest_profile_square(const std::vector<detail::ProfileChart>& charts, double margin_fraction, bool rotate,
                               double start_side, std::vector<detail::ProfileSlot>& slots) {
  constexpr int kColumns = 256;
  std::vector<std::size_t> order(charts.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return charts[a].size.prod() > charts[b].size.prod();
  });
  double area = 0;
  for (const auto& c : charts) area += c.size.prod();
  double lo = std::sqrt(area) * 0.5;
  double hi = start_side;
  std::vector<detail::ProfileSlot> trial;
  if (!detail::profile_pack_square(charts, order, hi, margin_fraction * hi, rotate, kColumns, trial)) {
    return std::numeric_limits<double>::infinity();
  }
  slots = trial;
  return bisect_side(lo, hi, 20, 1e-3, [&](double side) {
    if (!detail::profile_pack_square(charts, order, side, margin_fraction * side, rotate, kColumns, trial))
      return false;
    slots = trial;
    return true;
  });
}

}  // namespace

Status validate_pack_charts(std::span<const PackChart> charts) {
  for (std::size_t c = 0; c < charts.size(); ++c) {
    const PackChart& chart = charts[c];
    const std::string name = "pack: chart " + std::to_string(c);
    if (chart.triangles.empty()) return make_error(ErrorCode::kInvalidArgument, name + " has no triangles");
    if (!(chart.surface_area > 0) || !std::isfinite(chart.surface_area)) {
      return make_error(ErrorCode::kInvalidArgument, name + " has surface_area " + std::to_string(chart.surface_area));
    }
    for (const Vec2& p : chart.uv) {
      if (!p.allFinite()) return make_error(ErrorCode::kNonFinitePosition, name + " has a non-finite UV");
    }
    for (const Triangle& t : chart.triangles) {
      for (std::uint32_t v : t) {
        if (v >= chart.uv.size()) {
          return make_error(ErrorCode::kIndexOutOfRange,
                            name + " names UV " + std::to_string(v) + " of " + std::to_string(chart.uv.size()));
        }
      }
    }
  }
  return Ok{};
}

namespace {

// The points that may be hull vertices: all but those clearly inside the quadrilateral of
// the extreme points (Akl–Toussaint), which no hull vertex is. "Clearly": farther inside
// each edge than a rounding margin, so the kept set holds every hull vertex whatever the
// rounding of the test. A chart's UVs are mostly interior: at 1.25M faces this keeps a few
// thousand of 625k points, and the hull costs a pass instead of a sort of all of them.
std::vector<Vec2> hull_candidates(std::span<const Vec2> points) {
  if (points.size() < 16) return {points.begin(), points.end()};
  auto extreme = [&](auto better) { return *std::min_element(points.begin(), points.end(), better); };
  const Vec2 quad[4] = {extreme([](const Vec2& a, const Vec2& b) { return a.y() < b.y(); }),   // bottom
                        extreme([](const Vec2& a, const Vec2& b) { return a.x() > b.x(); }),   // right
                        extreme([](const Vec2& a, const Vec2& b) { return a.y() > b.y(); }),   // top
                        extreme([](const Vec2& a, const Vec2& b) { return a.x() < b.x(); })};  // left
  double extent = 0.0;
  for (const Vec2& q : quad) extent = std::max(extent, q.cwiseAbs().maxCoeff());
  for (int i = 0; i < 4; ++i) extent = std::max(extent, (quad[(i + 1) % 4] - quad[i]).cwiseAbs().maxCoeff());
  const double margin = 1e-9 * extent * extent;
  std::vector<Vec2> kept;
  for (const Vec2& p : points) {
    bool inside = true;
    for (int i = 0; i < 4 && inside; ++i) inside = cross2(quad[i], quad[(i + 1) % 4], p) > margin;
    if (!inside) kept.push_back(p);
  }
  return kept;
}

}  // namespace

std::vector<Vec2> convex_hull(std::span<const Vec2> points) {
  std::vector<Vec2> p = hull_candidates(points);
  std::sort(p.begin(), p.end(), [](const Vec2& a, const Vec2& b) {
    return a.y() < b.y() || (a.y() == b.y() && a.x() < b.x());
  });
  p.erase(std::unique(p.begin(), p.end()), p.end());
  if (p.size() < 3) return p;
  // Monotone chain over y (lowest-then-leftmost first): right chain up, left chain down.
  std::vector<Vec2> hull(2 * p.size());
  std::size_t k = 0;
  for (const Vec2& q : p) {
    while (k >= 2 && cross2(hull[k - 2], hull[k - 1], q) <= 0) --k;
    hull[k++] = q;
  }
  const std::size_t lower = k + 1;
  for (std::size_t i = p.size() - 1; i-- > 0;) {
    while (k >= lower && cross2(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
    hull[k++] = p[i];
  }
  hull.resize(k - 1);
  return hull;
}

namespace {

// The axis-aligned box of the hull rotated by `angle`.
MinAreaRect rotated_box(std::span<const Vec2> hull, double angle) {
  Vec2 lo = Vec2::Constant(std::numeric_limits<double>::infinity());
  Vec2 hi = -lo;
  for (const Vec2& p : hull) {
    const Vec2 q = rotate(p, angle);
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  return {angle, hi - lo, lo};
}

}  // namespace

MinAreaRect min_square_rect(std::span<const Vec2> hull) {
  MinAreaRect best;
  double best_side = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 360; ++k) {
    const MinAreaRect box = rotated_box(hull, std::numbers::pi * k / 360);
    if (box.size.maxCoeff() < best_side * (1 - 1e-12)) {
      best_side = box.size.maxCoeff();
      best = box;
    }
  }
  return landscape(best);
}

MinAreaRect min_area_rect(std::span<const Vec2> hull) {
  MinAreaRect best;
  if (hull.empty()) return best;
  double best_area = std::numeric_limits<double>::infinity();
  const std::size_t h = hull.size();
  for (std::size_t i = 0; i < std::max<std::size_t>(h, 1); ++i) {
    const Vec2 e = hull[(i + 1) % h] - hull[i];
    const MinAreaRect box = rotated_box(hull, h > 1 && e.norm() > 0 ? -std::atan2(e.y(), e.x()) : 0.0);
    if (box.size.prod() < best_area * (1 - 1e-12)) {
      best_area = box.size.prod();
      best = box;
    }
  }
  return landscape(best);
}

namespace {

// Each chart at unit density (UV area = surface area), its hull and its rectangle.
struct Prepared {
  std::vector<double> scale;
  std::vector<std::vector<Vec2>> hulls;
  std::vector<MinAreaRect> rect;  // minimal-area (rotate) or axis-aligned bounding rectangle
  double total_area = 0;
};

Result<Prepared> prepare(std::span<const PackChart> charts, bool rotate_charts, const CancelToken& cancel) {
  Prepared p;
  for (std::size_t c = 0; c < charts.size(); ++c) {
    if (cancel.is_cancelled()) return cancelled_error("pack");
    const double area = uv_area(charts[c]);
    if (!(area > 0)) {
      return make_error(ErrorCode::kInvalidArgument, "pack: chart " + std::to_string(c) + " has zero UV area");
    }
    p.scale.push_back(std::sqrt(charts[c].surface_area / area));
    p.total_area += charts[c].surface_area;
    std::vector<Vec2> used;
    used.reserve(charts[c].triangles.size() * 3);
    for (const Triangle& t : charts[c].triangles) {
      for (std::uint32_t v : t) used.push_back(p.scale[c] * charts[c].uv[v]);
    }
    p.hulls.push_back(convex_hull(used));
    if (rotate_charts) {
      p.rect.push_back(min_area_rect(p.hulls[c]));
    } else {
      Vec2 lo = Vec2::Constant(std::numeric_limits<double>::infinity());
      Vec2 hi = -lo;
      for (const Vec2& q : p.hulls[c]) {
        lo = lo.cwiseMin(q);
        hi = hi.cwiseMax(q);
      }
      p.rect.push_back({0.0, hi - lo, lo});
    }
  }
  return p;
}

// A packed square: its side and each chart's place (unit-density units).
struct Layout {
  double side = std::numeric_limits<double>::infinity();
  std::vector<detail::PlacedChart> slots;
};

// A chart in rectangle r (its frame: Rot(r.angle) p - r.min in [0, r.size]) turned by `turn`
// quarter turns and moved so the turned rectangle's lower-left corner is at `corner`.
detail::PlacedChart in_rect(const MinAreaRect& r, int turn, const Vec2& corner) {
  const Vec2 extent = (turn & 1) ? Vec2(r.size.y(), r.size.x()) : r.size;
  return {r.angle + turn * 0.5 * std::numbers::pi, detail::turn_point(-r.min, turn, r.size) + corner, corner,
          corner + extent};
}

// Packer (1): the rectangles, three orders; long charts retried diagonally.
Layout rectangle_layout(const Prepared& prepared, double margin_fraction, bool rotate_charts) {
  const std::size_t n = prepared.rect.size();
  Layout best;
  std::vector<MinAreaRect> best_rect;
  std::vector<Slot> slots;
  auto pack_all = [&](const std::vector<MinAreaRect>& rect) {
    auto by = [&](auto key) {
      std::vector<std::size_t> order(n);
      std::iota(order.begin(), order.end(), std::size_t{0});
      std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return key(a) > key(b); });
      return order;
    };
    std::vector<Vec2> sizes(n);
    for (std::size_t c = 0; c < n; ++c) sizes[c] = rect[c].size;
    const std::vector<std::size_t> orders[] = {
        by([&](std::size_t c) { return sizes[c].y(); }),
        by([&](std::size_t c) { return sizes[c].prod(); }),
        by([&](std::size_t c) { return sizes[c].x(); }),
    };
    for (const auto& order : orders) {
      std::vector<Slot> trial;
      const std::optional<double> side =
          smallest_square(sizes, order, margin_fraction, rotate_charts, best.side, trial);
      if (side && *side < best.side) {
        best.side = *side;
        best_rect = rect;
        slots = std::move(trial);
      }
    }
  };
  pack_all(prepared.rect);
  if (rotate_charts) {
    // Charts longer than half the square: at their smallest enclosing square instead (a long
    // strip lies diagonally); kept if the square shrinks.
    std::vector<MinAreaRect> alt = prepared.rect;
    bool any = false;
    for (std::size_t c = 0; c < n; ++c) {
      if (prepared.rect[c].size.x() > 0.5 * best.side) {
        alt[c] = min_square_rect(prepared.hulls[c]);
        any = true;
      }
    }
    if (any) pack_all(alt);
  }
  if (slots.size() != n) return best;  // no order packed (margins_fit rules that out): side stays infinite
  for (std::size_t c = 0; c < n; ++c) {
    const Vec2 corner = slots[c].pos + Vec2::Constant(0.5 * margin_fraction * best.side);
    best.slots.push_back(in_rect(best_rect[c], slots[c].turned ? 1 : 0, corner));
  }
  return best;
}

// Packer (2): the charts' column profiles, for few charts; replaces `layout` if smaller.
void try_profile_layout(std::span<const PackChart> charts, const Prepared& prepared, double margin_fraction,
                        bool rotate_charts, Layout& layout) {
  const std::size_t n = charts.size();
  if (n < 2 || n > kMaxProfileCharts) return;  // one chart: see try_raster_layout
  std::vector<detail::ProfileChart> profile(n);
  for (std::size_t c = 0; c < n; ++c) {
    const MinAreaRect& r = prepared.rect[c];
    profile[c].size = r.size;
    profile[c].boundary = boundary_segments(charts[c], [&](const Vec2& uv) {
      return Vec2(rotate(prepared.scale[c] * uv, r.angle) - r.min);
    });
  }
  std::vector<detail::ProfileSlot> slots;
  const double side = smallest_profile_square(profile, margin_fraction, rotate_charts, layout.side, slots);
  if (!(side < layout.side)) return;
  layout.side = side;
  for (std::size_t c = 0; c < n; ++c) layout.slots[c] = in_rect(prepared.rect[c], slots[c].turn, slots[c].shift);
}

// The angles the shape packer tries for chart c: quarter turns of its minimal-area rectangle
// (finer steps between them for few charts) and of its smallest enclosing square.
std::vector<double> raster_angles(const Prepared& prepared, std::size_t c, std::size_t n) {
  const int steps = n <= 16 ? 4 : n <= 64 ? 2 : 1;  // angles per quarter turn
  std::vector<double> angles;
  for (int k = 0; k < 4 * steps; ++k) angles.push_back(prepared.rect[c].angle + k * 0.5 * std::numbers::pi / steps);
  const double square = min_square_rect(prepared.hulls[c]).angle;
  for (int k = 0; k < 4; ++k) angles.push_back(square + k * 0.5 * std::numbers::pi);
  return angles;
}

// Packer (3): the charts' shapes on a grid, for few charts; replaces `layout` if smaller.
void try_raster_layout(std::span<const PackChart> charts, const Prepared& prepared, double margin_fraction,
                       bool rotate_charts, Layout& layout) {
  const std::size_t n = charts.size();
  // One chart: the rectangle layout already holds it in its smallest enclosing square.
  if (n < 2 || n > kMaxRasterCharts) return;
  std::vector<detail::RasterChart> raster(n);
  for (std::size_t c = 0; c < n; ++c) {
    raster[c] = {charts[c].uv, charts[c].triangles, prepared.scale[c],
                 rotate_charts ? raster_angles(prepared, c, n) : std::vector<double>{0.0}};
  }
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return charts[a].surface_area > charts[b].surface_area; });
  // A little room over the best square so far: the grid's rounding. (Repacking into the
  // smaller square found, with finer cells, gained under 1% on the bench's assets.)
  detail::RasterLayout r = detail::raster_pack(raster, order, 1.02 * layout.side, margin_fraction, kRasterGrid);
  if (r.side < layout.side) layout = {r.side, std::move(r.slots)};
}

// The similarity of each chart, and the figures of the layout.
PackResult placements_of(std::span<const PackChart> charts, const Prepared& prepared, const Layout& layout,
                         int texture_size) {
  PackResult result;
  const double inv = 1.0 / layout.side;
  double min_density = std::numeric_limits<double>::infinity();
  double max_density = 0;
  double rect_area = 0;
  for (std::size_t c = 0; c < charts.size(); ++c) {
    const detail::PlacedChart& slot = layout.slots[c];
    ChartPlacement p;
    p.scale = prepared.scale[c] * inv;
    p.angle = slot.angle;
    p.offset = slot.offset * inv;
    p.rect_min = slot.lo * inv;
    p.rect_max = slot.hi * inv;
    rect_area += (slot.hi - slot.lo).prod();
    const double density = texture_size * p.scale * std::sqrt(uv_area(charts[c]) / charts[c].surface_area);
    min_density = std::min(min_density, density);
    max_density = std::max(max_density, density);
    result.placements.push_back(p);
  }
  result.coverage = prepared.total_area * inv * inv;
  result.rect_fill = rect_area > 0 ? prepared.total_area / rect_area : 0;
  result.texel_density = max_density;
  result.density_ratio = max_density / min_density;
  return result;
}

}  // namespace

Result<PackResult> pack_charts(std::span<const PackChart> charts, const PackOptions& options, const CancelToken& cancel) {
  const auto start = StageClock::now();
  if (Status valid = validate(charts, options); !valid.ok()) return valid.take_error();
  if (charts.empty()) return PackResult{};
  SEAM_TRY(const Prepared prepared, prepare(charts, options.rotate, cancel));
  // Charts never touch, even with margin_px = 0 (a millionth of the atlas side between them),
  // so that rounding cannot make neighbours overlap.
  const double margin_fraction = std::max(options.margin_px / options.texture_size, 1e-6);
  Layout layout = rectangle_layout(prepared, margin_fraction, options.rotate);
  if (!std::isfinite(layout.side)) {
    return make_error(ErrorCode::kInvalidArgument,
                      "pack: no square holds the " + std::to_string(charts.size()) + " charts with their margins");
  }
  if (cancel.is_cancelled()) return cancelled_error("pack");
  try_profile_layout(charts, prepared, margin_fraction, options.rotate, layout);
  if (cancel.is_cancelled()) return cancelled_error("pack");
  try_raster_layout(charts, prepared, margin_fraction, options.rotate, layout);
  PackResult result = placements_of(charts, prepared, layout, options.texture_size);
  result.ms = ms_since(start);
  return result;
}

}  // namespace seam::core
