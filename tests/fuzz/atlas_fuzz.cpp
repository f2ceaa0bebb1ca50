// libFuzzer target for the atlas: pack_charts (the rectangle, column-profile and shape
// packers) and find_overlaps on charts decoded from the input, folded, degenerate,
// overlapping or malformed. Bad charts must come back as typed errors; a packed layout must
// keep every two charts apart, which find_overlaps on the placed charts checks exactly (no
// area between charts), and keep every point in [0,1]^2.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "core/atlas/overlap.h"
#include "core/atlas/pack.h"

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
