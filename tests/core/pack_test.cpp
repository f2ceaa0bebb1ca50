// Chart packing: the minimal rectangle against a brute-force rotation search, and packed
// layouts checked from the transformed UVs themselves (rectangles margin_px apart, all in
// [0,1]^2, no overlap by the exact test and by rasterization, one texel density, coverage
// equal to the placed area), on generated and on real flattened CGAL charts.
#include "core/atlas/pack.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <set>

#include "atlas_test_util.h"
#include "core/atlas/overlap.h"
#include "core/atlas/split.h"
#include "core/extrema/extrema.h"
#include "core/mesh/cut.h"
#include "core/mesh/topology.h"
#include "core/seam/seam.h"
#include "core/uv/parameterize.h"
#include "core/uv/uv_patch.h"
#include "test_data.h"
#include "uv_fixture.h"

namespace seam_pack_test {

using namespace seam::core;

namespace {

struct OwnedChart {
  std::vector<Vec2> uv;
  std::vector<Triangle> triangles;
  double surface_area = 0;
};

/// An a x b grid chart (2 triangles per cell), rotated by `angle` and shifted, whose surface
/// area is `density2` times its UV area.
OwnedChart grid_chart(double a, double b, double angle, const Vec2& shift, double density2, int n = 4) {
  OwnedChart c;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const Vec2 p(a * i / n, b * j / n);
      c.uv.push_back(Vec2(std::cos(angle) * p.x() - std::sin(angle) * p.y(),
                          std::sin(angle) * p.x() + std::cos(angle) * p.y()) + shift);
    }
  }
  auto id = [n](int i, int j) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      c.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      c.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  c.surface_area = density2 * a * b;
  return c;
}

double point_segment_distance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 d = b - a;
  const double len2 = d.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * d)).norm();
}

/// Distance between segments [a, b] and [c, d]; 0 when they cross.
double segment_distance(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  auto orient = [](const Vec2& p, const Vec2& q, const Vec2& x) {
    return (q.x() - p.x()) * (x.y() - p.y()) - (q.y() - p.y()) * (x.x() - p.x());
  };
  if (orient(a, b, c) * orient(a, b, d) < 0 && orient(c, d, a) * orient(c, d, b) < 0) return 0;
  return std::min({point_segment_distance(a, c, d), point_segment_distance(b, c, d), point_segment_distance(c, a, b),
                   point_segment_distance(d, a, b)});
}

double area_of(std::span<const Vec2> uv, std::span<const Triangle> tris) {
  double a = 0;
  for (const Triangle& t : tris) {
    const Vec2 e1 = uv[t[1]] - uv[t[0]];
    const Vec2 e2 = uv[t[2]] - uv[t[0]];
    a += 0.5 * std::abs(e1.x() * e2.y() - e1.y() * e2.x());
  }
  return a;
}

std::vector<PackChart> views(const std::vector<OwnedChart>& charts) {
  std::vector<PackChart> v;
  for (const OwnedChart& c : charts) v.push_back({c.uv, c.triangles, c.surface_area});
  return v;
}

