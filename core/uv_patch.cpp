#include "core/uv_patch.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace seam::core {

Result<std::vector<DiscPatch>> extract_disc_patches(const HalfedgeMesh& mesh, const Topology& topology) {
  const std::size_t num_components = topology.components.size();
  for (std::size_t c = 0; c < num_components; ++c) {
    const ComponentInfo& info = topology.components[c];
    if (info.euler_characteristic != 1 || info.boundary_loops != 1) {
      // Name one face so the caller can find the component.
      std::uint32_t face = 0;
      for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
        if (topology.face_component[FaceId(f)] == c) {
          face = static_cast<std::uint32_t>(f);
          break;
        }
      }
      return make_error(ErrorCode::kTopologyViolation,
                        "component " + std::to_string(c) + " (containing face " + std::to_string(face) +
                            ") is not a disc: Euler characteristic " + std::to_string(info.euler_characteristic) +
                            ", " + std::to_string(info.boundary_loops) +
                            " boundary loops; cut it open first (expected 1 and 1)",
                        {face});
    }
  }

  std::vector<DiscPatch> patches(num_components);
  std::vector<std::uint32_t> local(mesh.num_vertices(), VertexId::kInvalidValue);
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
    const std::uint32_t c = topology.vertex_component[VertexId(v)];
    if (c == VertexId::kInvalidValue) continue;  // isolated vertex: in no chart
    DiscPatch& p = patches[c];
    local[v] = static_cast<std::uint32_t>(p.positions.size());
    p.to_mesh.push_back(VertexId(v));
    p.positions.push_back(mesh.position(VertexId(v)));
  }
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    DiscPatch& p = patches[topology.face_component[FaceId(f)]];
    const auto vs = mesh.face_vertices(FaceId(f));
    p.triangles.push_back({local[vs[0].index()], local[vs[1].index()], local[vs[2].index()]});
    p.to_mesh_face.push_back(FaceId(f));
  }
  for (std::size_t l = 0; l < topology.boundary_loops.size(); ++l) {
    DiscPatch& p = patches[topology.boundary_loop_component[l]];
    // Boundary half-edges run clockwise around the disc (their twins belong to the
    // counter-clockwise faces), so the tails in reverse order are the counter-clockwise loop.
    const auto& loop = topology.boundary_loops[l];
    p.boundary.reserve(loop.size());
    for (auto it = loop.rbegin(); it != loop.rend(); ++it) p.boundary.push_back(local[mesh.tail(*it).index()]);
  }
  return patches;
}

Vec3 corner_angles(const DiscPatch& patch, std::size_t t) {
  const Triangle& tri = patch.triangles[t];
  Vec3 angles;
  for (int k = 0; k < 3; ++k) {
    const Vec3& p = patch.positions[tri[k]];
    const Vec3 a = patch.positions[tri[(k + 1) % 3]] - p;
    const Vec3 b = patch.positions[tri[(k + 2) % 3]] - p;
    // atan2 of |cross| and dot is accurate for angles near 0 and pi, unlike acos.
    angles[k] = std::atan2(a.cross(b).norm(), a.dot(b));
  }
  return angles;
}

Vec3 corner_cotans(const DiscPatch& patch, std::size_t t) {
  const Triangle& tri = patch.triangles[t];
  Vec3 cot;
  for (int k = 0; k < 3; ++k) {
    const Vec3& p = patch.positions[tri[k]];
    const Vec3 a = patch.positions[tri[(k + 1) % 3]] - p;
    const Vec3 b = patch.positions[tri[(k + 2) % 3]] - p;
    const double s = a.cross(b).norm();
    const double c = a.dot(b);
    double value = s > 0 ? c / s : (c >= 0 ? kCotanClamp : -kCotanClamp);
    cot[k] = std::clamp(value, -kCotanClamp, kCotanClamp);
  }
  return cot;
}

Eigen::SparseMatrix<double> cotan_laplacian(const DiscPatch& patch) {
  const auto n = static_cast<Eigen::Index>(patch.num_vertices());
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(patch.triangles.size() * 12);
  for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
    const Triangle& tri = patch.triangles[t];
    const Vec3 cot = corner_cotans(patch, t);
    for (int k = 0; k < 3; ++k) {
      // The corner k is opposite edge (k+1, k+2).
      const auto i = static_cast<Eigen::Index>(tri[(k + 1) % 3]);
      const auto j = static_cast<Eigen::Index>(tri[(k + 2) % 3]);
      const double w = 0.5 * cot[k];
      entries.emplace_back(i, j, -w);
      entries.emplace_back(j, i, -w);
      entries.emplace_back(i, i, w);
      entries.emplace_back(j, j, w);
    }
  }
  Eigen::SparseMatrix<double> laplacian(n, n);
  laplacian.setFromTriplets(entries.begin(), entries.end());
  return laplacian;
}

std::array<Vec2, 3> local_triangle_frame(const DiscPatch& patch, std::size_t t) {
  const Triangle& tri = patch.triangles[t];
  const Vec3 e1 = patch.positions[tri[1]] - patch.positions[tri[0]];
  const Vec3 e2 = patch.positions[tri[2]] - patch.positions[tri[0]];
  const double l1 = e1.norm();
  const Vec3 x = l1 > 0 ? Vec3(e1 / l1) : Vec3(1, 0, 0);
  const double ex = e2.dot(x);
  const double ey = (e2 - ex * x).norm();
  return {Vec2(0, 0), Vec2(l1, 0), Vec2(ex, ey)};
}

}  // namespace seam::core
