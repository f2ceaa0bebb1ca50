#include "api/pack_step.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include "core/atlas/overlap.h"
#include "core/atlas/pack.h"
#include "core/atlas/split.h"
#include "core/atlas/untangle.h"
#include "core/uv/uv_patch.h"

namespace seam::api {
namespace {

using nlohmann::json;

std::int64_t material_of(const GltfDocument& doc, const PackMember& m) {
  const json& prim = doc.json["meshes"][m.mesh]["primitives"][m.primitive];
  const auto it = prim.find("material");
  return it != prim.end() && it->is_number_unsigned() ? it->get<std::int64_t>() : -1;
}

// Members' group keys by params.group_by, numbered in order of first member.
std::vector<std::uint32_t> group_members(const GltfDocument& doc, const std::vector<PackMember>& members,
                                         const PackParams& params) {
  std::map<std::int64_t, std::uint32_t> ids;
  std::vector<std::uint32_t> out;
  for (std::size_t i = 0; i < members.size(); ++i) {
    std::int64_t key = static_cast<std::int64_t>(i);
    if (params.enabled) {
      switch (params.group_by) {
        case PackGroup::kAsset: key = 0; break;
        case PackGroup::kMesh: key = members[i].mesh; break;
        case PackGroup::kMaterial: key = material_of(doc, members[i]); break;
        case PackGroup::kPrimitive: break;
      }
    }
    const auto [it, added] = ids.try_emplace(key, static_cast<std::uint32_t>(ids.size()));
    out.push_back(it->second);
  }
  return out;
}

// One chart of one member, as pack_charts takes it.
struct ChartData {
  std::size_t member = 0;
  std::vector<std::uint32_t> vertices;  // output vertices of the member, in order
  std::vector<core::Vec2> uv;
  std::vector<core::Triangle> triangles;  // over `uv`
  std::vector<std::uint32_t> triangle_ids;  // each triangle's index in the member's cut
  double area = 0;
};

std::vector<ChartData> charts_of(const PrimitiveResult& r, std::size_t member) {
  std::vector<ChartData> charts(r.chart_area.size());
  std::vector<std::uint32_t> local(r.cut.uv.size());
  for (std::uint32_t v = 0; v < r.cut.uv.size(); ++v) {
    ChartData& c = charts[r.chart[v]];
    local[v] = static_cast<std::uint32_t>(c.vertices.size());
    c.vertices.push_back(v);
    c.uv.emplace_back(r.cut.uv[v][0], r.cut.uv[v][1]);
  }
  for (std::uint32_t i = 0; i < r.cut.triangles.size(); ++i) {
    const core::Triangle& t = r.cut.triangles[i];
    charts[r.chart[t[0]]].triangles.push_back({local[t[0]], local[t[1]], local[t[2]]});
    charts[r.chart[t[0]]].triangle_ids.push_back(i);
  }
  for (std::size_t c = 0; c < charts.size(); ++c) {
    charts[c].member = member;
    charts[c].area = r.chart_area[c];
  }
  return charts;
}

// The member's charts with area (charts of faces degenerate in 3D only, a collapsed face whose
// vertices are in no other face, have none to pack and keep their zero-area place).
std::vector<ChartData> packable_charts(const PrimitiveResult& r, std::size_t member) {
  std::vector<ChartData> out;
  for (auto& c : charts_of(r, member)) {
    if (c.area > 0) out.push_back(std::move(c));
  }
  return out;
}

// A piece after the first of its chart becomes a chart of its own: its vertices that an
// earlier piece holds (on the cut) are duplicated, with the same source vertex and UV. Returns
// the piece's output vertices.
std::vector<std::uint32_t> detach_piece(const core::ChartPiece& piece, const ChartData& chart,
                                        std::vector<char>& claimed, PrimitiveResult& r) {
  const auto id = static_cast<std::uint32_t>(r.chart_area.size());
  r.chart_area.push_back(piece.surface_area);
  std::vector<std::uint32_t> vertex_of(piece.vertices.size());  // piece-local vertex -> output vertex
  for (std::size_t i = 0; i < piece.vertices.size(); ++i) {
    std::uint32_t g = chart.vertices[piece.vertices[i]];
    if (claimed[g] != 0) {
      const auto copy = static_cast<std::uint32_t>(r.cut.source_vertex.size());
      r.cut.source_vertex.push_back(r.cut.source_vertex[g]);
      r.cut.uv.push_back(r.cut.uv[g]);
      r.chart.push_back(id);
      claimed.push_back(1);
      g = copy;
    }
    claimed[g] = 1;
    r.chart[g] = id;
    vertex_of[i] = g;
  }
  // Each triangle by its place in the chart, not by its corners: duplicate faces share them.
  for (std::size_t i = 0; i < piece.triangles.size(); ++i) {
    const core::Triangle& t = piece.triangles[i];
    r.cut.triangles[chart.triangle_ids[piece.chart_triangles[i]]] = {vertex_of[t[0]], vertex_of[t[1]], vertex_of[t[2]]};
  }
  return vertex_of;
}

// Writes the pieces of the member's charts (split or untangled, in order of chart) into its
// cut primitive: the first piece of a chart keeps the chart's id and vertices, the others are
// detached. A mirrored piece's u is negated (exact in float; packing moves it into place).
void apply_pieces(const std::vector<core::ChartPiece>& pieces, const std::vector<ChartData>& charts,
                  PrimitiveResult& r) {
  std::vector<char> claimed(r.cut.uv.size(), 0);
  std::vector<char> seen(charts.size(), 0);
  std::vector<std::uint32_t> mirrored;  // output vertices of mirrored pieces
  for (const core::ChartPiece& piece : pieces) {
    const ChartData& chart = charts[piece.chart];
    std::vector<std::uint32_t> vertices;
    if (seen[piece.chart] == 0) {  // the first piece keeps the chart's id and vertices
      seen[piece.chart] = 1;
      r.chart_area[r.chart[chart.vertices[piece.vertices.front()]]] = piece.surface_area;
      for (const std::uint32_t u : piece.vertices) {
        claimed[chart.vertices[u]] = 1;
        vertices.push_back(chart.vertices[u]);
      }
    } else {
      vertices = detach_piece(piece, chart, claimed, r);
    }
    if (piece.mirrored) mirrored.insert(mirrored.end(), vertices.begin(), vertices.end());
  }
  // Only now: a later piece's copy of a vertex on the cut takes the unmirrored UV.
  for (const std::uint32_t g : mirrored) r.cut.uv[g][0] = -r.cut.uv[g][0];
}

// pack.split: cuts the member's sprawling charts (core::split_sprawling_charts) in its cut
// primitive; counts what it did in `outcome`.
ApiResult<core::Ok> split_member_charts(PrimitiveResult& r, std::size_t member, PackOutcome& outcome) {
  const std::vector<ChartData> charts = packable_charts(r, member);
  std::vector<core::PackChart> input;
  for (const auto& c : charts) input.push_back({c.uv, c.triangles, c.area});
  auto split = core::split_sprawling_charts(input);
  if (!split.ok()) {
    return make_api_error(ApiErrorCode::kInternal, "splitting the UV charts failed: " + split.error().message);
  }
  apply_pieces(split->pieces, charts, r);
  outcome.charts_split = split->charts_split;
  outcome.split_cut_length = split->cut_length;
  return core::Ok{};
}

// Cuts the member's charts that fold or overlap themselves (core::untangle_charts; `uv: lscm`,
// `bff`, `arap` make them) into valid pieces, mirroring those that turn the wrong way; counts
// what it did in `outcome`. The charts go in with v negated: the output's v runs down (v' =
// 1 - v), and the core calls counter-clockwise in the parameterization's frame right.
ApiResult<core::Ok> untangle_member_charts(PrimitiveResult& r, std::size_t member, PackOutcome& outcome,
                                           const core::CancelToken& cancel) {
  const std::vector<ChartData> charts = packable_charts(r, member);
  std::vector<std::vector<core::Vec2>> upright(charts.size());
  std::vector<core::PackChart> input;
  for (std::size_t c = 0; c < charts.size(); ++c) {
    for (const core::Vec2& p : charts[c].uv) upright[c].emplace_back(p.x(), -p.y());
    input.push_back({upright[c], charts[c].triangles, charts[c].area});
  }
  auto untangled = core::untangle_charts(input, cancel);
  if (!untangled.ok()) {
    if (untangled.error().code == core::ErrorCode::kCancelled) return from_core(untangled.error());
    return make_api_error(ApiErrorCode::kInternal, "untangling the UV charts failed: " + untangled.error().message);
  }
  if (untangled->charts_untangled > 0) apply_pieces(untangled->pieces, charts, r);
  // Added up: a group packed twice (pack_uv_sets) untangles again what its placement made touch.
  outcome.untangle.charts += untangled->charts_untangled;
  outcome.untangle.pieces_added += untangled->pieces_added;
  outcome.untangle.pieces_mirrored += untangled->pieces_mirrored;
  outcome.untangle.unflipped += untangled->unflipped;
  outcome.untangle.cut_length += untangled->cut_length;
  return core::Ok{};
}

// Whether the member's flattening left anything to untangle: a flipped triangle or overlap,
// as parameterize measured them exactly on its stored UVs. The default map (SLIM, injective)
// leaves none, and the untangling's own check is not free: 0.94 s of the default job at
// 1.25M faces (pack 441 -> 1,384 ms), so it runs only where the flattening reported a tangle.
bool has_tangles(const PrimitiveResult& r) {
  const nlohmann::json& uv = r.summary.at("uv");
  return uv.at("flipped").get<std::size_t>() > 0 || uv.at("overlap_area").get<double>() > 0;
}

double orientation(const std::vector<std::array<float, 2>>& uv, const core::Triangle& t) {
  const auto& a = uv[t[0]];
  const auto& b = uv[t[1]];
  const auto& c = uv[t[2]];
  return (static_cast<double>(b[0]) - a[0]) * (static_cast<double>(c[1]) - a[1]) -
         (static_cast<double>(b[1]) - a[1]) * (static_cast<double>(c[0]) - a[0]);
}

// The member's triangles that the rounding of the placement to the grid turned over or
// flattened get a corner moved to a neighbouring grid point where that restores their turn
// without turning another triangle at that corner (core::restore_turns, the nudge parameterize
// applies to its own rounding). Untangled lscm/arap pieces hold slivers the placement's
// rotation and rounding turned over (bench6 arap and skinned lscm, one each). Returns how many
// stay turned. O(F) when nothing turned.
std::size_t restore_member_turns(PrimitiveResult& r, const std::vector<double>& signs) {
  bool turned = false;
  for (std::size_t t = 0; t < signs.size() && !turned; ++t) {
    const double now = orientation(r.cut.uv, r.cut.triangles[t]);
    turned = signs[t] != 0 && !(signs[t] > 0 ? now > 0 : now < 0);
  }
  if (!turned) return 0;
  std::vector<core::Vec2> uv(r.cut.uv.size());
  for (std::size_t v = 0; v < uv.size(); ++v) uv[v] = core::Vec2(r.cut.uv[v][0], r.cut.uv[v][1]);
  const core::Float32Rounding restored = core::restore_turns(r.cut.triangles, signs, uv);
  for (std::size_t v = 0; v < uv.size(); ++v) {
    r.cut.uv[v] = {static_cast<float>(uv[v].x()), static_cast<float>(uv[v].y())};
  }
  return restored.remaining;
}

// Moves every chart of the group by its placement; counts triangles whose orientation the
// rounding to float changed (or flattened) in each member and the nudges could not restore.
void place(std::vector<ChartData>& charts, const core::PackResult& packed, const std::vector<PackMember>& members,
           std::vector<PackOutcome>& outcomes) {
  std::map<std::size_t, std::vector<double>> before;
  for (const auto& c : charts) {
    auto& b = before[c.member];
    if (!b.empty()) continue;
    const PrimitiveResult& r = *members[c.member].result;
    for (const auto& t : r.cut.triangles) b.push_back(orientation(r.cut.uv, t));
  }
  for (std::size_t k = 0; k < charts.size(); ++k) {
    PrimitiveResult& r = *members[charts[k].member].result;
    for (std::size_t i = 0; i < charts[k].vertices.size(); ++i) {
      // On the storage grid (core::kUvGrid), as the flattening left them: exact as float.
      const core::Vec2 p = packed.placements[k].apply(charts[k].uv[i]);
      r.cut.uv[charts[k].vertices[i]] = {static_cast<float>(core::to_uv_grid(p.x())),
                                         static_cast<float>(core::to_uv_grid(p.y()))};
    }
  }
  for (const auto& [member, signs] : before)
    outcomes[member].flipped += restore_member_turns(*members[member].result, signs);
}

struct Measured {
  double overlap_area = 0;
  double coverage = 0;
};

// The group's layout measured: the area covered twice, within or between charts (exactly),
// and the charts' area (the atlas is the unit square).
ApiResult<Measured> measure_group(const std::vector<ChartData>& charts, const std::vector<PackMember>& members,
                                const core::CancelToken& cancel) {
  std::vector<core::Vec2> uv;
  std::vector<core::Triangle> triangles;
  std::vector<std::uint32_t> chart_of;
  std::map<std::size_t, bool> seen;
  std::uint32_t chart_base = 0;
  Measured out;
  for (const auto& c : charts) {
    if (seen[c.member]) continue;
    seen[c.member] = true;
    const PrimitiveResult& r = *members[c.member].result;
    const auto base = static_cast<std::uint32_t>(uv.size());
    for (const auto& p : r.cut.uv) uv.emplace_back(p[0], p[1]);
    for (const auto& t : r.cut.triangles) {
      triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
      chart_of.push_back(chart_base + r.chart[t[0]]);
      out.coverage += 0.5 * std::abs(orientation(r.cut.uv, t));
    }
    chart_base += static_cast<std::uint32_t>(r.chart_area.size());
  }
  auto overlap = core::find_overlaps(uv, triangles, chart_of, cancel);
  if (!overlap.ok()) return from_core(overlap.error());
  out.overlap_area = overlap->overlap_area;
  return out;
}

// A group's layout: its texture and density (with params.enabled) and what measure_group found.
struct GroupLayout {
  bool has_charts = false;
  double density = 0;
  int texture_size = 0;
  Measured measured;
};

// Packs group g's members into one layout and measures it: each member's charts untangled
// where its flattening left a tangle (or all of them, `again`), split with params.split (the
// first time only), placed by core::pack_charts with atlas_options.
ApiResult<GroupLayout> pack_group(std::uint32_t g, const std::vector<std::uint32_t>& group,
                                  const std::vector<PackMember>& members, const PackParams& params, bool again,
                                  std::vector<PackOutcome>& outcomes, const core::CancelToken& cancel) {
  std::vector<ChartData> charts;
  for (std::size_t i = 0; i < members.size(); ++i) {
    if (group[i] != g || members[i].result->cut.uv.empty()) continue;
    PrimitiveResult& r = *members[i].result;
    if (params.enabled && (again || has_tangles(r))) {
      SEAM_TRY(core::Ok untangled, untangle_member_charts(r, i, outcomes[i], cancel));
      (void)untangled;
    }
    if (params.enabled && params.split && !again) {
      SEAM_TRY(core::Ok split, split_member_charts(r, i, outcomes[i]));
      (void)split;
    }
    for (auto& c : packable_charts(r, i)) charts.push_back(std::move(c));
    outcomes[i].charts = r.chart_area.size();
    outcomes[i].flipped = 0;
  }
  GroupLayout layout;
  if (charts.empty()) return layout;
  layout.has_charts = true;
  if (params.enabled) {
    SEAM_TRY(const core::PackOptions options, atlas_options(params, charts.size()));
    std::vector<core::PackChart> input;
    for (const auto& c : charts) input.push_back({c.uv, c.triangles, c.area});
    auto packed = core::pack_charts(input, options, cancel);
    if (!packed.ok()) {
      if (packed.error().code == core::ErrorCode::kCancelled) return from_core(packed.error());
      return make_api_error(ApiErrorCode::kInternal, "packing the UV charts failed: " + packed.error().message);
    }
    place(charts, *packed, members, outcomes);
    layout.density = packed->texel_density;
    layout.texture_size = options.texture_size;
  }
  SEAM_TRY(layout.measured, measure_group(charts, members, cancel));
  return layout;
}

}  // namespace

ApiResult<core::PackOptions> atlas_options(const PackParams& params, std::size_t charts) {
  core::PackOptions options{params.texture_size, params.margin_px, params.rotate};
  if (core::margins_fit(charts, options)) return options;
  if (!params.sized_by_caller) {
    while (options.texture_size < 65536 && 4.0 * static_cast<double>(charts) * options.margin_px * options.margin_px >
                                               static_cast<double>(options.texture_size) * options.texture_size) {
      options.texture_size *= 2;
    }
    if (core::margins_fit(charts, options)) return options;
  }
  return make_api_error(ApiErrorCode::kInvalidParameter, core::margins_message(charts, options),
                        {{"parameter", "pack.texture_size"}, {"charts", charts}});
}

ApiResult<std::vector<PackOutcome>> pack_uv_sets(const GltfDocument& doc, const std::vector<PackMember>& members,
                                                 const PackParams& params, const core::CancelToken& cancel) {
  std::vector<PackOutcome> outcomes(members.size());
  const std::vector<std::uint32_t> group = group_members(doc, members, params);
  const std::uint32_t groups = group.empty() ? 0 : *std::max_element(group.begin(), group.end()) + 1;
  for (std::size_t i = 0; i < members.size(); ++i) outcomes[i].group = group[i];
  for (std::uint32_t g = 0; g < groups; ++g) {
    SEAM_TRY(GroupLayout layout, pack_group(g, group, members, params, false, outcomes, cancel));
    if (params.enabled && layout.measured.overlap_area > 0) {
      // The placement's rounding to the grid made a chart overlap itself where two of its
      // triangles lay less than a grid step apart (a net; the test assets never reach it):
      // untangle the group's charts on their placed UVs and pack it once more.
      SEAM_TRY(layout, pack_group(g, group, members, params, true, outcomes, cancel));
    }
    if (!layout.has_charts) continue;
    for (std::size_t i = 0; i < members.size(); ++i) {
      if (group[i] != g) continue;
      outcomes[i].coverage = layout.measured.coverage;
      outcomes[i].overlap_area = layout.measured.overlap_area;
      outcomes[i].texel_density = layout.density;
      outcomes[i].texture_size = layout.texture_size;
    }
  }
  return outcomes;
}

}  // namespace seam::api
