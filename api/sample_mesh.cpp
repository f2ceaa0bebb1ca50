#include "api/sample_mesh.h"

#include <cmath>
#include <numbers>

#include "api/gltf_writer.h"
#include "core/mesh/icosphere.h"

namespace seam::api {
namespace {

constexpr int kArms = 5;
constexpr double kArmLength = 1.8;  // arm tip at 1 + kArmLength body radii
constexpr double kArmSharpness = 6; // higher: thinner arms
constexpr double kFlatten = 0.45;   // z scale of the body

core::Vec3 arm_direction(int k) {
  const double a = 2 * std::numbers::pi * k / kArms;
  return {std::cos(a), std::sin(a), 0};
}

}  // namespace

core::IndexedMesh sample_mesh() {
  core::IndexedMesh m = core::icosphere(4);
  for (auto& p : m.positions) {
    double scale = 1;
    for (int k = 0; k < kArms; ++k) scale += kArmLength * std::pow(std::max(0.0, p.dot(arm_direction(k))), kArmSharpness);
    p *= scale;
    p.z() *= kFlatten;
  }
  return m;
}

std::vector<std::uint32_t> sample_tips() {
  const core::IndexedMesh m = sample_mesh();
  std::vector<std::uint32_t> tips;
  for (int k = 0; k < kArms; ++k) {
    std::uint32_t best = 0;
    for (std::uint32_t v = 0; v < m.positions.size(); ++v) {
      if (m.positions[v].dot(arm_direction(k)) > m.positions[best].dot(arm_direction(k))) best = v;
    }
    tips.push_back(best);
  }
  return tips;
}

ApiResult<std::string> sample_glb() {
  const core::IndexedMesh m = sample_mesh();
  std::vector<core::Vec3> normals(m.positions.size(), core::Vec3::Zero());
  for (const auto& t : m.triangles) {
    // Area-weighted face normals summed per vertex.
    const core::Vec3 n = (m.positions[t[1]] - m.positions[t[0]]).cross(m.positions[t[2]] - m.positions[t[0]]);
    for (auto v : t) normals[v] += n;
  }
  std::vector<float> values;
  values.reserve(normals.size() * 3);
  for (auto& n : normals) {
    n.normalize();
    values.insert(values.end(), {static_cast<float>(n.x()), static_cast<float>(n.y()), static_cast<float>(n.z())});
  }
  return write_plain_glb(m, {make_float_attribute("NORMAL", 3, values)});
}

}  // namespace seam::api
