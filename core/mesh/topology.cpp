#include "core/mesh/topology.h"

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

Topology compute_topology(const HalfedgeMesh& mesh) {
  Topology topo;
  const std::uint32_t kNone = VertexId::kInvalidValue;
  topo.face_component.assign(mesh.num_faces(), kNone);
  topo.vertex_component.assign(mesh.num_vertices(), kNone);

  // Flood fill over faces through interior edges. Edges are counted on the way (a boundary
  // edge from its one face, an interior edge from its lower half-edge) rather than in a pass
  // of their own: a second random walk over face_component costs as much as the fill.
  std::vector<FaceId> stack;
  for (std::size_t seed = 0; seed < mesh.num_faces(); ++seed) {
    if (topo.face_component[FaceId(seed)] != kNone) continue;
    const auto c = static_cast<std::uint32_t>(topo.components.size());
    std::size_t faces = 0;
    std::size_t edges = 0;
    topo.face_component[FaceId(seed)] = c;
    stack.push_back(FaceId(seed));
    while (!stack.empty()) {
      const FaceId f = stack.back();
      stack.pop_back();
      ++faces;
      HalfedgeId h = mesh.face_halfedge(f);
      for (int i = 0; i < 3; ++i, h = mesh.next(h)) {
        const HalfedgeId t = HalfedgeMesh::twin(h);
        const FaceId g = mesh.face(t);
        edges += !g.valid() || h.value() < t.value();
        if (g.valid() && topo.face_component[g] == kNone) {
          topo.face_component[g] = c;
          stack.push_back(g);
        }
      }
    }
    topo.components.emplace_back();
    topo.components[c].faces = faces;
    topo.components[c].edges = edges;
  }
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
    const HalfedgeId h = mesh.vertex_halfedge(VertexId(v));
    if (!h.valid()) continue;
    const FaceId f = mesh.face(h).valid() ? mesh.face(h) : mesh.face(HalfedgeMesh::twin(h));
    const std::uint32_t c = topo.face_component[f];
    topo.vertex_component[VertexId(v)] = c;
    ++topo.components[c].vertices;
  }

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
    const std::uint32_t c = topo.face_component[mesh.face(HalfedgeMesh::twin(start))];
    ++topo.components[c].boundary_loops;
    topo.boundary_loops.push_back(std::move(loop));
    topo.boundary_loop_component.push_back(c);
  }
  for (auto& c : topo.components) {
    c.euler_characteristic = static_cast<int>(c.vertices) - static_cast<int>(c.edges) + static_cast<int>(c.faces);
    c.genus = (2 - c.euler_characteristic - static_cast<int>(c.boundary_loops)) / 2;
  }
  return topo;
}

}  // namespace seam::core