/// Checks a packed layout from the placed UVs alone; returns the placed coverage.
double check_packed(const std::vector<OwnedChart>& charts, const PackResult& r, const PackOptions& o) {
  REQUIRE(r.placements.size() == charts.size());
  const double texel = 1.0 / o.texture_size;
  std::vector<Vec2> all_uv;
  std::vector<Triangle> all_tris;
  std::vector<std::uint32_t> chart_of;
  std::vector<std::pair<Vec2, Vec2>> boxes;
  double placed_area = 0;
  double min_density = 1e300;
  double max_density = 0;
  for (std::size_t c = 0; c < charts.size(); ++c) {
    const auto base = static_cast<std::uint32_t>(all_uv.size());
    Vec2 lo(1e300, 1e300);
    Vec2 hi(-1e300, -1e300);
    std::vector<Vec2> placed;
    for (const Vec2& p : charts[c].uv) {
      const Vec2 q = r.placements[c].apply(p);
      placed.push_back(q);
      all_uv.push_back(q);
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
    for (const Triangle& t : charts[c].triangles) {
      all_tris.push_back({base + t[0], base + t[1], base + t[2]});
      chart_of.push_back(static_cast<std::uint32_t>(c));
    }
    // The chart lies in its reported rectangle, which keeps margin/2 from the border.
    CHECK(lo.x() >= r.placements[c].rect_min.x() - 1e-9);
    CHECK(hi.y() <= r.placements[c].rect_max.y() + 1e-9);
    CHECK(lo.minCoeff() >= 0.5 * o.margin_px * texel - 1e-9);
    CHECK(hi.maxCoeff() <= 1 - 0.5 * o.margin_px * texel + 1e-9);
    boxes.emplace_back(lo, hi);
    const double a = area_of(placed, charts[c].triangles);
    placed_area += a;
    const double density = std::sqrt(a / charts[c].surface_area);
    min_density = std::min(min_density, density);
    max_density = std::max(max_density, density);
  }
  // Margins: any two placed charts are margin_px texels apart (distance between their
  // boundary segments; interiors cannot meet without the boundaries meeting, checked below).
  std::vector<std::vector<std::array<Vec2, 2>>> outline(charts.size());
  for (std::size_t c = 0; c < charts.size(); ++c) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
    for (const Triangle& t : charts[c].triangles) {
      for (int k = 0; k < 3; ++k) ++uses[std::minmax(t[k], t[(k + 1) % 3])];
    }
    for (const auto& [e, count] : uses) {
      if (count == 1) outline[c].push_back({r.placements[c].apply(charts[c].uv[e.first]), r.placements[c].apply(charts[c].uv[e.second])});
    }
  }
  const double margin = o.margin_px * texel;
  double closest = 1e300;
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    for (std::size_t j = i + 1; j < boxes.size(); ++j) {
      const double gap_x = std::max(boxes[j].first.x() - boxes[i].second.x(), boxes[i].first.x() - boxes[j].second.x());
      const double gap_y = std::max(boxes[j].first.y() - boxes[i].second.y(), boxes[i].first.y() - boxes[j].second.y());
      if (std::max(gap_x, gap_y) >= margin) continue;  // boxes already apart
      for (const auto& a : outline[i]) {
        for (const auto& b : outline[j]) closest = std::min(closest, segment_distance(a[0], a[1], b[0], b[1]));
      }
    }
  }
  if (closest < 1e300) CHECK(closest >= margin * (1 - 1e-6));
  CHECK(max_density / min_density == doctest::Approx(1.0).epsilon(1e-9));
  CHECK(r.density_ratio == doctest::Approx(1.0).epsilon(1e-9));
  CHECK(r.coverage == doctest::Approx(placed_area).epsilon(1e-9));
  auto overlap = find_overlaps(all_uv, all_tris, chart_of);
  REQUIRE(overlap.ok());
  CHECK(overlap->between_charts_area == 0);
  return placed_area;
}

/// Rasterizes the placed layout at res x res over its bounding box (an odd res keeps samples
/// off the diagonals of charts placed axis-aligned): no sample covered twice,
/// and the covered area (in [0,1]^2 units) matches the reported coverage. Returns the raster.
seam::atlas_test::RasterCount check_raster(const std::vector<OwnedChart>& charts, const PackResult& r, int res) {
  std::vector<Vec2> all_uv;
  std::vector<Triangle> all_tris;
  for (std::size_t c = 0; c < charts.size(); ++c) {
    const auto base = static_cast<std::uint32_t>(all_uv.size());
    for (const Vec2& p : charts[c].uv) all_uv.push_back(r.placements[c].apply(p));
    for (const Triangle& t : charts[c].triangles) all_tris.push_back({base + t[0], base + t[1], base + t[2]});
  }
  const seam::atlas_test::RasterCount raster = seam::atlas_test::rasterize(all_uv, all_tris, res);
  CHECK(raster.twice == 0);
  CHECK(raster.covered * raster.sample_area == doctest::Approx(r.coverage).epsilon(0.05));
  return raster;
}

/// Packs the charts and checks the layout (check_packed, and check_raster at res x res).
PackResult pack_checked(const std::vector<OwnedChart>& charts, const PackOptions& o, int res) {
  auto r = pack_charts(views(charts), o);
  REQUIRE(r.ok());
  check_packed(charts, *r, o);
  check_raster(charts, *r, res);
  return *r;
}

