// Atlas benchmark (issue 12): overlap of the default map before/after making it injective,
// its distortion cost, packing coverage of several meshes' charts, and each step's time.
//   build/atlas/bench/atlas_bench [overlap|readme|worst|pack|quick|all]
//   atlas_bench slim|slim-foldfree [mesh ...]: the README's distortion rows with the injective
//       (or fold-free) SLIM's steps, factorizations, contact-limited steps and CPU ms
#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "bench_util.h"
#include "core/atlas/features.h"
#include "core/atlas/overlap.h"
#include "core/atlas/pack.h"
#include "core/atlas/split.h"
#include "core/extrema/extrema.h"
#include "core/mesh/cut.h"
#include "core/mesh/split_pinched.h"
#include "core/mesh/topology.h"
#include "core/seam/cut_graph.h"
#include "core/seam/seam.h"
#include "core/uv/bff.h"
#include "core/uv/parameterize.h"
#include "core/uv/slim.h"
#include "core/uv/uv_patch.h"
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
  // As the service does: pinched vertices (CGAL's cow has one) split per fan first.
  const PinchSplit split =
      split_pinched_vertices(weld->positions, remap_triangles(soup.triangles, weld->input_to_welded));
  auto mesh = build_halfedge_mesh(split.positions, split.triangles);
  if (!mesh.ok()) {
    std::printf("build failed: %s\n", mesh.error().message.c_str());
    std::exit(1);
  }
  return std::move(mesh).value();
}

// The disc the service flattens: the skeleton seam through automatic extrema, or (cut_graph)
// only the cut graph, which leaves one chart per component with every handle opened.
Result<CutMesh> disc_of(const HalfedgeMesh& mesh, bool cut_graph_only, SeamMethod method = SeamMethod::kSkeleton) {
  if (cut_graph_only) {
    SEAM_TRY(std::vector<EdgeId> edges, compute_cut_graph(mesh));
    if (!edges.empty()) return cut_along_edges(mesh, edges);
    // Genus 0: the README's "cut graph" row is the seam through no extrema.
    SEAM_TRY(SeamResult seam, compute_seam(mesh, {}, {.method = SeamMethod::kSkeleton}));
    return cut_along_edges(mesh, all_cut_edges(seam));
  }
  SEAM_TRY(std::vector<VertexId> extrema, find_extrema(mesh));
  SEAM_TRY(SeamResult seam, compute_seam(mesh, extrema, {.method = method}));
  return cut_along_edges(mesh, all_cut_edges(seam));
}

