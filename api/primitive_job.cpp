// One primitive: weld -> canonical order -> repair -> build -> extrema -> seam -> cut -> flatten.
#include "api/primitive_job.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <unordered_set>
#include <utility>

#include "api/process_env.h"
#include "api/surface.h"
#include "core/atlas/features.h"
#include "core/mesh/cut.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/topology.h"
#include "core/timing.h"
#include "core/visibility/visibility.h"

namespace seam::api {
namespace {

using nlohmann::json;

using core::ms_since;

ApiError timeout(const char* stage) {
  return make_api_error(ApiErrorCode::kTimeout, std::string("the computation exceeded the time budget during ") + stage);
}

// The asset's vertices after the cut: one per (input vertex, cut vertex) pair, and every input
// triangle over them, in input order.
struct OutputVertices {
  CutPrimitive primitive;                   // source_vertex and triangles filled
  std::vector<core::VertexId> cut_vertex;   // per output vertex: the cut vertex its UV comes from
};

// Per welded vertex, a cut vertex to borrow for corners the topology left out (degenerate
// faces): the lowest cut copy in some face, else the lowest copy at all.
std::vector<core::VertexId> welded_to_cut(const Canonical& canon, const core::CutMesh& cut) {
  std::vector<core::VertexId> out(canon.welded_vertices);
  for (int pass = 0; pass < 2; ++pass) {
    for (std::uint32_t v = 0; v < cut.mesh.num_vertices(); ++v) {
      const core::VertexId cv(v);
      if (pass == 0 && cut.mesh.is_isolated(cv)) continue;
      core::VertexId& slot = out[canon.vertex_to_welded[cut.to_original[cv].index()]];
      if (!slot.valid()) slot = cv;
    }
  }
  return out;
}

// Kept faces keep their corners (matched by vertex, not by trusting the rotation) and take
// the repaired winding, so a reoriented face is written reoriented. A face left out of the
// topology (degenerate after welding) is kept in the asset: its corners borrow a cut vertex
// of their welded vertex, or of another corner of the face when theirs is in no face, so its
// UVs come from its vertices (a zero-area UV triangle when it repeats a welded vertex).
ApiResult<OutputVertices> map_output_vertices(const PrimitiveData& data, const Canonical& canon,
                                              const core::CutMesh& cut) {
  OutputVertices out;
  CutPrimitive& prim = out.primitive;
  prim.triangles.resize(data.mesh.triangles.size());
  prim.source_vertex.reserve(data.mesh.positions.size());
  out.cut_vertex.reserve(data.mesh.positions.size());
  // Output vertices are numbered in order of first use. An input vertex has a few cut copies at
  // most (one per side of the seams through it), so each keeps a chain of its output vertices:
  // two arrays instead of a hash map of (input, cut vertex) pairs, no hashing, no node per pair.
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> first_output(data.mesh.positions.size(), kNone);
  std::vector<std::uint32_t> next_output;  // per output vertex: another of the same input vertex
  next_output.reserve(data.mesh.positions.size());
  auto emit = [&](std::uint32_t input, core::VertexId cv) {
    for (std::uint32_t o = first_output[input]; o != kNone; o = next_output[o]) {
      if (out.cut_vertex[o] == cv) return o;
    }
    const auto o = static_cast<std::uint32_t>(prim.source_vertex.size());
    prim.source_vertex.push_back(input);
    out.cut_vertex.push_back(cv);
    next_output.push_back(std::exchange(first_output[input], o));
    return o;
  };
  for (std::size_t f = 0; f < data.mesh.triangles.size(); ++f) {
    const std::uint32_t mf = canon.input_to_face[f];
    if (mf == kNoFace) continue;
    const auto corners = cut.mesh.face_vertices(core::FaceId(mf));
    core::Triangle& tri = prim.triangles[f];
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint32_t input = data.mesh.triangles[f][k];
      const std::uint32_t welded = canon.input_to_vertex[input];
      core::VertexId cv;
      for (auto c : corners) {
        if (canon.vertex_to_welded[cut.to_original[c].index()] == welded) cv = c;
      }
      if (!cv.valid()) {
        return make_api_error(ApiErrorCode::kInternal, "cut face " + std::to_string(f) + " does not match its input triangle");
      }
      tri[k] = emit(input, cv);
    }
    if (canon.reoriented[mf]) std::swap(tri[1], tri[2]);
  }
  if (canon.degenerate_inputs.empty()) return out;
  const std::vector<core::VertexId> borrow = welded_to_cut(canon, cut);
  for (const std::uint32_t f : canon.degenerate_inputs) {
    // All three corners take one cut vertex (the first corner's that lies in some face, else
    // the first corner's), so the face has no area in texture space either and lies in one
    // chart. Corners in two charts (a repeated vertex beside another part's, or three points
    // of a line on both sides of a seam) would make a triangle across charts, which the atlas
    // step cannot place, and three points of a line would get a UV triangle with area over
    // other charts, which a baker would paint.
    core::VertexId first, in_face;
    for (std::size_t k = 0; k < 3; ++k) {
      const core::VertexId c = borrow[canon.input_to_vertex[data.mesh.triangles[f][k]]];
      if (!c.valid())
        return make_api_error(ApiErrorCode::kInternal, "degenerate face " + std::to_string(f) + " lost a vertex");
      if (!first.valid()) first = c;
      if (!in_face.valid() && !cut.mesh.is_isolated(c)) in_face = c;
    }
    const core::VertexId point = in_face.valid() ? in_face : first;
    for (std::size_t k = 0; k < 3; ++k) prim.triangles[f][k] = emit(data.mesh.triangles[f][k], point);
  }
  return out;
}

// Automatic extrema minus `excluded`, at most `budget` of them: the most prominent (ties: the
// lower vertex id), kept in the detector's order (by component, most prominent first). The
// detector's per-component cap is lowered to the budget too, so it never ranks more.
ApiResult<std::vector<core::VertexId>> automatic_extrema(const ExtremaSpec& spec, std::vector<core::VertexId> excluded,
                                                         const Surface& surface, std::size_t budget, unsigned threads,
                                                         const core::CancelToken& cancel) {
  if (budget == 0) return std::vector<core::VertexId>{};
  core::ExtremaOptions options = spec.auto_options;
  options.threads = threads;
  if (options.max_count == 0 || options.max_count > budget) options.max_count = budget;
  auto found = core::detect_extrema(surface.mesh, surface.topology, options, cancel);
  if (!found.ok()) return from_core(found.error());
  std::sort(excluded.begin(), excluded.end());
  std::vector<core::Extremum> kept;
  for (const auto& e : found->extrema) {
    if (!std::binary_search(excluded.begin(), excluded.end(), e.vertex)) kept.push_back(e);
  }
  if (kept.size() > budget) {
    std::vector<std::size_t> rank(kept.size());
    for (std::size_t i = 0; i < rank.size(); ++i) rank[i] = i;
    std::stable_sort(rank.begin(), rank.end(), [&](std::size_t a, std::size_t b) {
      if (kept[a].prominence != kept[b].prominence) return kept[a].prominence > kept[b].prominence;
      return kept[a].vertex < kept[b].vertex;
    });
    std::vector<bool> keep(kept.size(), false);
    for (std::size_t i = 0; i < budget; ++i) keep[rank[i]] = true;
    std::size_t w = 0;
    for (std::size_t i = 0; i < kept.size(); ++i) {
      if (keep[i]) kept[w++] = kept[i];
    }
    kept.resize(w);
  }
  std::vector<core::VertexId> out;
  out.reserve(kept.size());
  for (const auto& e : kept) out.push_back(e.vertex);
  return out;
}

// Explicit extrema first in the budget (the client named them), then the automatic ones.
ApiResult<std::vector<core::VertexId>> resolve_extrema(const ExtremaSpec& spec, const PrimitiveData& data,
                                                       const Surface& surface, const PrimitiveJobOptions& job,
                                                       const core::CancelToken& cancel) {
  const Canonical& canon = surface.canon;
  const core::HalfedgeMesh& mesh = surface.mesh;
  const std::size_t n = data.mesh.positions.size();
  auto check = [&](std::uint32_t i, const char* what) -> std::optional<ApiError> {
    if (i < n) return std::nullopt;
    return make_api_error(ApiErrorCode::kExtremumOutOfRange,
                          std::string(what) + " vertex " + std::to_string(i) + " is out of range: the primitive has " +
                              std::to_string(n) + " vertices",
                          {{"index", i}, {"vertices", n}});
  };
  SEAM_TRY(const std::size_t explicit_count, explicit_extrema_count(spec, job.max_extrema));
  std::vector<core::VertexId> result;
  // Copies of one input vertex (pinched or repaired splits) are one extremum: the response
  // names input vertices, and it never names one twice.
  std::unordered_set<std::uint32_t> inputs;
  auto add = [&](core::VertexId v) {
    if (inputs.insert(canon.vertex_to_input[v.index()]).second) result.push_back(v);
  };
  if (spec.automatic) {
    std::vector<core::VertexId> excluded;
    for (auto i : spec.exclude) {
      if (auto e = check(i, "excluded")) return *e;
      excluded.push_back(core::VertexId(canon.input_to_vertex[i]));
    }
    SEAM_TRY(
        const std::vector<core::VertexId> found,
        automatic_extrema(spec, std::move(excluded), surface, job.max_extrema - explicit_count, job.threads, cancel));
    for (auto v : found) add(v);
  }
  for (auto i : spec.indices) {
    if (auto e = check(i, "extremum")) return *e;
    const core::VertexId v(canon.input_to_vertex[i]);
    if (mesh.is_isolated(v)) {
      return make_api_error(ApiErrorCode::kExtremumOutOfRange,
                            "extremum vertex " + std::to_string(i) +
                                " lies in no face of the surface (no triangle uses it, or only triangles without "
                                "area): a seam cannot reach it",
                            {{"index", i}});
    }
    add(v);
  }
  // Snap each position to the nearest vertex that lies on the surface (isolated vertices
  // cannot be terminals).
  for (const auto& p : spec.positions) {
    const core::Vec3 q(p[0], p[1], p[2]);
    double best = std::numeric_limits<double>::infinity();
    core::VertexId best_v;
    for (std::uint32_t v = 0; v < mesh.num_vertices(); ++v) {
      if (mesh.is_isolated(core::VertexId(v))) continue;
      const double d = (mesh.position(core::VertexId(v)) - q).squaredNorm();
      if (d < best) {
        best = d;
        best_v = core::VertexId(v);
      }
    }
    if (best_v.valid()) add(best_v);
  }
  return result;
}

// The seam in input numbering, for the response and the primitive's extras.seam.
json seam_summary(const core::SeamResult& seam, const std::vector<core::EdgeId>& cut_edges, const Surface& s,
                  core::SeamMethod method) {
  const core::HalfedgeMesh& mesh = s.mesh;
  auto input_of = [&](core::VertexId v) { return s.canon.vertex_to_input[v.index()]; };
  auto edge_pairs = [&](const std::vector<core::EdgeId>& edges) {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
    for (auto e : edges) {
      const auto h = core::HalfedgeMesh::halfedge(e);
      const auto a = input_of(mesh.tail(h)), b = input_of(mesh.head(h));
      pairs.emplace_back(std::min(a, b), std::max(a, b));
    }
    std::sort(pairs.begin(), pairs.end());
    json out = json::array();
    for (const auto& [a, b] : pairs) out.push_back({a, b});
    return out;
  };
  // First occurrence kept: copies of one input vertex (splits, cut) are listed once.
  auto vertex_list = [&](const std::vector<core::VertexId>& vs) {
    json out = json::array();
    std::unordered_set<std::uint32_t> seen;
    for (auto v : vs) {
      const std::uint32_t i = input_of(v);
      if (seen.insert(i).second) out.push_back(i);
    }
    return out;
  };
  json polylines = json::array();
  for (const auto& branch : seam.branches) {
    json line = json::array();
    for (auto v : branch) {
      const auto& p = mesh.position(v);
      line.push_back({p.x(), p.y(), p.z()});
    }
    polylines.push_back(std::move(line));
  }
  return {{"method", core::seam_method_name(method)},
          {"edges", edge_pairs(cut_edges)},
          {"length", seam.length},
          {"extrema", vertex_list(seam.extrema)},
          {"terminals", vertex_list(seam.terminals)},
          {"steiner_points", vertex_list(seam.steiner_points)},
          {"cut_graph_edges", edge_pairs(seam.cut_graph_edges)},
          {"cut_graph_length", seam.cut_graph_length},
          {"optimal", seam.optimal},
          {"polylines", std::move(polylines)}};
}

json topology_summary(const PrimitiveData& data, const Surface& s) {
  return {{"vertices", data.mesh.positions.size()},
          {"faces", data.mesh.triangles.size()},
          {"welded_vertices", s.welded_vertices},
          {"pinched_vertices_split", s.canon.repairs.pinched_vertices},
          {"components", s.topology.components.size()},
          {"genus", s.topology.total_genus()},
          {"boundary_loops", s.topology.boundary_loops.size()}};
}

json repairs_summary(const core::RepairCounts& r) {
  return {{"non_manifold_edges", r.non_manifold_edges},
          {"reoriented_faces", r.reoriented_faces},
          {"degenerate_faces", r.degenerate_faces},
          {"pinched_vertices", r.pinched_vertices},
          {"split_off_faces", r.split_off_faces}};
}

json uv_summary(const core::UvResult& uv) {
  const auto& d = uv.distortion;
  return {{"method", core::uv_method_name(uv.method_used)},
          {"area_distortion", d.area},
          {"area_distortion_geometric", d.area_geometric},
          {"angle_distortion", d.angle},
          {"stretch_l2", d.stretch_l2},
          {"stretch_linf", d.stretch_linf},
          {"flipped", d.flipped},
          {"overlap_area", uv.overlap_area},
          {"two_level_charts", uv.two_level_charts}};
}

// The new UVs per output vertex. glTF puts the texture origin top-left with v growing down;
// v is flipped so a counter-clockwise triangle stays counter-clockwise in texture space. The
// UVs lie on core::kUvGrid, so 1 - v is exact and the flipped map is the one measured.
std::vector<std::array<float, 2>> output_uvs(const core::UvResult& uv, const std::vector<core::VertexId>& cut_vertex) {
  std::vector<std::array<float, 2>> out;
  out.reserve(cut_vertex.size());
  for (auto c : cut_vertex) {
    const core::Vec2& p = uv.uv[c];
    out.push_back({static_cast<float>(p.x()), static_cast<float>(1.0 - p.y())});
  }
  return out;
}

// The surface's edge between the originals of the ends of `e`, an edge of `sub` (the surface
// cut along its features, whose vertices map to the surface by sub_to_surface).
core::EdgeId surface_edge(core::EdgeId e, const core::HalfedgeMesh& sub,
                          const core::VertexData<core::VertexId>& sub_to_surface, const core::HalfedgeMesh& mesh) {
  const core::HalfedgeId h = core::HalfedgeMesh::halfedge(e);
  return core::HalfedgeMesh::edge(mesh.find_halfedge(sub_to_surface[sub.tail(h)], sub_to_surface[sub.head(h)]));
}

// A seam computed on `sub` expressed on the surface: vertices through sub_to_surface, edges
// found between the mapped ends.
core::SeamResult seam_on_surface(core::SeamResult seam, const core::HalfedgeMesh& sub,
                                 const core::VertexData<core::VertexId>& sub_to_surface, const core::HalfedgeMesh& mesh) {
  auto vertices = [&](std::vector<core::VertexId>& vs) {
    for (auto& v : vs) v = sub_to_surface[v];
  };
  auto edges = [&](std::vector<core::EdgeId>& es) {
    for (auto& e : es) e = surface_edge(e, sub, sub_to_surface, mesh);
  };
  vertices(seam.extrema);
  vertices(seam.terminals);
  vertices(seam.steiner_points);
  for (auto& branch : seam.branches) vertices(branch);
  edges(seam.seam_edges);
  edges(seam.cut_graph_edges);
  return seam;
}

// What steers the seam (API.md v2 "Seeing and steering"): per edge of the surface, the
// product of the hiding multipliers (views, openness) and the mean of its ends' _SEAM_COST.
struct Steering {
  std::vector<double> edge_costs;  ///< empty: nothing steers, the seam is the shortest
  core::Visibility visibility;
};

constexpr double kFreeEdge = 1e-3;  // _SEAM_COST 0 ("free") still has a positive weight

// _SEAM_COST per surface vertex: the largest over the input vertices welded into it.
ApiResult<std::vector<double>> vertex_costs(const PrimitiveData& data, const Surface& s) {
  const auto it = std::find_if(data.attributes.begin(), data.attributes.end(),
                               [](const AttributeArray& a) { return a.name == "_SEAM_COST"; });
  if (it == data.attributes.end()) return std::vector<double>{};
  if (it->component_type != 5126 || it->components != 1) {
    return malformed_asset("_SEAM_COST must be a SCALAR float attribute");
  }
  std::vector<double> welded(s.welded_vertices, 0.0);
  for (std::size_t i = 0; i < it->count; ++i) {
    float c;
    std::memcpy(&c, it->data.data() + 4 * i, 4);
    if (!std::isfinite(c) || c < 0) {
      return make_api_error(ApiErrorCode::kMalformedAsset,
                            "_SEAM_COST of vertex " + std::to_string(i) + " is " + std::to_string(c) +
                                "; it must be a finite number >= 0 (0 free, 1 neutral, large avoided)",
                            {{"vertex", i}});
    }
    double& w = welded[s.canon.input_to_vertex[i]];
    w = std::max(w, static_cast<double>(c));
  }
  std::vector<double> out(s.mesh.num_vertices());
  for (std::size_t v = 0; v < out.size(); ++v) out[v] = welded[s.canon.vertex_to_welded[v]];
  return out;
}

ApiResult<Steering> steering(const PrimitiveData& data, const Surface& s, const SeamParams& params, unsigned threads,
                             const core::CancelToken& cancel) {
  Steering out;
  SEAM_TRY(const std::vector<double> costs, vertex_costs(data, s));
  const bool hiding = !params.hide_from.empty() || params.hide_occluded;
  if (costs.empty() && !hiding) return out;
  out.edge_costs.assign(s.mesh.num_edges(), 1.0);
  if (hiding) {
    core::VisibilityOptions options;
    for (const auto& d : params.hide_from) options.views.emplace_back(d[0], d[1], d[2]);
    options.ambient_occlusion = params.hide_occluded;
    options.threads = threads;
    auto vis = core::compute_visibility(s.mesh, options, cancel);
    if (!vis.ok()) {
      // The only options a client sets here are the views (params_from_json refuses zero and
      // non-finite ones first); name the parameter like every other parameter error.
      ApiError error = from_core(vis.error());
      if (error.code == ApiErrorCode::kInvalidParameter) error.details["parameter"] = "hide_from";
      return error;
    }
    out.visibility = std::move(vis).value();
    out.edge_costs = core::hiding_multipliers(s.mesh, out.visibility, params.hide_strength);
  }
  if (!costs.empty()) {
    for (std::uint32_t e = 0; e < s.mesh.num_edges(); ++e) {
      const core::HalfedgeId h = core::HalfedgeMesh::halfedge(core::EdgeId(e));
      const double c = 0.5 * (costs[s.mesh.tail(h).index()] + costs[s.mesh.head(h).index()]);
      out.edge_costs[e] *= std::max(c, kFreeEdge);
    }
  }
  return out;
}

// The length of `edges` that some view sees (a face of the edge front-facing and unoccluded).
double visible_length(const core::HalfedgeMesh& mesh, const core::Visibility& vis, const std::vector<core::EdgeId>& edges) {
  double length = 0;
  for (const core::EdgeId e : edges) {
    const core::HalfedgeId h = core::HalfedgeMesh::halfedge(e);
    bool seen = false;
    for (const core::HalfedgeId side : {h, core::HalfedgeMesh::twin(h)}) {
      const core::FaceId f = mesh.face(side);
      seen = seen || (f.valid() && vis.seen[f] > 0);
    }
    if (seen) length += mesh.edge_length(e);
  }
  return length;
}

struct SeamCut {
  core::SeamResult seam;
  std::vector<core::EdgeId> cut_edges;  ///< on the surface: seam, cut graph and feature edges
  std::size_t feature_edges = 0;
};

// charts "seam": the seam on the surface. charts "features": the surface is first cut along
// its sharp edges; the seam then opens each side to a disc, its extrema leaves there.
ApiResult<SeamCut> seam_and_cuts(const Surface& surface, const std::vector<core::VertexId>& terminals,
                                 const SeamParams& params, const core::SeamOptions& options,
                                 const core::CancelToken& cancel) {
  SeamCut out;
  std::vector<core::EdgeId> features;
  if (params.charts == ChartMode::kFeatures) {
    auto found = core::find_feature_edges(surface.mesh, core::FeatureOptions{params.feature_angle_deg}, cancel);
    if (!found.ok()) return from_core(found.error());
    features = std::move(found->edges);
  }
  if (features.empty()) {
    auto seam = core::compute_seam(surface.mesh, surface.topology, terminals, options, cancel);
    if (!seam.ok()) return map_core_error(seam.error(), surface.canon, seam.error().code);
    out.seam = std::move(seam).value();
    out.cut_edges = core::all_cut_edges(out.seam);
    return out;
  }
  auto sides = core::cut_along_edges(surface.mesh, features);
  if (!sides.ok()) return from_core(sides.error());
  std::vector<core::VertexId> first_copy(surface.mesh.num_vertices());
  for (std::uint32_t v = sides->mesh.num_vertices(); v-- > 0;) first_copy[sides->to_original[core::VertexId(v)].index()] = core::VertexId(v);
  std::vector<core::VertexId> sub_terminals;
  for (auto t : terminals) sub_terminals.push_back(first_copy[t.index()]);
  // The steering costs are per edge of the surface; each side's edge takes its original's.
  std::vector<double> sub_costs;
  if (!options.edge_costs.empty()) {
    for (std::uint32_t e = 0; e < sides->mesh.num_edges(); ++e) {
      sub_costs.push_back(
          options.edge_costs[surface_edge(core::EdgeId(e), sides->mesh, sides->to_original, surface.mesh).index()]);
    }
  }
  core::SeamOptions sub_options = options;
  sub_options.edge_costs = sub_costs;
  auto seam = core::compute_seam(sides->mesh, sub_terminals, sub_options, cancel);
  if (!seam.ok()) return from_core(seam.error());
  out.seam = seam_on_surface(std::move(seam).value(), sides->mesh, sides->to_original, surface.mesh);
  out.cut_edges = core::all_cut_edges(out.seam);
  out.cut_edges.insert(out.cut_edges.end(), features.begin(), features.end());
  std::sort(out.cut_edges.begin(), out.cut_edges.end());
  out.cut_edges.erase(std::unique(out.cut_edges.begin(), out.cut_edges.end()), out.cut_edges.end());
  out.feature_edges = features.size();
  return out;
}

// Charts of the output vertices: the cut's connected components (degenerate faces borrow a
// cut vertex, so they join their chart), renumbered by first output vertex; and each chart's
// 3D area.
void label_charts(const core::CutMesh& cut, const std::vector<core::VertexId>& cut_vertex, PrimitiveResult& result) {
  const core::HalfedgeMesh& m = cut.mesh;
  std::vector<std::uint32_t> parent(m.num_vertices());
  for (std::uint32_t v = 0; v < parent.size(); ++v) parent[v] = v;
  auto find = [&](std::uint32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  std::vector<double> area(m.num_vertices(), 0.0);
  for (std::uint32_t f = 0; f < m.num_faces(); ++f) {
    const auto c = m.face_vertices(core::FaceId(f));
    const std::uint32_t r = find(c[0].value());
    for (std::size_t k = 1; k < 3; ++k) parent[find(c[k].value())] = r;
  }
  for (std::uint32_t f = 0; f < m.num_faces(); ++f) {
    const auto c = m.face_vertices(core::FaceId(f));
    const core::Vec3 n = (m.position(c[1]) - m.position(c[0])).cross(m.position(c[2]) - m.position(c[0]));
    area[find(c[0].value())] += 0.5 * n.norm();
  }
  std::vector<std::uint32_t> label(m.num_vertices(), std::numeric_limits<std::uint32_t>::max());
  result.chart.clear();
  result.chart_area.clear();
  for (const core::VertexId cv : cut_vertex) {
    const std::uint32_t r = find(cv.value());
    if (label[r] == std::numeric_limits<std::uint32_t>::max()) {
      label[r] = static_cast<std::uint32_t>(result.chart_area.size());
      result.chart_area.push_back(area[r]);
    }
    result.chart.push_back(label[r]);
  }
}

}  // namespace

// The cost cap comes first: an over-long explicit list is refused before the asset is parsed.
ApiResult<std::size_t> explicit_extrema_count(const ExtremaSpec& spec, std::size_t max_extrema) {
  const std::size_t count = spec.indices.size() + spec.positions.size();
  if (count > max_extrema) {
    return make_api_error(ApiErrorCode::kTooManyExtrema,
                          "extrema: " + std::to_string(count) + " explicit extrema, more than the limit of " +
                              std::to_string(max_extrema) + " (the server's --max-extrema)",
                          {{"count", count}, {"limit", max_extrema}});
  }
  return count;
}


ApiResult<PrimitiveResult> process_primitive(const PrimitiveData& data, const ExtremaSpec& extrema,
                                             const SeamParams& params, const PrimitiveJobOptions& options,
                                             const core::CancelToken& cancel) {
  json timings = json::object();
  auto t = core::StageClock::now();
  SEAM_TRY(const Surface surface, prepare_surface(data, params, cancel));
  timings["weld"] = ms_since(t);
  if (cancel.is_cancelled()) return timeout("welding");

  t = core::StageClock::now();
  SEAM_TRY(const std::vector<core::VertexId> terminals, resolve_extrema(extrema, data, surface, options, cancel));
  timings["extrema"] = ms_since(t);

  t = core::StageClock::now();
  core::SeamOptions seam_options;
  seam_options.method = params.method;
  seam_options.refine = params.refine;
  seam_options.threads = std::max(1u, options.threads);
  SEAM_TRY(const Steering steer, steering(data, surface, params, seam_options.threads, cancel));
  seam_options.edge_costs = steer.edge_costs;
  SEAM_TRY(const SeamCut seam_cut, seam_and_cuts(surface, terminals, params, seam_options, cancel));
  const core::SeamResult* seam = &seam_cut.seam;
  const std::vector<core::EdgeId>& cut_edges = seam_cut.cut_edges;
  timings["seam"] = ms_since(t);

  t = core::StageClock::now();
  auto cut = core::cut_along_edges(surface.mesh, cut_edges);
  if (!cut.ok()) return from_core(cut.error());
  const core::Topology cut_topology = core::compute_topology(cut->mesh);
  timings["cut"] = ms_since(t);
  if (cancel.is_cancelled()) return timeout("cutting");

  t = core::StageClock::now();
  std::optional<core::UvResult> uv;
  if (params.uv) {
    release_free_memory_before_flattening(cut->mesh.num_faces());
    core::UvOptions uv_options;
    uv_options.method = *params.uv;
    auto flattened = core::parameterize(cut->mesh, cut_topology, uv_options, cancel);
    if (!flattened.ok()) return from_core(flattened.error());
    uv = std::move(flattened).value();
  }
  timings["uv"] = ms_since(t);

  t = core::StageClock::now();
  SEAM_TRY(OutputVertices output, map_output_vertices(data, surface.canon, *cut));
  PrimitiveResult result;
  result.cut = std::move(output.primitive);
  if (uv) result.cut.uv = output_uvs(*uv, output.cut_vertex);
  label_charts(*cut, output.cut_vertex, result);
  json seam_json = seam_summary(*seam, cut_edges, surface, params.method);
  if (params.charts == ChartMode::kFeatures) seam_json["feature_edges"] = seam_cut.feature_edges;
  seam_json["cost"] = seam->cost;
  if (!steer.visibility.seen.empty()) {
    seam_json["visible_length"] = visible_length(surface.mesh, steer.visibility, seam->seam_edges);
  }
  result.cut.seam_extras = {{"method", seam_json["method"]},       {"length", seam->length},
                            {"edges", seam_json["edges"]},         {"extrema", seam_json["extrema"]},
                            {"terminals", seam_json["terminals"]}, {"steiner_points", seam_json["steiner_points"]},
                            {"cut_graph_edges", seam_json["cut_graph_edges"]}};
  if (uv) result.cut.seam_extras["uv_method"] = core::uv_method_name(uv->method_used);
  timings["output"] = ms_since(t);
  result.summary = {{"seam", std::move(seam_json)},
                    {"topology", topology_summary(data, surface)},
                    {"repairs", repairs_summary(surface.canon.repairs)},
                    {"cut", {{"vertices", cut->mesh.num_vertices()},
                             {"faces", cut->mesh.num_faces()},
                             {"euler_characteristic", cut_topology.euler_characteristic()},
                             {"boundary_loops", cut_topology.boundary_loops.size()},
                             {"asset_vertices", result.cut.source_vertex.size()}}},
                    {"uv", uv ? uv_summary(*uv) : json(nullptr)},
                    {"timings_ms", std::move(timings)}};
  return result;
}

}  // namespace seam::api
