// The weld stage: see api/surface.h.
#include "api/surface.h"

#include <algorithm>
#include <limits>
#include <numeric>
#include <utility>

#include "core/mesh/split_pinched.h"
#include "core/mesh/vertex_order.h"
#include "core/mesh/weld.h"
#include "core/timing.h"

namespace seam::api {
namespace {

using nlohmann::json;

using core::ms_since;

// The welded soup numbered as Canonical describes.
Canonical canonicalize(const core::WeldResult& weld, const std::vector<core::Triangle>& input_triangles) {
  Canonical c;
  const std::size_t wn = weld.positions.size();
  c.welded_vertices = wn;
  const std::vector<std::uint32_t> order = core::spatial_order(weld.positions);
  std::vector<std::uint32_t> rank(wn);
  c.positions.resize(wn);
  c.vertex_to_input.resize(wn);
  for (std::uint32_t k = 0; k < wn; ++k) {
    rank[order[k]] = k;
    c.positions[k] = weld.positions[order[k]];
    c.vertex_to_input[k] = weld.welded_to_input[order[k]];  // the smallest input index (weld.h)
  }
  c.input_to_vertex.resize(weld.input_to_welded.size());
  for (std::size_t i = 0; i < weld.input_to_welded.size(); ++i) c.input_to_vertex[i] = rank[weld.input_to_welded[i]];
  // Each face rotated to start at its smallest vertex (the winding kept), then the faces sorted.
  c.triangles.resize(input_triangles.size());
  for (std::size_t t = 0; t < input_triangles.size(); ++t) {
    core::Triangle tri;
    for (std::size_t k = 0; k < 3; ++k) tri[k] = c.input_to_vertex[input_triangles[t][k]];
    c.triangles[t] = core::rotated_to_smallest(tri);
  }
  c.face_to_input = core::sort_triangles(c.triangles, wn);
  c.input_to_face.resize(c.triangles.size());
  for (std::uint32_t f = 0; f < c.triangles.size(); ++f) c.input_to_face[c.face_to_input[f]] = f;
  return c;
}

// A welded vertex where several fans of triangles meet only at that vertex (scans, CGAL's cow,
// and split-vertex assets whose welding closes two sheets at a point) becomes one vertex per
// fan. The copies map back to the welded vertex and so to the same input vertex; the split is
// numbered from the canonical mesh, so it is as independent of the input order as the rest.
void split_pinched(Canonical& c) {
  core::PinchSplit split = core::split_pinched_vertices(c.positions, c.triangles);
  c.repairs.pinched_vertices = split.pinched_vertices;
  for (std::size_t v = c.vertex_to_input.size(); v < split.positions.size(); ++v) {
    c.vertex_to_input.push_back(c.vertex_to_input[split.source[v]]);
  }
  c.vertex_to_welded = std::move(split.source);
  c.positions = std::move(split.positions);
  c.triangles = std::move(split.triangles);
  c.reoriented.assign(c.triangles.size(), 0);
}

// The maps repair and split_pinched would leave on a soup the builder accepts: no copies, no
// reversed faces, nothing left out.
void mark_unrepaired(Canonical& c) {
  c.vertex_to_welded.resize(c.positions.size());
  std::iota(c.vertex_to_welded.begin(), c.vertex_to_welded.end(), 0u);
  c.reoriented.assign(c.triangles.size(), 0);
}

// repair: true. core::repair_mesh on the canonical soup (so the repair, too, is independent of
// the input order); the maps are composed so that they still lead to input indices.
void repair(Canonical& c) {
  core::RepairedMesh r = core::repair_mesh(c.positions, c.triangles);
  for (std::size_t v = c.vertex_to_input.size(); v < r.positions.size(); ++v) {
    c.vertex_to_input.push_back(c.vertex_to_input[r.vertex_source[v]]);
  }
  std::vector<std::uint32_t> face_to_input(r.face_source.size());
  for (std::size_t f = 0; f < face_to_input.size(); ++f) face_to_input[f] = c.face_to_input[r.face_source[f]];
  for (auto& f : c.input_to_face) f = r.input_to_face[f];
  for (auto f : r.degenerate_faces) c.degenerate_inputs.push_back(c.face_to_input[f]);
  std::sort(c.degenerate_inputs.begin(), c.degenerate_inputs.end());
  c.face_to_input = std::move(face_to_input);
  c.vertex_to_welded = std::move(r.vertex_source);
  c.positions = std::move(r.positions);
  c.triangles = std::move(r.triangles);
  c.reoriented = std::move(r.reoriented);
  c.repairs = r.counts;
}

// What the builder refused, recounted over the whole soup in input numbering (the builder names
// canonical elements and stops at 8), so the message, the count and `details` agree.
constexpr std::size_t kListedElements = 100;

json with_hint(json details, std::size_t count, const char* hint) {
  details["count"] = count;
  details["hint"] = hint;
  return details;
}

ApiError degenerate_faces_error(const Canonical& canon, const PrimitiveData& data) {
  std::vector<std::uint32_t> faces;
  for (std::uint32_t f = 0; f < data.mesh.triangles.size(); ++f) {
    const core::Triangle& t = canon.triangles[canon.input_to_face[f]];
    const bool repeated = t[0] == t[1] || t[1] == t[2] || t[2] == t[0];
    const auto& p = canon.positions;
    if (repeated || (p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]).squaredNorm() == 0.0) faces.push_back(f);
  }
  if (faces.empty()) return make_api_error(ApiErrorCode::kInternal, "the builder found a degenerate face, the recount none");
  const core::Triangle& t = data.mesh.triangles[faces[0]];
  const char* hint = "repair: true leaves them out of the topology and keeps them in the asset";
  const std::size_t count = faces.size();
  faces.resize(std::min(count, kListedElements));
  return make_api_error(ApiErrorCode::kDegenerateFace,
                        std::to_string(count) + (count == 1 ? " face is" : " faces are") +
                            " degenerate after welding (a repeated vertex or zero area), first face " +
                            std::to_string(faces[0]) + " (vertices " + std::to_string(t[0]) + ", " +
                            std::to_string(t[1]) + ", " + std::to_string(t[2]) + "); " + hint,
                        with_hint({{"faces", faces}}, count, hint));
}

// Edges of three or more faces (non_manifold), or of two faces traversing them the same way.
ApiError edge_error(ApiErrorCode code, const Canonical& canon) {
  std::vector<std::pair<std::uint64_t, std::uint32_t>> uses;  // (undirected key, tail)
  for (const auto& t : canon.triangles) {
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint64_t a = t[k], b = t[(k + 1) % 3];
      uses.emplace_back((std::min(a, b) << 32) | std::max(a, b), t[k]);
    }
  }
  std::sort(uses.begin(), uses.end());
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i + 1;
    while (j < uses.size() && uses[j].first == uses[i].first) ++j;
    const bool bad = code == ApiErrorCode::kNonManifoldEdge ? j - i > 2 : j - i == 2 && uses[i].second == uses[i + 1].second;
    if (bad) {
      const std::uint32_t a = canon.vertex_to_input[uses[i].first >> 32];
      const std::uint32_t b = canon.vertex_to_input[uses[i].first & 0xffffffffu];
      edges.emplace_back(std::min(a, b), std::max(a, b));
    }
    i = j;
  }
  if (edges.empty()) return make_api_error(ApiErrorCode::kInternal, "the builder refused an edge, the recount found none");
  std::sort(edges.begin(), edges.end());
  const std::size_t count = edges.size();
  const bool fin = code == ApiErrorCode::kNonManifoldEdge;
  const char* hint = fin ? "repair: true splits these edges into manifold sheets"
                         : "repair: true reverses the faces that disagree with their sheet";
  json listed = json::array();
  for (std::size_t e = 0; e < std::min(count, kListedElements); ++e) listed.push_back({edges[e].first, edges[e].second});
  return make_api_error(code,
                        std::to_string(count) + (count == 1 ? " edge is " : " edges are ") +
                            (fin ? "shared by three or more faces" : "traversed in the same direction by both of their faces (flipped faces)") +
                            ", first the edge between vertices " + std::to_string(edges[0].first) + " and " +
                            std::to_string(edges[0].second) + "; " + hint,
                        with_hint({{"edges", std::move(listed)}}, count, hint));
}

}  // namespace