void overlap_row(const std::string& name, const HalfedgeMesh& mesh, bool cut_graph_only,
                 SeamMethod method = SeamMethod::kSkeleton) {
  auto disc = disc_of(mesh, cut_graph_only, method);
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
                name.c_str(), mesh.num_faces(), topo.total_genus(), cut_graph_only ? "cutgraph" : seam_method_name(method),
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

// Charts of one mesh as the atlas sees them: per chart its UVs, triangles and 3D area.
struct OwnedChart {
  std::vector<Vec2> uv;
  std::vector<Triangle> triangles;
  double surface_area = 0;
};

struct Charted {
  std::vector<OwnedChart> charts;
  Distortion distortion;
  double overlap_area = 0;
  double ms_seam = 0;
  double ms_uv = 0;
  std::size_t features = 0;
};

// charts "seam": the skeleton seam through the extrema; "features": cut along the feature edges
// first, then each piece cut to a disc by its cut graph (what charts: "features" amounts to
// for a piece without protrusions).
Result<Charted> chart_mesh(const HalfedgeMesh& mesh, bool features) {
  Charted out;
  auto t0 = std::chrono::steady_clock::now();
  HalfedgeMesh disc;
  if (features) {
    SEAM_TRY(FeatureEdges f, find_feature_edges(mesh));
    out.features = f.edges.size();
    SEAM_TRY(CutMesh first, cut_along_edges(mesh, f.edges));
    SEAM_TRY(std::vector<EdgeId> rest, compute_cut_graph(first.mesh));
    SEAM_TRY(CutMesh second, cut_along_edges(first.mesh, rest));
    disc = std::move(second.mesh);
  } else {
    SEAM_TRY(CutMesh cut, disc_of(mesh, false));
    disc = std::move(cut.mesh);
  }
  out.ms_seam = ms_since(t0);
  t0 = std::chrono::steady_clock::now();
  SEAM_TRY(UvResult uv, parameterize(disc));
  out.ms_uv = ms_since(t0);
  out.distortion = uv.distortion;
  out.overlap_area = uv.overlap_area;
  const Topology topo = compute_topology(disc);
  SEAM_TRY(std::vector<DiscPatch> patches, extract_disc_patches(disc, topo));
  for (const DiscPatch& p : patches) {
    OwnedChart c;
    for (VertexId v : p.to_mesh) c.uv.push_back(uv.uv[v]);
    c.triangles = p.triangles;
    for (const Triangle& t : p.triangles) {
      c.surface_area +=
          0.5 * (p.positions[t[1]] - p.positions[t[0]]).cross(p.positions[t[2]] - p.positions[t[0]]).norm();
    }
    if (c.surface_area > 0) out.charts.push_back(std::move(c));
  }
  return out;
}

struct Packed {
  PackResult pack;
  double overlap_area = 0;
  double overlap_ms = 0;
};

Packed pack_and_check(const std::vector<OwnedChart>& charts, const PackOptions& options) {
  std::vector<PackChart> views;
  for (const OwnedChart& c : charts) views.push_back({c.uv, c.triangles, c.surface_area});
  auto r = pack_charts(views, options);
  if (!r.ok()) {
    std::printf("pack failed: %s\n", r.error().message.c_str());
    std::exit(1);
  }
  std::vector<Vec2> uv;
  std::vector<Triangle> tris;
  std::vector<std::uint32_t> chart_of;
  for (std::size_t c = 0; c < charts.size(); ++c) {
    const auto base = static_cast<std::uint32_t>(uv.size());
    for (const Vec2& p : charts[c].uv) uv.push_back(r->placements[c].apply(p));
    for (const Triangle& t : charts[c].triangles) {
      tris.push_back({base + t[0], base + t[1], base + t[2]});
      chart_of.push_back(static_cast<std::uint32_t>(c));
    }
  }
  auto overlap = find_overlaps(uv, tris, chart_of);
  return {*r, overlap.ok() ? overlap->overlap_area : -1, overlap.ok() ? overlap->ms : 0};
}

// The charts cut by split_sprawling_charts (default options) into pieces that keep their UVs.
struct Split {
  std::vector<OwnedChart> pieces;
  SplitResult result;
  double ms = 0;
};

Split split_charts(const std::vector<OwnedChart>& charts) {
  std::vector<PackChart> views;
  for (const OwnedChart& c : charts) views.push_back({c.uv, c.triangles, c.surface_area});
  const auto t0 = std::chrono::steady_clock::now();
  auto r = split_sprawling_charts(views);
  const double ms = ms_since(t0);
  if (!r.ok()) {
    std::printf("split failed: %s\n", r.error().message.c_str());
    std::exit(1);
  }
  Split out{{}, *r, ms};
  for (const ChartPiece& p : r->pieces) {
    OwnedChart c;
    for (std::uint32_t v : p.vertices) c.uv.push_back(charts[p.chart].uv[v]);
    c.triangles = p.triangles;
    c.surface_area = p.surface_area;
    out.pieces.push_back(std::move(c));
  }
  return out;
}

void pack_section() {
  std::printf("\n== packing (texture 1024, margin 4 px, rotate): per asset, charts of several CGAL meshes\n");
  std::printf("%-44s %-8s %6s %8s %8s %8s %9s %9s %8s %9s %9s\n", "asset", "charts", "n", "seam_ms", "uv_ms",
              "pack_ms", "coverage", "rect_fill", "density", "overlap", "angle");
  struct Asset {
    const char* label;
    std::vector<const char*> meshes;
    bool features;
  };
  const Asset assets[] = {
      {"animals: hand camel dino elephant", {"hand", "camel", "dino", "elephant"}, false},
      {"figures: homer man bear armadillo", {"homer", "man", "bear", "armadillo"}, false},
      {"mixed: bunny mushroom elk knot1 pig", {"bunny00", "mushroom", "elk", "knot1", "pig"}, false},
      {"hard: fandisk rotor pinion joint cube", {"fandisk", "rotor", "pinion", "joint", "cube"}, true},
      {"hard: cheese-box couplingdown turbine", {"cheese-box", "couplingdown", "turbine"}, true},
      {"hard as seam: fandisk rotor pinion joint cube", {"fandisk", "rotor", "pinion", "joint", "cube"}, false},
  };
  for (const Asset& a : assets) {
    std::vector<OwnedChart> charts;
    double seam_ms = 0;
    double uv_ms = 0;
    double angle_weighted = 0;
    double area = 0;
    for (const char* name : a.meshes) {
      const IndexedMesh soup = sb::load_cgal(name);
      auto weld = weld_vertices(soup.positions, {});
      auto mesh = weld.ok() ? build_halfedge_mesh(weld->positions, remap_triangles(soup.triangles, weld->input_to_welded))
                            : Result<HalfedgeMesh>(weld.error());
      if (!mesh.ok()) {
        std::printf("  (%s skipped: %s)\n", name, mesh.error().message.c_str());
        continue;
      }
      auto c = chart_mesh(*mesh, a.features);
      if (!c.ok()) {
        std::printf("  %s: %s\n", name, c.error().message.c_str());
        continue;
      }
      seam_ms += c->ms_seam;
      uv_ms += c->ms_uv;
      double mesh_area = 0;
      for (const OwnedChart& ch : c->charts) mesh_area += ch.surface_area;
      angle_weighted += c->distortion.angle * mesh_area;
      area += mesh_area;
      const Packed alone = pack_and_check(c->charts, {});
      std::printf("    %-14s %4zu charts, alone: coverage %.3f, rect_fill %.3f, angle %.3f\n", name, c->charts.size(),
                  alone.pack.coverage, alone.pack.rect_fill, c->distortion.angle);
      for (OwnedChart& ch : c->charts) charts.push_back(std::move(ch));
    }
    const Packed p = pack_and_check(charts, {});
    std::printf("%-44s %-8s %6zu %8.1f %8.1f %8.2f %9.3f %9.3f %8.4f %9.2g %9.3f\n", a.label,
                a.features ? "features" : "seam", charts.size(), seam_ms, uv_ms, p.pack.ms, p.pack.coverage,
                p.pack.rect_fill, p.pack.density_ratio, p.overlap_area, angle_weighted / area);
    // The same charts with the sprawling ones split (seam grows by the cuts; distortion kept).
    const Split split = split_charts(charts);
    const Packed q = pack_and_check(split.pieces, {});
    std::printf("%-44s %-8s %6zu %8.1f %8.1f %8.2f %9.3f %9.3f %8.4f %9.2g %9.3f   split %.1f ms, %zu charts cut, "
                "cuts %.0f%% of the boundary\n",
                "  + split sprawling charts", a.features ? "features" : "seam", split.pieces.size(), seam_ms, uv_ms,
                q.pack.ms, q.pack.coverage, q.pack.rect_fill, q.pack.density_ratio, q.overlap_area,
                angle_weighted / area, split.ms, split.result.charts_split,
                100 * split.result.cut_length / split.result.boundary_length);
    std::fflush(stdout);
  }
}

// 1,000 and 10,000 charts (random rectangles and L shapes at random angles and densities).
void pack_scale_section() {
  std::printf("\n== packing time (issue target: 1,000 charts <= 50 ms)\n");
  std::printf("%8s %9s %9s %9s %9s\n", "charts", "pack_ms", "coverage", "rect_fill", "overlap");
  for (int n : {100, 1000, 10000}) {
    std::vector<OwnedChart> charts;
    std::uint64_t state = 12345;
    auto rnd = [&]() {
      state = state * 6364136223846793005ull + 1442695040888963407ull;
      return static_cast<double>(state >> 11) / 9007199254740992.0;
    };
    for (int k = 0; k < n; ++k) {
      OwnedChart c;
      const double w = 0.1 + 2 * rnd();
      const double h = 0.1 + 2 * rnd();
      const double a = 6.283 * rnd();
      const bool ell = rnd() < 0.5;
      const std::vector<Vec2> corners = ell ? std::vector<Vec2>{{0, 0}, {w, 0}, {w, h / 3}, {w / 3, h / 3}, {w / 3, h}, {0, h}}
                                            : std::vector<Vec2>{{0, 0}, {w, 0}, {w, h}, {0, h}};
      for (const Vec2& p : corners) c.uv.emplace_back(std::cos(a) * p.x() - std::sin(a) * p.y(), std::sin(a) * p.x() + std::cos(a) * p.y());
      if (ell) {
        c.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}};
      } else {
        c.triangles = {{0, 1, 2}, {0, 2, 3}};
      }
      const double uv_area = ell ? (w * h / 3 + (w / 3) * (2 * h / 3)) : w * h;
      c.surface_area = uv_area * (0.5 + rnd());
      charts.push_back(std::move(c));
    }
    Packed best{};
    double best_ms = 1e300;
    for (int rep = 0; rep < 3; ++rep) {
      Packed p = pack_and_check(charts, {});
      if (p.pack.ms < best_ms) {
        best_ms = p.pack.ms;
        best = p;
      }
    }
    std::printf("%8d %9.2f %9.3f %9.3f %9.2g\n", n, best_ms, best.pack.coverage, best.pack.rect_fill, best.overlap_area);
    std::fflush(stdout);
  }
}

