// libFuzzer target for the whole per-primitive job on arbitrary small meshes: weld, repair,
// topology, extrema, steering, seam (every method), cut, flattening (every method) and the
// atlas step (api::process_primitive and api::pack_uv_sets: what every POST /seam runs on a
// client's triangles). Inputs are triangle soups on a small integer lattice, so they carry
// what real files carry: coincident vertices, faces that repeat a vertex or lie on a line,
// repeated faces, fins, flipped patches, pinched vertices, handles, many parts, extrema out of
// range or in no face.
//
// Input, front to back (past its end every byte reads 0):
//   byte 0  bits 0-2 the UV method (slim, lscm, bff, arap, none, then slim again), bits 3-4
//           the seam method (skeleton, mst, greedy, optimal), bit 5 refine off, bit 6 repair
//           off, bit 7 charts "features"
//   byte 1  the vertex count, 3 + byte % 64
//   byte 2  bits 0-2 explicit extrema + 1 (0: automatic only), bit 3 pack.split, bits 4-7
//           the scale (2^-8 .. 2^7)
//   byte 3  bit 0 hide_from (bits 1-2 its direction), bit 3 hide_occluded, bit 4 automatic
//           extrema beside the explicit ones, bit 5 run the atlas step (up to 8 charts), bit 6
//           pack.rotate, bit 7 run the job again on two threads
//   then x, y, z per vertex (signed bytes), the explicit extrema (indices mod vertices + 2),
//   and triangles of three bytes (indices mod the vertex count), at most 160.
//
// Properties, each a __builtin_trap when violated:
// - no exception escapes; an error is one process_primitive documents for such input (never
//   kInternal; kNonManifoldEdge and kInconsistentOrientation only with repair off);
// - no data lost: every input triangle is in the output over the same input vertices (the
//   output's source_vertex), in its own winding or the reversed one (repair reorients);
// - every chart of the cut is a disc: Euler characteristic = boundary loops (summary.cut);
// - one finite UV per output vertex; the default map (SLIM) flips nothing;
// - after the atlas step every UV is in [0,1]^2, no two charts share area (find_overlaps on
//   the written layout), and the default map does not overlap itself;
// - the result does not depend on the thread budget: one thread and two give the same output
//   and the same summary but for its timings.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "api/pack_step.h"
#include "api/primitive_job.h"
#include "core/atlas/overlap.h"
#include "core/cancel.h"

