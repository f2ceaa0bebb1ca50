// How far the default seam is from the exact optimum on arbitrary terminal sets (issue 16),
// and what the seam stage costs (issue 14 item 2), all through core::compute_seam on the
// whole pipeline (cut graph, boundary terminal) of CGAL meshes: open, closed, genus > 0.
//
// Per mesh: seeded random terminal sets (k = 3..8, any non-boundary vertex) and the
// farthest-point extrema rows (k = 4, 6, 8). Variants, each divided by `optimal` (method
// kOptimal, Dreyfus–Wagner):
//   paper   skeleton, refine: false (the paper's seam)
//   before  skeleton, refine on (as before issue 16)
//   impr    skeleton, improve only (no refine), exact off
//   heur    skeleton, improve + refine, exact off (the heuristic alone)
//   after   the default options (exact where cheap, else improve + refine)
// Seam-stage time = paths + method (ms, summed over the rows of a mesh), measured in one
// process with the variants run back to back per row; other sessions share the 2 cores, so
// compare the ratios, not the absolute figures.
//   ./bench/seam_quality_bench [--quick] [--verbose] [--fingerprint] [--sets N] [--mesh NAME]
//                              [--speed | --no-speed | --large]
//   --fingerprint: every row's exact lengths (%.17g) per variant, to show a change kept them
//   --large: the seam stage at 1.25M faces with 16 extrema (one run per variant)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "bench_util.h"
#include "core/mesh/topology.h"
#include "core/paths/geodesic.h"
#include "core/seam/seam.h"
#include "skeleton_fixtures.h"

using namespace seam;
using namespace seam::core;

namespace {

bool g_verbose = false;  // --verbose: every row above 1.01 to stderr
bool g_fingerprint = false;  // --fingerprint: every row's lengths to stdout
constexpr double kTargetWorst = 1.03;
constexpr double kTargetMean = 1.005;

struct Variant {
  const char* name;
  SeamOptions options;
};

std::vector<Variant> variants() {
  return {
      {"paper", SeamOptions{.refine = false}},
      {"before", SeamOptions{.refine = true, .improve = false, .local_refine = true, .exact_budget = 0}},
      {"impr", SeamOptions{.refine = true, .improve = true, .local_refine = false, .exact_budget = 0}},
      {"heur", SeamOptions{.refine = true, .improve = true, .local_refine = true, .exact_budget = 0}},
      {"after", SeamOptions{}},
  };
}

struct Tally {
  std::vector<double> ratios;
  double ms = 0;
  std::size_t claimed_optimal = 0;
  std::size_t wrong_claims = 0;  // optimal claimed but longer than the optimum

  void add(double ratio, double stage_ms) {
    ratios.push_back(ratio);
    ms += stage_ms;
  }
  double worst() const { return ratios.empty() ? 0 : *std::max_element(ratios.begin(), ratios.end()); }
  double mean() const {
    double sum = 0;
    for (double r : ratios) sum += r;
    return ratios.empty() ? 0 : sum / static_cast<double>(ratios.size());
  }
  std::size_t above(double x) const {
    return static_cast<std::size_t>(std::count_if(ratios.begin(), ratios.end(), [&](double r) { return r > x; }));
  }
};

double stage_ms(const SeamResult& r) { return r.stats.paths_ms + r.stats.method_ms; }

std::vector<std::vector<VertexId>> terminal_sets(const HalfedgeMesh& mesh, const EdgeGraph& graph, std::size_t sets,
                                                 std::uint64_t seed, bool farthest_rows) {
  std::vector<VertexId> interior;
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
    if (!mesh.is_boundary(VertexId(v)) && !mesh.is_isolated(VertexId(v))) interior.push_back(VertexId(v));
  }
  std::mt19937_64 rng(seed);
  std::vector<std::vector<VertexId>> out;
  for (std::size_t i = 0; i < sets; ++i) {
    const std::size_t k = 3 + i % 6;
    std::vector<VertexId> set;
    while (set.size() < k) {
      const VertexId v = interior[rng() % interior.size()];
      if (std::find(set.begin(), set.end(), v) == set.end()) set.push_back(v);
    }
    out.push_back(std::move(set));
  }
  if (farthest_rows) {
    for (std::size_t k : {4u, 6u, 8u}) out.push_back(fixtures::farthest_point_extrema(mesh, graph, k));
  }
  return out;
}

