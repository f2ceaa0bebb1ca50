#include "core/atlas/features.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "core/mesh/cut.h"
#include "core/timing.h"

namespace seam::core {

namespace {

Vec3 face_normal(const HalfedgeMesh& mesh, FaceId f) {
  const auto v = mesh.face_vertices(f);
  return (mesh.position(v[1]) - mesh.position(v[0])).cross(mesh.position(v[2]) - mesh.position(v[0]));
}

double bounding_diagonal(const HalfedgeMesh& mesh) {
  if (mesh.num_vertices() == 0) return 0;
  Vec3 lo = mesh.position(VertexId(std::uint32_t{0}));
  Vec3 hi = lo;
  for (const Vec3& p : mesh.positions()) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return (hi - lo).norm();
}

// Removes dangling pieces shorter than max_length; returns how many edges it removed.
std::size_t prune_dangling(const HalfedgeMesh& mesh, std::vector<std::uint8_t>& feature, double max_length) {
  const std::size_t nv = mesh.num_vertices();
  std::size_t removed = 0;
  auto degree = [&](VertexId v) {
    int d = 0;
    mesh.for_each_outgoing(v, [&](HalfedgeId h) { d += feature[HalfedgeMesh::edge(h).index()] ? 1 : 0; });
    return d;
  };
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t i = 0; i < nv; ++i) {
      const VertexId start(i);
      if (mesh.is_boundary(start) || degree(start) != 1) continue;
      // Walk the chain while it passes through interior vertices of feature degree 2.
      std::vector<EdgeId> chain;
      double length = 0;
      VertexId v = start;
      EdgeId came = EdgeId::invalid();
      while (true) {
        HalfedgeId next = HalfedgeId::invalid();
        mesh.for_each_outgoing(v, [&](HalfedgeId h) {
          const EdgeId e = HalfedgeMesh::edge(h);
          if (feature[e.index()] && e != came && !next.valid()) next = h;
        });
        if (!next.valid()) break;
        came = HalfedgeMesh::edge(next);
        chain.push_back(came);
        length += mesh.edge_length(came);
        v = mesh.head(next);
        if (v == start || mesh.is_boundary(v) || degree(v) != 2 || length >= max_length) break;
      }
      if (length >= max_length) continue;
      for (EdgeId e : chain) feature[e.index()] = 0;
      removed += chain.size();
      changed = true;
    }
  }
  return removed;
}

// Removes every lone edge: both ends interior and on no other feature. Cutting cannot open it
// (cut_along_edges refuses the slit, is_slit), however long it is. Returns how many it removed.
std::size_t drop_lone_edges(const HalfedgeMesh& mesh, std::vector<std::uint8_t>& feature) {
  const std::vector<std::uint32_t> degree = cut_degrees(mesh, feature);
  std::size_t removed = 0;
  for (std::size_t e = 0; e < feature.size(); ++e) {
    if (!feature[e] || !is_slit(mesh, degree, EdgeId(e))) continue;
    feature[e] = 0;  // its ends had no other feature, so no other edge's test changes
    ++removed;
  }
  return removed;
}

}  // namespace

Result<FeatureEdges> find_feature_edges(const HalfedgeMesh& mesh, const FeatureOptions& options,
                                        const CancelToken& cancel) {
  const auto start = StageClock::now();
  if (!(options.feature_angle_deg >= 0 && options.feature_angle_deg <= 180)) {
    return make_error(ErrorCode::kInvalidArgument,
                      "feature_angle_deg must be in 0..180, got " + std::to_string(options.feature_angle_deg));
  }
  if (!(options.max_dangling_fraction >= 0 && options.max_dangling_fraction <= 1)) {
    return make_error(ErrorCode::kInvalidArgument, "max_dangling_fraction must be in 0..1");
  }
  const double cos_limit = std::cos(options.feature_angle_deg * std::numbers::pi / 180);
  std::vector<std::uint8_t> feature(mesh.num_edges(), 0);
  FeatureEdges out;
  std::uint32_t poll = 0;
  for (std::size_t i = 0; i < mesh.num_edges(); ++i) {
    if (cancel.poll(poll)) return cancelled_error("find_feature_edges");
    const EdgeId e(i);
    if (mesh.is_boundary(e)) continue;
    const Vec3 n0 = face_normal(mesh, mesh.face(HalfedgeMesh::halfedge(e, 0)));
    const Vec3 n1 = face_normal(mesh, mesh.face(HalfedgeMesh::halfedge(e, 1)));
    const double l0 = n0.norm();
    const double l1 = n1.norm();
    if (!(l0 > 0) || !(l1 > 0)) continue;
    // Angle between the normals above the limit <=> its cosine below cos(limit).
    if (n0.dot(n1) / (l0 * l1) < cos_limit) {
      feature[i] = 1;
      ++out.sharp;
    }
  }
  if (options.max_dangling_fraction > 0 && out.sharp > 0) {
    const double max_length = options.max_dangling_fraction >= 1 ? std::numeric_limits<double>::infinity()
                                                                  : options.max_dangling_fraction * bounding_diagonal(mesh);
    out.pruned = prune_dangling(mesh, feature, max_length);
  }
  out.pruned += drop_lone_edges(mesh, feature);
  for (std::size_t i = 0; i < feature.size(); ++i) {
    if (feature[i]) out.edges.push_back(EdgeId(i));
  }
  out.ms = ms_since(start);
  return out;
}

}  // namespace seam::core