// Every row of the README's distortion table (distortion_bench): each seam, before and after.
void readme_section() {
  std::printf("== README distortion table rows: SLIM fold-free only (before) vs injective (after)\n");
  for (const char* name : {"hand", "camel", "dino", "elephant", "armadillo", "homer"}) {
    const HalfedgeMesh mesh = build(sb::load_cgal(name));
    overlap_row(name, mesh, true);
    for (SeamMethod m : {SeamMethod::kMst, SeamMethod::kGreedy, SeamMethod::kSkeleton, SeamMethod::kOptimal}) {
      overlap_row(name, mesh, false, m);
    }
  }
}

double cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return 1e3 * static_cast<double>(ts.tv_sec) + 1e-6 * static_cast<double>(ts.tv_nsec);
}

// One row of the injective SLIM's cost: SLIM itself on every chart (steps, factorizations,
// collision-limited steps, energy), then the default parameterize() (area_g, angle, flips,
// overlap), each in process CPU ms. With `fold_free`, the same without injectivity.
void slim_cost_row(const std::string& name, const HalfedgeMesh& mesh, bool cut_graph_only, SeamMethod method,
                   bool fold_free) {
  auto disc = disc_of(mesh, cut_graph_only, method);
  if (!disc.ok()) return;
  auto patches = extract_disc_patches(disc->mesh, compute_topology(disc->mesh));
  if (!patches.ok()) return;
  int steps = 0;
  int factorizations = 0;
  int collided = 0;
  double energy = 0;
  double slim_ms = 0;
  for (const DiscPatch& patch : *patches) {
    std::vector<Vec2> start = flatten_bff(patch, CancelToken::none()).value();
    repair_flips(patch, start);
    const double t0 = cpu_ms();
    const SlimResult s = flatten_slim(patch, std::move(start), {.injective = !fold_free}, CancelToken::none()).value();
    slim_ms += cpu_ms() - t0;
    steps += s.iterations;
    factorizations += s.factorizations;
    collided += s.collision_limited_steps;
    energy = std::max(energy, s.energy_end);
  }
  UvOptions options;
  options.injective = !fold_free;
  const double t0 = cpu_ms();
  auto r = parameterize(disc->mesh, options);
  const double ms = cpu_ms() - t0;
  if (!r.ok()) return;
  const Distortion& d = r->distortion;
  std::printf("%-10s %-9s %-9s %5d %5d %5d %9.4f %8.1f %8.1f %8.4f %7.3f %5zu %9.2g\n", name.c_str(),
              cut_graph_only ? "cutgraph" : seam_method_name(method), fold_free ? "foldfree" : "injective", steps,
              factorizations, collided, energy, slim_ms, ms, d.area_geometric, d.angle, d.flipped,
              r->overlap_fraction);
  std::fflush(stdout);
}

