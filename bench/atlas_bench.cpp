// Atlas benchmark (issue 12): overlap of the default map before/after making it injective,
// its distortion cost, packing coverage of several meshes' charts, and each step's time.
//   build/atlas/bench/atlas_bench [overlap|pack|all]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "bench_util.h"
#include "core/atlas/overlap.h"
#include "core/extrema/extrema.h"
#include "core/mesh/cut.h"
#include "core/mesh/topology.h"
#include "core/seam/cut_graph.h"
#include "core/seam/seam.h"
#include "core/uv/parameterize.h"
#include "fixtures.h"

using namespace seam::core;
namespace sb = seam::bench;

namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

HalfedgeMesh build(const IndexedMesh& soup) {
  auto weld = weld_vertices(soup.positions, {});
  if (!weld.ok()) std::exit(1);
  auto mesh = build_halfedge_mesh(weld->positions, remap_triangles(soup.triangles, weld->input_to_welded));
  if (!mesh.ok()) {
    std::printf("build failed: %s\n", mesh.error().message.c_str());
    std::exit(1);
  }
  return std::move(mesh).value();
}

// The disc the service flattens: the skeleton seam through automatic extrema, or (cut_graph)
// only the cut graph, which leaves one chart per component with every handle opened.
Result<CutMesh> disc_of(const HalfedgeMesh& mesh, bool cut_graph_only) {
  if (cut_graph_only) {
    SEAM_TRY(std::vector<EdgeId> edges, compute_cut_graph(mesh));
    return cut_along_edges(mesh, edges);
  }
  SEAM_TRY(std::vector<VertexId> extrema, find_extrema(mesh));
  SEAM_TRY(SeamResult seam, compute_seam(mesh, extrema, {}));
  return cut_along_edges(mesh, all_cut_edges(seam));
}

void overlap_row(const std::string& name, const HalfedgeMesh& mesh, bool cut_graph_only) {
  auto disc = disc_of(mesh, cut_graph_only);
  if (!disc.ok()) {
    std::printf("%-16s cut failed: %s\n", name.c_str(), disc.error().message.c_str());
    return;
  }
  const Topology topo = compute_topology(mesh);
  double before[3] = {};
  for (bool injective : {false, true}) {
    UvOptions options;
    options.injective = injective;
    const auto t0 = std::chrono::steady_clock::now();
    auto r = parameterize(disc->mesh, options);
    const double ms = ms_since(t0);
    if (!r.ok()) {
      std::printf("%-16s parameterize failed: %s\n", name.c_str(), r.error().message.c_str());
      return;
    }
    const Distortion& d = r->distortion;
    std::printf("%-16s %7zu %5d %-9s %-6s %8.1f %7.2f %8.4f %8.3f %7.3f %7.3f %5zu %8.5f %5zu %5zu",
                name.c_str(), mesh.num_faces(), topo.total_genus(), cut_graph_only ? "cutgraph" : "skeleton",
                injective ? "after" : "before", ms, r->overlap_ms, d.area_geometric, d.angle, d.stretch_l2,
                d.area, d.flipped, r->overlap_fraction, r->overlapping_starts, r->charts_not_injective);
    if (injective) {
      std::printf("   area_g %+5.1f%% angle %+5.1f%% L2 %+5.1f%%", 100 * (d.area_geometric / before[0] - 1),
                  100 * (d.angle / before[1] - 1), 100 * (d.stretch_l2 / before[2] - 1));
    } else {
      before[0] = d.area_geometric;
      before[1] = d.angle;
      before[2] = d.stretch_l2;
    }
    std::printf("\n");
    std::fflush(stdout);
  }
}

void overlap_section(bool quick) {
  std::printf("== overlap of the default map (SLIM), before (fold-free only) and after (injective)\n");
  std::printf("%-16s %7s %5s %-9s %-6s %8s %7s %8s %8s %7s %7s %5s %8s %5s %5s\n", "mesh", "faces", "genus",
              "cut", "map", "ms", "ovl_ms", "area_g", "angle", "L2", "area", "flips", "overlap", "restart",
              "noninj");
  const char* readme_rows[] = {"hand", "camel", "dino", "armadillo", "elephant", "homer", "bear", "man"};
  const char* quick_rows[] = {"hand", "elephant"};
  const std::vector<const char*> names = quick ? std::vector<const char*>(std::begin(quick_rows), std::end(quick_rows))
                                               : std::vector<const char*>(std::begin(readme_rows), std::end(readme_rows));
  for (const char* name : names) overlap_row(name, build(sb::load_cgal(name)), false);
  // High genus: CGAL's genus models, and voxel slabs with g handles (the genus-21 robot part).
  for (const char* name : {"3torus", "double-torus-example", "elephant"}) {
    overlap_row(name, build(sb::load_cgal(name)), true);
  }
  for (int genus : {5, 21}) {
    const seam::fixtures::Soup slab = seam::fixtures::holed_slab(genus);
    IndexedMesh soup{slab.positions, slab.triangles};
    const std::string label = "slab-g" + std::to_string(genus) + (quick ? "" : "-sub2");
    if (!quick) soup = sb::subdivide(sb::subdivide(soup));
    const HalfedgeMesh mesh = build(soup);
    overlap_row(label, mesh, true);
    overlap_row(label, mesh, false);
  }
}

}  // namespace

int main(int argc, char** argv) {
  const std::string what = argc > 1 ? argv[1] : "all";
  const bool quick = what == "quick";
  if (what == "overlap" || what == "all" || quick) overlap_section(quick);
  return 0;
}