namespace {

using seam::api::ApiErrorCode;

// The input read front to back; past its end every read is 0.
struct Reader {
  const std::uint8_t* data;
  std::size_t size;
  std::size_t at = 0;
  std::uint8_t byte() { return at < size ? data[at++] : 0; }
  bool done() const { return at >= size; }
};

[[noreturn]] void fail(const char* what) {
  std::fprintf(stderr, "mesh_fuzz: %s\n", what);
  __builtin_trap();
}

struct Case {
  seam::api::PrimitiveData data;
  seam::api::ExtremaSpec extrema;
  seam::api::SeamParams params;
  bool pack = false;     // run the atlas step (its shape packer is most of an input's time)
  bool threads = false;  // run the job again on two threads and compare
};

Case decode(Reader& in) {
  using namespace seam;
  Case c;
  const std::uint8_t flags = in.byte();
  const std::size_t n = 3 + in.byte() % 64;
  const std::uint8_t shape = in.byte();
  const std::uint8_t steer = in.byte();
  constexpr std::array<core::UvMethod, 4> kUv{core::UvMethod::kSlim, core::UvMethod::kLscm, core::UvMethod::kBff,
                                              core::UvMethod::kArap};
  const std::size_t uv = flags & 7;  // 4: none; 5-7: the default too, so that most cases flatten
  c.params.uv = uv == 4 ? std::nullopt : std::optional(kUv[uv < 4 ? uv : 0]);
  constexpr std::array<core::SeamMethod, 4> kMethod{core::SeamMethod::kSkeleton, core::SeamMethod::kMst,
                                                    core::SeamMethod::kGreedy, core::SeamMethod::kOptimal};
  c.params.method = kMethod[(flags >> 3) & 3];
  c.params.refine = (flags & 0x20) == 0;
  c.params.repair = (flags & 0x40) == 0;
  c.params.charts = (flags & 0x80) ? api::ChartMode::kFeatures : api::ChartMode::kSeam;
  c.params.pack.split = (shape & 0x08) != 0;
  c.params.pack.texture_size = 64;
  const double scale = std::ldexp(1.0, static_cast<int>(shape >> 4) - 8);  // 2^-8 .. 2^7
  if (steer & 0x01) c.params.hide_from.push_back({(steer & 0x02) ? 1.0 : -1.0, (steer & 0x04) ? 0.5 : 0.0, 1.0});
  c.params.hide_occluded = (steer & 0x08) != 0;
  c.pack = (steer & 0x20) != 0;
  c.threads = (steer & 0x80) != 0;
  c.params.pack.rotate = (steer & 0x40) != 0;  // 20 orientations per chart instead of one

  core::IndexedMesh& mesh = c.data.mesh;
  for (std::size_t v = 0; v < n; ++v) {
    const double x = static_cast<std::int8_t>(in.byte());
    const double y = static_cast<std::int8_t>(in.byte());
    const double z = static_cast<std::int8_t>(in.byte());
    mesh.positions.emplace_back(scale * x, scale * y, scale * z);
  }
  const std::size_t explicit_extrema = shape % 8;
  if (explicit_extrema > 0) {
    c.extrema.automatic = (steer & 0x10) != 0;  // auto plus an include list, or the list alone
    // Now and then an index past the vertices: a typed error, never a read.
    for (std::size_t e = 0; e < explicit_extrema - 1; ++e) c.extrema.indices.push_back(in.byte() % (n + 2));
  }
  while (!in.done() && mesh.triangles.size() < 160) {
    const std::uint8_t a = in.byte(), b = in.byte(), d = in.byte();
    mesh.triangles.push_back(
        {static_cast<std::uint32_t>(a % n), static_cast<std::uint32_t>(b % n), static_cast<std::uint32_t>(d % n)});
  }
  api::AttributeArray position;
  position.name = "POSITION";
  position.count = n;
  position.data.resize(n * 12);
  for (std::size_t v = 0; v < n; ++v) {
    for (int k = 0; k < 3; ++k) {
      const float f = static_cast<float>(mesh.positions[v][k]);
      std::memcpy(position.data.data() + 12 * v + 4 * k, &f, 4);
    }
  }
  c.data.attributes.push_back(std::move(position));
  return c;
}

bool allowed(ApiErrorCode code, const seam::api::SeamParams& params) {
  switch (code) {
    case ApiErrorCode::kEmptyMesh:
    case ApiErrorCode::kDegenerateFace:
    case ApiErrorCode::kExtremumOutOfRange:
    case ApiErrorCode::kTooManyTerminals:
    case ApiErrorCode::kSolverFailed:
      return true;
    case ApiErrorCode::kNonManifoldEdge:
    case ApiErrorCode::kInconsistentOrientation:
      return !params.repair;
    default:
      return false;
  }
}

// Every input triangle is in the output over the same input vertices, in its own winding or
// the reversed one (repair reorients patches).
void check_triangles(const Case& c, const seam::api::CutPrimitive& cut) {
  if (cut.triangles.size() != c.data.mesh.triangles.size()) fail("the output lost or gained triangles");
  for (std::uint32_t s : cut.source_vertex) {
    if (s >= c.data.mesh.positions.size()) fail("an output vertex has no input vertex");
  }
  for (std::size_t f = 0; f < cut.triangles.size(); ++f) {
    std::array<std::uint32_t, 3> out{};
    for (int k = 0; k < 3; ++k) {
      if (cut.triangles[f][k] >= cut.source_vertex.size()) fail("an output index is out of range");
      out[k] = cut.source_vertex[cut.triangles[f][k]];
    }
    const auto& in = c.data.mesh.triangles[f];
    bool same = false;
    for (int r = 0; r < 3 && !same; ++r) {
      const bool forward = out[0] == in[r] && out[1] == in[(r + 1) % 3] && out[2] == in[(r + 2) % 3];
      const bool backward = out[0] == in[r] && out[1] == in[(r + 2) % 3] && out[2] == in[(r + 1) % 3];
      same = forward || backward;
    }
    if (!same) fail("an output triangle is not its input triangle");
  }
}

void check_result(const Case& c, const seam::api::PrimitiveResult& r) {
  check_triangles(c, r.cut);
  const auto& cut = r.summary.at("cut");
  const long long chi = cut.at("euler_characteristic").get<long long>();
  const long long loops = cut.at("boundary_loops").get<long long>();
  if (chi != loops) fail("the cut is not a disc per chart (euler characteristic != boundary loops)");
  if (!r.cut.uv.empty()) {
    if (r.cut.uv.size() != r.cut.source_vertex.size()) fail("not one UV per output vertex");
    for (const auto& uv : r.cut.uv) {
      if (!std::isfinite(uv[0]) || !std::isfinite(uv[1])) fail("a UV is not finite");
    }
    const auto& summary = r.summary.at("uv");
    const std::string method = summary.at("method").get<std::string>();
    if (c.params.uv == seam::core::UvMethod::kSlim && method == "slim" && summary.at("flipped").get<long long>() != 0) {
      fail("the default map flipped a triangle");
    }
  }
}

// The summary without its timings, which differ from run to run.
nlohmann::json without_timings(nlohmann::json summary) {
  summary.erase("timings_ms");
  return summary;
}

void check_pack(const Case& c, seam::api::PrimitiveResult& r) {
  using namespace seam;
  // Many charts make the shape packer slow under the sanitizers; atlas_fuzz has the packer.
  if (r.cut.uv.empty() || !c.pack || r.chart_area.size() > 8) return;
  api::GltfDocument doc;
  doc.json = {{"meshes", {{{"primitives", {nlohmann::json::object()}}}}}};
  const std::vector<api::PackMember> members{{0, 0, &r}};
  auto packed = api::pack_uv_sets(doc, members, c.params.pack, core::CancelToken{});
  if (!packed.ok()) {
    std::fprintf(stderr, "mesh_fuzz: %s\n", packed.error().message.c_str());
    fail("the atlas step refused a flattened primitive");
  }
  std::vector<core::Vec2> uv;
  for (const auto& p : r.cut.uv) {
    if (!(p[0] >= 0 && p[0] <= 1 && p[1] >= 0 && p[1] <= 1)) fail("a packed UV is outside [0,1]^2");
    uv.emplace_back(p[0], p[1]);
  }
  std::vector<std::uint32_t> chart_of;
  for (const auto& t : r.cut.triangles) {
    // A triangle across two charts gets a UV triangle across the atlas (F14).
    if (r.chart[t[1]] != r.chart[t[0]] || r.chart[t[2]] != r.chart[t[0]]) fail("a packed triangle spans two charts");
    chart_of.push_back(r.chart[t[0]]);
  }
  auto overlap = core::find_overlaps(uv, r.cut.triangles, chart_of);
  if (!overlap.ok()) fail("find_overlaps refused the packed layout");
  if (overlap->between_charts_area > 0) fail("two packed charts overlap");
  // The default map is injective; packing moves each chart by a similarity and rounds to the UV
  // grid, which moves a UV by half a step (2^-25 in the unit square). Where the
  // map only touches itself (two boundary edges from one vertex on one line: F15), that can open a
  // sliver at most a few such units wide along an edge: allowed up to the edges' total length
  // times 2^-22; anything wider is a real fold.
  double edges = 0;
  for (const auto& t : r.cut.triangles) {
    for (int k = 0; k < 3; ++k) edges += (uv[t[k]] - uv[t[(k + 1) % 3]]).norm();
  }
  if (c.params.uv == core::UvMethod::kSlim && overlap->overlap_area > edges * 0x1p-22) {
    fail("the packed default map overlaps itself");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace seam;
  Reader in{data, size};
  Case c = decode(in);
  const core::CancelToken cancel;
  auto one = api::process_primitive(c.data, c.extrema, c.params, {.threads = 1}, cancel);
  if (!one.ok()) {
    if (!allowed(one.error().code, c.params)) {
      std::fprintf(stderr, "mesh_fuzz: %s: %s\n", std::string(api::code_name(one.error().code)).c_str(),
                   one.error().message.c_str());
      __builtin_trap();
    }
    return 0;
  }
  check_result(c, *one);
  if (c.threads) {
    auto two = api::process_primitive(c.data, c.extrema, c.params, {.threads = 2}, cancel);
    if (!two.ok()) fail("two threads failed where one succeeded");
    if (two->cut.source_vertex != one->cut.source_vertex || two->cut.triangles != one->cut.triangles ||
        two->cut.uv != one->cut.uv || without_timings(two->summary) != without_timings(one->summary)) {
      fail("the result depends on the thread budget");
    }
  }
  check_pack(c, *one);
  return 0;
}