/// A square ring: outer side `outer`, a square hole of side `inner` centred in x and a little
/// low (no edge at 45 degrees, whose points the raster oracle's samples could hit), 8 triangles.
OwnedChart ring_chart(double outer, double inner) {
  OwnedChart c;
  const double a = 0.5 * (outer - inner);
  const double b = 0.75 * a;
  c.uv = {{0, 0}, {outer, 0}, {outer, outer}, {0, outer}, {a, b}, {a + inner, b}, {a + inner, b + inner}, {a, b + inner}};
  for (std::uint32_t k = 0; k < 4; ++k) {
    const std::uint32_t n = (k + 1) % 4;
    c.triangles.push_back({k, n, 4 + n});
    c.triangles.push_back({k, 4 + n, 4 + k});
  }
  c.surface_area = outer * outer - inner * inner;
  return c;
}

/// An L of side 1 and arm width t, rotated by `angle`: the unit square without its upper right
/// (1 - t) x (1 - t) corner.
OwnedChart ell_chart(double t, double angle) {
  OwnedChart c;
  for (const Vec2& p : {Vec2(0, 0), Vec2(1, 0), Vec2(1, t), Vec2(t, t), Vec2(t, 1), Vec2(0, 1)}) {
    c.uv.emplace_back(std::cos(angle) * p.x() - std::sin(angle) * p.y(), std::sin(angle) * p.x() + std::cos(angle) * p.y());
  }
  c.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}};
  c.surface_area = 2 * t - t * t;
  return c;
}

/// A chart of the unit cells (i, j) of an n x n grid that `keep` selects, two triangles each,
/// with shared corners; its surface area is `density2` times its UV area.
template <class Keep>
OwnedChart cells_chart(int n, double density2, Keep&& keep) {
  OwnedChart c;
  std::map<std::pair<int, int>, std::uint32_t> corner;
  auto id = [&](int i, int j) {
    const auto [it, added] = corner.try_emplace({i, j}, static_cast<std::uint32_t>(c.uv.size()));
    if (added) c.uv.emplace_back(i, j);
    return it->second;
  };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      if (!keep(i, j)) continue;
      c.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      c.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      c.surface_area += density2;
    }
  }
  return c;
}

/// A comb: a spine along the bottom and four long teeth (fills about a third of its square).
OwnedChart comb_chart() {
  return cells_chart(32, 2.0, [](int i, int j) { return j < 4 || i % 8 < 3; });
}

}  // namespace

TEST_CASE("the minimal-area rectangle of a rotated rectangle is the rectangle, of a polygon, no larger than a fine search") {
  for (double angle : {0.0, 0.3, 1.0, 2.5}) {
    const OwnedChart c = grid_chart(3, 1, angle, Vec2(5, -2), 1, 1);
    const std::vector<Vec2> hull = convex_hull(c.uv);
    CHECK(hull.size() == 4);
    const MinAreaRect r = min_area_rect(hull);
    CHECK(r.size.x() == doctest::Approx(3));
    CHECK(r.size.y() == doctest::Approx(1));
  }
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<Vec2> pts;
    for (int k = 0; k < 40; ++k) pts.emplace_back(3 * u(rng), u(rng) + 0.5 * pts.size() * 0.02);
    const std::vector<Vec2> hull = convex_hull(pts);
    // Every point is inside (or on) the counter-clockwise hull.
    for (const Vec2& p : pts) {
      for (std::size_t i = 0; i < hull.size(); ++i) {
        const Vec2 e = hull[(i + 1) % hull.size()] - hull[i];
        const Vec2 d = p - hull[i];
        CHECK(e.x() * d.y() - e.y() * d.x() >= -1e-12);
      }
    }
    const MinAreaRect r = min_area_rect(hull);
    CHECK(r.size.x() >= r.size.y());
    double brute = 1e300;
    for (int k = 0; k < 3600; ++k) {
      const double a = std::numbers::pi * k / 3600;
      Vec2 lo(1e300, 1e300);
      Vec2 hi(-1e300, -1e300);
      for (const Vec2& p : pts) {
        const Vec2 q(std::cos(a) * p.x() - std::sin(a) * p.y(), std::sin(a) * p.x() + std::cos(a) * p.y());
        lo = lo.cwiseMin(q);
        hi = hi.cwiseMax(q);
      }
      brute = std::min(brute, (hi - lo).prod());
    }
    CHECK(r.size.prod() <= brute * (1 + 1e-9));
    CHECK(r.size.prod() >= brute * (1 - 1e-3));  // the search is fine enough to come close
    // The rectangle's rotation really encloses the points.
    for (const Vec2& p : pts) {
      const Vec2 q(std::cos(r.angle) * p.x() - std::sin(r.angle) * p.y(), std::sin(r.angle) * p.x() + std::cos(r.angle) * p.y());
      CHECK(q.x() >= r.min.x() - 1e-9);
      CHECK(q.y() >= r.min.y() - 1e-9);
      CHECK(q.x() <= r.min.x() + r.size.x() + 1e-9);
      CHECK(q.y() <= r.min.y() + r.size.y() + 1e-9);
    }
  }
}