ApiError map_core_error(const core::Error& error, const Canonical& canon, core::ErrorCode code) {
  ApiError out = from_core(error);
  if (!out.details.contains("elements")) return out;
  const bool vertices = code == core::ErrorCode::kNonManifoldEdge || code == core::ErrorCode::kNonManifoldVertex ||
                        code == core::ErrorCode::kInconsistentOrientation || code == core::ErrorCode::kNonFinitePosition;
  const bool faces = code == core::ErrorCode::kDegenerateFace;
  if (!vertices && !faces) return out;
  const auto& map = vertices ? canon.vertex_to_input : canon.face_to_input;
  json mapped = json::array();
  for (const auto& e : out.details["elements"]) {
    const auto w = e.get<std::uint32_t>();
    mapped.push_back(w < map.size() ? map[w] : w);
  }
  out.details[vertices ? "vertices" : "faces"] = std::move(mapped);
  out.details.erase("elements");
  return out;
}

namespace {

// The builder's refusals in input numbering; the rest as the core says them.
ApiError build_error(const core::Error& error, const Canonical& canon, const PrimitiveData& data) {
  switch (error.code) {
    case core::ErrorCode::kDegenerateFace: return degenerate_faces_error(canon, data);
    case core::ErrorCode::kNonManifoldEdge: return edge_error(ApiErrorCode::kNonManifoldEdge, canon);
    case core::ErrorCode::kInconsistentOrientation:
      return edge_error(ApiErrorCode::kInconsistentOrientation, canon);
    case core::ErrorCode::kEmptyMesh:
      if (data.mesh.triangles.empty()) break;
      // Every triangle was left out: say so, rather than that there are none.
      return make_api_error(ApiErrorCode::kEmptyMesh,
                            "the mesh has no triangle with area: all " + std::to_string(data.mesh.triangles.size()) +
                                " repeat a vertex or lie on a line",
                            {{"degenerate_faces", canon.degenerate_inputs.size()}});
    case core::ErrorCode::kInvalidArgument:
    case core::ErrorCode::kIndexOutOfRange:
    case core::ErrorCode::kNonFinitePosition:
    case core::ErrorCode::kNonManifoldVertex:
    case core::ErrorCode::kTooManyTerminals:
    case core::ErrorCode::kTopologyViolation:
    case core::ErrorCode::kSolverFailed:
    case core::ErrorCode::kCancelled: break;
  }
  return map_core_error(error, canon, error.code);
}

}  // namespace

