#include "api/sample_mesh.h"

#include <cmath>
#include <map>
#include <numbers>

#include "api/gltf_writer.h"

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

// The unit icosphere (same construction as tests/fixtures.h, kept here so the library does
// not depend on test code).
core::IndexedMesh icosphere(int levels) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  core::IndexedMesh s;
  for (auto p : {core::Vec3(-1, t, 0), core::Vec3(1, t, 0), core::Vec3(-1, -t, 0), core::Vec3(1, -t, 0),
                 core::Vec3(0, -1, t), core::Vec3(0, 1, t), core::Vec3(0, -1, -t), core::Vec3(0, 1, -t),
                 core::Vec3(t, 0, -1), core::Vec3(t, 0, 1), core::Vec3(-t, 0, -1), core::Vec3(-t, 0, 1)}) {
    s.positions.push_back(p.normalized());
  }
  s.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                 {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      const auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      const auto id = static_cast<std::uint32_t>(s.positions.size());
      s.positions.push_back((s.positions[a] + s.positions[b]).normalized());
      mid.emplace(key, id);
      return id;
    };
    std::vector<core::Triangle> next;
    for (const auto& tri : s.triangles) {
      const auto a = midpoint(tri[0], tri[1]);
      const auto b = midpoint(tri[1], tri[2]);
      const auto c = midpoint(tri[2], tri[0]);
      next.push_back({tri[0], a, c});
      next.push_back({tri[1], b, a});
      next.push_back({tri[2], c, b});
      next.push_back({a, b, c});
    }
    s.triangles = std::move(next);
  }
  return s;
}

}  // namespace

core::IndexedMesh sample_mesh() {
  core::IndexedMesh m = icosphere(4);
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
