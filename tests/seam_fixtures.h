// Meshes with protrusions and their tip vertices, for the seam tests and benchmarks, plus the
// deterministic extrema rule used on real meshes (farthest-point sampling along edges).
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/paths/geodesic.h"
#include "core/mesh/halfedge_mesh.h"
#include "fixtures.h"

namespace seam::fixtures {

/// A soup with the vertices at the ends of its protrusions.
struct Protrusions {
  Soup soup;
  std::vector<std::uint32_t> tips;
};

/// A unit icosphere pushed out along each of `directions`: a vertex at angle a from a
/// direction moves out by height * profile(a / width), with profile 1 on a plateau (a
/// cylinder-like finger when `plateau` is true) or a smooth cosine bump otherwise. The tip is
/// the vertex farthest from the origin within each bump. Genus 0, closed.
inline Protrusions bumpy_sphere(const std::vector<Vec3>& directions, double height, double width, int levels,
                                bool plateau = false) {
  Protrusions out{icosphere(levels), {}};
  std::vector<Vec3> base = out.soup.positions;
  for (std::size_t v = 0; v < base.size(); ++v) {
    double scale = 1.0;
    for (const Vec3& d : directions) {
      const double a = std::acos(std::clamp(base[v].dot(d.normalized()), -1.0, 1.0)) / width;
      if (a >= 1.0) continue;
      const double profile = plateau ? (a < 0.6 ? 1.0 : 0.5 + 0.5 * std::cos(std::numbers::pi * (a - 0.6) / 0.4))
                                     : 0.5 + 0.5 * std::cos(std::numbers::pi * a);
      // Along the finger the radius also grows with the angle so the side walls are not
      // vertical (a plateau alone would give a mushroom cap, not a finger).
      scale = std::max(scale, 1.0 + height * profile * (plateau ? (1.0 - 0.3 * a) : 1.0));
    }
    out.soup.positions[v] = base[v] * scale;
  }
  for (const Vec3& d : directions) {
    std::uint32_t best = 0;
    double best_score = -1;
    for (std::size_t v = 0; v < base.size(); ++v) {
      const double score = out.soup.positions[v].dot(d.normalized());
      if (score > best_score) {
        best_score = score;
        best = static_cast<std::uint32_t>(v);
      }
    }
    out.tips.push_back(best);
  }
  return out;
}

/// An icosphere (levels >= 2) with k <= 12 thin spikes along the icosahedron's vertices.
inline Protrusions spiky_sphere(int k, int levels = 3) {
  const Soup ico = icosphere(0);
  std::vector<Vec3> dirs(ico.positions.begin(), ico.positions.begin() + k);
  return bumpy_sphere(dirs, 1.2, 0.35, levels);
}

/// A star-shaped blob: `arms` broad arms in the equatorial plane, tilted alternately.
inline Protrusions star_blob(int arms = 5, int levels = 3) {
  std::vector<Vec3> dirs;
  for (int i = 0; i < arms; ++i) {
    const double a = 2 * std::numbers::pi * i / arms;
    dirs.emplace_back(std::cos(a), std::sin(a), i % 2 ? 0.25 : -0.25);
  }
  return bumpy_sphere(dirs, 0.9, 0.6, levels);
}

/// A "hand": a palm with four parallel fingers and a thumb, each a cylinder-like plateau
/// protrusion of a sphere. Tips in order: thumb, index, middle, ring, little.
inline Protrusions hand(int levels = 4) {
  std::vector<Vec3> dirs = {Vec3(1, -0.2, 0.8), Vec3(0.45, 0, 1), Vec3(0.15, 0, 1), Vec3(-0.15, 0, 1),
                            Vec3(-0.45, 0, 1)};
  return bumpy_sphere(dirs, 1.6, 0.17, levels, true);
}

/// Deterministic extrema for real meshes: farthest-point sampling by edge-graph distance.
/// The first is the vertex farthest from vertex 0's component seed (the smallest non-isolated
/// vertex), each next one maximizes the distance to those already chosen (ties: smallest id).
/// On several components the distances to unreachable vertices are ignored (first component).
inline std::vector<core::VertexId> farthest_point_extrema(const core::HalfedgeMesh& mesh, std::size_t k) {
  using core::VertexId;
  const core::EdgeGraph graph = core::build_edge_graph(mesh);
  std::uint32_t seed = 0;
  while (seed < mesh.num_vertices() && mesh.is_isolated(VertexId(seed))) ++seed;
  auto farthest = [&](const std::vector<double>& d) {
    std::uint32_t best = seed;
    for (std::uint32_t v = 0; v < d.size(); ++v) {
      if (d[v] != core::ShortestPathTree::kUnreached && d[v] > d[best]) best = v;
    }
    return best;
  };
  std::vector<VertexId> out;
  const VertexId s0[] = {VertexId(seed)};
  auto first = core::dijkstra(graph, s0);
  if (!first.ok()) return out;
  out.push_back(VertexId(farthest(first->distance)));
  while (out.size() < k) {
    auto tree = core::dijkstra(graph, out);
    if (!tree.ok()) break;
    const std::uint32_t next = farthest(tree->distance);
    if (tree->distance[next] == 0) break;
    out.push_back(VertexId(next));
  }
  return out;
}

}  // namespace seam::fixtures
