// Exact UV overlap detection: touching layouts (shared edges, shared vertices, collinear
// contact) report nothing, overlapping ones report the area a rasterization measures, and
// malformed input is a typed error. The predicates themselves: predicates_test.cpp.
#include "core/atlas/overlap.h"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "atlas_test_util.h"
#include "core/mesh/cut.h"
#include "core/seam/cut_graph.h"
#include "core/uv/parameterize.h"
#include "fixture_mesh.h"
#include "test_data.h"

namespace seam_overlap_test {

using namespace seam::core;
namespace fx = seam::fixtures;
namespace at = seam::atlas_test;

namespace {

/// A strip of `n` x 2 quads bent around the origin through `turn` radians (radius 1 to 2).
/// Beyond 2 pi the strip covers itself.
struct Layout {
  std::vector<Vec2> uv;
  std::vector<Triangle> triangles;
};

Layout bent_strip(int n, double turn) {
  Layout l;
  for (int i = 0; i <= n; ++i) {
    const double a = turn * i / n;
    for (int j = 0; j <= 2; ++j) l.uv.emplace_back((1 + 0.5 * j) * std::cos(a), (1 + 0.5 * j) * std::sin(a));
  }
  auto id = [](int i, int j) { return static_cast<std::uint32_t>(3 * i + j); };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < 2; ++j) {
      l.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      l.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return l;
}

OverlapResult overlaps_of(const Layout& l) {
  auto r = find_overlaps(l.uv, l.triangles);
  REQUIRE(r.ok());
  return *r;
}

}  // namespace

TEST_CASE("touching is not overlap: shared edges, shared vertices, collinear contact") {
  using T = std::array<Vec2, 3>;
  const T base{Vec2(0, 0), Vec2(2, 0), Vec2(0, 2)};
  CHECK_FALSE(triangle_interiors_intersect(base, T{Vec2(2, 0), Vec2(2, 2), Vec2(0, 2)}));   // shared edge
  CHECK_FALSE(triangle_interiors_intersect(base, T{Vec2(0, 0), Vec2(-1, -1), Vec2(1, -3)}));  // shared vertex
  CHECK_FALSE(triangle_interiors_intersect(base, T{Vec2(0.5, 0), Vec2(1.5, 0), Vec2(1, -1)}));  // on an edge
  CHECK_FALSE(triangle_interiors_intersect(base, T{Vec2(1, 1), Vec2(3, 1), Vec2(3, 3)}));  // vertex on edge
  CHECK_FALSE(triangle_interiors_intersect(base, T{Vec2(0, 0), Vec2(1, 1), Vec2(2, 2)}));  // degenerate
  CHECK(triangle_interiors_intersect(base, base));                                         // identical
  CHECK(triangle_interiors_intersect(base, T{Vec2(0, 2), Vec2(2, 0), Vec2(0, 0)}));       // identical, cw
  CHECK(triangle_interiors_intersect(base, T{Vec2(0.2, 0.2), Vec2(0.4, 0.2), Vec2(0.2, 0.4)}));  // inside
  // Shifted copy: T2 = (1,0),(3,0),(1,2) meets T1 in the triangle (1,0),(2,0),(1,1), area 1/2.
  const T shifted{Vec2(1, 0), Vec2(3, 0), Vec2(1, 2)};
  CHECK(triangle_interiors_intersect(base, shifted));
  CHECK(triangle_intersection_area(base, shifted) == doctest::Approx(0.5));
  CHECK(triangle_intersection_area(base, base) == doctest::Approx(2.0));
  // A hexagram: two triangles crossing in a hexagon of 2/3 of either's area.
  const T up{Vec2(0, 1), Vec2(-std::sqrt(3.0) / 2, -0.5), Vec2(std::sqrt(3.0) / 2, -0.5)};
  const T down{Vec2(0, -1), Vec2(std::sqrt(3.0) / 2, 0.5), Vec2(-std::sqrt(3.0) / 2, 0.5)};
  CHECK(triangle_intersection_area(up, down) == doctest::Approx(2.0 / 3.0 * (3 * std::sqrt(3.0) / 4)));
}

TEST_CASE("a strip bent through less than a full turn has no overlap, past it the excess shows") {
  const OverlapResult open = overlaps_of(bent_strip(60, 1.9 * std::numbers::pi));
  CHECK_FALSE(open.overlaps);
  CHECK(open.overlap_area == 0);
  CHECK(open.overlapping_pairs == 0);
  CHECK(open.proven_by_boundary);  // a disc with a simple boundary (clockwise, as its triangles)
  CHECK(open.candidate_pairs == 0);
  // Exactly a full turn: the ends touch along a radial edge and nothing more.
  CHECK_FALSE(overlaps_of(bent_strip(60, 2 * std::numbers::pi)).overlaps);
  // Two unit squares sharing the edge x = 1 with vertices of their own at equal coordinates
  // (a mesh split along a hard edge or a seam): vertices at one point are one, the shared
  // edge's two directions cancel, and the boundary of the 2 x 1 rectangle proves it.
  Layout squares;
  squares.uv = {Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1), Vec2(1, 0), Vec2(2, 0), Vec2(2, 1), Vec2(1, 1)};
  squares.triangles = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}};
  const OverlapResult split = overlaps_of(squares);
  CHECK_FALSE(split.overlaps);
  CHECK(split.proven_by_boundary);
  // Touching along half of that edge, or only at a corner (a pinch): the boundaries meet, so
  // the proof defers and the pairs decide: no overlap.
  for (const double shift : {0.5, 1.0}) {
    Layout touch = squares;
    for (int v = 4; v < 8; ++v) touch.uv[v].y() += shift;
    const OverlapResult touching = overlaps_of(touch);
    CAPTURE(shift);
    CHECK_FALSE(touching.overlaps);
    CHECK_FALSE(touching.proven_by_boundary);
    CHECK(touching.candidate_pairs > 0);
  }
  squares.uv[4].x() = squares.uv[7].x() = 1.25;  // apart: proven without pairs
  CHECK(overlaps_of(squares).proven_by_boundary);
  squares.uv[4].x() = squares.uv[7].x() = 0.75;  // overlapping by a quarter of a square
  const OverlapResult over = overlaps_of(squares);
  CHECK_FALSE(over.proven_by_boundary);
  CHECK(over.overlap_area == doctest::Approx(0.25));

  const Layout bent = bent_strip(80, 2.5 * std::numbers::pi);
  const OverlapResult r = overlaps_of(bent);
  CHECK(r.overlaps);
  // The raster oracle: pair-weighted count of doubly covered samples.
  const at::RasterCount raster = at::rasterize(bent.uv, bent.triangles, 1500);
  CHECK(r.overlap_area == doctest::Approx(raster.pair_weighted * raster.sample_area).epsilon(0.01));
  // And the geometry: the excess half turn of the annulus (the polygon inscribes the circles).
  const double annulus_sector = 0.5 * (0.5 * std::numbers::pi) * (4 - 1);
  CHECK(r.overlap_area == doctest::Approx(annulus_sector).epsilon(0.01));
  CHECK(r.overlap_fraction == doctest::Approx(r.overlap_area / r.uv_area));
  CHECK(r.within_chart_area == r.overlap_area);
  CHECK(r.first_pair[0] < r.first_pair[1]);
}