struct MeshSpec {
  std::string name;
  bool random_sets;  // large meshes: only the farthest-point rows
};

void run_mesh(const MeshSpec& spec, std::size_t sets, std::vector<Tally>& overall) {
  const HalfedgeMesh mesh = bench::build_welded(bench::load_cgal(spec.name));
  const Topology topo = compute_topology(mesh);
  const EdgeGraph graph = build_edge_graph(mesh);
  const auto all = terminal_sets(mesh, graph, spec.random_sets ? sets : 0,
                                 0x5ea3u + std::hash<std::string>{}(spec.name) % 1000, true);
  const auto vars = variants();
  std::vector<Tally> tally(vars.size());
  double optimal_ms = 0;
  for (const auto& extrema : all) {
    auto optimal = compute_seam(mesh, extrema, SeamOptions{.method = SeamMethod::kOptimal});
    if (!optimal.ok()) {
      std::fprintf(stderr, "%s: optimal failed: %s\n", spec.name.c_str(), optimal.error().message.c_str());
      continue;
    }
    optimal_ms += stage_ms(*optimal);
    std::string fingerprint;
    for (std::size_t i = 0; i < vars.size(); ++i) {
      auto r = compute_seam(mesh, extrema, vars[i].options);
      if (!r.ok()) {
        std::fprintf(stderr, "%s: %s failed: %s\n", spec.name.c_str(), vars[i].name, r.error().message.c_str());
        std::exit(1);
      }
      const double ratio = optimal->length > 0 ? r->length / optimal->length : 1.0;
      if (g_verbose && ratio > 1.01) {
        std::fprintf(stderr, "%s k=%zu %s: %.4f (seam %.5f, optimal %.5f, terminals %zu vs %zu)\n", spec.name.c_str(),
                     extrema.size(), vars[i].name, ratio, r->length, optimal->length, r->terminals.size(),
                     optimal->terminals.size());
      }
      tally[i].add(ratio, stage_ms(*r));
      overall[i].add(ratio, 0);
      char fp[64];
      std::snprintf(fp, sizeof fp, " %s %.17g", vars[i].name, r->length);
      fingerprint += fp;
      if (r->optimal) {
        ++tally[i].claimed_optimal;
        if (ratio > 1.0 + 1e-9) ++tally[i].wrong_claims;
      }
    }
    if (g_fingerprint) {
      std::printf("fingerprint %s k=%zu optimal %.17g%s\n", spec.name.c_str(), extrema.size(), optimal->length,
                  fingerprint.c_str());
    }
  }
  std::printf("| %s | %zu | %d/%zu | %zu |", spec.name.c_str(), mesh.num_faces(), topo.total_genus(),
              topo.boundary_loops.size(), all.size());
  for (std::size_t i = 0; i < vars.size(); ++i) {
    std::printf(" %.4f / %.4f / %zu / %zu |", tally[i].worst(), tally[i].mean(), tally[i].above(1.01),
                tally[i].above(1.03));
  }
  const double paper = tally[0].ms > 0 ? tally[0].ms : 1e-9;
  std::printf(" %.1f |", tally[0].ms);
  for (std::size_t i = 1; i < vars.size(); ++i) std::printf(" %.2f |", tally[i].ms / paper);
  std::printf(" %.2f | %zu (%zu wrong) |\n", optimal_ms / paper, tally.back().claimed_optimal,
              tally.back().wrong_claims);
  std::fflush(stdout);
}

