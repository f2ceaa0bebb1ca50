// glTF I/O throughput: load (parse + read primitive), the job's weld stage (api::prepare_surface:
// weld, canonical numbering, build, topology; weld_ms), and encode, for GLB and
// Draco GLB of ~100k and ~1M faces made at run time by midpoint-subdividing CGAL meshes.
// Prints a table; asserts nothing. Run: build-*/bench/gltf_bench [--quick] [--glb-only] [--write-glb PATH]
// cut_write_ms is the job's encode stage (write_cut_asset); /0.3s is its ratio to issue 14's
// target of 0.3 s at 1.25M faces (the bunny00 x16 row, 1.2M faces).
// --write-glb writes the largest mesh (bunny00 x16, 1.2M faces) as a plain GLB, the input of
// `/usr/bin/time -v seamd seam PATH out.glb` for the whole job's stage timings and peak RSS.
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <unordered_map>

#include "api/gltf_reader.h"
#include "api/gltf_writer.h"
#include "api/mesh_io.h"
#include "api/surface.h"
#include "bench_util.h"

namespace {

using namespace seam;
using Clock = std::chrono::steady_clock;

double ms(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

core::IndexedMesh subdivide(const core::IndexedMesh& in) {
  core::IndexedMesh out{in.positions, {}};
  std::unordered_map<std::uint64_t, std::uint32_t> mid;
  auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
    const std::uint64_t key = (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
    auto [it, inserted] = mid.try_emplace(key, static_cast<std::uint32_t>(out.positions.size()));
    if (inserted) out.positions.push_back(0.5 * (in.positions[a] + in.positions[b]));
    return it->second;
  };
  for (const auto& t : in.triangles) {
    const auto a = midpoint(t[0], t[1]), b = midpoint(t[1], t[2]), c = midpoint(t[2], t[0]);
    out.triangles.push_back({t[0], a, c});
    out.triangles.push_back({t[1], b, a});
    out.triangles.push_back({t[2], c, b});
    out.triangles.push_back({a, b, c});
  }
  return out;
}

template <class F>
double best_of(int runs, F&& f) {
  double best = 1e300;
  for (int i = 0; i < runs; ++i) {
    const auto t = Clock::now();
    f();
    best = std::min(best, ms(t));
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  seam::bench::run_as_deployed(argv);
  bool quick = false;
  bool glb_only = false;
  const char* write_path = nullptr;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0) quick = true;
    if (std::strcmp(argv[i], "--glb-only") == 0) glb_only = true;
    if (std::strcmp(argv[i], "--write-glb") == 0 && i + 1 < argc) write_path = argv[++i];
  }
  struct Input {
    const char* name;
    int levels;
  };
  const Input inputs[] = {{"elephant", 2}, {"bunny00", quick ? 1 : 2}};
  std::printf("%-14s %9s %6s %11s %10s %10s %10s %12s %6s\n", "mesh", "faces", "format", "bytes", "encode_ms", "load_ms",
              "weld_ms", "cut_write_ms", "/0.3s");
  for (const auto& input : inputs) {
    auto loaded = api::read_mesh_file(std::string(SEAM_TEST_DATA_DIR) + "/meshes/" + input.name + ".off");
    if (!loaded.ok()) {
      std::fprintf(stderr, "missing %s: run scripts/fetch-test-data.sh\n", input.name);
      return 1;
    }
    core::IndexedMesh mesh = std::move(loaded).value();
    for (int l = 0; l < input.levels; ++l) mesh = subdivide(mesh);
    if (write_path && &input == &inputs[std::size(inputs) - 1]) {
      const std::string glb = std::move(api::write_plain_glb(mesh, {}, false)).value();
      std::ofstream(write_path, std::ios::binary).write(glb.data(), static_cast<std::streamsize>(glb.size()));
      std::printf("wrote %s: %zu faces, %zu bytes\n", write_path, mesh.triangles.size(), glb.size());
      return 0;
    }
    for (bool draco : {false, true}) {
      if (draco && glb_only) continue;
      const int runs = draco && mesh.triangles.size() > 500000 ? 1 : 3;
      std::string glb;
      const double encode_ms = best_of(runs, [&] { glb = std::move(api::write_plain_glb(mesh, {}, draco)).value(); });
      api::GltfDocument doc;
      api::PrimitiveData prim;
      api::ReadLimits limits;
      const double load_ms = best_of(runs, [&] {
        doc = std::move(api::parse_asset(glb, api::AssetKind::kGlb, limits)).value();
        prim = std::move(api::read_primitive(doc, 0, 0, limits)).value();
      });
      // The job's whole weld stage (timings_ms.weld): weld, canonical numbering, build (repair
      // only if the builder refuses), topology.
      const double weld_ms = best_of(runs, [&] {
        auto surface = api::prepare_surface(prim, api::SeamParams{}, core::CancelToken::none());
        if (!surface.ok()) std::fprintf(stderr, "weld stage failed: %s\n", surface.error().message.c_str());
      });
      // The cut asset writer with an identity cut plus a UV set: the encode stage of a request.
      api::CutPrimitive cut;
      cut.source_vertex.resize(prim.mesh.positions.size());
      for (std::uint32_t v = 0; v < cut.source_vertex.size(); ++v) cut.source_vertex[v] = v;
      cut.triangles = prim.mesh.triangles;
      cut.uv.assign(cut.source_vertex.size(), {0.25f, 0.75f});
      const api::ReplacedPrimitive replaced{0, 0, &prim, &cut, draco};
      const double cut_ms = best_of(runs, [&] { (void)api::write_cut_asset(doc, std::span(&replaced, 1)); });
      std::printf("%-14s %9zu %6s %11zu %10.1f %10.1f %10.1f %12.1f %6.2f\n", input.name, mesh.triangles.size(),
                  draco ? "draco" : "glb", glb.size(), encode_ms, load_ms, weld_ms, cut_ms, cut_ms / 300.0);
      std::fflush(stdout);
    }
  }
  return 0;
}
