// Flattening benchmark: time and distortion per method on real CGAL discs, on growing
// meshes (10k .. ~1M faces), and (once the seam pipeline links) on closed protrusion meshes
// cut by each seam method. Prints tables; asserts nothing.
//
//   uv_bench            all sections
//   uv_bench quick      skips the ~1M-face sizes and most seam meshes
//   uv_bench seams      only the seam table
//   uv_bench scale      only the scaling table (10k, 100k, ~1M faces)
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "api/mesh_io.h"
#include "bench_util.h"
#include "core/mesh/cut.h"
#include "core/extrema/extrema.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/uv/parameterize.h"
#include "core/seam/seam.h"
#include "core/mesh/topology.h"
#include "core/mesh/weld.h"

using namespace seam::core;

namespace {

std::string mesh_path(const std::string& name) { return std::string(SEAM_TEST_DATA_DIR) + "/meshes/" + name + ".off"; }

bool load(const std::string& name, IndexedMesh& out) {
  auto mesh = seam::api::read_mesh_file(mesh_path(name));
  if (!mesh.ok()) {
    std::printf("  (skipping %s: %s)\n", name.c_str(), mesh.error().message.c_str());
    return false;
  }
  out = std::move(mesh).value();
  return true;
}

bool build(const IndexedMesh& soup, HalfedgeMesh& out) {
  auto weld = weld_vertices(soup.positions, {});
  if (!weld.ok()) return false;
  const auto tris = remap_triangles(soup.triangles, weld->input_to_welded);
  auto mesh = build_halfedge_mesh(weld->positions, tris);
  if (!mesh.ok()) {
    std::printf("  (build failed: %s)\n", mesh.error().message.c_str());
    return false;
  }
  out = std::move(mesh).value();
  return true;
}

/// A wavy height field over [0,1]^2 with 2 n^2 faces: a curved (non-developable) disc.
IndexedMesh height_field(int n) {
  IndexedMesh m;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const double x = static_cast<double>(i) / n;
      const double y = static_cast<double>(j) / n;
      m.positions.emplace_back(x, y, 0.25 * std::sin(6 * x) * std::cos(4 * y) + 0.3 * x * y);
    }
  }
  auto id = [&](int i, int j) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return m;
}

// Each method, plus SLIM with the paper's anisotropic proxy ("slim2x2") to show what the
// default's isotropic proxy trades for its speed.
struct Variant {
  const char* label;
  UvOptions options;
};
const Variant kVariants[] = {
    {"lscm", {.method = UvMethod::kLscm}},
    {"bff", {.method = UvMethod::kBff}},
    {"arap", {.method = UvMethod::kArap}},
    {"slim2x2", {.method = UvMethod::kSlim, .slim_proxy = seam::core::SlimProxy::kAnisotropic}},
    {"slim", {.method = UvMethod::kSlim}},
};

void header() {
  std::printf("%-26s %9s %-7s %9s %9s %8s %8s %8s %10s %7s %9s\n", "mesh", "faces", "uv", "ms", "area", "area_geo",
              "angle", "L2", "Linf", "flips", "f32fixed");
}

void row(const std::string& name, const HalfedgeMesh& mesh, const Variant& variant) {
  const UvMethod method = variant.options.method;
  const auto t0 = std::chrono::steady_clock::now();
  auto r = parameterize(mesh, variant.options);
  const double total_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (!r.ok()) {
    std::printf("%-26s %9zu %-7s  error: %s\n", name.c_str(), mesh.num_faces(), variant.label,
                r.error().message.c_str());
    return;
  }
  const Distortion& d = r->distortion;
  std::printf("%-26s %9zu %-7s %9.1f %9.3f %8.3f %8.3f %8.3f %10.3f %7zu %5zu/%-3zu%s\n", name.c_str(),
              mesh.num_faces(), variant.label, total_ms, d.area, d.area_geometric, d.angle,
              d.stretch_l2, d.stretch_linf, d.flipped, r->float32_degenerate - r->float32_unrepaired,
              r->float32_degenerate, r->method_used != method ? " (arap fell back)" : "");
  std::fflush(stdout);
}

}  // namespace

