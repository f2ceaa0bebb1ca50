#include "core/mesh/halfedge_mesh.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace seam::core {
namespace {

constexpr std::size_t kMaxReported = 8;

std::string vertex_pair(std::uint32_t a, std::uint32_t b) {
  return "(" + std::to_string(a) + ", " + std::to_string(b) + ")";
}

// One corner of one triangle seen as the directed edge tail -> head, kept in the bucket of
// its smaller vertex (which is therefore not stored: 8 bytes instead of 16 halve the traffic
// of the scatter and of the sorts, the bulk of the build's time).
struct CornerEdge {
  std::uint32_t high;    // the larger vertex of the undirected edge
  std::uint32_t corner;  // 3 * face + i, the directed edge t[i] -> t[i+1]
};

// The corner edges bucketed by smaller vertex: bucket v is corners[bucket_start[v],
// bucket_start[v + 1]), sorted by (high, corner).
struct CornerGroups {
  std::vector<std::uint32_t> bucket_start;  // num_vertices + 1 entries
  std::vector<CornerEdge> corners;
};

// The kernel behind build_halfedge_mesh and sorted_edge_uses: a counting sort by the smaller
// vertex (linear, cache-friendly), then a tiny insertion sort by the larger vertex inside each
// bucket. Both passes are stable in the corner index, so the order depends only on the input
// order. Triangles with an index >= nv are left out.
CornerGroups group_corner_edges(std::span<const Triangle> triangles, std::size_t nv) {
  const std::size_t nf = triangles.size();
  auto in_range = [nv](const Triangle& t) { return t[0] < nv && t[1] < nv && t[2] < nv; };
  CornerGroups g;
  std::vector<std::uint32_t>& bucket_start = g.bucket_start;
  bucket_start.assign(nv + 1, 0);
  for (std::size_t f = 0; f < nf; ++f) {
    if (!in_range(triangles[f])) continue;
    for (unsigned i = 0; i < 3; ++i) ++bucket_start[std::min(triangles[f][i], triangles[f][(i + 1) % 3]) + 1];
  }
  for (std::size_t v = 0; v < nv; ++v) bucket_start[v + 1] += bucket_start[v];
  std::vector<CornerEdge>& corners = g.corners;
  corners.resize(bucket_start[nv]);
  std::vector<std::uint32_t> fill(bucket_start.begin(), bucket_start.end() - 1);
  for (std::size_t f = 0; f < nf; ++f) {
    if (!in_range(triangles[f])) continue;
    for (unsigned i = 0; i < 3; ++i) {
      const std::uint32_t a = triangles[f][i];
      const std::uint32_t b = triangles[f][(i + 1) % 3];
      corners[fill[std::min(a, b)]++] = {std::max(a, b), static_cast<std::uint32_t>(3 * f + i)};
    }
  }
  for (std::size_t v = 0; v < nv; ++v) {
    if (bucket_start[v + 1] - bucket_start[v] > 32) {
      // A high-valence vertex (a cone apex, a pole): insertion sort would be quadratic.
      std::sort(corners.begin() + bucket_start[v], corners.begin() + bucket_start[v + 1],
                [](const CornerEdge& x, const CornerEdge& y) {
                  return x.high != y.high ? x.high < y.high : x.corner < y.corner;
                });
      continue;
    }
    for (std::uint32_t i = bucket_start[v] + 1; i < bucket_start[v + 1]; ++i) {
      const CornerEdge item = corners[i];
      std::uint32_t j = i;
      for (; j > bucket_start[v] && corners[j - 1].high > item.high; --j) corners[j] = corners[j - 1];
      corners[j] = item;
    }
  }
  return g;
}

}  // namespace

HalfedgeId HalfedgeMesh::find_halfedge(VertexId a, VertexId b) const {
  HalfedgeId found;
  for_each_outgoing(a, [&](HalfedgeId h) {
    if (head(h) == b) found = h;
  });
  return found;
}

double HalfedgeMesh::edge_length(EdgeId e) const {
  const HalfedgeId h = halfedge(e);
  return (position(head(h)) - position(tail(h))).norm();
}

std::size_t HalfedgeMesh::valence(VertexId v) const {
  std::size_t count = 0;
  for_each_outgoing(v, [&](HalfedgeId) { ++count; });
  return count;
}

std::vector<Triangle> HalfedgeMesh::triangles() const {
  std::vector<Triangle> result(num_faces());
  for (std::size_t f = 0; f < num_faces(); ++f) {
    const auto vs = face_vertices(FaceId(f));
    result[f] = {vs[0].value(), vs[1].value(), vs[2].value()};
  }
  return result;
}