TEST_CASE("many random charts: margins hold, all in [0,1]^2, no overlap, one density, deterministic") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> side(0.05, 3);
  std::uniform_real_distribution<double> angle(0, 2 * std::numbers::pi);
  std::uniform_real_distribution<double> density(0.2, 5);
  std::vector<OwnedChart> charts;
  for (int k = 0; k < 150; ++k) {
    charts.push_back(grid_chart(side(rng), side(rng), angle(rng), Vec2(side(rng), side(rng)), density(rng), 2));
  }
  for (const PackOptions& o : {PackOptions{}, PackOptions{.texture_size = 512, .margin_px = 8, .rotate = false},
                               PackOptions{.texture_size = 4096, .margin_px = 0}}) {
    CAPTURE(o.texture_size);
    auto r = pack_charts(views(charts), o);
    REQUIRE(r.ok());
    const double coverage = check_packed(charts, *r, o);
    // Random rectangles at random angles: kept unrotated, their boxes are about half empty.
    CHECK(coverage > (o.rotate ? 0.55 : 0.25));
    auto again = pack_charts(views(charts), o);
    REQUIRE(again.ok());
    for (std::size_t c = 0; c < charts.size(); ++c) {
      CHECK(again->placements[c].offset == r->placements[c].offset);
      CHECK(again->placements[c].angle == r->placements[c].angle);
    }
  }
  // Rectangles packed tightly: with rotation and no margin, coverage is their fill.
  auto tight = pack_charts(views(charts), {.margin_px = 0});
  REQUIRE(tight.ok());
  CHECK(tight->rect_fill == doctest::Approx(1.0));
  CHECK(tight->coverage > 0.75);
}

TEST_CASE("rotation: thin diagonal strips pack far better turned to their minimal rectangles") {
  std::vector<OwnedChart> strips;
  for (int k = 0; k < 12; ++k) strips.push_back(grid_chart(10, 0.5, 0.3 + 0.1 * k, Vec2(k, 0), 1));
  auto turned = pack_charts(views(strips), {});
  auto kept = pack_charts(views(strips), {.rotate = false});
  REQUIRE(turned.ok());
  REQUIRE(kept.ok());
  check_packed(strips, *turned, {});
  check_packed(strips, *kept, {.rotate = false});
  CHECK(turned->coverage > 2 * kept->coverage);
  // One long strip alone lies diagonally in the square (its minimal rectangle would waste it).
  std::vector<OwnedChart> one{strips[0]};
  auto single = pack_charts(views(one), {});
  REQUIRE(single.ok());
  check_packed(one, *single, {});
  // Area 5: laid flat along a side 5 / 10^2 = 0.05; along the diagonal 5 / (10.5 / sqrt 2)^2 = 0.091.
  CHECK(single->coverage > 0.085);
}

TEST_CASE("real flattened CGAL charts packed together: no UV point covered twice") {
  std::vector<OwnedChart> charts;
  for (const char* name : {"hand", "elephant", "bunny00", "mushroom"}) {
    const HalfedgeMesh mesh = seam::test_data::load_cgal_halfedge(name);
    HalfedgeMesh disc = mesh;
    if (compute_topology(mesh).components.size() != 1 || !check_is_disc(mesh).ok()) {
      disc = seam::fixtures::cut_along_seam(mesh);
    }
    auto uv = parameterize(disc);
    REQUIRE(uv.ok());
    const Topology topo = compute_topology(disc);
    auto patches = extract_disc_patches(disc, topo);
    REQUIRE(patches.ok());
    for (const DiscPatch& p : *patches) {
      OwnedChart c;
      for (VertexId v : p.to_mesh) c.uv.push_back(uv->uv[v]);
      c.triangles = p.triangles;
      for (const Triangle& t : p.triangles) {
        c.surface_area += 0.5 * (p.positions[t[1]] - p.positions[t[0]]).cross(p.positions[t[2]] - p.positions[t[0]]).norm();
      }
      charts.push_back(std::move(c));
    }
  }
  REQUIRE(charts.size() >= 4);
  pack_checked(charts, {}, 2047);
}

