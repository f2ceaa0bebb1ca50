// The shape packer's chart cells (core/atlas/raster_pack.h): the cells a chart touches in
// any orientation, drawn from its outline and winding numbers where its triangles have one
// orientation and triangle by triangle otherwise, checked against a separating-axis oracle
// (every cell a triangle meets is marked; every marked cell is within a hair of one) and
// against each other; and the packer's layouts keep the charts' points apart.
#include "core/atlas/raster_pack.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "core/mesh/topology.h"
#include "core/uv/parameterize.h"
#include "core/uv/uv_patch.h"
#include "test_data.h"

namespace seam_raster_pack_test {

using namespace seam::core;
using seam::core::detail::ChartCells;
using seam::core::detail::RasterChart;

namespace {

struct OwnedChart {
  std::vector<Vec2> uv;
  std::vector<Triangle> triangles;
  RasterChart view(double scale = 1) const { return {uv, triangles, scale, {0.0}}; }
};

// An n x n grid over [x0, x0 + side]^2 with its centre hole of h x h cells left out (h = 0:
// none), two triangles per cell, counter-clockwise, appended to `c`.
void add_grid(OwnedChart& c, double x0, double y0, double side, int n, int hole = 0) {
  const auto base = static_cast<std::uint32_t>(c.uv.size());
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) c.uv.emplace_back(x0 + side * i / n, y0 + side * j / n);
  }
  auto id = [&](int i, int j) { return base + static_cast<std::uint32_t>(j * (n + 1) + i); };
  const int h0 = (n - hole) / 2;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      if (hole > 0 && i >= h0 && i < h0 + hole && j >= h0 && j < h0 + hole) continue;
      c.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      c.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
}

// The same triangles, each with vertices of its own (a soup, as a mesh split at every edge).
OwnedChart unwelded(const OwnedChart& c) {
  OwnedChart out;
  for (const Triangle& t : c.triangles) {
    const auto base = static_cast<std::uint32_t>(out.uv.size());
    for (std::uint32_t v : t) out.uv.push_back(c.uv[v]);
    out.triangles.push_back({base, base + 1, base + 2});
  }
  return out;
}

// Whether the closed triangle (a, b, c) and the closed box [lo, hi] come within `tol` of each
// other (separating axes: the box's two, the triangle's three edge normals). tol < 0 asks
// them to overlap by at least -tol.
bool meets(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& lo, const Vec2& hi, double tol) {
  const std::array<Vec2, 3> tri = {a, b, c};
  const std::array<Vec2, 4> box = {lo, Vec2(hi.x(), lo.y()), hi, Vec2(lo.x(), hi.y())};
  std::vector<Vec2> axes = {Vec2(1, 0), Vec2(0, 1)};
  for (int k = 0; k < 3; ++k) {
    const Vec2 e = tri[(k + 1) % 3] - tri[k];
    if (e.norm() > 0) axes.emplace_back(-e.y() / e.norm(), e.x() / e.norm());
  }
  for (const Vec2& n : axes) {
    double t0 = 1e300, t1 = -1e300, b0 = 1e300, b1 = -1e300;
    for (const Vec2& p : tri) t0 = std::min(t0, n.dot(p)), t1 = std::max(t1, n.dot(p));
    for (const Vec2& p : box) b0 = std::min(b0, n.dot(p)), b1 = std::max(b1, n.dot(p));
    if (t1 + tol < b0 || b1 + tol < t0) return false;
  }
  return true;
}

// Checks the cells of `chart` at `angle` against the oracle: a cell that a triangle overlaps
// by 1e-6 of a cell is marked, and a marked cell is within 1e-6 of a cell of a triangle.
void check_against_oracle(const OwnedChart& chart, double scale, double angle, double cell) {
  const ChartCells cells(chart.view(scale));
  const ChartCells::Cells got = cells.cells(angle, cell);
  REQUIRE(got.words == (got.w + 63) / 64);
  REQUIRE(got.bits.size() == static_cast<std::size_t>(got.words) * got.h);
  const double c = std::cos(angle), s = std::sin(angle);
  std::vector<Vec2> p;
  for (const Vec2& q : chart.uv) p.emplace_back(scale * (c * q.x() - s * q.y()), scale * (s * q.x() + c * q.y()));
  std::vector<std::pair<Vec2, Vec2>> box;  // each triangle's, to skip far cells quickly
  for (const Triangle& t : chart.triangles) {
    box.emplace_back(p[t[0]].cwiseMin(p[t[1]]).cwiseMin(p[t[2]]), p[t[0]].cwiseMax(p[t[1]]).cwiseMax(p[t[2]]));
  }
  std::size_t marked = 0, missed = 0, spurious = 0;
  for (int j = 0; j < got.h; ++j) {
    for (int i = 0; i < got.w; ++i) {
      const Vec2 lo = got.lo + Vec2(i, j) * cell;
      const Vec2 hi = lo + Vec2::Constant(cell);
      bool overlaps = false, near = false;
      for (std::size_t k = 0; k < chart.triangles.size(); ++k) {
        if ((box[k].first.array() > hi.array() + cell).any() || (box[k].second.array() < lo.array() - cell).any()) {
          continue;
        }
        const Triangle& t = chart.triangles[k];
        near = near || meets(p[t[0]], p[t[1]], p[t[2]], lo, hi, 1e-6 * cell);
        overlaps = overlaps || meets(p[t[0]], p[t[1]], p[t[2]], lo, hi, -1e-6 * cell);
        if (overlaps) break;
      }
      const bool set = got.at(i, j);
      marked += set;
      missed += overlaps && !set;
      spurious += set && !near;
    }
  }
  CAPTURE(angle);
  CHECK(marked > 0);
  CHECK(missed == 0);
  CHECK(spurious == 0);
}

}  // namespace