namespace {

Status check_positions(std::span<const Vec3> positions) {
  std::vector<std::uint32_t> bad;
  for (std::size_t v = 0; v < positions.size() && bad.size() < kMaxReported; ++v) {
    if (!positions[v].allFinite()) bad.push_back(static_cast<std::uint32_t>(v));
  }
  if (bad.empty()) return Ok{};
  return make_error(ErrorCode::kNonFinitePosition, "vertex " + std::to_string(bad[0]) + " has a NaN or infinite coordinate",
                    bad);
}

// Per-face validation before anything is built, so later steps can trust indices.
Status check_faces(std::span<const Vec3> positions, std::span<const Triangle> triangles) {
  const std::size_t nv = positions.size();
  std::vector<std::uint32_t> out_of_range;
  std::vector<std::uint32_t> degenerate;
  std::string degenerate_reason;
  for (std::size_t f = 0; f < triangles.size(); ++f) {
    const Triangle& t = triangles[f];
    if (t[0] >= nv || t[1] >= nv || t[2] >= nv) {
      if (out_of_range.size() < kMaxReported) out_of_range.push_back(static_cast<std::uint32_t>(f));
      continue;
    }
    const bool repeated = t[0] == t[1] || t[1] == t[2] || t[2] == t[0];
    // Exactly zero area only: slivers are legal input; a zero cross product would make
    // every angle- or area-based weight downstream undefined.
    const bool flat =
        !repeated && (positions[t[1]] - positions[t[0]]).cross(positions[t[2]] - positions[t[0]]).squaredNorm() == 0.0;
    if ((repeated || flat) && degenerate.size() < kMaxReported) {
      if (degenerate.empty()) degenerate_reason = repeated ? "repeats a vertex" : "has zero area";
      degenerate.push_back(static_cast<std::uint32_t>(f));
    }
  }
  if (!out_of_range.empty()) {
    return make_error(ErrorCode::kIndexOutOfRange,
                      "face " + std::to_string(out_of_range[0]) + " names a vertex index >= the " + std::to_string(nv) +
                          " vertices",
                      out_of_range);
  }
  if (!degenerate.empty()) {
    const Triangle& t = triangles[degenerate[0]];
    return make_error(ErrorCode::kDegenerateFace,
                      "face " + std::to_string(degenerate[0]) + " (" + std::to_string(t[0]) + ", " +
                          std::to_string(t[1]) + ", " + std::to_string(t[2]) + ") " + degenerate_reason,
                      degenerate);
  }
  return Ok{};
}

// Every corner's half-edge: edges are numbered in the order of their grouped uses, a two-face
// edge's second use takes the twin.
struct EdgeNumbering {
  std::vector<HalfedgeId> corner_halfedge;    // corner 3f + i -> its half-edge t[i] -> t[i+1]
  std::vector<std::uint8_t> edge_is_boundary;  // per edge: used by one face
};

Result<EdgeNumbering> number_edges(std::span<const Triangle> triangles, std::size_t nv) {
  const CornerGroups groups = group_corner_edges(triangles, nv);
  const std::vector<CornerEdge>& corners = groups.corners;
  auto corner_tail = [&](std::uint32_t c) { return triangles[c / 3][c % 3]; };
  EdgeNumbering out;
  out.corner_halfedge.resize(3 * triangles.size());
  out.edge_is_boundary.reserve(3 * triangles.size() / 2 + 16);
  std::vector<std::uint32_t> non_manifold;
  std::vector<std::uint32_t> misoriented;
  std::uint32_t a = 0;  // the bucket of corners[i]: the smaller vertex
  for (std::size_t i = 0; i < corners.size();) {
    while (groups.bucket_start[a + 1] <= i) ++a;
    std::size_t j = i + 1;
    while (j < groups.bucket_start[a + 1] && corners[j].high == corners[i].high) ++j;
    const std::uint32_t b = corners[i].high;
    if (j - i > 2) {
      if (non_manifold.size() < 2 * kMaxReported) non_manifold.insert(non_manifold.end(), {a, b});
    } else if (j - i == 2 && corner_tail(corners[i].corner) == corner_tail(corners[i + 1].corner)) {
      if (misoriented.size() < 2 * kMaxReported) misoriented.insert(misoriented.end(), {a, b});
    } else {
      const auto e = static_cast<std::uint32_t>(out.edge_is_boundary.size());
      out.edge_is_boundary.push_back(j - i == 1);
      out.corner_halfedge[corners[i].corner] = HalfedgeId(2 * e);
      if (j - i == 2) out.corner_halfedge[corners[i + 1].corner] = HalfedgeId(2 * e + 1);
    }
    i = j;
  }
  if (!non_manifold.empty()) {
    return make_error(ErrorCode::kNonManifoldEdge,
                      "edge " + vertex_pair(non_manifold[0], non_manifold[1]) + " is shared by three or more faces",
                      non_manifold);
  }
  if (!misoriented.empty()) {
    return make_error(ErrorCode::kInconsistentOrientation,
                      "edge " + vertex_pair(misoriented[0], misoriented[1]) +
                          " is traversed in the same direction by both of its faces (flipped face)",
                      misoriented);
  }
  return out;
}

Error pinched_error(const std::vector<std::uint32_t>& pinched) {
  return make_error(ErrorCode::kNonManifoldVertex,
                    "vertex " + std::to_string(pinched[0]) +
                        " joins several separate fans of faces (a pinched or bowtie vertex)",
                    pinched);
}

// A vertex whose rotation does not reach all of its outgoing half-edges has several closed
// fans (a bowtie between interior fans has no boundary for link_boundary to see). A rotation
// is a cycle of distinct outgoing half-edges, so it never reaches more than all of them: the
// rotations together reach all half-edges exactly when each one does, and the per-vertex count
// (another pass over the tails) is only needed to name the offenders.
Status check_rotations(const HalfedgeMesh& mesh) {
  const std::size_t nv = mesh.num_vertices();
  std::size_t reached = 0;
  for (std::size_t v = 0; v < nv; ++v) reached += mesh.valence(VertexId(v));
  if (reached == mesh.num_halfedges()) return Ok{};
  std::vector<std::uint32_t> outgoing(nv, 0);
  for (std::size_t h = 0; h < mesh.num_halfedges(); ++h) ++outgoing[mesh.tail(HalfedgeId(h)).index()];
  std::vector<std::uint32_t> pinched;
  for (std::size_t v = 0; v < nv && pinched.size() < kMaxReported; ++v) {
    if (mesh.valence(VertexId(v)) != outgoing[v]) pinched.push_back(static_cast<std::uint32_t>(v));
  }
  SEAM_ASSERT(!pinched.empty());
  return pinched_error(pinched);
}

}  // namespace