TEST_CASE("a chart folded past the edges its triangles use once is packed by its triangles") {
  // A unit square with a flap folded out past its top edge: the flap's triangle and its mirror
  // share all their edges, so the edges used once are the square's alone, and a packer that
  // read the chart's shape from them left the flap out and put other charts under it (found by
  // atlas_fuzz). Beside it, small squares that fill whatever room the packers see.
  OwnedChart folded;
  folded.uv = {Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1), Vec2(0.5, 1.6)};
  folded.triangles = {{0, 1, 2}, {0, 2, 3}, {3, 2, 4}, {3, 4, 2}};
  folded.surface_area = 1.6;
  std::vector<OwnedChart> charts = {folded};
  for (int k = 0; k < 6; ++k) charts.push_back(grid_chart(0.3, 0.25, 0.1 * k, Vec2::Zero(), 1.0, 1));
  for (const bool rotate : {true, false}) {
    PackOptions o;
    o.rotate = rotate;
    auto r = pack_charts(views(charts), o);
    REQUIRE(r.ok());
    std::vector<Vec2> uv;
    std::vector<Triangle> triangles;
    std::vector<std::uint32_t> chart_of;
    for (std::size_t c = 0; c < charts.size(); ++c) {
      const auto base = static_cast<std::uint32_t>(uv.size());
      for (const Vec2& p : charts[c].uv) {
        uv.push_back(r->placements[c].apply(p));
        CHECK(uv.back().minCoeff() >= 0);
        CHECK(uv.back().maxCoeff() <= 1);
      }
      for (const Triangle& t : charts[c].triangles) {
        triangles.push_back({base + t[0], base + t[1], base + t[2]});
        chart_of.push_back(static_cast<std::uint32_t>(c));
      }
    }
    auto overlap = find_overlaps(uv, triangles, chart_of);
    REQUIRE(overlap.ok());
    CAPTURE(rotate);
    CHECK(overlap->between_charts_area == 0);
  }
}

TEST_CASE("pack refuses bad options and malformed charts with typed errors") {
  std::vector<OwnedChart> charts{grid_chart(1, 1, 0, Vec2::Zero(), 1)};
  CHECK(pack_charts(views(charts), {.texture_size = 8}).error().code == ErrorCode::kInvalidArgument);
  CHECK(pack_charts(views(charts), {.margin_px = -1}).error().code == ErrorCode::kInvalidArgument);
  CHECK(pack_charts(views(charts), {.texture_size = 64, .margin_px = 9}).error().code == ErrorCode::kInvalidArgument);
  charts[0].surface_area = 0;
  CHECK(pack_charts(views(charts)).error().code == ErrorCode::kInvalidArgument);
  charts[0].surface_area = 1;
  charts[0].triangles.push_back({0, 1, 999});
  CHECK(pack_charts(views(charts)).error().code == ErrorCode::kIndexOutOfRange);
  charts[0].triangles.pop_back();
  charts[0].uv[0].x() = std::nan("");
  CHECK(pack_charts(views(charts)).error().code == ErrorCode::kNonFinitePosition);
  charts[0].uv[0].x() = 0;
  for (Vec2& p : charts[0].uv) p = Vec2(1, 1);  // zero UV area
  CHECK(pack_charts(views(charts)).error().code == ErrorCode::kInvalidArgument);
  auto none = pack_charts(std::span<const PackChart>{});
  REQUIRE(none.ok());
  CHECK(none->placements.empty());
}

TEST_CASE("shape packing nests a chart in a ring's hole, which no rectangle packer can") {
  // A 10 x 10 ring with a 6 x 6 hole and a 4 x 4 square: rectangles need a square of side
  // >= 14 (the square beside the ring), so their coverage is at most 80 / 196 = 0.41.
  const std::vector<OwnedChart> charts{ring_chart(10, 6), grid_chart(4, 4, 0.4, Vec2(30, 30), 1)};
  const PackResult r = pack_checked(charts, {}, 2039);
  CHECK(r.coverage > 0.7);
  // The square lies inside the ring's outer box.
  for (const Vec2& p : charts[1].uv) {
    const Vec2 q = r.placements[1].apply(p);
    CHECK((q.array() > r.placements[0].rect_min.array()).all());
    CHECK((q.array() < r.placements[0].rect_max.array()).all());
  }
}

