// Untangling charts before packing (core/atlas/untangle.h): a folded chart and a chart that
// overlaps itself without a fold come out as pieces that partition the chart, keep every UV,
// turn one way (after mirroring) and overlap nowhere; a valid chart is left as it is.
#include "core/atlas/untangle.h"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "core/atlas/overlap.h"
#include "core/atlas/predicates.h"

namespace seam_untangle_test {

using namespace seam::core;

namespace {

struct Chart {
  std::vector<Vec2> uv;
  std::vector<Triangle> triangles;
  double surface_area = 1;
  PackChart view() const { return {uv, triangles, surface_area}; }
};

/// A grid of nx x ny unit quads, two counter-clockwise triangles each, with `move` applied to
/// every vertex.
template <typename Move>
Chart grid(int nx, int ny, Move move) {
  Chart c;
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) c.uv.push_back(move(Vec2(i, j)));
  }
  auto id = [&](int i, int j) { return static_cast<std::uint32_t>(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      c.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      c.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return c;
}

/// A strip of n x 2 quads wound around the origin through `turn` radians, radius growing
/// from 1 to 2 along its length so that past one turn its end lies over its start (all
/// triangles counter-clockwise: it overlaps itself without a fold).
Chart spiral(int n, double turn) {
  Chart c;
  for (int i = 0; i <= n; ++i) {
    const double a = turn * i / n;
    const double r = 1 + 0.1 * a / (2 * std::numbers::pi);
    for (int j = 0; j <= 2; ++j) c.uv.emplace_back((r + 0.25 * j) * std::cos(a), (r + 0.25 * j) * std::sin(a));
  }
  auto id = [](int i, int j) { return static_cast<std::uint32_t>(3 * i + j); };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < 2; ++j) {
      c.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i + 1, j)});
      c.triangles.push_back({id(i, j), id(i, j + 1), id(i + 1, j + 1)});
    }
  }
  return c;
}

int turn_of(const Chart& c, const Triangle& t) {
  return orient2d(c.uv[t[0]], c.uv[t[1]], c.uv[t[2]]);
}

/// What every untangling must give: the pieces of chart `index` partition its triangles, keep
/// each triangle's corners (so its UVs), turn counter-clockwise once mirrored, overlap
/// nowhere, and share the chart's surface area.
void check_pieces(const Chart& chart, std::size_t index, const UntangleResult& r) {
  std::vector<int> uses(chart.triangles.size(), 0);
  double surface = 0;
  for (const ChartPiece& piece : r.pieces) {
    if (piece.chart != index) continue;
    surface += piece.surface_area;
    REQUIRE(piece.triangles.size() == piece.chart_triangles.size());
    std::vector<Vec2> uv;
    for (std::uint32_t v : piece.vertices)
      uv.emplace_back(piece.mirrored ? -chart.uv[v].x() : chart.uv[v].x(), chart.uv[v].y());
    for (std::size_t i = 0; i < piece.triangles.size(); ++i) {
      const std::uint32_t t = piece.chart_triangles[i];
      ++uses[t];
      for (int k = 0; k < 3; ++k) CHECK(piece.vertices[piece.triangles[i][k]] == chart.triangles[t][k]);
      const Triangle& local = piece.triangles[i];
      CHECK(orient2d(uv[local[0]], uv[local[1]], uv[local[2]]) >= 0);
    }
    auto overlap = find_overlaps(uv, piece.triangles);
    REQUIRE(overlap.ok());
    CHECK_FALSE(overlap->overlaps);
  }
  for (int u : uses) CHECK(u == 1);
  CHECK(surface == doctest::Approx(chart.surface_area));
}

UntangleResult untangled(const std::vector<PackChart>& charts) {
  auto r = untangle_charts(charts);
  REQUIRE(r.ok());
  return std::move(r).value();
}

}  // namespace

TEST_CASE("a folded chart splits at the fold: the folded-back part is one mirrored piece") {
  // 4 x 2 quads; past u = 3 the grid folds back over itself (u -> 6 - u), so the last column
  // turns clockwise and lies over the column before it.
  const Chart chart = grid(4, 2, [](Vec2 p) { return p.x() > 3 ? Vec2(6 - p.x(), p.y()) : p; });
  std::size_t clockwise = 0;
  for (const Triangle& t : chart.triangles) clockwise += turn_of(chart, t) < 0 ? 1 : 0;
  REQUIRE(clockwise == 4);
  const UntangleResult r = untangled({chart.view()});
  check_pieces(chart, 0, r);
  CHECK(r.charts_untangled == 1);
  CHECK(r.pieces.size() == 2);
  CHECK(r.pieces_added == 1);
  CHECK(r.pieces_mirrored == 1);
  CHECK(r.unflipped == 4);
  CHECK(r.pieces[1].mirrored);
  CHECK(r.pieces[1].triangles.size() == 4);
  CHECK(r.cut_length > 0);
}

