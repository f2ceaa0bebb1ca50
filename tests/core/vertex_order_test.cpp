// Spatial (Z-order) vertex numbering: a permutation, independent of the input order, and
// local: mesh neighbours get close numbers.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdlib>
#include <numeric>
#include <random>

#include "core/mesh/vertex_order.h"
#include "fixtures.h"

namespace seam_vertex_order_test {

using namespace seam::core;
namespace fx = seam::fixtures;

namespace {

// Mean |new(a) - new(b)| over the edges of the triangles under the numbering `rank`.
double mean_edge_span(const fx::Soup& s, const std::vector<std::uint32_t>& rank) {
  double sum = 0;
  std::size_t count = 0;
  for (const auto& t : s.triangles) {
    for (int k = 0; k < 3; ++k) {
      sum += std::abs(static_cast<double>(rank[t[k]]) - static_cast<double>(rank[t[(k + 1) % 3]]));
      ++count;
    }
  }
  return sum / static_cast<double>(count);
}

}  // namespace

TEST_CASE("spatial_order is a permutation that does not depend on the input order") {
  const fx::Soup sphere = fx::icosphere(4);
  const std::vector<std::uint32_t> order = spatial_order(sphere.positions);
  REQUIRE(order.size() == sphere.positions.size());
  std::vector<std::uint32_t> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (std::uint32_t i = 0; i < sorted.size(); ++i) CHECK(sorted[i] == i);

  std::vector<std::uint32_t> shuffle(sphere.positions.size());
  std::iota(shuffle.begin(), shuffle.end(), 0u);
  std::mt19937 rng(7);
  std::shuffle(shuffle.begin(), shuffle.end(), rng);
  std::vector<Vec3> shuffled;
  for (std::uint32_t i : shuffle) shuffled.push_back(sphere.positions[i]);
  const std::vector<std::uint32_t> order2 = spatial_order(shuffled);
  for (std::size_t k = 0; k < order.size(); ++k) CHECK(shuffled[order2[k]] == sphere.positions[order[k]]);
}

TEST_CASE("mesh neighbours get close numbers") {
  const fx::Soup sphere = fx::icosphere(5);  // 10k vertices, numbered by subdivision level
  const std::size_t n = sphere.positions.size();
  const std::vector<std::uint32_t> order = spatial_order(sphere.positions);
  std::vector<std::uint32_t> z_rank(n), random_rank(n), identity(n);
  for (std::uint32_t k = 0; k < n; ++k) z_rank[order[k]] = k;
  std::iota(identity.begin(), identity.end(), 0u);
  random_rank = identity;
  std::mt19937 rng(11);
  std::shuffle(random_rank.begin(), random_rank.end(), rng);
  const double z = mean_edge_span(sphere, z_rank);
  const double input = mean_edge_span(sphere, identity);
  const double random = mean_edge_span(sphere, random_rank);
  MESSAGE("mean edge span: Z-order ", z, ", subdivision order ", input, ", random ", random);
  CHECK(z < 0.1 * random);
  CHECK(z < input);
}

TEST_CASE("degenerate inputs: empty, one point, all points equal") {
  CHECK(spatial_order(std::vector<Vec3>{}).empty());
  CHECK(spatial_order(std::vector<Vec3>{Vec3(1, 2, 3)}) == std::vector<std::uint32_t>{0});
  const std::vector<Vec3> same(5, Vec3(1, 1, 1));
  CHECK(spatial_order(same) == std::vector<std::uint32_t>{0, 1, 2, 3, 4});
}

TEST_CASE("the order is the documented one: by code, then (x, y, z), then index, with many ties") {
  // Points on a coarse lattice with repeats and sub-grid offsets, so that many vertices share a
  // Morton code (ties broken by position, then by index) and many codes share their low bytes.
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> cell(0, 40), sub(0, 3);
  std::vector<Vec3> points;
  for (int i = 0; i < 20000; ++i) {
    points.emplace_back(cell(rng) + 1e-9 * sub(rng), cell(rng) + 1e-9 * sub(rng), cell(rng));
  }
  points.emplace_back(1000, 1000, 1000);  // stretches the box so cells share codes
  const std::vector<std::uint32_t> order = spatial_order(points);

  // The reference: the comparison the header documents, by std::sort.
  Vec3 lo = points[0], hi = points[0];
  for (const Vec3& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double scale = static_cast<double>((1u << 21) - 1) / (hi - lo).maxCoeff();
  auto code = [&](const Vec3& p) {
    std::uint64_t c = 0;
    const Vec3 q = (p - lo) * scale;
    const std::uint64_t x = static_cast<std::uint64_t>(q.x()), y = static_cast<std::uint64_t>(q.y()),
                        z = static_cast<std::uint64_t>(q.z());
    for (int b = 0; b < 21; ++b) c |= ((x >> b) & 1) << (3 * b) | ((y >> b) & 1) << (3 * b + 1) | ((z >> b) & 1) << (3 * b + 2);
    return c;
  };
  std::vector<std::uint32_t> expected(points.size());
  std::iota(expected.begin(), expected.end(), 0u);
  std::sort(expected.begin(), expected.end(), [&](std::uint32_t a, std::uint32_t b) {
    const std::uint64_t ca = code(points[a]), cb = code(points[b]);
    if (ca != cb) return ca < cb;
    const Vec3& p = points[a];
    const Vec3& q = points[b];
    if (p.x() != q.x()) return p.x() < q.x();
    if (p.y() != q.y()) return p.y() < q.y();
    if (p.z() != q.z()) return p.z() < q.z();
    return a < b;
  });
  CHECK(order == expected);
}

TEST_CASE("rotated_to_smallest starts a face at its first smallest vertex and keeps the winding") {
  CHECK(rotated_to_smallest({4, 2, 7}) == Triangle{2, 7, 4});
  CHECK(rotated_to_smallest({1, 5, 3}) == Triangle{1, 5, 3});
  CHECK(rotated_to_smallest({9, 8, 0}) == Triangle{0, 9, 8});
  // Ties (degenerate faces): the first smallest corner, as std::min_element finds it.
  CHECK(rotated_to_smallest({2, 1, 1}) == Triangle{1, 1, 2});
  CHECK(rotated_to_smallest({1, 3, 1}) == Triangle{1, 3, 1});
  CHECK(rotated_to_smallest({5, 5, 5}) == Triangle{5, 5, 5});
}

TEST_CASE("sort_triangles is std::stable_sort on the triples, with repeats and a crowded first vertex") {
  // Random triples over few vertices (so triples repeat and share their first vertex), plus a
  // vertex that starts 200 triangles (its bucket takes the large-bucket branch).
  std::mt19937 rng(9);
  std::uniform_int_distribution<std::uint32_t> vertex(0, 30);
  std::vector<Triangle> triangles;
  for (int i = 0; i < 5000; ++i) triangles.push_back({vertex(rng), vertex(rng), vertex(rng)});
  for (int i = 0; i < 200; ++i) triangles.push_back({31, vertex(rng) % 4, vertex(rng) % 4});
  std::shuffle(triangles.begin(), triangles.end(), rng);

  std::vector<std::uint32_t> expected(triangles.size());
  std::iota(expected.begin(), expected.end(), 0u);
  std::stable_sort(expected.begin(), expected.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return triangles[a] < triangles[b]; });
  std::vector<Triangle> sorted = triangles;
  CHECK(sort_triangles(sorted, 33) == expected);  // vertex 32 starts none: an empty last bucket
  for (std::size_t i = 0; i < sorted.size(); ++i) CHECK(sorted[i] == triangles[expected[i]]);

  std::vector<Triangle> none;
  CHECK(sort_triangles(none, 0).empty());
}

}  // namespace seam_vertex_order_test