TEST_CASE("shape packing interlocks L-shapes beyond any rectangle packer's reach") {
  // An L of arm width 1/3 fills 5/9 of its minimal rectangle (its bounding square), so packed
  // as rectangles the coverage is below 0.556; pairs of Ls interlock into 1 x 4/3 rectangles.
  std::vector<OwnedChart> charts;
  for (int k = 0; k < 8; ++k) charts.push_back(ell_chart(1.0 / 3, 0.7 * k));
  for (const PackOptions& o : {PackOptions{}, PackOptions{.texture_size = 256, .margin_px = 2}}) {
    CAPTURE(o.texture_size);
    CHECK(pack_checked(charts, o, 2039).coverage > 5.0 / 9 + 0.02);
  }
}

TEST_CASE("1,000 charts: margins hold, no overlap, one density") {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> side(0.1, 2);
  std::uniform_real_distribution<double> angle(0, 2 * std::numbers::pi);
  std::vector<OwnedChart> charts;
  for (int k = 0; k < 1000; ++k) {
    charts.push_back(k % 2 ? grid_chart(side(rng), side(rng), angle(rng), Vec2::Zero(), 1 + k % 3, 1)
                           : ell_chart(0.2 + 0.1 * (k % 5), angle(rng)));
  }
  CHECK(pack_checked(charts, {}, 4093).coverage > 0.5);
}

TEST_CASE("splitting a sprawling chart: the pieces partition it, keep its scale, and pack better") {
  const std::vector<OwnedChart> charts{comb_chart(), grid_chart(5, 4, 0.3, Vec2(50, 0), 2, 8)};
  auto split = split_sprawling_charts(views(charts));
  REQUIRE(split.ok());
  CHECK(split->charts_split == 1);  // the square grid fills its square
  std::vector<OwnedChart> pieces;
  std::map<std::size_t, std::vector<std::array<std::uint32_t, 3>>> triangles_of;  // per chart, as input vertices
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::set<std::size_t>> comb_edges;  // pieces per edge
  std::map<std::size_t, double> area_of_chart;
  for (std::size_t p = 0; p < split->pieces.size(); ++p) {
    const ChartPiece& piece = split->pieces[p];
    OwnedChart c;
    for (std::uint32_t v : piece.vertices) c.uv.push_back(charts[piece.chart].uv[v]);
    c.triangles = piece.triangles;
    c.surface_area = piece.surface_area;
    area_of_chart[piece.chart] += piece.surface_area;
    // Same scale as its chart: surface area / UV area of each piece is the chart's, 2.
    CHECK(piece.surface_area / area_of(c.uv, c.triangles) == doctest::Approx(2.0));
    REQUIRE(piece.chart_triangles.size() == piece.triangles.size());
    for (std::size_t i = 0; i < piece.triangles.size(); ++i) {
      const Triangle& t = piece.triangles[i];
      std::array<std::uint32_t, 3> source{piece.vertices[t[0]], piece.vertices[t[1]], piece.vertices[t[2]]};
      CHECK(charts[piece.chart].triangles.at(piece.chart_triangles[i]) == Triangle{source[0], source[1], source[2]});
      triangles_of[piece.chart].push_back(source);
      for (int k = 0; k < 3; ++k) {
        if (piece.chart == 0) comb_edges[std::minmax(source[k], source[(k + 1) % 3])].insert(p);
      }
    }
    pieces.push_back(std::move(c));
  }
  CHECK(pieces.size() >= 3);
  CHECK(pieces.size() <= SplitOptions{}.max_pieces + 1);
  // Every triangle of every chart is in exactly one piece, unchanged.
  for (std::size_t c = 0; c < charts.size(); ++c) {
    std::vector<std::array<std::uint32_t, 3>> expected;
    for (const Triangle& t : charts[c].triangles) expected.push_back({t[0], t[1], t[2]});
    std::sort(expected.begin(), expected.end());
    std::sort(triangles_of[c].begin(), triangles_of[c].end());
    CHECK(triangles_of[c] == expected);
    CHECK(area_of_chart[c] == doctest::Approx(charts[c].surface_area));
  }
  // The cut length: edges shared by two pieces, at the comb's scale sqrt(2).
  double cut = 0;
  for (const auto& [e, owners] : comb_edges) {
    if (owners.size() == 2) cut += std::sqrt(2.0) * (charts[0].uv[e.first] - charts[0].uv[e.second]).norm();
    CHECK(owners.size() <= 2);
  }
  CHECK(split->cut_length == doctest::Approx(cut));
  CHECK(cut > 0);
  // Packed: the pieces cover more than the whole comb, with the layout checked.
  const PackResult whole = pack_checked(charts, {}, 2047);
  const PackResult cut_up = pack_checked(pieces, {}, 2047);
  CHECK(cut_up.coverage > whole.coverage + 0.1);
  // Deterministic.
  auto again = split_sprawling_charts(views(charts));
  REQUIRE(again.ok());
  REQUIRE(again->pieces.size() == split->pieces.size());
  for (std::size_t p = 0; p < split->pieces.size(); ++p) CHECK(again->pieces[p].vertices == split->pieces[p].vertices);
  // min_fill 0 splits nothing.
  auto none = split_sprawling_charts(views(charts), {.min_fill = 0});
  REQUIRE(none.ok());
  CHECK(none->pieces.size() == charts.size());
  CHECK(none->cut_length == 0);
}

