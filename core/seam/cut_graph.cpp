#include "core/seam/cut_graph.h"

#include <algorithm>
#include <numeric>

#include "core/mesh/cut.h"
#include "core/mesh/submesh.h"
#include "core/mesh/topology.h"
#include "core/paths/geodesic.h"

namespace seam::core {

namespace {

// One root per component that needs cutting: the apex of its first boundary loop, else its
// smallest vertex.
std::vector<VertexId> cut_roots(const Topology& topo, const ConedMesh& coned, const std::vector<std::uint8_t>& needs) {
  std::vector<VertexId> roots;
  std::vector<std::uint8_t> has_root(topo.components.size(), 0);
  for (std::size_t l = 0; l < topo.boundary_loops.size(); ++l) {
    const std::uint32_t c = topo.boundary_loop_component[l];
    if (needs[c] && !has_root[c]) {
      has_root[c] = 1;
      roots.push_back(coned.apexes[l]);
    }
  }
  for (std::size_t v = 0; v < coned.num_original_vertices; ++v) {
    const std::uint32_t c = topo.vertex_component[VertexId(v)];
    if (c != VertexId::kInvalidValue && needs[c] && !has_root[c]) {
      has_root[c] = 1;
      roots.push_back(VertexId(v));
    }
  }
  return roots;
}

// The coned mesh's edge graph with every boundary loop of a component that needs cutting
// contracted into its apex: the loop's vertices have no edges of their own, each of their
// other edges leaves from the apex, and edges inside the loop (the loop's and the apex's)
// are gone. A shortest-path tree on it reaches each loop once, by one real edge, so with
// the loop's spokes added it stays a tree with every loop whole. On the plain coned graph,
// equal distances (the spokes weigh 0) could hang a loop's vertices from two other loops,
// whose paths then closed a cycle through the loop and cut a piece off (mesh_fuzz F13).
EdgeGraph contracted_graph(const HalfedgeMesh& mesh, const ConedMesh& coned, const Topology& topo,
                           const std::vector<std::uint8_t>& needs, std::vector<VertexId>& node) {
  const HalfedgeMesh& closed = coned.mesh;
  const std::size_t nv = closed.num_vertices();
  node.resize(nv);
  for (std::size_t v = 0; v < nv; ++v) node[v] = VertexId(v);
  for (std::size_t l = 0; l < topo.boundary_loops.size(); ++l) {
    if (!needs[topo.boundary_loop_component[l]]) continue;
    for (HalfedgeId b : topo.boundary_loops[l]) node[mesh.tail(b).index()] = coned.apexes[l];  // same ids in `closed`
  }
  EdgeGraph graph;
  graph.offsets.assign(nv + 1, 0);
  auto for_each_edge = [&](auto&& f) {
    for (std::size_t h = 0; h < closed.num_halfedges(); ++h) {
      const HalfedgeId half(h);
      const VertexId a = node[closed.tail(half).index()];
      const VertexId b = node[closed.head(half).index()];
      if (a != b) f(a, b, half);
    }
  };
  for_each_edge([&](VertexId a, VertexId, HalfedgeId) { ++graph.offsets[a.index() + 1]; });
  for (std::size_t v = 0; v < nv; ++v) graph.offsets[v + 1] += graph.offsets[v];
  graph.head.resize(graph.offsets[nv]);
  graph.halfedge.resize(graph.offsets[nv]);
  graph.weight.resize(graph.offsets[nv]);
  std::vector<std::uint32_t> fill(graph.offsets.begin(), graph.offsets.end() - 1);
  for_each_edge([&](VertexId a, VertexId b, HalfedgeId half) {
    const std::uint32_t slot = fill[a.index()]++;
    graph.head[slot] = b;
    graph.halfedge[slot] = half;
    graph.weight[slot] = coned.edge_weights[HalfedgeMesh::edge(half).index()];
  });
  return graph;
}

// Cotree: a maximum spanning forest of the dual graph over the edges not in the tree, heaviest
// loops first, so the leftover edges (added to `in_graph`) close the shortest loops (greedy
// homotopy basis). Only edges of components that need cutting take part.
Status add_cotree_leftovers(const ConedMesh& coned, const ShortestPathTree& spt,
                            const std::vector<std::uint8_t>& needs_vertex, std::vector<std::uint8_t>& in_graph,
                            const CancelToken& cancel) {
  const HalfedgeMesh& closed = coned.mesh;
  std::vector<std::uint32_t> candidates;
  std::vector<double> loop_length(closed.num_edges(), 0.0);
  for (std::size_t e = 0; e < closed.num_edges(); ++e) {
    if (in_graph[e]) continue;
    const HalfedgeId h = HalfedgeMesh::halfedge(EdgeId(e));
    const VertexId a = closed.tail(h);
    if (!spt.reached(a) || !needs_vertex[a.index()]) continue;
    const VertexId b = closed.head(h);
    loop_length[e] = spt.distance[a.index()] + spt.distance[b.index()] + coned.edge_weights[e];
    candidates.push_back(static_cast<std::uint32_t>(e));
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [&](std::uint32_t x, std::uint32_t y) { return loop_length[x] > loop_length[y]; });
  std::vector<std::uint32_t> parent(closed.num_faces());
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::uint32_t polls = 0;
  for (std::uint32_t e : candidates) {
    if (cancel.poll(polls)) return cancelled_error("cut graph");
    const std::uint32_t f = find(closed.face(HalfedgeMesh::halfedge(EdgeId(e), 0)).value());
    const std::uint32_t g = find(closed.face(HalfedgeMesh::halfedge(EdgeId(e), 1)).value());
    if (f != g) {
      parent[f] = g;
    } else {
      in_graph[e] = 1;  // leftover: closes a non-contractible loop
    }
  }
  return Ok{};
}

// Removes dangling branches from `in_graph`: vertices of degree one, repeatedly, except the
// apexes, so every boundary loop stays joined.
Status prune_dangling(const ConedMesh& coned, std::vector<std::uint8_t>& in_graph, const CancelToken& cancel) {
  const HalfedgeMesh& closed = coned.mesh;
  std::vector<std::uint32_t> degree = cut_degrees(closed, in_graph);
  std::vector<VertexId> stack;
  for (std::size_t v = 0; v < closed.num_vertices(); ++v) {
    if (degree[v] == 1 && !coned.is_apex(VertexId(v))) stack.push_back(VertexId(v));
  }
  std::uint32_t polls = 0;
  while (!stack.empty()) {
    if (cancel.poll(polls)) return cancelled_error("cut graph");
    const VertexId v = stack.back();
    stack.pop_back();
    if (degree[v.index()] != 1) continue;
    closed.for_each_outgoing(v, [&](HalfedgeId h) {
      const std::size_t e = HalfedgeMesh::edge(h).index();
      if (!in_graph[e]) return;
      in_graph[e] = 0;
      --degree[v.index()];
      const VertexId w = closed.head(h);
      if (--degree[w.index()] == 1 && !coned.is_apex(w)) stack.push_back(w);
    });
  }
  return Ok{};
}

}  // namespace

Result<std::vector<EdgeId>> compute_cut_graph(const HalfedgeMesh& mesh, const CancelToken& cancel) {
  const Topology topo = compute_topology(mesh);
  std::vector<std::uint8_t> needs(topo.components.size(), 0);
  bool any = false;
  for (std::size_t c = 0; c < topo.components.size(); ++c) {
    needs[c] = topo.components[c].genus > 0 || topo.components[c].boundary_loops > 1;
    any = any || needs[c];
  }
  if (!any) return std::vector<EdgeId>{};

  SEAM_TRY(ConedMesh coned, cone_boundary_loops(mesh));
  const HalfedgeMesh& closed = coned.mesh;
  const std::size_t nv = closed.num_vertices();
  const std::size_t nv_orig = coned.num_original_vertices;
  // Whether each coned vertex's component needs cutting (apexes take their loop's component).
  std::vector<std::uint8_t> needs_vertex(nv, 0);
  for (std::size_t v = 0; v < nv; ++v) {
    const std::uint32_t c = v < nv_orig ? topo.vertex_component[VertexId(v)] : topo.boundary_loop_component[v - nv_orig];
    needs_vertex[v] = c != VertexId::kInvalidValue && needs[c];
  }

  // T: a shortest-path tree of the loops contracted, each loop then joined by its spokes.
  std::vector<VertexId> node;
  const EdgeGraph graph = contracted_graph(mesh, coned, topo, needs, node);
  SEAM_TRY(ShortestPathTree spt, dijkstra(graph, cut_roots(topo, coned, needs), {}, cancel));
  std::vector<std::uint8_t> in_graph(closed.num_edges(), 0);  // T, then T plus leftover edges
  for (std::size_t v = 0; v < nv; ++v) {
    const HalfedgeId p = spt.parent[v];
    if (p.valid()) in_graph[HalfedgeMesh::edge(p).index()] = 1;
    if (node[v].index() != v && spt.reached(node[v])) {
      // A loop vertex: its spoke, and its loop's distance for the cotree's ordering.
      in_graph[HalfedgeMesh::edge(closed.find_halfedge(node[v], VertexId(v))).index()] = 1;
      spt.distance[v] = spt.distance[node[v].index()];
    }
  }
  if (auto status = add_cotree_leftovers(coned, spt, needs_vertex, in_graph, cancel); !status.ok()) {
    return status.take_error();
  }
  if (auto status = prune_dangling(coned, in_graph, cancel); !status.ok()) return status.take_error();

  std::vector<EdgeId> kept;
  for (std::size_t e = 0; e < closed.num_edges(); ++e) {
    if (in_graph[e] && !coned.is_virtual(EdgeId(e))) kept.push_back(EdgeId(e));
  }
  std::vector<VertexId> to_mesh(nv);
  for (std::size_t v = 0; v < nv; ++v) to_mesh[v] = v < nv_orig ? VertexId(v) : VertexId();
  std::vector<EdgeId> out = map_edges(closed, to_mesh, mesh, kept);
  // A boundary edge is already open; cutting it again would change nothing.
  out.erase(std::remove_if(out.begin(), out.end(), [&](EdgeId e) { return mesh.is_boundary(e); }), out.end());
  return out;
}

}  // namespace seam::core
