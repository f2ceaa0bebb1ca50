// Flattening at scale (issue 14, item 3): the default map's time against BFF's on ~1M faces,
// paired in one run, and where SLIM's time goes. Target: default <= 1.5x BFF's own time
// (`uv: bff`), both through parameterize() as the service calls it.
//
// Also: the nested dissection order of the largest chart's vertex graph, METIS_NodeND as
// nested_dissection_order calls it against CHOLMOD's cholmod_metis (METIS's defaults), paired.
//
//   flatten_bench [pairs [min_faces [mesh ...]]]   default: 3 pairs, 900000 faces; lion-head (a
//       disc) and camel (closed, cut by the skeleton seam through its automatic extrema)
// Each mesh is midpoint-subdivided to >= min_faces faces and its vertices and triangles numbered
// as the service numbers every mesh (bench::service_numbered). Prints tables; asserts nothing.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "bench_util.h"
#include "core/extrema/extrema.h"
#include "core/mesh/cut.h"
#include "core/mesh/topology.h"
#include "core/seam/seam.h"
#include "core/uv/bff.h"
#include "core/uv/multilevel.h"
#include "core/uv/parameterize.h"
#include "core/uv/slim.h"
#include "core/uv/sparse_cholesky.h"

using namespace seam;

namespace {

constexpr double kTargetRatio = 1.5;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

// The mesh to flatten: a disc as it is, a closed mesh cut along its default seam.
core::HalfedgeMesh disc_of(const std::string& name, std::size_t min_faces) {
  const core::IndexedMesh soup = bench::service_numbered(bench::subdivide_to(bench::load_cgal(name), min_faces));
  core::HalfedgeMesh mesh = bench::build_welded(soup);
  const core::Topology topology = core::compute_topology(mesh);
  if (topology.boundary_loops.size() > 0) return mesh;
  const auto extrema = core::find_extrema(mesh).value();
  const auto seam = core::compute_seam(mesh, extrema, {}).value();
  return std::move(core::cut_along_edges(mesh, core::all_cut_edges(seam)).value().mesh);
}

// Stage by stage on the largest chart: BFF, then SLIM's own breakdown, on the whole chart and on
// the coarse chart of the two-level path with the service's options (coarse_slim_options).
void breakdown(const std::string& name, const core::HalfedgeMesh& disc) {
  const core::Topology topology = core::compute_topology(disc);
  auto patches = core::extract_disc_patches(disc, topology).value();
  const auto largest = std::max_element(patches.begin(), patches.end(), [](const auto& a, const auto& b) {
    return a.triangles.size() < b.triangles.size();
  });
  std::vector<core::Vec2> start;
  const double bff_ms = bench::best_ms(1, [&] { start = core::flatten_bff(*largest, core::CancelToken::none()).value(); });
  core::repair_flips(*largest, start);
  core::SlimResult slim;
  const double slim_ms = bench::best_ms(1, [&] {
    slim = core::flatten_slim(*largest, start, {}, core::CancelToken::none()).value();
  });
  const core::TwoLevelResult two =
      core::slim_two_level(*largest, start, core::default_coarse_vertices(largest->num_vertices()),
                           core::coarse_slim_options({}))
          .value();
  const core::SlimTimings& t = slim.timings;
  std::printf("%-10s %9zu %8.0f %8.0f %5d %5d %6.3f %6.3f %4d %7.0f %7.0f %8.0f %7.0f %7.0f %7.0f%s\n",
              name.c_str(), largest->triangles.size(), bff_ms, slim_ms, slim.iterations, slim.factorizations,
              slim.energy_start, slim.energy_end, slim.collision_limited_steps, t.start_ms, t.analyze_ms,
              t.assemble_ms, t.factor_ms, t.line_search_ms, t.collision_ms, slim.tutte_start ? " (tutte start)" : "");
  const core::SlimTimings& c = two.coarse.timings;
  std::printf(
      "%-10s %9s %8s %8.0f %5d %5d %6.3f %6.3f %4d %7.0f %7.0f %8.0f %7.0f %7.0f %7.0f  two-level: %zu coarse "
      "vertices, coarsen %.0f ms, prolong+untangle %.0f ms (%zu folds)%s\n",
      "", "", "", two.coarsen_ms + two.slim_ms + two.finish_ms, two.coarse.iterations, two.coarse.factorizations,
      two.coarse.energy_start, two.coarse.energy_end, two.coarse.collision_limited_steps, c.start_ms, c.analyze_ms,
      c.assemble_ms, c.factor_ms, c.line_search_ms, c.collision_ms, two.coarse_vertices, two.coarsen_ms, two.finish_ms,
      two.folds_untangled, two.uv.empty() ? " FOLDED: falls back" : "");
  std::fflush(stdout);
}

// Entries in L and factorization flops of an analysis in `order`.
std::pair<double, double> fill_of(const Eigen::SparseMatrix<double>& lower, std::vector<int> order) {
  core::SparseCholesky solver;
  solver.use_order(std::move(order));
  solver.analyzePattern(lower);
  return {solver.cholmod().lnz, solver.cholmod().fl};
}

// nested_dissection_order against CHOLMOD's METIS call with METIS's defaults, `pairs` times.
void orders(const std::string& name, const core::HalfedgeMesh& disc, int pairs) {
  auto patches = core::extract_disc_patches(disc, core::compute_topology(disc)).value();
  const auto largest = std::max_element(patches.begin(), patches.end(), [](const auto& a, const auto& b) {
    return a.triangles.size() < b.triangles.size();
  });
  const Eigen::SparseMatrix<double> lower = core::vertex_graph_lower(*largest);
  std::vector<double> ours_ms, cholmod_ms;
  std::vector<int> ours, theirs;
  for (int i = 0; i < pairs; ++i) {
    ours_ms.push_back(bench::best_ms(1, [&] { ours = core::nested_dissection_order(lower); }));
    cholmod_ms.push_back(bench::best_ms(1, [&] {
      cholmod_common common;
      cholmod_start(&common);
      cholmod_sparse view = Eigen::viewAsCholmod(lower.selfadjointView<Eigen::Lower>());
      theirs.assign(static_cast<std::size_t>(lower.rows()), 0);
      cholmod_metis(&view, nullptr, 0, 1, theirs.data(), &common);
      cholmod_finish(&common);
    }));
  }
  const auto [ours_lnz, ours_fl] = fill_of(lower, ours);
  const auto [their_lnz, their_fl] = fill_of(lower, theirs);
  std::printf("%-10s %9zu %9.0f %9.0f %6.2f %8.2f %8.2f %7.2f %7.2f\n", name.c_str(), largest->num_vertices(),
              median(ours_ms), median(cholmod_ms), median(ours_ms) / median(cholmod_ms), ours_lnz / 1e6,
              their_lnz / 1e6, ours_fl / 1e9, their_fl / 1e9);
  std::fflush(stdout);
}

// Paired parameterize() runs: BFF, the default (two-level SLIM on charts this large) and SLIM
// on the whole chart, `pairs` times; medians, the default's ratio to BFF and both SLIMs'
// distortion.
void paired(const std::string& name, const core::HalfedgeMesh& disc, int pairs) {
  std::vector<double> bff, def, full;
  core::UvResult d, f;
  for (int i = 0; i < pairs; ++i) {
    bff.push_back(bench::best_ms(1, [&] { (void)core::parameterize(disc, {.method = core::UvMethod::kBff}); }));
    def.push_back(bench::best_ms(1, [&] { d = core::parameterize(disc).value(); }));
    full.push_back(bench::best_ms(1, [&] { f = core::parameterize(disc, {.multilevel_min_faces = 0}).value(); }));
  }
  const double ratio = median(def) / median(bff);
  std::printf("%-10s %9zu %9.0f %9.0f %9.0f %6.2f %-6s %8.3f %8.3f %6.3f %6.3f %6zu %8.2g\n", name.c_str(),
              disc.num_faces(), median(bff), median(def), median(full), ratio, ratio <= kTargetRatio ? "met" : "missed",
              d.distortion.area_geometric, f.distortion.area_geometric, d.distortion.angle, f.distortion.angle,
              d.distortion.flipped, d.overlap_area);
  std::fflush(stdout);
}

// The per-stage breakdown and the order table.
void sections(const std::vector<std::string>& names, const std::vector<core::HalfedgeMesh>& discs, int pairs) {
  std::printf("== SLIM on the largest chart, ms (one run each)\n");
  std::printf("%-10s %9s %8s %8s %5s %5s %6s %6s %4s %7s %7s %8s %7s %7s %7s\n", "mesh", "faces", "bff", "slim",
              "iters", "facts", "E0", "E1", "coll", "start", "analyze", "assemble", "factor", "search", "collide");
  for (std::size_t i = 0; i < names.size(); ++i) breakdown(names[i], discs[i]);

  std::printf(
      "\n== nested dissection of the largest chart's vertex graph, median of %d pairs: ours =\n"
      "   METIS_NodeND with one refinement pass per level, cholmod = cholmod_metis (defaults)\n",
      pairs);
  std::printf("%-10s %9s %9s %9s %6s %8s %8s %7s %7s\n", "mesh", "vertices", "ours ms", "cholmod", "ratio", "L ours",
              "L chol", "GF ours", "GF chol");
  for (std::size_t i = 0; i < names.size(); ++i) orders(names[i], discs[i], pairs);
}

}  // namespace

