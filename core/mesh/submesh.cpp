#include "core/mesh/submesh.h"

#include <algorithm>
#include <cmath>

namespace seam::core {

Result<ComponentMesh> extract_faces(const HalfedgeMesh& mesh, std::span<const FaceId> faces) {
  ComponentMesh out;
  out.face_to_parent.assign(faces.begin(), faces.end());
  out.to_parent.reserve(3 * faces.size());
  for (FaceId f : faces) {
    for (VertexId v : mesh.face_vertices(f)) out.to_parent.push_back(v);
  }
  std::sort(out.to_parent.begin(), out.to_parent.end());
  out.to_parent.erase(std::unique(out.to_parent.begin(), out.to_parent.end()), out.to_parent.end());
  auto local = [&](VertexId v) {
    return static_cast<std::uint32_t>(std::lower_bound(out.to_parent.begin(), out.to_parent.end(), v) -
                                      out.to_parent.begin());
  };
  std::vector<Vec3> positions;
  positions.reserve(out.to_parent.size());
  for (VertexId v : out.to_parent) positions.push_back(mesh.position(v));
  std::vector<Triangle> triangles;
  triangles.reserve(faces.size());
  for (FaceId f : faces) {
    const auto vs = mesh.face_vertices(f);
    triangles.push_back({local(vs[0]), local(vs[1]), local(vs[2])});
  }
  SEAM_TRY(out.mesh, build_halfedge_mesh(positions, triangles));
  return out;
}

Result<ConedMesh> cone_boundary_loops(const HalfedgeMesh& mesh) {
  ConedMesh out;
  out.num_original_vertices = mesh.num_vertices();
  std::vector<Vec3> positions(mesh.positions().begin(), mesh.positions().end());
  std::vector<Triangle> triangles = mesh.triangles();

  const std::vector<std::vector<HalfedgeId>> loops = boundary_loops(mesh);
  for (const std::vector<HalfedgeId>& loop : loops) {
    Vec3 centroid = Vec3::Zero();
    Vec3 normal = Vec3::Zero();
    for (HalfedgeId b : loop) {
      const Vec3& p = mesh.position(mesh.tail(b));
      const Vec3& q = mesh.position(mesh.head(b));
      centroid += p;
      normal += p.cross(q);  // Newell: twice the vector area of the loop
    }
    centroid /= static_cast<double>(loop.size());
    double radius = 0;
    for (HalfedgeId b : loop) radius += (mesh.position(mesh.tail(b)) - centroid).norm();
    radius /= static_cast<double>(loop.size());
    // A flat loop (a planar hole) would put the apex in the loop's plane, where a cone triangle
    // on a straight stretch has zero area; lifting it off the plane avoids that. The side does
    // not matter for topology, and apex positions never enter a seam's length.
    if (normal.norm() > 0) {
      normal.normalize();
    } else {
      normal = Vec3::UnitZ();
    }
    if (!(radius > 0)) radius = 1;
    const auto apex = static_cast<std::uint32_t>(positions.size());
    positions.push_back(centroid + 0.5 * radius * normal);
    out.apexes.push_back(VertexId(apex));
    // A boundary half-edge runs a -> b with no face; the cone triangle (a, b, apex) is the
    // face it was missing, with the orientation the builder requires.
    for (HalfedgeId b : loop) triangles.push_back({mesh.tail(b).value(), mesh.head(b).value(), apex});
  }
  if (!loops.empty()) {
    SEAM_TRY(out.mesh, build_halfedge_mesh(positions, triangles));
  } else {
    out.mesh = mesh;
  }
  out.edge_weights.resize(out.mesh.num_edges());
  for (std::size_t e = 0; e < out.mesh.num_edges(); ++e) {
    out.edge_weights[e] = out.is_virtual(EdgeId(e)) ? 0.0 : out.mesh.edge_length(EdgeId(e));
  }
  return out;
}

std::vector<EdgeId> map_edges(const HalfedgeMesh& from, std::span<const VertexId> vertex_map, const HalfedgeMesh& to,
                              std::span<const EdgeId> edges) {
  std::vector<EdgeId> out;
  out.reserve(edges.size());
  for (EdgeId e : edges) {
    const HalfedgeId h = HalfedgeMesh::halfedge(e);
    const VertexId a = vertex_map[from.tail(h).index()];
    const VertexId b = vertex_map[from.head(h).index()];
    if (!a.valid() || !b.valid() || a == b) continue;
    const HalfedgeId g = to.find_halfedge(a, b);
    if (g.valid()) out.push_back(HalfedgeMesh::edge(g));
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace seam::core