// Issue 14 item 2: the seam stage (paths + method) of each variant against the paper's, on
// subdivided meshes of 10k..80k faces, best of 3 with the variants interleaved per repetition.
void speed_table(bool quick, bool large) {
  std::printf("\n## Seam-stage time (ms, best of 3, variants interleaved) and ratio to the paper's seam (target "
              "<= 2.0)\n\n");
  std::printf("| mesh | faces | k | paper ms | before x | impr x | heur x | after x | after optimal | impr/paper len | "
              "after/paper len |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
  struct Size {
    const char* name;
    std::size_t faces;
  };
  std::vector<Size> sizes = {{"hand", 9000}, {"camel", 19000}, {"dino", 30000}, {"camel", 70000}};
  if (quick) sizes.resize(1);
  if (large) sizes = {{"camel", 1000000}};
  const auto vars = variants();
  for (const auto& size : sizes) {
    const HalfedgeMesh mesh =
        bench::build_welded(bench::spatially_ordered(bench::subdivide_to(bench::load_cgal(size.name), size.faces)));
    const EdgeGraph graph = build_edge_graph(mesh);
    for (std::size_t k : large ? std::vector<std::size_t>{16} : std::vector<std::size_t>{4, 8}) {
      const auto extrema = fixtures::farthest_point_extrema(mesh, graph, k);
      std::vector<double> best(vars.size(), 1e300), length(vars.size(), 0);
      bool after_optimal = false;
      for (int rep = 0; rep < (large ? 1 : 3); ++rep) {
        for (std::size_t i = 0; i < vars.size(); ++i) {
          auto r = compute_seam(mesh, extrema, vars[i].options);
          if (!r.ok()) {
            std::fprintf(stderr, "%s: %s\n", size.name, r.error().message.c_str());
            std::exit(1);
          }
          best[i] = std::min(best[i], stage_ms(*r));
          length[i] = r->length;
          if (i + 1 == vars.size()) after_optimal = r->optimal;
        }
      }
      std::printf("| %s | %zu | %zu | %.1f |", size.name, mesh.num_faces(), k, best[0]);
      for (std::size_t i = 1; i < vars.size(); ++i) std::printf(" %.2f |", best[i] / best[0]);
      std::printf(" %s | %.4f | %.4f |\n", after_optimal ? "yes" : "no", length[2] / length[0], length.back() / length[0]);
      std::fflush(stdout);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  seam::bench::run_as_deployed(argv);
  bool quick = false, speed_only = false, no_speed = false, large = false;
  std::size_t sets = 12;
  std::string only;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0) quick = true;
    if (std::strcmp(argv[i], "--verbose") == 0) g_verbose = true;
    if (std::strcmp(argv[i], "--fingerprint") == 0) g_fingerprint = true;
    if (std::strcmp(argv[i], "--speed") == 0) speed_only = true;
    if (std::strcmp(argv[i], "--large") == 0) speed_only = large = true;
    if (std::strcmp(argv[i], "--no-speed") == 0) no_speed = true;
    if (std::strcmp(argv[i], "--sets") == 0 && i + 1 < argc) sets = std::stoul(argv[++i]);
    if (std::strcmp(argv[i], "--mesh") == 0 && i + 1 < argc) only = argv[++i];
  }
  std::vector<MeshSpec> meshes = {{"hand", true},     {"elk", true},       {"mushroom", true}, {"eight", true},
                                  {"elephant", true}, {"knot1", true},       {"bones", true},    {"dino", true},
                                  {"lion-head", true}, {"camel", true},    {"armadillo", false}, {"bunny00", false}};
  if (quick) meshes = {{"hand", true}, {"mushroom", true}, {"eight", true}};
  if (!only.empty()) meshes = {{only, true}};

  std::printf("## Seam length / exact optimum (worst / mean / count > 1.01 / count > 1.03), seam-stage time\n\n");
  std::printf("Rows: %zu seeded random sets (k = 3..8) + farthest-point k = 4, 6, 8 (large meshes: those only).\n",
              sets);
  std::printf("Time: paper = seam-stage ms summed over the rows; the others as multiples of it.\n\n");
  std::printf("| mesh | faces | genus/loops | rows | paper | before | impr | heur | after | paper ms | before x | "
              "impr x | heur x | after x | optimal x | after claims optimal |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  const auto vars = variants();
  std::vector<Tally> overall(vars.size());
  if (speed_only) {
    speed_table(quick, large);
    return 0;
  }
  for (const auto& spec : meshes) run_mesh(spec, sets, overall);
  std::printf("\n| all rows | count | worst | mean | > 1.01 | > 1.03 | target worst <= %.3f | target mean <= %.3f |\n",
              kTargetWorst, kTargetMean);
  std::printf("|---|---|---|---|---|---|---|---|\n");
  for (std::size_t i = 0; i < vars.size(); ++i) {
    const Tally& t = overall[i];
    std::printf("| %s | %zu | %.4f | %.4f | %zu | %zu | %s | %s |\n", vars[i].name, t.ratios.size(), t.worst(),
                t.mean(), t.above(1.01), t.above(1.03), t.worst() <= kTargetWorst ? "met" : "MISSED",
                t.mean() <= kTargetMean ? "met" : "MISSED");
  }
  if (!no_speed && only.empty()) speed_table(quick, false);
  return 0;
}