TEST_CASE("chart cells from the outline: the cells the triangles touch, in any orientation") {
  OwnedChart square;
  add_grid(square, 0.3, -0.2, 2.0, 6);
  OwnedChart ring;
  add_grid(ring, 0, 0, 3.0, 9, 5);
  CHECK(ChartCells(square.view()).by_outline());
  CHECK(ChartCells(ring.view()).by_outline());
  for (double angle : {0.0, 0.3, std::numbers::pi / 4, 2.0, 4.5}) {
    check_against_oracle(square, 1.0, angle, 0.13);
    check_against_oracle(ring, 0.7, angle, 0.09);
  }
}

TEST_CASE("chart cells: overlapping triangles of one orientation still fill from the outline") {
  // Two grids overlapping by half, nothing shared: winding 2 where they overlap.
  OwnedChart two;
  add_grid(two, 0, 0, 2.0, 4);
  add_grid(two, 1.0, 0.5, 2.0, 5);
  REQUIRE(ChartCells(two.view()).by_outline());
  for (double angle : {0.0, 1.1}) check_against_oracle(two, 1.0, angle, 0.1);
}

TEST_CASE("chart cells: a mesh split at every edge has the outline of the welded one") {
  OwnedChart ring;
  add_grid(ring, 0, 0, 3.0, 8, 4);
  const OwnedChart soup = unwelded(ring);
  const ChartCells welded_cells(ring.view());
  const ChartCells soup_cells(soup.view());
  CHECK(soup_cells.by_outline());
  for (double angle : {0.0, 0.7, 3.0}) {
    const auto a = welded_cells.cells(angle, 0.11);
    const auto b = soup_cells.cells(angle, 0.11);
    CHECK(a.w == b.w);
    CHECK(a.h == b.h);
    CHECK(a.bits == b.bits);
  }
}

TEST_CASE("chart cells: folded or degenerate triangles are drawn one by one, with the same cells") {
  OwnedChart grid;
  add_grid(grid, 0, 0, 2.0, 5);
  // A degenerate triangle along one of the chart's own edges adds no cell.
  OwnedChart with_sliver = grid;
  with_sliver.triangles.push_back({0, 1, 1});
  const ChartCells plain(grid.view());
  const ChartCells sliver(with_sliver.view());
  REQUIRE(plain.by_outline());
  CHECK_FALSE(sliver.by_outline());
  for (double angle : {0.0, 0.4, 2.5}) CHECK(plain.cells(angle, 0.07).bits == sliver.cells(angle, 0.07).bits);

  // A fold: one vertex pulled across its neighbours flips triangles; the oracle still holds.
  OwnedChart folded = grid;
  folded.uv[7 + 6] += Vec2(0.9, 0.5);
  CHECK_FALSE(ChartCells(folded.view()).by_outline());
  for (double angle : {0.0, 0.9}) check_against_oracle(folded, 1.0, angle, 0.1);
}

TEST_CASE("chart cells of randomly jittered grids, folded or not, at random angles and cell sizes") {
  std::mt19937 rng(2026);
  std::uniform_real_distribution<double> unit(0, 1);
  int by_outline = 0, by_triangles = 0;
  for (int trial = 0; trial < 40; ++trial) {
    OwnedChart chart;
    add_grid(chart, 0, 0, 2.0, 6, trial % 3 == 0 ? 2 : 0);
    // Jitter up to 0.45 of the spacing keeps every triangle's orientation only sometimes.
    const double amount = 0.15 * (1 + trial % 4) * (2.0 / 6);
    for (Vec2& p : chart.uv) p += amount * Vec2(unit(rng) - 0.5, unit(rng) - 0.5) * 2;
    (ChartCells(chart.view()).by_outline() ? by_outline : by_triangles) += 1;
    check_against_oracle(chart, 0.5 + unit(rng), 2 * std::numbers::pi * unit(rng), 0.05 + 0.2 * unit(rng));
  }
  // Both ways were exercised.
  CHECK(by_outline > 5);
  CHECK(by_triangles > 5);
}