// The steps that fill the mesh's arrays (a friend of HalfedgeMesh).
struct HalfedgeMeshBuilder {
  // The interior half-edges: tail, face, and next/prev around their face.
  static HalfedgeMesh link_faces(std::span<const Vec3> positions, std::span<const Triangle> triangles,
                                 const EdgeNumbering& edges) {
    const std::size_t nh = 2 * edges.edge_is_boundary.size();
    HalfedgeMesh mesh;
    mesh.positions_.assign(positions.begin(), positions.end());
    mesh.next_.assign(nh, HalfedgeId());
    mesh.prev_.assign(nh, HalfedgeId());
    mesh.tail_.assign(nh, VertexId());
    mesh.face_.assign(nh, FaceId());
    mesh.vertex_halfedge_.assign(positions.size(), HalfedgeId());
    mesh.face_halfedge_.resize(triangles.size());
    for (std::size_t f = 0; f < triangles.size(); ++f) {
      for (unsigned i = 0; i < 3; ++i) {
        const HalfedgeId h = edges.corner_halfedge[3 * f + i];
        mesh.tail_[h.index()] = VertexId(triangles[f][i]);
        mesh.face_[h.index()] = FaceId(f);
        mesh.next_[h.index()] = edges.corner_halfedge[3 * f + (i + 1) % 3];
        mesh.prev_[h.index()] = edges.corner_halfedge[3 * f + (i + 2) % 3];
        mesh.vertex_halfedge_[triangles[f][i]] = h;
      }
      mesh.face_halfedge_[f] = edges.corner_halfedge[3 * f];
    }
    return mesh;
  }

  // The boundary half-edges: the twin of a lone interior half-edge a->b runs b->a, and the
  // boundary ones link into loops. A manifold vertex has at most one outgoing boundary
  // half-edge; two mean two fans pinched together (kNonManifoldVertex). A boundary vertex's
  // vertex_halfedge becomes its boundary half-edge.
  static Status link_boundary(HalfedgeMesh& mesh, const EdgeNumbering& edges) {
    const std::size_t ne = edges.edge_is_boundary.size();
    std::vector<std::uint32_t> pinched;
    std::vector<HalfedgeId> boundary_out(mesh.num_vertices());
    for (std::size_t e = 0; e < ne; ++e) {
      if (!edges.edge_is_boundary[e]) continue;
      const HalfedgeId h(2 * e + 1);
      const VertexId tail = mesh.tail_[mesh.next_[2 * e].index()];  // head(2e)
      mesh.tail_[h.index()] = tail;
      if (boundary_out[tail.index()].valid()) {
        if (pinched.size() < kMaxReported) pinched.push_back(tail.value());
        continue;
      }
      boundary_out[tail.index()] = h;
    }
    if (!pinched.empty()) return pinched_error(pinched);
    for (std::size_t e = 0; e < ne; ++e) {
      if (!edges.edge_is_boundary[e]) continue;
      const HalfedgeId h(2 * e + 1);
      const HalfedgeId n = boundary_out[mesh.head(h).index()];
      mesh.next_[h.index()] = n;
      mesh.prev_[n.index()] = h;
    }
    for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
      if (boundary_out[v].valid()) mesh.vertex_halfedge_[v] = boundary_out[v];
    }
    return Ok{};
  }
};