TEST_CASE("charts placed apart or touching do not overlap, a moved copy does and is counted between charts") {
  const HalfedgeMesh disc = fx::build_fixture(fx::disc(5, 20));
  Layout l;
  std::vector<std::uint32_t> chart;
  for (int copy = 0; copy < 3; ++copy) {
    const auto base = static_cast<std::uint32_t>(l.uv.size());
    // Unit discs centred 2 apart: the first two touch at a vertex (x = 1), the third overlaps the second.
    const double cx = copy == 2 ? 3.5 : 2.0 * copy;
    for (const Vec3& p : disc.positions()) l.uv.emplace_back(p.x() + cx, p.y());
    for (const Triangle& t : disc.triangles()) {
      l.triangles.push_back({base + t[0], base + t[1], base + t[2]});
      chart.push_back(static_cast<std::uint32_t>(copy));
    }
  }
  auto r = find_overlaps(l.uv, l.triangles, chart);
  REQUIRE(r.ok());
  CHECK(r->overlaps);
  CHECK(r->within_chart_area == 0);
  CHECK(r->between_charts_area == r->overlap_area);
  const at::RasterCount raster = at::rasterize(l.uv, l.triangles, 2000);
  CHECK(r->overlap_area == doctest::Approx(raster.pair_weighted * raster.sample_area).epsilon(0.02));

  // Without the third copy: the two discs touch at (1, 0) only.
  Layout two = l;
  two.triangles.resize(2 * disc.num_faces());
  auto touching = find_overlaps(two.uv, two.triangles);
  REQUIRE(touching.ok());
  CHECK_FALSE(touching->overlaps);
}

TEST_CASE("a genus-3 slab cut to a disc and flattened: the reported overlap is what a rasterization counts") {
  const HalfedgeMesh slab = fx::build_fixture(fx::holed_slab(3));
  auto cut_edges = compute_cut_graph(slab);
  REQUIRE(cut_edges.ok());
  auto cut = cut_along_edges(slab, *cut_edges);
  REQUIRE(cut.ok());
  UvOptions bff;
  bff.method = UvMethod::kBff;
  for (const UvOptions& options : {UvOptions{}, bff}) {
    auto uv = parameterize(cut->mesh, options);
    REQUIRE(uv.ok());
    auto r = find_overlaps(cut->mesh, uv->uv);
    REQUIRE(r.ok());
    const std::vector<Triangle> tris = cut->mesh.triangles();
    const at::RasterCount raster = at::rasterize(uv->uv.raw(), tris, 2048);
    const double raster_area = raster.pair_weighted * raster.sample_area;
    CAPTURE(uv_method_name(options.method));
    CAPTURE(r->overlap_area);
    CAPTURE(raster_area);
    // Raster error: about one sample row along each overlap boundary.
    CHECK(std::abs(r->overlap_area - raster_area) <= 0.02 * r->uv_area);
    CHECK(r->overlaps == (r->overlap_area > 0));
    if (raster.twice > 0) CHECK(r->overlaps);
  }
}