// `slim [mesh ...]`: the README's distortion rows (and man's skeleton row) with SLIM's cost.
void slim_cost_section(const std::vector<std::string>& only, bool fold_free) {
  std::printf("%-10s %-9s %-9s %5s %5s %5s %9s %8s %8s %8s %7s %5s %9s\n", "mesh", "cut", "map", "steps", "facts",
              "coll", "energy", "slim_cpu", "job_cpu", "area_g", "angle", "flips", "overlap");
  for (const char* name : {"hand", "camel", "dino", "elephant", "cow", "armadillo", "homer", "man"}) {
    if (!only.empty() && std::find(only.begin(), only.end(), name) == only.end()) continue;
    const HalfedgeMesh mesh = build(sb::load_cgal(name));
    if (std::string(name) == "man") {
      slim_cost_row(name, mesh, false, SeamMethod::kSkeleton, fold_free);
      continue;
    }
    slim_cost_row(name, mesh, true, SeamMethod::kSkeleton, fold_free);
    for (SeamMethod m : {SeamMethod::kMst, SeamMethod::kGreedy, SeamMethod::kSkeleton}) {
      slim_cost_row(name, mesh, false, m, fold_free);
    }
  }
  // The genus-21 slab of the high-genus table (Tutte starts, many contacts).
  if (!only.empty() && std::find(only.begin(), only.end(), "slab-g21") == only.end()) return;
  const seam::fixtures::Soup slab = seam::fixtures::holed_slab(21);
  const HalfedgeMesh mesh = build(sb::subdivide(sb::subdivide(IndexedMesh{slab.positions, slab.triangles})));
  slim_cost_row("slab-g21", mesh, true, SeamMethod::kSkeleton, fold_free);
  slim_cost_row("slab-g21", mesh, false, SeamMethod::kSkeleton, fold_free);
}

}  // namespace

int main(int argc, char** argv) {
  seam::bench::run_as_deployed(argv);
  const std::string what = argc > 1 ? argv[1] : "all";
  const bool quick = what == "quick";
  if (what == "overlap" || what == "all" || quick) overlap_section(quick);
  if (what == "readme") readme_section();
  if (what == "slim" || what == "slim-foldfree") {
    slim_cost_section(std::vector<std::string>(argv + 2, argv + argc), what == "slim-foldfree");
  }
  if (what == "worst") {  // the rows where injectivity costs most (docs/uv.md)
    overlap_row("man", build(sb::load_cgal("man")), false, SeamMethod::kSkeleton);
    overlap_row("elephant", build(sb::load_cgal("elephant")), false, SeamMethod::kMst);
    overlap_row("armadillo", build(sb::load_cgal("armadillo")), false, SeamMethod::kGreedy);
  }
  if (what == "pack" || what == "all") {
    pack_section();
    pack_scale_section();
  }
  return 0;
}
