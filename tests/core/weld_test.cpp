#include <doctest/doctest.h>

#include <map>
#include <random>
#include <tuple>

#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/topology.h"
#include "core/mesh/weld.h"
#include "fixtures.h"

namespace seam_weld_test {

using namespace seam::core;
namespace fx = seam::fixtures;

TEST_CASE("exact welding sees through an exporter's UV seam") {
  const auto split = fx::uv_sphere(16, 8, true);
  const auto joined = fx::uv_sphere(16, 8, false);
  REQUIRE(split.positions.size() == joined.positions.size() + 7);

  auto unwelded = build_halfedge_mesh(split.positions, split.triangles);
  REQUIRE(unwelded.ok());
  const Topology before = compute_topology(*unwelded);
  CHECK(before.components.size() == 1);
  CHECK(before.components[0].boundary_loops == 1);
  CHECK(before.components[0].euler_characteristic == 1);

  auto weld = weld_vertices(split.positions, {});
  REQUIRE(weld.ok());
  CHECK(weld->positions.size() == joined.positions.size());
  const auto tris = remap_triangles(split.triangles, weld->input_to_welded);
  auto welded = build_halfedge_mesh(weld->positions, tris);
  REQUIRE(welded.ok());
  const Topology after = compute_topology(*welded);
  CHECK(after.components[0].boundary_loops == 0);
  CHECK(after.components[0].euler_characteristic == 2);
  CHECK(after.components[0].genus == 0);
}

TEST_CASE("the representative of a welded vertex is its smallest input index") {
  std::vector<Vec3> p = {Vec3(1, 0, 0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 0, -0.0), Vec3(2, 0, 0)};
  auto weld = weld_vertices(p, {});
  REQUIRE(weld.ok());
  CHECK(weld->welded_to_input == std::vector<std::uint32_t>{0, 1, 4});
  CHECK(weld->input_to_welded == std::vector<std::uint32_t>{0, 1, 0, 1, 2});
}

TEST_CASE("epsilon welding merges near vertices transitively and nothing farther") {
  std::vector<Vec3> p = {Vec3(0, 0, 0), Vec3(0.0009, 0, 0), Vec3(0.0018, 0, 0), Vec3(0.01, 0, 0)};
  auto exact = weld_vertices(p, {});
  REQUIRE(exact.ok());
  CHECK(exact->positions.size() == 4);
  auto near = weld_vertices(p, {.epsilon = 0.001});
  REQUIRE(near.ok());
  CHECK(near->positions.size() == 2);
  CHECK(near->input_to_welded == std::vector<std::uint32_t>{0, 0, 0, 1});
}

TEST_CASE("epsilon welding agrees with brute force on a jittered cloud") {
  std::vector<Vec3> p;
  std::uint64_t state = 12345;
  auto rnd = [&] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) / static_cast<double>(1ULL << 53);
  };
  for (int i = 0; i < 400; ++i) p.emplace_back(rnd(), rnd(), rnd() * 0.1);
  const double eps = 0.03;
  auto weld = weld_vertices(p, {.epsilon = eps});
  REQUIRE(weld.ok());
  // Brute force: connected components of the "closer than eps" graph.
  std::vector<std::uint32_t> label(p.size());
  for (std::uint32_t i = 0; i < p.size(); ++i) label[i] = i;
  bool changed = true;
  while (changed) {
    changed = false;
    for (std::size_t i = 0; i < p.size(); ++i) {
      for (std::size_t j = 0; j < p.size(); ++j) {
        if ((p[i] - p[j]).norm() < eps && label[j] < label[i]) {
          label[i] = label[j];
          changed = true;
        }
      }
    }
  }
  for (std::size_t i = 0; i < p.size(); ++i) {
    CHECK(weld->welded_to_input[weld->input_to_welded[i]] == label[i]);
  }
}

TEST_CASE("welding rejects bad input with typed errors") {
  std::vector<Vec3> p = {Vec3(0, 0, 0), Vec3(std::nan(""), 0, 0)};
  auto r = weld_vertices(p, {});
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == ErrorCode::kNonFinitePosition);
  CHECK(r.error().elements == std::vector<std::uint32_t>{1});
  auto negative = weld_vertices(std::vector<Vec3>{Vec3(0, 0, 0)}, {.epsilon = -1.0});
  REQUIRE_FALSE(negative.ok());
  CHECK(negative.error().code == ErrorCode::kInvalidArgument);
  auto nan_eps = weld_vertices(std::vector<Vec3>{Vec3(0, 0, 0)}, {.epsilon = std::nan("")});
  REQUIRE_FALSE(nan_eps.ok());
  CHECK(nan_eps.error().code == ErrorCode::kInvalidArgument);
}

TEST_CASE("remapping keeps an out-of-range index out of range for the builder") {
  const std::vector<Triangle> tris = {{0, 1, 7}};
  const std::vector<std::uint32_t> map = {0, 0, 1};
  const auto out = remap_triangles(tris, map);
  CHECK(out[0][0] == 0);
  CHECK(out[0][2] == VertexId::kInvalidValue);
}

TEST_CASE("exact welding numbers vertices as a brute-force std::map weld does") {
  // Many repeats (with -0.0 and +0.0 mixed) in random order: the numbering must be the order
  // of first occurrence and the representative the smallest input index.
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> pick(-30, 30);
  std::vector<Vec3> points;
  for (int i = 0; i < 50000; ++i) {
    const int x = pick(rng);
    points.emplace_back(x == 0 && i % 2 ? -0.0 : 0.25 * x, 0.5 * pick(rng) / 8, 0.0);
  }
  const WeldResult weld = weld_vertices(points, {}).value();
  std::map<std::tuple<double, double, double>, std::uint32_t> seen;
  std::vector<std::uint32_t> expected_welded_to_input;
  for (std::uint32_t i = 0; i < points.size(); ++i) {
    const auto key = std::make_tuple(points[i].x() + 0.0, points[i].y() + 0.0, points[i].z() + 0.0);
    const auto [it, inserted] = seen.try_emplace(key, static_cast<std::uint32_t>(seen.size()));
    if (inserted) expected_welded_to_input.push_back(i);
    REQUIRE(weld.input_to_welded[i] == it->second);
  }
  CHECK(weld.welded_to_input == expected_welded_to_input);
  CHECK(weld.positions.size() == seen.size());
}

}  // namespace seam_weld_test