TEST_CASE("a strip wound past a full turn overlaps itself without a fold and splits where it comes round") {
  const Chart chart = spiral(48, 2.5 * std::numbers::pi);
  for (const Triangle& t : chart.triangles) REQUIRE(turn_of(chart, t) > 0);
  auto before = find_overlaps(chart.uv, chart.triangles);
  REQUIRE(before.ok());
  REQUIRE(before->overlaps);
  const UntangleResult r = untangled({chart.view()});
  check_pieces(chart, 0, r);
  CHECK(r.charts_untangled == 1);
  CHECK(r.pieces_mirrored == 0);
  CHECK(r.unflipped == 0);
  // The first piece goes round once (38.4 of the 48 columns of 4 triangles); what comes round
  // over it is one more piece.
  CHECK(r.pieces.size() == 2);
  CHECK(r.pieces[0].triangles.size() >= 38 * 4 - 4);
}

TEST_CASE("a valid chart, or one with a triangle of no area, is left as one piece with its own order") {
  Chart chart = grid(3, 3, [](Vec2 p) { return Vec2(p.x() + 0.1 * p.y() * p.y(), p.y()); });
  // A sliver of zero area along the bottom edge: no interior, so neither flipped nor overlapping.
  chart.uv.emplace_back(1.5, 0);
  chart.triangles.push_back({0, 1, static_cast<std::uint32_t>(chart.uv.size() - 1)});
  REQUIRE(turn_of(chart, chart.triangles.back()) == 0);
  const UntangleResult r = untangled({chart.view(), chart.view()});
  check_pieces(chart, 0, r);
  check_pieces(chart, 1, r);
  CHECK(r.charts_untangled == 0);
  CHECK(r.pieces_added == 0);
  REQUIRE(r.pieces.size() == 2);
  const ChartPiece& piece = r.pieces[0];
  CHECK_FALSE(piece.mirrored);
  for (std::uint32_t t = 0; t < chart.triangles.size(); ++t) CHECK(piece.chart_triangles[t] == t);
  CHECK(piece.vertices.front() == chart.triangles[0][0]);
  CHECK(r.cut_length == 0);
}

TEST_CASE("a chart that turns clockwise everywhere is mirrored whole, and a degenerate triangle joins a piece") {
  Chart chart = grid(2, 2, [](Vec2 p) { return Vec2(-p.x(), p.y()); });
  chart.uv.emplace_back(-3, 0);  // on the line v = 0 through vertices 0, 1, 2: no area
  chart.triangles.push_back({1, 2, static_cast<std::uint32_t>(chart.uv.size() - 1)});
  REQUIRE(turn_of(chart, chart.triangles.back()) == 0);
  const UntangleResult r = untangled({chart.view()});
  check_pieces(chart, 0, r);
  CHECK(r.charts_untangled == 1);
  CHECK(r.pieces.size() == 1);
  CHECK(r.pieces_mirrored == 1);
  CHECK(r.unflipped == 8);
}

TEST_CASE("untangling is deterministic: the same charts give the same pieces") {
  const Chart fold = grid(6, 3, [](Vec2 p) { return p.x() > 2 ? Vec2(4 - p.x(), p.y() + 0.05 * p.x()) : p; });
  const Chart coil = spiral(64, 3.2 * std::numbers::pi);
  const std::vector<PackChart> charts{fold.view(), coil.view(), fold.view()};
  const UntangleResult a = untangled(charts);
  const UntangleResult b = untangled(charts);
  check_pieces(fold, 0, a);
  check_pieces(coil, 1, a);
  check_pieces(fold, 2, a);
  CHECK(a.charts_untangled == 3);
  REQUIRE(a.pieces.size() == b.pieces.size());
  for (std::size_t i = 0; i < a.pieces.size(); ++i) {
    CHECK(a.pieces[i].chart == b.pieces[i].chart);
    CHECK(a.pieces[i].vertices == b.pieces[i].vertices);
    CHECK(a.pieces[i].chart_triangles == b.pieces[i].chart_triangles);
    CHECK(a.pieces[i].mirrored == b.pieces[i].mirrored);
    CHECK(a.pieces[i].surface_area == b.pieces[i].surface_area);
  }
  CHECK(a.cut_length == b.cut_length);
}

TEST_CASE("untangle refuses malformed charts with typed errors") {
  Chart chart = grid(1, 1, [](Vec2 p) { return p; });
  chart.triangles.push_back({0, 1, 9});
  CHECK(untangle_charts(std::vector<PackChart>{chart.view()}).error().code == ErrorCode::kIndexOutOfRange);
  Chart flat = grid(2, 1, [](Vec2 p) { return Vec2(p.x(), 0); });
  CHECK(untangle_charts(std::vector<PackChart>{flat.view()}).error().code == ErrorCode::kInvalidArgument);
  CancelToken cancel;
  cancel.cancel();
  const Chart fold = grid(4, 2, [](Vec2 p) { return p.x() > 3 ? Vec2(6 - p.x(), p.y()) : p; });
  CHECK(untangle_charts(std::vector<PackChart>{fold.view()}, cancel).error().code == ErrorCode::kCancelled);
}

}  // namespace seam_untangle_test
