#include "core/atlas/atlas.h"

#include <algorithm>
#include <chrono>
#include <limits>
#include <cmath>
#include <string>

#include "core/atlas/overlap.h"
#include "core/mesh/topology.h"
#include "core/uv/uv_patch.h"

namespace seam::core {

namespace {

struct MemberCharts {
  std::vector<DiscPatch> patches;
  std::vector<std::vector<Vec2>> uv;  // per patch, per local vertex
  std::vector<double> area;           // per patch, 3D
};

Result<MemberCharts> member_charts(const HalfedgeMesh& mesh, const VertexData<Vec2>& uv, std::size_t index) {
  if (uv.size() != mesh.num_vertices()) {
    return make_error(ErrorCode::kInvalidArgument, "pack_atlas: member " + std::to_string(index) + " has " +
                                                       std::to_string(uv.size()) + " UVs for " +
                                                       std::to_string(mesh.num_vertices()) + " vertices");
  }
  if (mesh.num_faces() == 0) {
    return make_error(ErrorCode::kEmptyMesh, "pack_atlas: member " + std::to_string(index) + " has no faces");
  }
  MemberCharts out;
  SEAM_TRY(out.patches, extract_disc_patches(mesh, compute_topology(mesh)));
  for (const DiscPatch& p : out.patches) {
    std::vector<Vec2> chart_uv(p.num_vertices());
    for (std::size_t v = 0; v < chart_uv.size(); ++v) chart_uv[v] = uv[p.to_mesh[v]];
    double area = 0;
    for (const Triangle& t : p.triangles) {
      area += 0.5 * (p.positions[t[1]] - p.positions[t[0]]).cross(p.positions[t[2]] - p.positions[t[0]]).norm();
    }
    out.uv.push_back(std::move(chart_uv));
    out.area.push_back(area);
  }
  return out;
}

}  // namespace

Result<AtlasResult> pack_atlas(std::span<const AtlasMesh> members, const PackOptions& options,
                               const CancelToken& cancel) {
  std::vector<MemberCharts> groups;
  std::vector<PackChart> views;
  for (std::size_t m = 0; m < members.size(); ++m) {
    SEAM_TRY(MemberCharts charts, member_charts(members[m].mesh.get(), members[m].uv.get(), m));
    groups.push_back(std::move(charts));
  }
  for (const MemberCharts& g : groups) {
    for (std::size_t c = 0; c < g.patches.size(); ++c) views.push_back({g.uv[c], g.patches[c].triangles, g.area[c]});
  }
  SEAM_TRY(PackResult pack, pack_charts(views, options, cancel));

  AtlasResult result;
  result.charts = views.size();
  result.coverage = pack.coverage;
  result.pack_ms = pack.ms;
  // The group's stored layout, for the overlap and density measurements.
  std::vector<Vec2> all_uv;
  std::vector<Triangle> all_triangles;
  std::vector<std::uint32_t> chart_of;
  double min_density = std::numeric_limits<double>::infinity();
  double max_density = 0;
  std::size_t chart = 0;
  for (std::size_t m = 0; m < members.size(); ++m) {
    if (cancel.is_cancelled()) return cancelled_error("pack_atlas");
    const MemberCharts& g = groups[m];
    VertexData<Vec2> out(members[m].mesh.get().num_vertices(), Vec2::Zero());
    for (std::size_t c = 0; c < g.patches.size(); ++c, ++chart) {
      std::vector<Vec2> uv(g.uv[c].size());
      for (std::size_t v = 0; v < uv.size(); ++v) {
        uv[v] = pack.placements[chart].apply(g.uv[c][v]).cwiseMax(0.0).cwiseMin(1.0);
      }
      const Float32Rounding rounding = round_to_float32(g.patches[c], uv);
      result.float32_degenerate += rounding.degenerate;
      result.float32_unrepaired += rounding.remaining;
      double uv_area = 0;
      const auto base = static_cast<std::uint32_t>(all_uv.size());
      for (const Triangle& t : g.patches[c].triangles) {
        const Vec2 e1 = uv[t[1]] - uv[t[0]];
        const Vec2 e2 = uv[t[2]] - uv[t[0]];
        uv_area += 0.5 * std::abs(cross2(e1, e2));
        all_triangles.push_back({base + t[0], base + t[1], base + t[2]});
        chart_of.push_back(static_cast<std::uint32_t>(chart));
      }
      const double density = std::sqrt(uv_area / g.area[c]);
      min_density = std::min(min_density, density);
      max_density = std::max(max_density, density);
      for (std::size_t v = 0; v < uv.size(); ++v) {
        out[g.patches[c].to_mesh[v]] = uv[v];
        all_uv.push_back(uv[v]);
      }
    }
    result.uv.push_back(std::move(out));
  }
  result.density_ratio = max_density > 0 ? max_density / min_density : 1.0;
  SEAM_TRY(OverlapResult overlap, find_overlaps(all_uv, all_triangles, chart_of, cancel));
  result.overlap_area = overlap.overlap_area;
  result.overlap_fraction = overlap.overlap_fraction;
  result.between_charts_area = overlap.between_charts_area;
  result.overlap_ms = overlap.ms;
  return result;
}

}  // namespace seam::core