ApiResult<Surface> prepare_surface(const PrimitiveData& data, const SeamParams& params, const core::CancelToken& cancel) {
  SurfaceTimings time;
  auto t = core::StageClock::now();
  Canonical canon;
  {
    auto weld = core::weld_vertices(data.mesh.positions, core::WeldOptions{params.weld_epsilon}, cancel);
    if (!weld.ok()) return from_core(weld.error());
    time.weld = ms_since(t);
    t = core::StageClock::now();
    canon = canonicalize(*weld, data.mesh.triangles);  // the weld's maps are freed at the brace
    time.canonicalize = ms_since(t);
  }

  // Both the repair and the pinch split change nothing on a soup the builder accepts (repair.h,
  // split_pinched.h), so they run only after a refusal, and a clean soup is built once.
  t = core::StageClock::now();
  auto built = core::build_halfedge_mesh(canon.positions, canon.triangles);
  time.build = ms_since(t);
  if (built.ok()) {
    mark_unrepaired(canon);
  } else {
    t = core::StageClock::now();
    if (params.repair) repair(canon);
    else split_pinched(canon);
    time.repair = ms_since(t);
    t = core::StageClock::now();
    built = core::build_halfedge_mesh(canon.positions, canon.triangles);
    time.build += ms_since(t);
    if (!built.ok()) return build_error(built.error(), canon, data);
  }

  t = core::StageClock::now();
  core::Topology topology = core::compute_topology(*built);
  time.topology = ms_since(t);
  time.total = time.weld + time.canonicalize + time.repair + time.build + time.topology;
  // The mesh holds the positions and the faces now; the soup's copies would only add to the
  // job's peak memory.
  canon.positions = {};
  canon.triangles = {};
  const std::size_t welded = canon.welded_vertices;
  return Surface{std::move(canon), std::move(built).value(), std::move(topology), welded, time};
}

}  // namespace seam::api