TEST_CASE("malformed layouts are typed errors") {
  std::vector<Vec2> uv{Vec2(0, 0), Vec2(1, 0), Vec2(0, 1)};
  std::vector<Triangle> tris{{0, 1, 3}};
  auto r = find_overlaps(uv, tris);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == ErrorCode::kIndexOutOfRange);
  tris = {{0, 1, 2}};
  uv[1] = Vec2(std::nan(""), 0);
  r = find_overlaps(uv, tris);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == ErrorCode::kNonFinitePosition);
  uv[1] = Vec2(1, 0);
  const std::vector<std::uint32_t> chart{0, 0};
  r = find_overlaps(uv, tris, chart);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == ErrorCode::kInvalidArgument);
  CancelToken token;
  token.cancel();
  const Layout big = bent_strip(4000, 1.0);
  r = find_overlaps(big.uv, big.triangles, {}, token);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == ErrorCode::kCancelled);
  // Empty layouts are fine: nothing overlaps.
  auto empty = find_overlaps(std::span<const Vec2>{}, std::span<const Triangle>{});
  REQUIRE(empty.ok());
  CHECK_FALSE(empty->overlaps);
}

TEST_CASE("the boundary proof of no overlap agrees with testing every pair, and defers on touches, nesting and flips") {
  // Layouts of 1-3 charts: bent strips (some past a full turn), discs placed apart, touching,
  // overlapping or nested, with jitter and the odd flipped triangle. The oracle tests every
  // pair of triangles exactly.
  const HalfedgeMesh disc = fx::build_fixture(fx::disc(4, 12));
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int proven = 0;
  int deferred = 0;
  for (int trial = 0; trial < 200; ++trial) {
    Layout l;
    const int charts = 1 + trial % 3;
    for (int c = 0; c < charts; ++c) {
      const auto base = static_cast<std::uint32_t>(l.uv.size());
      Layout part;
      if ((trial + c) % 2 == 0) {
        part = bent_strip(12 + trial % 7, (1.2 + 1.3 * unit(rng)) * std::numbers::pi);
      } else {
        for (const Vec3& p : disc.positions()) part.uv.emplace_back(p.x(), p.y());
        part.triangles = disc.triangles();
      }
      const double scale = c == 0 ? 1.0 : 0.2 + unit(rng);
      const Vec2 offset(c == 0 ? 0.0 : 6.0 * unit(rng) - 3.0, c == 0 ? 0.0 : 6.0 * unit(rng) - 3.0);
      for (Vec2& p : part.uv) p = scale * p + offset + Vec2(0.01 * unit(rng), 0.01 * unit(rng)) * (trial % 4 == 0);
      if (trial % 9 == 0) std::swap(part.triangles[0][1], part.triangles[0][2]);  // one flipped triangle
      for (const Vec2& p : part.uv) l.uv.push_back(p);
      for (const Triangle& t : part.triangles) l.triangles.push_back({base + t[0], base + t[1], base + t[2]});
    }
    bool any = false;
    for (std::size_t a = 0; a < l.triangles.size() && !any; ++a) {
      for (std::size_t b = a + 1; b < l.triangles.size() && !any; ++b) {
        const std::array<Vec2, 3> ta{l.uv[l.triangles[a][0]], l.uv[l.triangles[a][1]], l.uv[l.triangles[a][2]]};
        const std::array<Vec2, 3> tb{l.uv[l.triangles[b][0]], l.uv[l.triangles[b][1]], l.uv[l.triangles[b][2]]};
        any = triangle_interiors_intersect(ta, tb);
      }
    }
    const OverlapResult r = overlaps_of(l);
    CAPTURE(trial);
    CHECK(r.overlaps == any);
    if (r.proven_by_boundary) {
      CHECK_FALSE(any);
      CHECK(r.overlap_area == 0);
      ++proven;
    } else {
      ++deferred;
    }
  }
  // Both paths were taken often enough to mean something.
  CHECK(proven >= 30);
  CHECK(deferred >= 30);
}

TEST_CASE("a chart inside another, both counter-clockwise and disjoint in outline, is found by the pair test") {
  const HalfedgeMesh disc = fx::build_fixture(fx::disc(4, 12));
  Layout l;
  for (double scale : {1.0, 0.3}) {
    const auto base = static_cast<std::uint32_t>(l.uv.size());
    for (const Vec3& p : disc.positions()) l.uv.emplace_back(scale * p.x() + 0.01, scale * p.y() + 0.02);
    for (const Triangle& t : disc.triangles()) l.triangles.push_back({base + t[0], base + t[1], base + t[2]});
  }
  const OverlapResult r = overlaps_of(l);
  CHECK_FALSE(r.proven_by_boundary);
  CHECK(r.overlaps);
  // The small disc's area (0.3^2 of the big one's) is covered twice.
  CHECK(r.overlap_area == doctest::Approx(r.uv_area * 0.09 / 1.09).epsilon(1e-9));
}

}  // namespace seam_overlap_test
