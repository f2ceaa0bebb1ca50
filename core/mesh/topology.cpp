#include "core/mesh/topology.h"

#include "core/seam/tree_util.h"

namespace seam::core {

int Topology::total_genus() const {
  int g = 0;
  for (const auto& c : components) g += c.genus;
  return g;
}

int Topology::euler_characteristic() const {
  int chi = 0;
  for (const auto& c : components) chi += c.euler_characteristic;
  return chi;
}

std::vector<std::vector<HalfedgeId>> boundary_loops(const HalfedgeMesh& mesh) {
  std::vector<std::vector<HalfedgeId>> loops;
  std::vector<std::uint8_t> visited(mesh.num_halfedges(), 0);
  for (std::size_t i = 0; i < mesh.num_halfedges(); ++i) {
    const HalfedgeId start(i);
    if (!mesh.is_boundary(start) || visited[i]) continue;
    std::vector<HalfedgeId> loop;
    HalfedgeId h = start;
    do {
      visited[h.index()] = 1;
      loop.push_back(h);
      h = mesh.next(h);
    } while (h != start);
    loops.push_back(std::move(loop));
  }
  return loops;
}

Status check_topology_of(const HalfedgeMesh& mesh, const Topology& topology) {
  if (topology.face_component.size() != mesh.num_faces() || topology.vertex_component.size() != mesh.num_vertices()) {
    return make_error(ErrorCode::kInvalidArgument, "the topology was not computed from this mesh");
  }
  return Ok{};
}

Topology compute_topology(const HalfedgeMesh& mesh) {
  Topology topo;
  topo.face_component.assign(mesh.num_faces(), kNone);
  topo.vertex_component.assign(mesh.num_vertices(), kNone);

  // Faces joined through interior edges, united toward the smaller face so that a component's
  // root is its smallest face. Edges are read in id order (each one's two half-edges side by
  // side), where a flood fill chases next() and twin() across memory.
  const std::size_t nf = mesh.num_faces();
  detail::UnionFind sets(nf);
  for (std::size_t e = 0; e < mesh.num_edges(); ++e) {
    const FaceId f = mesh.face(HalfedgeId(2 * e));
    const FaceId g = mesh.face(HalfedgeId(2 * e + 1));
    if (f.valid() && g.valid()) sets.unite(f.value(), g.value());
  }
  // A root precedes its members, so their component is numbered when they ask for it.
  for (std::uint32_t f = 0; f < nf; ++f) {
    const std::uint32_t root = sets.find(f);
    if (root == f) {
      topo.face_component[FaceId(f)] = static_cast<std::uint32_t>(topo.components.size());
      topo.components.emplace_back();
    } else {
      topo.face_component[FaceId(f)] = topo.face_component[FaceId(root)];
    }
    ++topo.components[topo.face_component[FaceId(f)]].faces;
  }
  for (std::size_t e = 0; e < mesh.num_edges(); ++e) {
    const FaceId f = mesh.face(HalfedgeId(2 * e));
    ++topo.components[topo.face_component[f.valid() ? f : mesh.face(HalfedgeId(2 * e + 1))]].edges;
  }
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
    const HalfedgeId h = mesh.vertex_halfedge(VertexId(v));
    if (!h.valid()) continue;
    const FaceId f = mesh.face(h).valid() ? mesh.face(h) : mesh.face(HalfedgeMesh::twin(h));
    const std::uint32_t c = topo.face_component[f];
    topo.vertex_component[VertexId(v)] = c;
    ++topo.components[c].vertices;
  }

  topo.boundary_loops = boundary_loops(mesh);
  for (const std::vector<HalfedgeId>& loop : topo.boundary_loops) {
    const std::uint32_t c = topo.face_component[mesh.face(HalfedgeMesh::twin(loop.front()))];
    ++topo.components[c].boundary_loops;
    topo.boundary_loop_component.push_back(c);
  }
  for (auto& c : topo.components) {
    c.euler_characteristic = static_cast<int>(c.vertices) - static_cast<int>(c.edges) + static_cast<int>(c.faces);
    c.genus = (2 - c.euler_characteristic - static_cast<int>(c.boundary_loops)) / 2;
  }
  return topo;
}

}  // namespace seam::core
