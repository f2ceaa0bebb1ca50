// Meshes with protrusions for the skeleton seam's tests and benchmarks, and the
// deterministic extremum rule used on real meshes (farthest-point sampling).
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/paths/geodesic.h"
#include "core/mesh/halfedge_mesh.h"
#include "fixtures.h"

namespace seam::fixtures {

/// `n` well-spread unit directions (a Fibonacci spiral), deterministic.
inline std::vector<Vec3> spread_directions(int n) {
  std::vector<Vec3> dirs;
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double y = 1.0 - 2.0 * (i + 0.5) / n;
    const double r = std::sqrt(std::max(0.0, 1.0 - y * y));
    dirs.emplace_back(r * std::cos(golden * i), y, r * std::sin(golden * i));
  }
  return dirs;
}

/// An icosphere with a smooth radial spike along each direction: a vertex at angle a < width
/// from a direction moves out to radius 1 + height * (1 - a / width)^2. Radial moves keep it a
/// closed embedded genus-0 surface. The spike tips are the vertices nearest the directions.
struct SpikySphere {
  Soup soup;
  std::vector<std::uint32_t> tips;
};

inline SpikySphere spiky_sphere(int levels, const std::vector<Vec3>& directions, double height = 1.5,
                                double width = 0.45) {
  SpikySphere s{icosphere(levels), {}};
  for (auto& p : s.soup.positions) {
    double scale = 1.0;
    for (const Vec3& d : directions) {
      const double a = std::acos(std::clamp(p.dot(d.normalized()), -1.0, 1.0));
      if (a < width) scale = std::max(scale, 1.0 + height * (1.0 - a / width) * (1.0 - a / width));
    }
    p *= scale;
  }
  for (const Vec3& d : directions) {
    std::uint32_t best = 0;
    for (std::uint32_t v = 0; v < s.soup.positions.size(); ++v) {
      if (s.soup.positions[v].normalized().dot(d.normalized()) >
          s.soup.positions[best].normalized().dot(d.normalized())) {
        best = v;
      }
    }
    s.tips.push_back(best);
  }
  return s;
}

/// Farthest-point sampling on the edge graph: the first extremum is the vertex farthest from
/// vertex 0, each next one the vertex farthest from those chosen (ties: lowest id).
inline std::vector<core::VertexId> farthest_point_extrema(const core::HalfedgeMesh& mesh,
                                                          const core::EdgeGraph& graph, std::size_t count) {
  using core::VertexId;
  std::vector<VertexId> chosen;
  std::vector<VertexId> sources = {VertexId(0u)};
  for (std::size_t i = 0; i < count; ++i) {
    auto tree = core::dijkstra(graph, sources);
    if (!tree.ok()) break;
    VertexId far(0u);
    for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
      const double d = tree->distance[v];
      if (d != core::ShortestPathTree::kUnreached && d > tree->distance[far.index()]) far = VertexId(v);
    }
    chosen.push_back(far);
    if (i == 0) sources.clear();
    sources.push_back(far);
  }
  return chosen;
}

}  // namespace seam::fixtures
