#include "core/cut.h"

#include <algorithm>
#include <numeric>
#include <string>
#include <vector>

#include "core/cut_check.h"
#include "core/topology.h"

namespace seam::core {

namespace {

std::uint32_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t x) {
  while (parent[x] != x) {
    parent[x] = parent[parent[x]];  // path halving keeps the trees flat without recursion
    x = parent[x];
  }
  return x;
}

}  // namespace

Result<CutMesh> cut_along_edges(const HalfedgeMesh& mesh, std::span<const EdgeId> edges) {
  const std::size_t ne = mesh.num_edges();
  std::vector<std::uint8_t> is_cut(ne, 0);
  for (EdgeId e : edges) {
    if (!e.valid() || e.index() >= ne) {
      return make_error(ErrorCode::kInvalidArgument,
                        "cut edge " + std::to_string(e.value()) + " is out of range (the mesh has " +
                            std::to_string(ne) + " edges)",
                        {e.value()});
    }
    is_cut[e.index()] = 1;
  }

  // A corner is an interior half-edge standing for its tail in its face. Corners across an
  // uncut interior edge share their vertex copy; union-find over corners yields the wedges
  // without walking rotations (which would need care at boundary vertices).
  const std::size_t nh = mesh.num_halfedges();
  std::vector<std::uint32_t> parent(nh);
  std::iota(parent.begin(), parent.end(), 0u);
  auto unite = [&](HalfedgeId a, HalfedgeId b) {
    const std::uint32_t ra = find_root(parent, a.value());
    const std::uint32_t rb = find_root(parent, b.value());
    if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
  };
  for (std::size_t e = 0; e < ne; ++e) {
    if (is_cut[e]) continue;
    const HalfedgeId a = HalfedgeMesh::halfedge(EdgeId(e), 0);
    const HalfedgeId b = HalfedgeMesh::halfedge(EdgeId(e), 1);
    if (mesh.is_boundary(a) || mesh.is_boundary(b)) continue;
    // tail(a) == head(b) == tail(next(b)), and symmetrically.
    unite(a, mesh.next(b));
    unite(b, mesh.next(a));
  }

  // Numbering: the wedge met first around v (counter-clockwise from vertex_halfedge(v))
  // keeps v's id, further wedges are appended in vertex order. So an uncut mesh maps to
  // itself and ids stay stable for callers that only care about unduplicated vertices.
  const std::size_t nv = mesh.num_vertices();
  std::vector<std::uint32_t> wedge_vertex(nh, VertexId::kInvalidValue);
  CutMesh out;
  std::vector<Vec3> positions(mesh.positions().begin(), mesh.positions().end());
  out.to_original.resize(nv);
  for (std::size_t v = 0; v < nv; ++v) out.to_original[VertexId(v)] = VertexId(v);
  for (std::size_t v = 0; v < nv; ++v) {
    bool first = true;
    mesh.for_each_outgoing(VertexId(v), [&](HalfedgeId h) {
      if (mesh.is_boundary(h)) return;
      const std::uint32_t root = find_root(parent, h.value());
      if (wedge_vertex[root] != VertexId::kInvalidValue) return;
      if (first) {
        wedge_vertex[root] = static_cast<std::uint32_t>(v);
        first = false;
      } else {
        wedge_vertex[root] = static_cast<std::uint32_t>(positions.size());
        positions.push_back(mesh.position(VertexId(v)));
        out.to_original.raw().push_back(VertexId(v));
      }
    });
  }

  // An interior cut edge both of whose ends keep a single wedge (a slit between two vertices
  // touching no other cut) would be glued shut again: a two-edge boundary loop is not a
  // simplicial mesh. Report it instead of silently leaving the edge closed.
  for (std::size_t e = 0; e < ne; ++e) {
    if (!is_cut[e]) continue;
    const HalfedgeId a = HalfedgeMesh::halfedge(EdgeId(e), 0);
    const HalfedgeId b = HalfedgeMesh::halfedge(EdgeId(e), 1);
    if (mesh.is_boundary(a) || mesh.is_boundary(b)) continue;
    if (find_root(parent, a.value()) == find_root(parent, mesh.next(b).value()) &&
        find_root(parent, b.value()) == find_root(parent, mesh.next(a).value())) {
      const auto u = mesh.tail(a).value();
      const auto v = mesh.head(a).value();
      return make_error(ErrorCode::kTopologyViolation,
                        "cut edge " + std::to_string(e) + " (" + std::to_string(u) + ", " + std::to_string(v) +
                            ") cannot open: neither end meets another cut edge or the boundary (a slit)",
                        {static_cast<std::uint32_t>(e)});
    }
  }

  std::vector<Triangle> triangles(mesh.num_faces());
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    HalfedgeId h = mesh.face_halfedge(FaceId(f));
    for (unsigned i = 0; i < 3; ++i, h = mesh.next(h)) {
      triangles[f][i] = wedge_vertex[find_root(parent, h.value())];
    }
  }
  auto built = build_halfedge_mesh(positions, triangles);
  if (!built.ok()) {
    // Defensive: the wedge construction of a valid mesh always rebuilds; report, don't abort.
    Error error = built.take_error();
    error.code = ErrorCode::kTopologyViolation;
    error.message = "cutting along the given edges does not give a simplicial mesh: " + error.message;
    return error;
  }
  out.mesh = std::move(built).value();
  return out;
}