TEST_CASE("chart cells of a comb of thin teeth, whose outline crosses every row many times") {
  // 200 teeth 0.01 wide and 2 tall on a strip of two rows: one orientation, an outline shorter
  // than the triangles, and ~20 crossings per cell at cells of 0.1 (drawn triangle by
  // triangle); the cells are still those the triangles touch.
  OwnedChart comb;
  const int teeth = 200;
  const double d = 0.01;
  auto at = [&](int row, int i) { return static_cast<std::uint32_t>(row * (teeth + 1) + i); };
  for (int row = 0; row < 3; ++row) {
    for (int i = 0; i <= teeth; ++i) comb.uv.emplace_back(i * d, (row - 2) * d);
  }
  for (int row = 0; row < 2; ++row) {
    for (int i = 0; i < teeth; ++i) {
      comb.triangles.push_back({at(row, i), at(row, i + 1), at(row + 1, i + 1)});
      comb.triangles.push_back({at(row, i), at(row + 1, i + 1), at(row + 1, i)});
    }
  }
  for (int i = 0; i < teeth; ++i) {
    comb.uv.emplace_back((i + 0.5) * d, 2.0);
    comb.triangles.push_back({at(2, i), at(2, i + 1), static_cast<std::uint32_t>(comb.uv.size() - 1)});
  }
  REQUIRE(ChartCells(comb.view()).by_outline());
  check_against_oracle(comb, 1.0, 0.0, 0.1);
  check_against_oracle(comb, 1.0, 0.2, 0.1);
}

TEST_CASE("chart cells of a real flattened mesh, and random rotations and cell sizes") {
  const HalfedgeMesh mesh = seam::test_data::load_cgal_halfedge("mushroom");
  const Topology topo = compute_topology(mesh);
  auto patches = extract_disc_patches(mesh, topo);
  REQUIRE(patches.ok());
  REQUIRE(!patches->empty());
  auto uv = parameterize(mesh);
  REQUIRE(uv.ok());
  const DiscPatch& patch = patches->front();
  OwnedChart chart;
  for (VertexId v : patch.to_mesh) chart.uv.push_back(uv->uv[v]);
  chart.triangles = patch.triangles;
  const ChartCells cells(chart.view());
  CHECK(cells.by_outline());
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(0, 2 * std::numbers::pi);
  Vec2 lo = chart.uv[0], hi = chart.uv[0];
  for (const Vec2& p : chart.uv) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double extent = (hi - lo).maxCoeff();
  for (int k = 0; k < 3; ++k) check_against_oracle(chart, 1.0, angle(rng), extent / (12 + 9 * k));
}

TEST_CASE("raster_pack: charts placed apart by the margin, inside the returned square") {
  std::vector<OwnedChart> owned(4);
  add_grid(owned[0], 0, 0, 4.0, 6, 2);
  add_grid(owned[1], 0, 0, 1.5, 3);
  add_grid(owned[2], 5, 5, 2.5, 4);
  owned[3] = unwelded(owned[1]);
  std::vector<RasterChart> charts;
  for (const OwnedChart& c : owned) charts.push_back({c.uv, c.triangles, 1.0, {0.0, std::numbers::pi / 2, 0.5}});
  const std::vector<std::size_t> order = {0, 2, 1, 3};
  const double margin = 0.02;
  const detail::RasterLayout layout = detail::raster_pack(charts, order, 12.0, margin, 256);
  REQUIRE(std::isfinite(layout.side));
  REQUIRE(layout.slots.size() == owned.size());
  // Each chart's points as placed: inside the square by half a margin, and the boxes of two
  // charts' points apart by a margin along x or y (what the grown cells guarantee).
  std::vector<std::pair<Vec2, Vec2>> boxes;
  for (std::size_t k = 0; k < owned.size(); ++k) {
    const detail::PlacedChart& slot = layout.slots[k];
    const double c = std::cos(slot.angle), s = std::sin(slot.angle);
    Vec2 lo = Vec2::Constant(1e300), hi = -lo;
    for (const Vec2& q : owned[k].uv) {
      const Vec2 p = Vec2(c * q.x() - s * q.y(), s * q.x() + c * q.y()) + slot.offset;
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    CHECK(lo.minCoeff() >= 0.5 * margin * layout.side - 1e-9);
    CHECK(hi.maxCoeff() <= layout.side * (1 - 0.5 * margin) + 1e-9);
    boxes.emplace_back(lo, hi);
  }
  // Grids are convex or a ring around a hole too small for the others, so boxes apart is
  // what apart means here.
  for (std::size_t a = 0; a < boxes.size(); ++a) {
    for (std::size_t b = a + 1; b < boxes.size(); ++b) {
      const double gap_x = std::max(boxes[b].first.x() - boxes[a].second.x(), boxes[a].first.x() - boxes[b].second.x());
      const double gap_y = std::max(boxes[b].first.y() - boxes[a].second.y(), boxes[a].first.y() - boxes[b].second.y());
      CAPTURE(a);
      CAPTURE(b);
      CHECK(std::max(gap_x, gap_y) >= margin * layout.side - 1e-9);
    }
  }
}

}  // namespace seam_raster_pack_test