TEST_CASE("split: a chart that holds a triangle twice gives each copy to one piece, by its place in the chart") {
  // Duplicate faces stay in the asset and in their chart; the API maps pieces back to the
  // cut triangles through chart_triangles, so the two copies must be told apart there.
  OwnedChart comb = comb_chart();
  const std::size_t original = comb.triangles.size();
  for (std::size_t t = 0; t < original; t += 7) comb.triangles.push_back(comb.triangles[t]);
  const std::vector<OwnedChart> charts{comb};
  auto split = split_sprawling_charts(views(charts));
  REQUIRE(split.ok());
  REQUIRE(split->pieces.size() >= 2);
  std::vector<int> uses(comb.triangles.size(), 0);
  for (const ChartPiece& piece : split->pieces) {
    REQUIRE(piece.chart_triangles.size() == piece.triangles.size());
    for (std::size_t i = 0; i < piece.triangles.size(); ++i) {
      const Triangle& t = piece.triangles[i];
      REQUIRE(piece.chart_triangles[i] < uses.size());
      ++uses[piece.chart_triangles[i]];
      CHECK(comb.triangles[piece.chart_triangles[i]] ==
            Triangle{piece.vertices[t[0]], piece.vertices[t[1]], piece.vertices[t[2]]});
    }
  }
  CHECK(std::all_of(uses.begin(), uses.end(), [](int u) { return u == 1; }));
}

TEST_CASE("chart_pieces: cuts are edges two pieces share, between vertices or between UV points") {
  // A unit square of two triangles, flat-shaded (each triangle its own three vertices), and a
  // fin: a third triangle on the diagonal's vertices, in the first triangle's piece.
  const std::vector<Vec2> uv = {{0, 0}, {1, 0}, {1, 1}, {0, 0}, {1, 1}, {0, 1}, {1, 1}};
  const std::vector<Triangle> triangles = {{0, 1, 2}, {3, 4, 5}, {0, 6, 1}};
  const PackChart chart{uv, triangles, 1.0};
  const std::vector<std::vector<std::uint32_t>> parts = {{0, 2}, {1}};
  // By vertex: the halves share no vertex, so nothing is cut; the fin's (0, 1) edge is used
  // twice by one piece (neither a cut nor a border).
  const ChartPieces by_vertex = chart_pieces(chart, 0, parts);
  CHECK(by_vertex.cut_length == 0);
  REQUIRE(by_vertex.pieces.size() == 2);
  CHECK(by_vertex.pieces[0].vertices == std::vector<std::uint32_t>{0, 1, 2, 6});
  CHECK(by_vertex.pieces[1].vertices == std::vector<std::uint32_t>{3, 4, 5});
  // By point (3 is 0, 4 and 6 are 2): the fin lies on the first triangle's three edges, and
  // the diagonal, used three times (twice by the first piece), is the one cut, counted once.
  // The border is the second triangle's other edges. The UV area counts the fin, so the scale
  // to unit density is sqrt(1 / 1.5).
  const std::vector<std::uint32_t> point = {0, 1, 2, 0, 2, 5, 2};
  const ChartPieces by_point = chart_pieces(chart, 0, parts, point);
  const double scale = std::sqrt(1 / 1.5);
  CHECK(by_point.cut_length == doctest::Approx(std::sqrt(2.0) * scale));
  CHECK(by_point.boundary_length == doctest::Approx(2 * scale));
  // One piece: no cut, though the diagonal is used three times.
  const std::vector<std::vector<std::uint32_t>> whole = {{0, 1, 2}};
  CHECK(chart_pieces(chart, 0, whole, point).cut_length == 0);
}