Status check_is_disc(const HalfedgeMesh& mesh) {
  const Topology topo = compute_topology(mesh);
  for (std::size_t c = 0; c < topo.components.size(); ++c) {
    const ComponentInfo& info = topo.components[c];
    if (info.euler_characteristic != 1 || info.boundary_loops != 1) {
      // Name the component by its smallest face so the caller can find it.
      std::uint32_t first_face = 0;
      for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
        if (topo.face_component[FaceId(f)] == c) {
          first_face = static_cast<std::uint32_t>(f);
          break;
        }
      }
      return make_error(ErrorCode::kTopologyViolation,
                        "component " + std::to_string(c) + " (containing face " + std::to_string(first_face) +
                            ") is not a disc: Euler characteristic " + std::to_string(info.euler_characteristic) +
                            ", " + std::to_string(info.boundary_loops) + " boundary loops, genus " +
                            std::to_string(info.genus),
                        {first_face});
    }
  }
  return Ok{};
}

Status check_cut_is_disc(const HalfedgeMesh& mesh, std::span<const EdgeId> edges) {
  const std::size_t ne = mesh.num_edges();
  const std::size_t nh = mesh.num_halfedges();
  const std::size_t nf = mesh.num_faces();
  std::vector<std::uint8_t> is_cut(ne, 0);
  for (EdgeId e : edges) {
    if (!e.valid() || e.index() >= ne) {
      return make_error(ErrorCode::kInvalidArgument, "cut edge " + std::to_string(e.value()) + " is out of range",
                        {e.value()});
    }
    is_cut[e.index()] = 1;
  }
  // Wedges (corner union-find, as in cut_along_edges) and face components (face union-find
  // across uncut interior edges), in one pass over the edges.
  std::vector<std::uint32_t> corner(nh);
  std::iota(corner.begin(), corner.end(), 0u);
  std::vector<std::uint32_t> face(nf);
  std::iota(face.begin(), face.end(), 0u);
  auto unite = [](std::vector<std::uint32_t>& parent, std::uint32_t a, std::uint32_t b) {
    a = find_root(parent, a);
    b = find_root(parent, b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  };
  for (std::size_t e = 0; e < ne; ++e) {
    const HalfedgeId a = HalfedgeMesh::halfedge(EdgeId(e), 0);
    const HalfedgeId b = HalfedgeMesh::halfedge(EdgeId(e), 1);
    if (is_cut[e] || mesh.is_boundary(a) || mesh.is_boundary(b)) continue;
    unite(corner, a.value(), mesh.next(b).value());
    unite(corner, b.value(), mesh.next(a).value());
    unite(face, mesh.face(a).value(), mesh.face(b).value());
  }
  // Euler characteristic per component: wedges - edges (cut interior edges twice) + faces.
  std::vector<std::int64_t> chi(nf, 0);
  for (std::size_t f = 0; f < nf; ++f) ++chi[find_root(face, static_cast<std::uint32_t>(f))];
  for (std::size_t e = 0; e < ne; ++e) {
    const HalfedgeId a = HalfedgeMesh::halfedge(EdgeId(e), 0);
    const HalfedgeId b = HalfedgeMesh::halfedge(EdgeId(e), 1);
    const HalfedgeId inside = mesh.is_boundary(a) ? b : a;
    const bool interior = !mesh.is_boundary(a) && !mesh.is_boundary(b);
    chi[find_root(face, mesh.face(inside).value())] -= 1;
    // A cut edge becomes one edge on each side, and the sides may end up in different parts.
    if (interior && is_cut[e]) chi[find_root(face, mesh.face(b).value())] -= 1;
    if (interior && is_cut[e] && find_root(corner, a.value()) == find_root(corner, mesh.next(b).value()) &&
        find_root(corner, b.value()) == find_root(corner, mesh.next(a).value())) {
      return make_error(ErrorCode::kTopologyViolation,
                        "cut edge " + std::to_string(e) + " cannot open: neither end meets another cut edge or "
                        "the boundary (a slit)",
                        {static_cast<std::uint32_t>(e)});
    }
  }
  for (std::size_t h = 0; h < nh; ++h) {
    if (mesh.is_boundary(HalfedgeId(h)) || find_root(corner, static_cast<std::uint32_t>(h)) != h) continue;
    ++chi[find_root(face, mesh.face(HalfedgeId(h)).value())];  // one vertex per wedge
  }
  for (std::size_t f = 0; f < nf; ++f) {
    if (find_root(face, static_cast<std::uint32_t>(f)) != f || chi[f] == 1) continue;
    return make_error(ErrorCode::kTopologyViolation,
                      "the part containing face " + std::to_string(f) + " is not a disc after the cut: Euler "
                      "characteristic " + std::to_string(chi[f]) + " (a disc has 1)",
                      {static_cast<std::uint32_t>(f)});
  }
  return Ok{};
}

}  // namespace seam::core
