#include "core/uv/parameterize.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>
#include <string>
#include <utility>

#include "core/atlas/overlap.h"
#include "core/mesh/topology.h"
#include "core/timing.h"
#include "core/uv/arap.h"
#include "core/uv/bff.h"
#include "core/uv/collision.h"
#include "core/uv/distortion.h"
#include "core/uv/lscm.h"
#include "core/uv/multilevel.h"
#include "core/uv/slim.h"
#include "core/uv/sparse_cholesky.h"
#include "core/uv/uv_patch.h"

namespace seam::core {

const char* uv_method_name(UvMethod method) {
  switch (method) {
    case UvMethod::kLscm:
      return "lscm";
    case UvMethod::kBff:
      return "bff";
    case UvMethod::kArap:
      return "arap";
    case UvMethod::kSlim:
      return "slim";
  }
  return "unknown";
}

namespace {

// BFF's A_II and SLIM's proxy are systems on one vertex graph (the interior, and every vertex
// but the pinned one): on large charts one nested dissection of the whole graph serves both
// (sparse_cholesky.h), so METIS runs once per chart instead of twice (at 1M faces about 2.6 s
// of SLIM's 3.1 s analysis). Empty below the size where the solvers would pick AMD anyway.
std::vector<int> shared_vertex_order(const DiscPatch& patch) {
  if (static_cast<Eigen::Index>(patch.num_vertices()) < SparseCholesky::kNestedDissectionMin) return {};
  return nested_dissection_order(vertex_graph_lower(patch));
}

double signed_area(const Vec2& a, const Vec2& b, const Vec2& c) {
  return 0.5 * cross2(a, b, c);
}

struct Chart {
  std::vector<Vec2> uv;  // per patch vertex, at 3D scale, min corner at the origin
  Vec2 size = Vec2::Zero();
  Vec2 offset = Vec2::Zero();
};

// Scales the chart so its UV area equals its 3D area (all charts share one texel density),
// then moves its bounding box to the origin.
Chart normalise_chart(const DiscPatch& patch, std::vector<Vec2> uv) {
  double area_3d = 0;
  double area_2d = 0;
  for (const Triangle& t : patch.triangles) {
    const Vec3& p0 = patch.positions[t[0]];
    area_3d += 0.5 * (patch.positions[t[1]] - p0).cross(patch.positions[t[2]] - p0).norm();
    area_2d += std::abs(signed_area(uv[t[0]], uv[t[1]], uv[t[2]]));
  }
  const double scale = (area_3d > 0 && area_2d > 0) ? std::sqrt(area_3d / area_2d) : 1.0;
  Vec2 lo = Vec2::Constant(std::numeric_limits<double>::infinity());
  Vec2 hi = -lo;
  for (Vec2& p : uv) {
    p *= scale;
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  for (Vec2& p : uv) p -= lo;
  Chart chart;
  chart.uv = std::move(uv);
  chart.size = hi - lo;
  return chart;
}

// Shelf packing: charts by decreasing height, rows about as wide as the square root of the
// total box area, so the atlas is roughly square. Returns the atlas size.
Vec2 pack_charts(std::vector<Chart>& charts, double gap_fraction) {
  double box_area = 0;
  double widest = 0;
  for (const Chart& c : charts) {
    box_area += c.size.x() * c.size.y();
    widest = std::max(widest, c.size.x());
  }
  const double gap = charts.size() > 1 ? gap_fraction * std::sqrt(box_area) : 0.0;
  const double row_width = std::max(widest, std::sqrt(box_area) * 1.1);
  std::vector<std::size_t> order(charts.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return charts[a].size.y() > charts[b].size.y(); });
  double x = 0;
  double y = 0;
  double row_height = 0;
  Vec2 extent = Vec2::Zero();
  for (std::size_t idx : order) {
    Chart& c = charts[idx];
    if (x > 0 && x + c.size.x() > row_width) {
      x = 0;
      y += row_height + gap;
      row_height = 0;
    }
    c.offset = Vec2(x, y);
    x += c.size.x() + gap;
    row_height = std::max(row_height, c.size.y());
    extent = extent.cwiseMax(c.offset + c.size);
  }
  return extent;
}

// SLIM on a coarse copy of a large chart (multilevel.h): BFF's start, coarsened in its own
// plane, optimised there, and carried back. Empty when the fine map would fold or overlap
// itself, or the coarse chart failed other than by cancellation (then the caller runs SLIM on
// the chart itself).
Result<std::optional<std::vector<Vec2>>> flatten_two_level(const DiscPatch& patch, const UvOptions& options,
                                                           UvResult& result, const CancelToken& cancel) {
  SEAM_TRY(std::vector<Vec2> start, flatten_bff(patch, cancel));
  if (repair_flips(patch, start) > 0) return std::optional<std::vector<Vec2>>();
  const std::size_t coarse = default_coarse_vertices(patch.num_vertices());
  auto two_level = slim_two_level(
      patch, start, coarse,
      coarse_slim_options(
          {.iterations = options.slim_iterations, .proxy = options.slim_proxy, .injective = options.injective}),
      cancel);
  // Cancellation ends the request; any other failure on the coarse chart leaves the chart to
  // SLIM on the whole chart, which reports its own errors.
  if (!two_level.ok() && two_level.error().code == ErrorCode::kCancelled) return two_level.take_error();
  if (!two_level.ok() || two_level->uv.empty()) return std::optional<std::vector<Vec2>>();
  if (two_level->coarse.overlapping_start) ++result.overlapping_starts;
  return std::optional<std::vector<Vec2>>(std::move(two_level->uv));
}

// Flattens one chart by options.method. Records in `result` an ARAP chart that fell back to
// its BFF start (method_used) and a SLIM start whose boundary crossed itself.
Result<std::vector<Vec2>> flatten_chart(const DiscPatch& patch, const UvOptions& options, UvResult& result,
                                        const CancelToken& cancel) {
  std::vector<Vec2> uv;
  switch (options.method) {
    case UvMethod::kLscm: {
      SEAM_TRY(uv, flatten_lscm(patch, cancel));
      return uv;
    }
    case UvMethod::kBff: {
      SEAM_TRY(uv, flatten_bff(patch, cancel));
      repair_flips(patch, uv);
      return uv;
    }
    case UvMethod::kArap: {
      SEAM_TRY(std::vector<Vec2> start_uv, flatten_bff(patch, cancel));
      repair_flips(patch, start_uv);
      SEAM_TRY(uv, flatten_arap(patch, start_uv, options.arap_iterations, cancel));
      repair_flips(patch, uv);
      // ARAP's local/global steps have no flip guarantee; never trade a clean start for flips.
      if (count_flipped(patch, uv) > count_flipped(patch, start_uv)) {
        result.method_used = UvMethod::kBff;
        return start_uv;
      }
      return uv;
    }
    case UvMethod::kSlim: {
      if (options.multilevel_min_faces > 0 && patch.triangles.size() >= options.multilevel_min_faces) {
        SEAM_TRY(std::optional<std::vector<Vec2>> two_level, flatten_two_level(patch, options, result, cancel));
        if (two_level) {
          ++result.two_level_charts;
          return std::move(*two_level);
        }
        ++result.two_level_fallbacks;
      }
      const std::vector<int> order = shared_vertex_order(patch);
      SEAM_TRY(std::vector<Vec2> start_uv, flatten_bff(patch, cancel, order));
      repair_flips(patch, start_uv);
      SEAM_TRY(SlimResult slim, flatten_slim(patch, std::move(start_uv),
                                             {.iterations = options.slim_iterations,
                                              .proxy = options.slim_proxy,
                                              .injective = options.injective,
                                              .vertex_order = order},
                                             cancel));
      if (slim.overlapping_start) ++result.overlapping_starts;
      return std::move(slim.uv);
    }
  }
  return make_error(ErrorCode::kInvalidArgument, "parameterize: unknown UV method");
}

Status validate(const HalfedgeMesh& disc_mesh, const UvOptions& options) {
  if (options.arap_iterations < 0 || options.arap_iterations > 1000) {
    return make_error(ErrorCode::kInvalidArgument,
                      "arap_iterations must be in 0..1000, got " + std::to_string(options.arap_iterations));
  }
  if (options.slim_iterations < 0 || options.slim_iterations > 1000) {
    return make_error(ErrorCode::kInvalidArgument,
                      "slim_iterations must be in 0..1000, got " + std::to_string(options.slim_iterations));
  }
  if (!(options.chart_gap >= 0 && options.chart_gap <= 1)) {
    return make_error(ErrorCode::kInvalidArgument, "chart_gap must be in 0..1");
  }
  if (disc_mesh.num_faces() == 0) return make_error(ErrorCode::kEmptyMesh, "parameterize: the mesh has no faces");
  return Ok{};
}

// Packs the charts, fits the atlas into [0,1]^2, rounds to the UV grid (what ships is what is
// measured) and measures distortion and overlap.
Status finish_atlas(const HalfedgeMesh& disc_mesh, const std::vector<DiscPatch>& patches, std::vector<Chart> charts,
                    double chart_gap, UvResult& result, const CancelToken& cancel) {
  const Vec2 extent = pack_charts(charts, chart_gap);
  const double fit = std::max(extent.x(), extent.y());
  const double inv = fit > 0 ? 1.0 / fit : 1.0;
  result.uv.assign(disc_mesh.num_vertices(), Vec2::Zero());
  for (std::size_t c = 0; c < patches.size(); ++c) {
    const DiscPatch& patch = patches[c];
    std::vector<Vec2>& uv = charts[c].uv;
    for (Vec2& p : uv) p = ((p + charts[c].offset) * inv).cwiseMax(0.0).cwiseMin(1.0);
    const Float32Rounding rounding = round_to_float32(patch, uv);
    result.float32_degenerate += rounding.degenerate;
    result.float32_unrepaired += rounding.remaining;
    for (std::size_t v = 0; v < patch.num_vertices(); ++v) result.uv[patch.to_mesh[v]] = uv[v];
  }
  result.distortion = measure_distortion(disc_mesh, result.uv);
  SEAM_TRY(OverlapResult overlap, find_overlaps(disc_mesh, result.uv, cancel));
  result.overlap_area = overlap.overlap_area;
  result.overlap_fraction = overlap.overlap_fraction;
  result.overlap_ms = overlap.ms;
  return Ok{};
}

}  // namespace

Result<UvResult> parameterize(const HalfedgeMesh& disc_mesh, const UvOptions& options, const CancelToken& cancel) {
  return parameterize(disc_mesh, compute_topology(disc_mesh), options, cancel);
}

Result<UvResult> parameterize(const HalfedgeMesh& disc_mesh, const Topology& topology, const UvOptions& options,
                              const CancelToken& cancel) {
  if (Status valid = validate(disc_mesh, options); !valid.ok()) return valid.take_error();
  if (auto own = check_topology_of(disc_mesh, topology); !own.ok()) return own.take_error();
  SEAM_TRY(std::vector<DiscPatch> patches, extract_disc_patches(disc_mesh, topology));

  UvResult result;
  result.method_used = options.method;
  result.charts = patches.size();
  const auto start = StageClock::now();
  std::vector<Chart> charts;
  charts.reserve(patches.size());
  for (const DiscPatch& patch : patches) {
    if (cancel.is_cancelled()) return cancelled_error("parameterize");
    SEAM_TRY(std::vector<Vec2> uv, flatten_chart(patch, options, result, cancel));
    if (count_flipped(patch, uv) > 0 || !boundary_is_simple(patch, uv)) ++result.charts_not_injective;
    charts.push_back(normalise_chart(patch, std::move(uv)));
  }
  result.solve_ms = ms_since(start);
  if (Status done = finish_atlas(disc_mesh, patches, std::move(charts), options.chart_gap, result, cancel);
      !done.ok()) {
    return done.take_error();
  }
  return result;
}

}  // namespace seam::core