TEST_CASE("split refuses bad options and malformed charts with typed errors") {
  std::vector<OwnedChart> charts{comb_chart()};
  CHECK(split_sprawling_charts(views(charts), {.min_fill = 1.5}).error().code == ErrorCode::kInvalidArgument);
  CHECK(split_sprawling_charts(views(charts), {.max_pieces = 0}).error().code == ErrorCode::kInvalidArgument);
  CHECK(split_sprawling_charts(views(charts), {.min_triangles = 1}).error().code == ErrorCode::kInvalidArgument);
  charts[0].triangles.push_back({0, 1, 99999});
  CHECK(split_sprawling_charts(views(charts)).error().code == ErrorCode::kIndexOutOfRange);
}

namespace {

// Gift wrapping, the oracle for convex_hull: from the lowest-then-leftmost point, the next
// vertex is the one every other point lies left of (the farthest on ties), counter-clockwise.
std::vector<Vec2> jarvis_hull(const std::vector<Vec2>& pts) {
  auto cross = [](const Vec2& o, const Vec2& a, const Vec2& b) {
    return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
  };
  const Vec2 start = *std::min_element(pts.begin(), pts.end(), [](const Vec2& a, const Vec2& b) {
    return a.y() < b.y() || (a.y() == b.y() && a.x() < b.x());
  });
  std::vector<Vec2> hull;
  Vec2 at = start;
  do {
    hull.push_back(at);
    Vec2 next = at;
    for (const Vec2& q : pts) {
      if (q == at) continue;
      const double c = next == at ? -1.0 : cross(at, next, q);
      if (next == at || c < 0 || (c == 0 && (q - at).squaredNorm() > (next - at).squaredNorm())) next = q;
    }
    at = next;
  } while (at != start && hull.size() <= pts.size());
  return hull;
}

}  // namespace

TEST_CASE("convex_hull equals gift wrapping on clouds whose points are mostly inside (the pre-filter's case)") {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<std::vector<Vec2>> clouds;
  for (int trial = 0; trial < 6; ++trial) {
    std::vector<Vec2> disc;
    while (disc.size() < 3000) {
      const Vec2 p(u(rng), u(rng));
      if (p.squaredNorm() <= 1) disc.emplace_back(100 * p.x() + 7, 0.01 * p.y() - 3);  // thin and far from 0
    }
    for (int k = 0; k < 40; ++k) {  // points on the circle itself, so many are hull vertices
      const double a = 2 * std::numbers::pi * u(rng);
      disc.emplace_back(100 * std::cos(a) + 7, 0.01 * std::sin(a) - 3);
    }
    clouds.push_back(std::move(disc));
  }
  std::vector<Vec2> grid;  // collinear hull edges, exact ties in every coordinate
  for (int i = 0; i < 40; ++i) {
    for (int j = 0; j < 25; ++j) grid.emplace_back(i * 0.5, j * 0.25);
  }
  clouds.push_back(grid);
  std::vector<Vec2> diamond;  // the extreme points' quadrilateral is the hull itself
  for (int i = -20; i <= 20; ++i) {
    for (int j = -20 + std::abs(i); j <= 20 - std::abs(i); ++j) diamond.emplace_back(i, j);
  }
  clouds.push_back(diamond);
  for (std::size_t c = 0; c < clouds.size(); ++c) {
    CAPTURE(c);
    const std::vector<Vec2> hull = convex_hull(clouds[c]);
    const std::vector<Vec2> oracle = jarvis_hull(clouds[c]);
    REQUIRE(hull.size() == oracle.size());
    for (std::size_t i = 0; i < hull.size(); ++i) CHECK(hull[i] == oracle[i]);
  }
}

}  // namespace seam_pack_test
