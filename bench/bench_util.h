// Shared by the benchmarks: timing, real-mesh loading, subdivision to large sizes.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "api/mesh_io.h"
#include "api/process_env.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/types.h"
#include "core/mesh/vertex_order.h"
#include "core/mesh/weld.h"

namespace seam::bench {

// Every benchmark measures the process environment the service runs under
// (api/process_env.h: no OpenBLAS thread pool): executes the benchmark again with it if need be.
inline void run_as_deployed(char** argv) { api::reexec_with(api::ProcessEnv{}, argv); }

/// Wall milliseconds taken by f(), best of `repeats` runs (the minimum filters scheduler noise).
template <class F>
double best_ms(int repeats, F&& f) {
  double best = 1e300;
  for (int i = 0; i < repeats; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    const auto t1 = std::chrono::steady_clock::now();
    best = std::min(best, std::chrono::duration<double, std::milli>(t1 - t0).count());
  }
  return best;
}

/// CGAL's `name`.off from the test-data cache; exits with a hint when it is missing.
inline core::IndexedMesh load_cgal(const std::string& name) {
  const std::string path = std::string(SEAM_TEST_DATA_DIR) + "/meshes/" + name + ".off";
  auto mesh = api::read_mesh_file(path);
  if (!mesh.ok()) {
    std::fprintf(stderr, "cannot load %s (%s): run scripts/fetch-test-data.sh\n", path.c_str(),
                 mesh.error().message.c_str());
    std::exit(1);
  }
  return std::move(mesh).value();
}

/// One 1-to-4 midpoint subdivision (shared midpoints, so the topology is kept).
inline core::IndexedMesh subdivide(const core::IndexedMesh& in) {
  core::IndexedMesh out;
  out.positions = in.positions;
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
  auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
    const auto key = std::minmax(a, b);
    auto [it, inserted] = mid.try_emplace(key, static_cast<std::uint32_t>(out.positions.size()));
    if (inserted) out.positions.push_back(0.5 * (in.positions[a] + in.positions[b]));
    return it->second;
  };
  out.triangles.reserve(4 * in.triangles.size());
  for (const auto& t : in.triangles) {
    const auto a = midpoint(t[0], t[1]);
    const auto b = midpoint(t[1], t[2]);
    const auto c = midpoint(t[2], t[0]);
    out.triangles.push_back({t[0], a, c});
    out.triangles.push_back({t[1], b, a});
    out.triangles.push_back({t[2], c, b});
    out.triangles.push_back({a, b, c});
  }
  return out;
}

/// The mesh renumbered along a Z-order curve (core::spatial_order), as the service numbers
/// every mesh it receives (api/pipeline.cpp). Subdivided meshes otherwise keep each level's
/// new vertices after the old ones, which costs graph searches ~40% in cache misses.
inline core::IndexedMesh spatially_ordered(const core::IndexedMesh& m) {
  const std::vector<std::uint32_t> order = core::spatial_order(m.positions);
  std::vector<std::uint32_t> rank(order.size());
  core::IndexedMesh z;
  z.positions.reserve(order.size());
  for (std::uint32_t k = 0; k < order.size(); ++k) {
    rank[order[k]] = k;
    z.positions.push_back(m.positions[order[k]]);
  }
  z.triangles.reserve(m.triangles.size());
  for (const auto& t : m.triangles) z.triangles.push_back({rank[t[0]], rank[t[1]], rank[t[2]]});
  return z;
}

/// spatially_ordered, and the triangles numbered as the service numbers them too (api/surface.cpp,
/// canonicalize): each rotated to start at its smallest vertex, winding kept, then sorted by
/// their vertex triples. The triangles' order changes the floating-point order of every sum over
/// them, and SLIM's contact-limited descent is sensitive to that: camel x64's coarse chart ended
/// at energy 4.36 in subdivision order and stalled at 5.99 in this one before issue 14's fix
/// of held vertices (core/uv/slim.cpp, add_contacts). Benchmarks of the flattening use this.
inline core::IndexedMesh service_numbered(const core::IndexedMesh& m) {
  core::IndexedMesh z = spatially_ordered(m);
  for (auto& t : z.triangles) t = core::rotated_to_smallest(t);
  core::sort_triangles(z.triangles, z.positions.size());
  return z;
}

/// Welds (exactly) and builds the half-edge mesh; exits with a message if the builder refuses.
inline core::HalfedgeMesh build_welded(const core::IndexedMesh& soup) {
  auto weld = core::weld_vertices(soup.positions, {});
  const auto tris = core::remap_triangles(soup.triangles, weld->input_to_welded);
  auto mesh = core::build_halfedge_mesh(weld->positions, tris);
  if (!mesh.ok()) {
    std::fprintf(stderr, "mesh: %s\n", mesh.error().message.c_str());
    std::exit(1);
  }
  return std::move(mesh).value();
}

/// Subdivides until the mesh has at least `min_faces` faces.
inline core::IndexedMesh subdivide_to(core::IndexedMesh mesh, std::size_t min_faces) {
  while (mesh.triangles.size() < min_faces) mesh = subdivide(mesh);
  return mesh;
}

}  // namespace seam::bench