Result<HalfedgeMesh> build_halfedge_mesh(std::span<const Vec3> positions, std::span<const Triangle> triangles) {
  if (triangles.empty()) return make_error(ErrorCode::kEmptyMesh, "the mesh has no triangles");
  if (triangles.size() > (std::size_t{1} << 29) || positions.size() >= VertexId::kInvalidValue) {
    return make_error(ErrorCode::kInvalidArgument, "the mesh is too large for 32-bit half-edge ids");
  }
  if (auto status = check_positions(positions); !status.ok()) return status.take_error();
  if (auto status = check_faces(positions, triangles); !status.ok()) return status.take_error();
  SEAM_TRY(const EdgeNumbering edges, number_edges(triangles, positions.size()));
  HalfedgeMesh mesh = HalfedgeMeshBuilder::link_faces(positions, triangles, edges);
  if (auto status = HalfedgeMeshBuilder::link_boundary(mesh, edges); !status.ok()) return status.take_error();
  if (auto status = check_rotations(mesh); !status.ok()) return status.take_error();
  return mesh;
}

std::vector<EdgeCorner> sorted_edge_uses(std::span<const Triangle> triangles, std::size_t num_vertices) {
  const CornerGroups groups = group_corner_edges(triangles, num_vertices);
  std::vector<EdgeCorner> uses(groups.corners.size());
  for (std::size_t v = 0; v < num_vertices; ++v) {
    for (std::uint32_t i = groups.bucket_start[v]; i < groups.bucket_start[v + 1]; ++i) {
      uses[i] = {(std::uint64_t{v} << 32) | groups.corners[i].high, groups.corners[i].corner};
    }
  }
  return uses;
}

Status check_invariants(const HalfedgeMesh& mesh) {
  auto fail = [](const std::string& what, std::uint32_t element) {
    return make_error(ErrorCode::kTopologyViolation, "half-edge invariant broken: " + what, {element});
  };
  const std::size_t nh = mesh.num_halfedges();
  if (nh % 2 != 0) return fail("odd number of half-edges", 0);
  for (std::size_t i = 0; i < nh; ++i) {
    const HalfedgeId h(i);
    const HalfedgeId n = mesh.next(h);
    if (!n.valid() || n.index() >= nh) return fail("next out of range", h.value());
    if (mesh.prev(n) != h) return fail("prev(next(h)) != h", h.value());
    if (mesh.head(h) != mesh.tail(n)) return fail("head(h) != tail(next(h))", h.value());
    if (mesh.tail(h) == mesh.head(h)) return fail("half-edge is a loop", h.value());
    if (mesh.face(h) != mesh.face(n)) return fail("next(h) lies in another face", h.value());
    if (!mesh.is_boundary(h) && mesh.next(mesh.next(mesh.next(h))) != h) {
      return fail("face is not a triangle", h.value());
    }
    if (mesh.is_boundary(h) && mesh.is_boundary(HalfedgeMesh::twin(h))) {
      return fail("edge with no face", h.value());
    }
  }
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    if (mesh.face(mesh.face_halfedge(FaceId(f))) != FaceId(f)) {
      return fail("face_halfedge(f) not in f", static_cast<std::uint32_t>(f));
    }
  }
  std::vector<std::uint32_t> outgoing(mesh.num_vertices(), 0);
  for (std::size_t h = 0; h < nh; ++h) ++outgoing[mesh.tail(HalfedgeId(h)).index()];
  for (std::size_t i = 0; i < mesh.num_vertices(); ++i) {
    const VertexId v(i);
    const HalfedgeId h = mesh.vertex_halfedge(v);
    if (!h.valid()) {
      if (outgoing[i] != 0) return fail("isolated vertex with half-edges", v.value());
      continue;
    }
    if (mesh.tail(h) != v) return fail("vertex_halfedge(v) not outgoing", v.value());
    bool has_boundary = false;
    mesh.for_each_outgoing(v, [&](HalfedgeId o) { has_boundary |= mesh.is_boundary(o); });
    if (has_boundary && !mesh.is_boundary(h)) return fail("boundary vertex without boundary half-edge", v.value());
    if (mesh.valence(v) != outgoing[i]) return fail("rotation misses outgoing half-edges", v.value());
  }
  return Ok{};
}

}  // namespace seam::core
