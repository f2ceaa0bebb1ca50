// The experiment the paper motivates (issues 6 and 7): how the seam changes the distortion of
// the flattened chart. For real CGAL meshes with protrusions and their automatic extrema,
// cut along the cut graph alone (no extrema: the documented minimal disc-opening seam), or
// along the mst / greedy / skeleton / optimal seam, flatten with LSCM and with the default
// method, and print seam length, area distortion (arithmetic and geometric), angle
// distortion and flipped triangles.
//   build/release/bench/distortion_bench [mesh ...]
#include <cstdio>
#include <string>
#include <vector>

#include "bench_util.h"
#include "core/mesh/split_pinched.h"
#include "core/mesh/cut.h"
#include "core/extrema/extrema.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/uv/parameterize.h"
#include "core/seam/seam.h"
#include "core/mesh/weld.h"

using namespace seam;
using core::SeamMethod;

namespace {

void run_row(const std::string& mesh_name, const char* label, const core::HalfedgeMesh& mesh,
             std::span<const core::VertexId> extrema, SeamMethod method) {
  core::SeamOptions options;
  options.method = method;
  options.optimal_max_terminals = 8;
  double seam_ms = 0;
  core::Result<core::SeamResult> seam = core::make_error(core::ErrorCode::kInvalidArgument, "not run");
  seam_ms = bench::best_ms(1, [&] { seam = core::compute_seam(mesh, extrema, options); });
  if (!seam.ok()) {
    std::printf("%-10s %-10s %s\n", mesh_name.c_str(), label, seam.error().message.c_str());
    return;
  }
  auto cut = core::cut_along_edges(mesh, core::all_cut_edges(*seam));
  if (!cut.ok()) {
    std::printf("%-10s %-10s cut failed: %s\n", mesh_name.c_str(), label, cut.error().message.c_str());
    return;
  }
  std::printf("%-10s %-10s %7.3f %7.1f", mesh_name.c_str(), label, seam->length + seam->cut_graph_length, seam_ms);
  for (core::UvMethod uv : {core::UvMethod::kLscm, core::UvOptions{}.method}) {
    core::UvOptions uv_options;
    uv_options.method = uv;
    auto flat = core::parameterize(cut->mesh, uv_options);
    if (!flat.ok()) {
      std::printf(" | %-36s", flat.error().message.substr(0, 36).c_str());
      continue;
    }
    const auto& d = flat->distortion;
    std::printf(" | %9.3g %7.3f %6.3f %5zu %6.0f", d.area, d.area_geometric, d.angle, d.flipped, flat->solve_ms);
  }
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  seam::bench::run_as_deployed(argv);
  std::vector<std::string> names = {"hand", "camel", "dino", "elephant", "cow", "homer", "armadillo"};
  if (argc > 1) names.assign(argv + 1, argv + argc);
  std::printf("default uv method: %s; extrema: find_extrema() with default options; optimal limited to 8 terminals\n\n",
              core::uv_method_name(core::UvOptions{}.method));
  std::printf("%-10s %-10s %7s %7s | %-36s | %-36s\n", "", "", "", "", "LSCM", "default");
  std::printf("%-10s %-10s %7s %7s | %9s %7s %6s %5s %6s | %9s %7s %6s %5s %6s\n", "mesh", "seam", "length", "seam_ms",
              "area", "area_g", "angle", "flips", "ms", "area", "area_g", "angle", "flips", "ms");
  for (const auto& name : names) {
    const auto soup = bench::load_cgal(name);
    const auto weld = core::weld_vertices(soup.positions, {}).value();
    const auto tris = core::remap_triangles(soup.triangles, weld.input_to_welded);
    // As the service does: pinched vertices (CGAL's cow has one) split per fan first.
    const auto split = core::split_pinched_vertices(weld.positions, tris);
    const auto mesh = core::build_halfedge_mesh(split.positions, split.triangles).value();
    const auto extrema = core::find_extrema(mesh).value();
    std::printf("%-10s (%zu faces, %zu auto extrema)\n", name.c_str(), mesh.num_faces(), extrema.size());
    run_row(name, "cut graph", mesh, {}, SeamMethod::kSkeleton);
    for (SeamMethod m : {SeamMethod::kMst, SeamMethod::kGreedy, SeamMethod::kSkeleton, SeamMethod::kOptimal}) {
      run_row(name, core::seam_method_name(m), mesh, extrema, m);
    }
  }
  std::printf("\narea = area-weighted mean of max(s1 s2, 1/(s1 s2)); area_g = its geometric form\n"
              "exp(mean |log s1 s2|); angle = mean s1/s2; flips = triangles with non-positive UV area.\n"
              "length = seam + cut graph (model units); 'cut graph' = no extrema (documented minimal seam).\n");
  return 0;
}