// Closed protrusion meshes: automatic extrema, each seam method, cut, then flatten.
void seam_section(bool quick) {
  std::printf("\n== closed meshes cut by each seam (automatic extrema), then flattened\n");
  std::printf("%-12s %6s %-9s %4s %-7s %8s %9s %8s %8s %8s %7s %9s\n", "mesh", "faces", "seam", "ext", "uv", "ms",
              "area", "area_geo", "angle", "L2", "flips", "f32fixed");
  const char* names_full[] = {"hand", "camel", "dino", "armadillo", "elephant", "homer", "bear", "cow", "man"};
  const char* names_quick[] = {"hand", "camel", "elephant"};
  std::vector<const char*> names(quick ? std::begin(names_quick) : std::begin(names_full),
                                 quick ? std::end(names_quick) : std::end(names_full));
  for (const char* name : names) {
    IndexedMesh soup;
    HalfedgeMesh mesh;
    if (!load(name, soup) || !build(soup, mesh)) continue;
    auto extrema = find_extrema(mesh);
    if (!extrema.ok()) {
      std::printf("%-12s extrema failed: %s\n", name, extrema.error().message.c_str());
      continue;
    }
    for (SeamMethod sm : {SeamMethod::kSkeleton, SeamMethod::kMst, SeamMethod::kGreedy, SeamMethod::kOptimal}) {
      auto seam = compute_seam(mesh, *extrema, {.method = sm});
      if (!seam.ok()) {
        std::printf("%-12s %6zu %-9s %4zu  seam error: %s\n", name, mesh.num_faces(), seam_method_name(sm),
                    extrema->size(), seam.error().message.c_str());
        continue;
      }
      auto cut = cut_along_edges(mesh, all_cut_edges(*seam));
      if (!cut.ok()) {
        std::printf("%-12s cut error: %s\n", name, cut.error().message.c_str());
        continue;
      }
      for (const Variant& variant : kVariants) {
        const auto t0 = std::chrono::steady_clock::now();
        auto r = parameterize(cut->mesh, variant.options);
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        if (!r.ok()) {
          std::printf("%-12s %6zu %-9s %4zu %-7s  error: %s\n", name, mesh.num_faces(), seam_method_name(sm),
                      extrema->size(), variant.label, r.error().message.c_str());
          continue;
        }
        const Distortion& d = r->distortion;
        std::printf("%-12s %6zu %-9s %4zu %-7s %8.1f %9.3f %8.3f %8.3f %8.3f %7zu %5zu/%-3zu\n", name,
                    mesh.num_faces(), seam_method_name(sm), extrema->size(), variant.label, ms,
                    d.area, d.area_geometric, d.angle, d.stretch_l2, d.flipped,
                    r->float32_degenerate - r->float32_unrepaired, r->float32_degenerate);
        std::fflush(stdout);
      }
    }
  }
}

int main(int argc, char** argv) {
  seam::bench::run_as_deployed(argv);
  const bool quick = argc > 1 && std::strcmp(argv[1], "quick") == 0;
  const bool seams_only = argc > 1 && std::strcmp(argv[1], "seams") == 0;
  const bool scale_only = argc > 1 && std::strcmp(argv[1], "scale") == 0;
  if (seams_only) {
    seam_section(false);
    return 0;
  }
  if (!scale_only) {
  std::printf("== real CGAL discs (1 boundary loop, genus 0); ms = parameterize() incl. packing+measuring\n");
  header();
  for (const char* name : {"nefertiti", "patch-01", "three_peaks", "mushroom", "lion-head", "mannequin-devil"}) {
    IndexedMesh soup;
    HalfedgeMesh mesh;
    if (!load(name, soup) || !build(soup, mesh)) continue;
    for (const Variant& m : kVariants) row(name, mesh, m);
  }

  }
  std::printf("\n== scaling: lion-head midpoint-subdivided, and a wavy height field\n");
  header();
  {
    IndexedMesh soup;
    if (load("lion-head", soup)) {
      for (int level = 0; level <= (quick ? 2 : 3); ++level) {
        HalfedgeMesh mesh;
        if (build(soup, mesh)) {
          for (const Variant& m : kVariants) row("lion-head/sub" + std::to_string(level), mesh, m);
        }
        if (level < 3) soup = seam::bench::subdivide(soup);
      }
    }
    for (int n : {71, 224, 707}) {
      if (quick && n > 300) continue;
      HalfedgeMesh mesh;
      if (!build(height_field(n), mesh)) continue;
      for (const Variant& m : kVariants) row("heightfield/" + std::to_string(n), mesh, m);
    }
  }
  if (!scale_only) seam_section(quick);
  return 0;
}
