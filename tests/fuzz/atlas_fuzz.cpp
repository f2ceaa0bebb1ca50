// libFuzzer target for the atlas: pack_charts (the rectangle, column-profile and shape
// packers), untangle_charts and find_overlaps on charts decoded from the input, folded,
// degenerate, overlapping or malformed. Bad charts must come back as typed errors; a packed
// layout must keep every two charts apart, which find_overlaps on the placed charts checks
// exactly (no area between charts), and keep every point in [0,1]^2. The untangled pieces
// must hold every triangle of their chart exactly once, over the chart's own UVs, each piece
// turning one way (clockwise exactly when it is mirrored; zero-area triangles aside) and
// overlapping itself nowhere.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "core/atlas/overlap.h"
#include "core/atlas/pack.h"
#include "core/atlas/predicates.h"
#include "core/atlas/untangle.h"

namespace {

// The input read front to back; past its end every read is 0.
struct Reader {
  const std::uint8_t* data;
  std::size_t size;
  std::size_t at = 0;
  std::uint8_t byte() { return at < size ? data[at++] : 0; }
  int coordinate() { return static_cast<std::int16_t>(byte() | (byte() << 8)); }
};

struct Chart {
  std::vector<seam::core::Vec2> uv;
  std::vector<seam::core::Triangle> triangles;
  double area = 0;
};

// The untangling's properties (see the file comment); traps on a violation.
void check_untangled(const std::vector<Chart>& charts, const std::vector<seam::core::PackChart>& input) {
  using namespace seam::core;
  auto untangled = untangle_charts(input);
  if (!untangled.ok()) return;  // the same typed errors as packing
  std::vector<std::vector<int>> seen(charts.size());
  for (std::size_t c = 0; c < charts.size(); ++c) seen[c].assign(charts[c].triangles.size(), 0);
  for (const ChartPiece& piece : untangled->pieces) {
    if (piece.chart >= charts.size()) __builtin_trap();
    const Chart& chart = charts[piece.chart];
    if (piece.triangles.size() != piece.chart_triangles.size()) __builtin_trap();
    std::vector<Vec2> uv;
    for (std::uint32_t v : piece.vertices) {
      if (v >= chart.uv.size()) __builtin_trap();
      uv.push_back(chart.uv[v]);
    }
    const double mirror = piece.mirrored ? -1.0 : 1.0;
    for (std::size_t i = 0; i < piece.triangles.size(); ++i) {
      const std::uint32_t t = piece.chart_triangles[i];
      if (t >= chart.triangles.size() || seen[piece.chart][t]++ != 0) __builtin_trap();
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t local = piece.triangles[i][k];
        if (local >= piece.vertices.size() || piece.vertices[local] != chart.triangles[t][k]) __builtin_trap();
      }
      // Turning one way: counter-clockwise, or clockwise in a mirrored piece; a zero-area
      // triangle covers nothing and may sit in any piece.
      const Triangle& local = piece.triangles[i];
      const int turn = orient2d(uv[local[0]], uv[local[1]], uv[local[2]]);
      if (turn != 0 && turn * mirror < 0) __builtin_trap();
    }
    // Within the piece no two interiors meet (mirrored or not, overlap is the same).
    const std::vector<std::uint32_t> one(piece.triangles.size(), 0);
    auto overlaps = find_overlaps(uv, piece.triangles, one);
    if (!overlaps.ok() || overlaps->overlap_area > 0) __builtin_trap();
  }
  for (const auto& per_chart : seen) {
    for (int count : per_chart) {
      if (count != 1) __builtin_trap();
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace seam::core;
  Reader in{data, size};
  const std::uint8_t head = in.byte();
  const std::size_t count = 1 + head % 6;
  PackOptions options;
  options.texture_size = 16 << (in.byte() % 7);  // 16 .. 1024
  options.margin_px = in.byte() % 9;
  options.rotate = (head & 0x80) == 0;
  std::vector<Chart> charts(count);
  for (Chart& c : charts) {
    const std::size_t vertices = 3 + in.byte() % 40;
    const std::size_t triangles = 1 + in.byte() % 48;
    const double scale = std::ldexp(1.0, static_cast<int>(in.byte() % 24) - 12);  // 2^-12 .. 2^11
    for (std::size_t v = 0; v < vertices; ++v) c.uv.emplace_back(scale * in.coordinate(), scale * in.coordinate());
    for (std::size_t t = 0; t < triangles; ++t) {
      // Indices past the chart's vertices now and then: a typed error, never a read.
      const std::uint8_t a = in.byte(), b = in.byte(), d = in.byte();
      const std::size_t limit = (head & 0x40) ? 256 : vertices;
      c.triangles.push_back({static_cast<std::uint32_t>(a % limit), static_cast<std::uint32_t>(b % limit),
                             static_cast<std::uint32_t>(d % limit)});
    }
    c.area = (in.byte() % 8 == 0) ? 0.0 : 0.5 + in.byte();
  }
  std::vector<PackChart> input;
  for (const Chart& c : charts) input.push_back({c.uv, c.triangles, c.area});
  check_untangled(charts, input);
  auto packed = pack_charts(input, options);
  if (!packed.ok()) return 0;
  if (packed->placements.size() != charts.size()) __builtin_trap();

  // The placed layout: every point in [0,1]^2, and no area shared between two charts.
  std::vector<Vec2> uv;
  std::vector<Triangle> triangles;
  std::vector<std::uint32_t> chart_of;
  for (std::size_t k = 0; k < charts.size(); ++k) {
    const auto base = static_cast<std::uint32_t>(uv.size());
    for (const Vec2& p : charts[k].uv) {
      const Vec2 q = packed->placements[k].apply(p);
      uv.push_back(q);
    }
    for (const Triangle& t : charts[k].triangles) {
      for (std::uint32_t v : t) {
        const Vec2& q = uv[base + v];
        if (!(q.x() >= -1e-9 && q.y() >= -1e-9 && q.x() <= 1 + 1e-9 && q.y() <= 1 + 1e-9)) __builtin_trap();
      }
      triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
      chart_of.push_back(static_cast<std::uint32_t>(k));
    }
  }
  auto overlaps = find_overlaps(uv, triangles, chart_of);
  if (!overlaps.ok()) __builtin_trap();
  if (overlaps->between_charts_area > 0) __builtin_trap();
  return 0;
}