int main(int argc, char** argv) {
  seam::bench::run_as_deployed(argv);
  // --paired: the paired table alone.
  const bool paired_only = argc > 1 && std::string(argv[1]) == "--paired";
  if (paired_only) --argc, ++argv;
  const int pairs = argc > 1 ? std::max(1, std::atoi(argv[1])) : 3;
  const std::size_t min_faces = argc > 2 ? std::strtoull(argv[2], nullptr, 10) : 900'000;
  std::vector<std::string> names = {"lion-head", "camel"};
  if (argc > 3) names.assign(argv + 3, argv + argc);
  std::vector<core::HalfedgeMesh> discs;
  for (const auto& name : names) discs.push_back(disc_of(name, min_faces));

  if (!paired_only) sections(names, discs, pairs);
  std::printf(
      "\n== parameterize(): default vs uv=bff, median of %d pairs (target ratio <= %.1f); single =\n"
      "   SLIM on the whole chart (the default below multilevel_min_faces)\n",
      pairs, kTargetRatio);
  std::printf("%-10s %9s %9s %9s %9s %6s %-6s %8s %8s %6s %6s %6s %8s\n", "mesh", "faces", "bff ms", "default",
              "single", "ratio", "target", "area_g", "single", "angle", "single", "flips", "overlap");
  for (std::size_t i = 0; i < names.size(); ++i) paired(names[i], discs[i], pairs);
  return 0;
}
