// Feature edges: a cube's 12 edges (its face diagonals are flat), none on a smooth sphere,
// the angle threshold as the definition says, dangling creases pruned by length, and the cube
// cut along its features opens into 6 squares flattened with angle distortion 1.
#include "core/atlas/features.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/mesh/cut.h"
#include "core/mesh/topology.h"
#include "core/uv/parameterize.h"
#include "fixture_mesh.h"
#include "test_data.h"

namespace seam_features_test {

using namespace seam::core;
namespace fx = seam::fixtures;

namespace {

/// A sheet over [0,2] x [0,1] on an nx x ny grid with heights height(i, y) at column i.
template <class Height>
fx::Soup sheet(int nx, int ny, Height height) {
  fx::Soup s;
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      const double y = 1.0 * j / ny;
      s.positions.emplace_back(2.0 * i / nx, y, height(i, y));
    }
  }
  auto id = [&](int i, int j) { return static_cast<std::uint32_t>(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      s.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      s.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return s;
}

/// Creased along y = 1/2 for small x: z = 2 max(0, 1 - x) |y - 1/2| on a 40 x 10 grid. The
/// crease's dihedral angle 2 atan(2 (1 - x)) falls below 60 degrees at x = 0.71, so it runs
/// from the boundary at x = 0 to an interior end: a dangling piece of length ~0.7.
fx::Soup fading_crease() {
  return sheet(40, 10, [](int i, double y) { return 2 * std::max(0.0, 1 - 2.0 * i / 40) * std::abs(y - 0.5); });
}

/// On an 8 x 4 grid whose two middle columns (x = 1, 1.25) rise by |y - 1/2|: one sharp edge
/// (90 degrees) lies on y = 1/2 between those columns, both its ends interior and on no other
/// sharp edge (a lone edge), and two more (63 degrees) run in from the boundary.
fx::Soup lone_crease() {
  return sheet(8, 4, [](int i, double y) { return (i == 4 || i == 5) ? std::abs(y - 0.5) : 0.0; });
}

/// Brute-force oracle: the interior edges whose face normals differ by more than `deg` degrees,
/// with the angle from atan2 of |n0 x n1| and n0 . n1.
std::vector<EdgeId> sharp_edges(const HalfedgeMesh& mesh, double deg) {
  std::vector<EdgeId> sharp;
  for (std::size_t i = 0; i < mesh.num_edges(); ++i) {
    const EdgeId e(i);
    if (mesh.is_boundary(e)) continue;
    Vec3 n[2];
    for (unsigned side = 0; side < 2; ++side) {
      const auto v = mesh.face_vertices(mesh.face(HalfedgeMesh::halfedge(e, side)));
      n[side] = (mesh.position(v[1]) - mesh.position(v[0])).cross(mesh.position(v[2]) - mesh.position(v[0]));
    }
    const double angle = std::atan2(n[0].cross(n[1]).norm(), n[0].dot(n[1])) * 180 / std::numbers::pi;
    if (angle > deg) sharp.push_back(e);
  }
  return sharp;
}

std::size_t count_sharp(const HalfedgeMesh& mesh, double deg) {
  return sharp_edges(mesh, deg).size();
}

}  // namespace

TEST_CASE("a cube's features are its 12 edges, they open it into 6 squares with no distortion") {
  for (const char* source : {"cgal cube", "voxel"}) {
    CAPTURE(source);
    const HalfedgeMesh cube = std::string(source) == "voxel"
                                  ? fx::build_fixture(fx::voxel_surface({{0, 0, 0}}))
                                  : seam::test_data::load_cgal_halfedge("cube");
    REQUIRE(check_invariants(cube).ok());
    auto f = find_feature_edges(cube);
    REQUIRE(f.ok());
    CHECK(f->edges.size() == 12);
    CHECK(f->sharp == 12);
    CHECK(f->pruned == 0);
    CHECK(f->edges.size() == count_sharp(cube, 60));
    // Above 90 degrees nothing is sharp.
    auto none = find_feature_edges(cube, {.feature_angle_deg = 95});
    REQUIRE(none.ok());
    CHECK(none->edges.empty());

    auto cut = cut_along_edges(cube, f->edges);
    REQUIRE(cut.ok());
    const Topology topo = compute_topology(cut->mesh);
    CHECK(topo.components.size() == 6);
    CHECK(check_is_disc(cut->mesh).ok());
    auto uv = parameterize(cut->mesh);
    REQUIRE(uv.ok());
    CHECK(uv->charts == 6);
    CHECK(uv->distortion.angle == doctest::Approx(1.0).epsilon(1e-3));
    CHECK(uv->distortion.area == doctest::Approx(1.0).epsilon(1e-3));
    CHECK(uv->overlap_area == 0);
  }
}

TEST_CASE("a smooth sphere has no feature edges, a coarse one has them only below its dihedral angle") {
  const HalfedgeMesh sphere = fx::build_fixture(fx::icosphere(3));
  auto f = find_feature_edges(sphere);
  REQUIRE(f.ok());
  CHECK(f->edges.empty());
  CHECK(f->sharp == 0);
  // The icosahedron's dihedral angle is 180 - 138.19 = 41.81 degrees between normals.
  const HalfedgeMesh ico = fx::build_fixture(fx::icosphere(0));
  auto at40 = find_feature_edges(ico, {.feature_angle_deg = 40, .max_dangling_fraction = 0});
  auto at45 = find_feature_edges(ico, {.feature_angle_deg = 45, .max_dangling_fraction = 0});
  REQUIRE(at40.ok());
  REQUIRE(at45.ok());
  CHECK(at40->edges.size() == 30);
  CHECK(at45->edges.empty());
}

TEST_CASE("a crease that fades out is a dangling piece: kept when long, dropped when the limit says so") {
  const HalfedgeMesh sheet = fx::build_fixture(fading_crease());
  const std::size_t sharp = count_sharp(sheet, 60);
  REQUIRE(sharp > 0);
  auto keep_all = find_feature_edges(sheet, {.max_dangling_fraction = 0});
  REQUIRE(keep_all.ok());
  CHECK(keep_all->edges.size() == sharp);
  CHECK(keep_all->pruned == 0);
  // ~0.7 long against a diagonal of ~2.3: above the default 0.1 of the diagonal, kept.
  auto by_default = find_feature_edges(sheet);
  REQUIRE(by_default.ok());
  CHECK(by_default->edges.size() == sharp);
  auto drop = find_feature_edges(sheet, {.max_dangling_fraction = 0.5});
  REQUIRE(drop.ok());
  CHECK(drop->edges.empty());
  CHECK(drop->pruned == sharp);
}

TEST_CASE("a lone sharp edge is never a feature: cutting could not open it (fuzz F17)") {
  const HalfedgeMesh sheet = fx::build_fixture(lone_crease());
  const std::vector<EdgeId> sharp = sharp_edges(sheet, 62);  // (edges at exactly 60 degrees: a rounding tie)
  REQUIRE(sharp.size() == 3);
  // Every sharp edge, the lone one too: the cut refuses it as a slit.
  auto all = cut_along_edges(sheet, sharp);
  REQUIRE_FALSE(all.ok());
  CHECK(all.error().code == ErrorCode::kTopologyViolation);
  for (const double fraction : {0.0, 0.1}) {  // keep every dangling piece, or the default
    auto found = find_feature_edges(sheet, {.feature_angle_deg = 62, .max_dangling_fraction = fraction});
    REQUIRE(found.ok());
    CHECK(found->sharp == 3);
    CHECK(found->edges.size() == 2);  // the two from the boundary, 0.25 long (over 0.1 x 2.29)
    CHECK(found->pruned == 1);
    auto cut = cut_along_edges(sheet, found->edges);
    CHECK(cut.ok());
  }
}

TEST_CASE("feature options out of range are typed errors") {
  const HalfedgeMesh cube = fx::build_fixture(fx::voxel_surface({{0, 0, 0}}));
  CHECK(find_feature_edges(cube, {.feature_angle_deg = -1}).error().code == ErrorCode::kInvalidArgument);
  CHECK(find_feature_edges(cube, {.feature_angle_deg = 181}).error().code == ErrorCode::kInvalidArgument);
  CHECK(find_feature_edges(cube, {.max_dangling_fraction = 2}).error().code == ErrorCode::kInvalidArgument);
  CHECK(find_feature_edges(cube, {.feature_angle_deg = std::nan("")}).error().code == ErrorCode::kInvalidArgument);
}

}  // namespace seam_features_test
