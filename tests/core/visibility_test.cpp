// Visibility by ray casting (core/visibility): what a camera sees, what the mesh hides from
// it, how open each face is, and the edge multipliers a hidden seam uses.
#include "core/visibility/visibility.h"

#include <doctest/doctest.h>

#include <limits>

#include "core/mesh/halfedge_mesh.h"
#include "fixture_mesh.h"
#include "fixtures.h"

namespace seam_visibility_test {

using namespace seam::core;
namespace fixtures = seam::fixtures;

namespace {

Vec3 normal(const HalfedgeMesh& m, FaceId f) {
  const auto c = m.face_vertices(f);
  return (m.position(c[1]) - m.position(c[0])).cross(m.position(c[2]) - m.position(c[0])).normalized();
}

Vec3 centroid(const HalfedgeMesh& m, FaceId f) {
  const auto c = m.face_vertices(f);
  return (m.position(c[0]) + m.position(c[1]) + m.position(c[2])) / 3.0;
}

}  // namespace

TEST_CASE("a camera looking down sees the top faces, at the cosine of their tilt, and nothing else") {
  const HalfedgeMesh cube = fixtures::build_fixture(fixtures::voxel_surface({{0, 0, 0}}));
  auto vis = compute_visibility(cube, VisibilityOptions{{Vec3(0, 0, -2)}});
  REQUIRE(vis.ok());
  for (std::uint32_t f = 0; f < cube.num_faces(); ++f) {
    const double up = normal(cube, FaceId(f)).z();
    CHECK(vis->seen[FaceId(f)] == doctest::Approx(std::max(0.0, up)));
  }
  CHECK(vis->rays == cube.num_faces());
  // A tilted view sees the top and two sides, each at its cosine.
  auto tilted = compute_visibility(cube, VisibilityOptions{{Vec3(-1, -1, -1)}});
  REQUIRE(tilted.ok());
  const Vec3 to_camera = Vec3(1, 1, 1).normalized();
  for (std::uint32_t f = 0; f < cube.num_faces(); ++f) {
    CHECK(tilted->seen[FaceId(f)] == doctest::Approx(std::max(0.0, normal(cube, FaceId(f)).dot(to_camera))));
  }
}

TEST_CASE("what the mesh hides is not seen, and a narrow gap is not open") {
  // Two unit cubes one above the other with a gap of one unit between them.
  const HalfedgeMesh two = fixtures::build_fixture(fixtures::voxel_surface({{0, 0, 0}, {0, 0, 2}}));
  VisibilityOptions options{{Vec3(0, 0, -1)}};
  options.ambient_occlusion = true;
  options.ao_rays = 64;
  options.ao_distance = 0.5;
  auto vis = compute_visibility(two, options);
  REQUIRE(vis.ok());
  int hidden_tops = 0, seen_tops = 0;
  for (std::uint32_t f = 0; f < two.num_faces(); ++f) {
    const FaceId id(f);
    const Vec3 n = normal(two, id), c = centroid(two, id);
    if (n.z() > 0.5 && c.z() < 1.5) {  // the lower cube's top, under the upper cube
      CHECK(vis->seen[id] == 0.0);
      CHECK(vis->openness[id] < 0.9);  // the cube above covers about a quarter of its sky
      CHECK(vis->openness[id] > 0.5);
      ++hidden_tops;
    } else if (n.z() > 0.5) {  // the upper cube's top: in the open
      CHECK(vis->seen[id] == doctest::Approx(1.0));
      CHECK(vis->openness[id] == 1.0);
      ++seen_tops;
    }
  }
  CHECK(hidden_tops == 2);
  CHECK(seen_tops == 2);
  // The same with four threads: the same numbers.
  options.threads = 4;
  auto again = compute_visibility(two, options);
  REQUIRE(again.ok());
  CHECK(again->seen.raw() == vis->seen.raw());
  CHECK(again->openness.raw() == vis->openness.raw());
}

TEST_CASE("hiding multipliers: seen edges cost 1 + strength, unseen 1, silhouettes count as seen") {
  const HalfedgeMesh cube = fixtures::build_fixture(fixtures::voxel_surface({{0, 0, 0}}));
  auto vis = compute_visibility(cube, VisibilityOptions{{Vec3(0, 0, -1)}});
  REQUIRE(vis.ok());
  const std::vector<double> m = hiding_multipliers(cube, *vis, 4.0);
  REQUIRE(m.size() == cube.num_edges());
  for (std::uint32_t e = 0; e < cube.num_edges(); ++e) {
    const HalfedgeId h = HalfedgeMesh::halfedge(EdgeId(e));
    const double z = std::min(cube.position(cube.tail(h)).z(), cube.position(cube.head(h)).z());
    CHECK(m[e] == doctest::Approx(z == 1.0 ? 5.0 : 1.0));  // edges of the top square cost 5
  }
}

TEST_CASE("a view direction of any finite magnitude sees what its unit vector sees") {
  // (1e200, 1e200, 1e200) overflowed the squared norm (the view saw nothing) and
  // (1e-200, 1e-200, 1e-200) underflowed it (refused as zero).
  const HalfedgeMesh cube = fixtures::build_fixture(fixtures::voxel_surface({{0, 0, 0}}));
  auto unit = compute_visibility(cube, VisibilityOptions{{Vec3(-1, -1, -1)}});
  REQUIRE(unit.ok());
  for (const double scale : {1e200, 1e-200, 1e300, 1e-310}) {
    CAPTURE(scale);
    auto scaled = compute_visibility(cube, VisibilityOptions{{Vec3(-scale, -scale, -scale)}});
    REQUIRE(scaled.ok());
    for (std::uint32_t f = 0; f < cube.num_faces(); ++f) CHECK(scaled->seen[FaceId(f)] == unit->seen[FaceId(f)]);
  }
  const double max = std::numeric_limits<double>::max();
  auto largest = compute_visibility(cube, VisibilityOptions{{Vec3(-max, -max, -max)}});
  REQUIRE(largest.ok());
  for (std::uint32_t f = 0; f < cube.num_faces(); ++f) CHECK(largest->seen[FaceId(f)] == unit->seen[FaceId(f)]);
}

TEST_CASE("bad views are refused") {
  const HalfedgeMesh cube = fixtures::build_fixture(fixtures::voxel_surface({{0, 0, 0}}));
  CHECK(compute_visibility(cube, VisibilityOptions{{Vec3(0, 0, 0)}}).error().code == ErrorCode::kInvalidArgument);
  CHECK(compute_visibility(cube, VisibilityOptions{{Vec3(0, std::nan(""), 1)}}).error().code == ErrorCode::kInvalidArgument);
  VisibilityOptions many;
  many.ambient_occlusion = true;
  many.ao_rays = 0;
  CHECK(compute_visibility(cube, many).error().code == ErrorCode::kInvalidArgument);
}

}  // namespace seam_visibility_test
