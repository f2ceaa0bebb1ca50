// The skeleton seam's stages on real meshes: lengths against the baselines and the exact
// optimum (table 1), and per-stage timings on 10k..1M faces (table 2). "moves" is the global
// improvement (core/seam/improve.h); compute_seam's exact-when-cheap path is not used here
// (see seam_quality_bench).
//   cmake -DSEAM_BUILD_BENCH=ON ... && ninja skeleton_bench && ./bench/skeleton_bench [--quick]
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "bench_util.h"
#include "core/seam/baselines.h"
#include "core/seam/skeleton_trace.h"
#include "core/paths/steiner.h"
#include "core/mesh/topology.h"
#include "core/mesh/weld.h"
#include "skeleton_fixtures.h"

using namespace seam;
using namespace seam::core;

namespace {

double now_ms() {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

HalfedgeMesh build(const IndexedMesh& soup) { return bench::build_welded(soup); }

const char* valid(const HalfedgeMesh& mesh, const SteinerTree& tree, std::span<const VertexId> terminals) {
  return check_full_component_tree(mesh, tree.edges, terminals).ok() ? "yes" : "NO";
}

void quality_table(bool quick) {
  std::printf("\n## Seam length per method (extrema: farthest-point sampling from vertex 0)\n\n");
  std::printf("| mesh | faces | k | paper | paper+refine+moves | mst | greedy | optimal | paper/opt | refined/opt | "
              "refined/mst | refined/greedy | leaves ok | fallback |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  const std::vector<std::string> names = quick ? std::vector<std::string>{"hand"}
                                               : std::vector<std::string>{"hand", "camel", "dino", "mushroom",
                                                                          "armadillo", "bunny00"};
  for (const auto& name : names) {
    const HalfedgeMesh mesh = build(bench::load_cgal(name));
    const auto topo = compute_topology(mesh);
    if (topo.components.size() != 1 || topo.total_genus() != 0 || !topo.boundary_loops.empty()) {
      std::printf("| %s | %zu | - | skipped: not one closed genus-0 component | | | | | | | | | | |\n", name.c_str(),
                  mesh.num_faces());
      continue;
    }
    const SearchSurface surface(mesh);
    for (std::size_t k : {4u, 6u, 8u}) {
      const auto extrema = fixtures::farthest_point_extrema(mesh, surface.graph(), k);
      auto paths = compute_terminal_paths(surface, extrema);
      SkeletonTrace plain_trace, refined_trace;
      auto plain = skeleton_seam_traced(surface, *paths, {.refine = false}, &plain_trace);
      auto refined = skeleton_seam_traced(surface, *paths, {.refine = true}, &refined_trace);
      auto mst = mst_seam(surface, *paths);
      auto greedy = greedy_seam(surface, extrema);
      auto optimal = optimal_seam(surface, extrema, 10);
      const double opt = optimal.ok() ? optimal->length : 0.0;
      const double m = mst.ok() ? mst->length : 0.0;
      const double g = greedy.ok() ? greedy->length : 0.0;
      std::printf("| %s | %zu | %zu | %.4f | %.4f | %.4f | %.4f | %.4f | %.4f | %.4f | %.4f | %.4f | %s | %s |\n",
                  name.c_str(), mesh.num_faces(), k, plain->tree.length, refined->tree.length, m, g, opt,
                  opt > 0 ? plain->tree.length / opt : 0.0, opt > 0 ? refined->tree.length / opt : 0.0,
                  m > 0 ? refined->tree.length / m : 0.0, g > 0 ? refined->tree.length / g : 0.0,
                  valid(mesh, refined->tree, extrema),
                  plain_trace.fallback || refined_trace.fallback ? "YES" : "no");
    }
  }
}

void timing_table(bool quick) {
  std::printf("\n## Timings (ms, best of 3, one run above 500k faces; paths on all cores)\n\n");
  std::printf("| mesh | faces | k | paths | tour | shrink | straighten | refine | moves | seam total | removals | "
              "rejected |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  struct Size {
    std::string name;
    std::size_t faces;
  };
  std::vector<Size> sizes = {{"hand", 9000}, {"camel", 70000}, {"camel", 1000000}};
  if (quick) sizes.resize(1);
  for (const auto& size : sizes) {
    const HalfedgeMesh mesh = build(bench::subdivide_to(bench::load_cgal(size.name), size.faces));
    const SearchSurface surface(mesh);
    for (std::size_t k : {4u, 8u, 16u, 32u}) {
      const auto extrema = fixtures::farthest_point_extrema(mesh, surface.graph(), k);
      double paths_ms = 1e300, tour = 0, shrink = 0, straighten = 0, refine = 0, moves = 0, total = 1e300;
      std::size_t removals = 0, rejected = 0;
      const int reps = mesh.num_faces() > 500000 ? 1 : 3;
      for (int rep = 0; rep < reps; ++rep) {
        const double t0 = now_ms();
        auto paths = compute_terminal_paths(surface, extrema);
        const double t1 = now_ms();
        auto r = skeleton_seam(surface, *paths);
        const double t2 = now_ms();
        if (!r.ok()) {
          std::fprintf(stderr, "skeleton failed: %s\n", r.error().message.c_str());
          std::exit(1);
        }
        if (t2 - t0 < total) {
          total = t2 - t0;
          paths_ms = t1 - t0;
          tour = r->stats.tour_ms;
          shrink = r->stats.shrink_ms;
          straighten = r->stats.straighten_ms;
          refine = r->stats.refine_ms;
          moves = r->stats.improve_ms;
          removals = r->stats.removals;
          rejected = r->stats.rejected_removals;
        }
      }
      std::printf("| %s | %zu | %zu | %.1f | %.2f | %.2f | %.2f | %.2f | %.2f | %.1f | %zu | %zu |\n",
                  size.name.c_str(), mesh.num_faces(), k, paths_ms, tour, shrink, straighten, refine, moves, total,
                  removals, rejected);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  seam::bench::run_as_deployed(argv);
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  const bool timing_only = argc > 1 && std::strcmp(argv[1], "--timing") == 0;
  const bool quality_only = argc > 1 && std::strcmp(argv[1], "--quality") == 0;
  if (!timing_only) quality_table(quick);
  if (!quality_only) timing_table(quick);
  return 0;
}
