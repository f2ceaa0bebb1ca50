// Automatic extrema (issue 7): detection time and found counts on real meshes at their own
// size and subdivided 1-to-4 to >= 100k and >= 1M faces, against the seam's own time with
// the found extrema; and how far the tips move when the same shape is subdivided.
//   cmake -DSEAM_BUILD_BENCH=ON ... && ninja extrema_bench && ./bench/extrema_bench [--quick] [--no-seam]
//   [--seam-all] (the seam is timed up to 400k faces unless --seam-all)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

#include "bench_util.h"
#include "core/extrema/extrema.h"
#include "core/seam/seam.h"
#include "core/mesh/weld.h"

using namespace seam;
using namespace seam::core;

namespace {

HalfedgeMesh build(const IndexedMesh& soup) { return bench::build_welded(soup); }

double area_of(const HalfedgeMesh& mesh) {
  double area = 0;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    const auto v = mesh.face_vertices(FaceId(f));
    area += 0.5 * (mesh.position(v[1]) - mesh.position(v[0])).cross(mesh.position(v[2]) - mesh.position(v[0])).norm();
  }
  return area;
}

// Largest distance from a tip of `tips` to the nearest tip of `reference`, in sqrt(area).
double drift(const std::vector<Vec3>& tips, const std::vector<Vec3>& reference, double unit) {
  double worst = 0;
  for (const Vec3& p : tips) {
    double nearest = INFINITY;
    for (const Vec3& q : reference) nearest = std::min(nearest, (p - q).norm());
    worst = std::max(worst, nearest);
  }
  return worst / unit;
}

// CPU milliseconds of the process during f(): with one thread it is the work itself, much
// less disturbed than wall time on a machine shared with other jobs.
template <class F>
double cpu_ms(F&& f) {
  timespec a{}, b{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &a);
  f();
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &b);
  return (b.tv_sec - a.tv_sec) * 1e3 + (b.tv_nsec - a.tv_nsec) * 1e-6;
}

}  // namespace

int main(int argc, char** argv) {
  seam::bench::run_as_deployed(argv);
  bool quick = false, seam_too = true;
  std::size_t seam_max_faces = 400000;  // the seam on larger meshes takes minutes on 2 cores
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--quick")) quick = true;
    if (!std::strcmp(argv[i], "--no-seam")) seam_too = false;
    if (!std::strcmp(argv[i], "--seam-all")) seam_max_faces = SIZE_MAX;
  }
  const std::vector<std::string> names =
      quick ? std::vector<std::string>{"elephant"} : std::vector<std::string>{"elephant", "camel", "armadillo"};
  const std::vector<std::size_t> sizes = quick ? std::vector<std::size_t>{0, 100000}
                                               : std::vector<std::size_t>{0, 100000, 1000000};
  const ExtremaOptions options;  // the defaults the service uses
  std::printf("## Automatic extrema: detection time vs the seam's own time (defaults: min_protrusion %.2f, "
              "%zu samples, threads = hardware)\n\n",
              options.min_protrusion, options.samples);
  std::printf("| mesh | faces | vertices | found | prominences | detect wall ms (best of %d) | detect CPU ms, 1 thread | "
              "seam wall ms (skeleton, found extrema) | detect/seam wall | tip drift vs level 0 (sqrt(area)) |\n",
              quick ? 1 : 2);
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
  for (const auto& name : names) {
    const IndexedMesh base = bench::load_cgal(name);
    std::vector<Vec3> level0_tips;
    for (std::size_t min_faces : sizes) {
      const IndexedMesh soup = bench::subdivide_to(base, min_faces);
      const HalfedgeMesh mesh = build(soup);
      const double unit = std::sqrt(area_of(mesh));
      ExtremaResult result;
      const double ms = bench::best_ms(quick ? 1 : 2, [&] {
        auto r = detect_extrema(mesh, options);
        if (!r.ok()) {
          std::fprintf(stderr, "%s: %s\n", name.c_str(), r.error().message.c_str());
          std::exit(1);
        }
        result = std::move(r).value();
      });
      ExtremaOptions serial = options;
      serial.threads = 1;
      const double serial_ms = cpu_ms([&] { (void)detect_extrema(mesh, serial); });
      std::vector<VertexId> tips;
      std::vector<Vec3> tip_positions;
      std::string prominences;
      for (const auto& e : result.extrema) {
        tips.push_back(e.vertex);
        tip_positions.push_back(mesh.position(e.vertex));
        char buf[16];
        std::snprintf(buf, sizeof buf, "%s%.2f", prominences.empty() ? "" : " ", e.prominence);
        prominences += buf;
      }
      if (min_faces == 0) level0_tips = tip_positions;
      double seam_ms = NAN;
      if (seam_too && mesh.num_faces() <= seam_max_faces) {
        seam_ms = bench::best_ms(1, [&] {
          auto seam = compute_seam(mesh, tips);
          if (!seam.ok()) std::fprintf(stderr, "%s: seam: %s\n", name.c_str(), seam.error().message.c_str());
        });
      }
      std::printf("| %s%s | %zu | %zu | %zu | %s | %.1f | %.1f | %.1f | %.2f | %.3f |\n", name.c_str(),
                  min_faces == 0 ? "" : " (subdivided)", mesh.num_faces(), mesh.num_vertices(),
                  result.extrema.size(), prominences.c_str(), ms, serial_ms, seam_ms, ms / seam_ms,
                  drift(tip_positions, level0_tips, unit));
      std::fflush(stdout);
    }
  }
  return 0;
}
