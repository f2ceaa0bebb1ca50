// Foundation benchmark: weld + half-edge build + topology, and one single-source Dijkstra,
// on real CGAL meshes and subdivided ~1M-face versions. Prints a table; asserts nothing.
//   build/release/bench/mesh_bench
#include <cstdio>

#include "bench_util.h"
#include "core/paths/geodesic.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/topology.h"
#include "core/mesh/weld.h"

using namespace seam;

int main() {
  struct Input {
    std::string name;
    core::IndexedMesh mesh;
  };
  std::vector<Input> inputs;
  for (const char* name : {"hand", "elephant", "camel", "knot1", "lion-head"}) inputs.push_back({name, bench::load_cgal(name)});
  inputs.push_back({"elephant x4^k", bench::subdivide_to(bench::load_cgal("elephant"), 1'000'000)});
  inputs.push_back({"hand x4^k", bench::subdivide_to(bench::load_cgal("hand"), 1'000'000)});
  // The subdivided meshes append each level's new vertices after the old ones, so neighbours
  // are far apart in memory; the same meshes renumbered along a Z-order curve, as the service
  // numbers every mesh it receives (api/pipeline.cpp):
  for (std::size_t i : {inputs.size() - 2, inputs.size() - 1}) {
    inputs.push_back({inputs[i].name + " Z", bench::spatially_ordered(inputs[i].mesh)});
  }

  std::printf("%-14s %9s %8s %8s %8s %13s %12s %8s %8s %11s\n", "mesh", "faces", "weld_ms", "build_ms", "topo_ms",
              "build+topo/Mf", "+weld/Mf", "graph_ms", "dijk_ms", "dijk/Mf");
  for (const auto& in : inputs) {
    core::WeldResult weld;
    core::HalfedgeMesh mesh;
    std::vector<core::Triangle> tris;
    const double weld_ms = bench::best_ms(3, [&] { weld = core::weld_vertices(in.mesh.positions, {}).value(); });
    tris = core::remap_triangles(in.mesh.triangles, weld.input_to_welded);
    const double build_ms = bench::best_ms(3, [&] { mesh = core::build_halfedge_mesh(weld.positions, tris).value(); });
    core::Topology topo;
    const double topo_ms = bench::best_ms(3, [&] { topo = core::compute_topology(mesh); });
    core::EdgeGraph graph;
    const double graph_ms = bench::best_ms(3, [&] { graph = core::build_edge_graph(mesh); });
    const core::VertexId source[] = {core::VertexId(0u)};
    const double dijkstra_ms = bench::best_ms(3, [&] { (void)core::dijkstra(graph, source).value(); });
    const double mf = static_cast<double>(in.mesh.triangles.size()) / 1e6;
    std::printf("%-14s %9zu %8.1f %8.1f %8.1f %13.1f %12.1f %8.1f %8.1f %11.1f\n", in.name.c_str(),
                in.mesh.triangles.size(), weld_ms, build_ms, topo_ms, (build_ms + topo_ms) / mf,
                (weld_ms + build_ms + topo_ms) / mf, graph_ms, dijkstra_ms, dijkstra_ms / mf);
  }
  std::printf("\nper million faces (Mf): build+topo target <= 250 ms; +weld adds exact welding;\n"
              "dijk = one full single-source Dijkstra (target <= 150 ms/Mf); graph = the edge graph\n"
              "(CSR adjacency), built once per mesh and shared by every Dijkstra run.\n");
  return 0;
}
