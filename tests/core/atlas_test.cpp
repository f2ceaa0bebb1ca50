// pack_atlas: several meshes' UV maps in one layout — UVs float32-exact in [0,1]^2, one texel
// density across members, no UV point covered twice (exact and rasterized), coverage equal to
// the stored chart area; malformed members are typed errors.
#include <doctest/doctest.h>

#include <cmath>

#include "atlas_test_util.h"
#include "core/atlas/atlas.h"
#include "core/atlas/features.h"
#include "core/extrema/extrema.h"
#include "core/mesh/cut.h"
#include "core/seam/seam.h"
#include "core/uv/parameterize.h"
#include "fixture_mesh.h"
#include "test_data.h"

namespace seam_atlas_test {

using namespace seam::core;
namespace fx = seam::fixtures;

namespace {

HalfedgeMesh disc_of(const HalfedgeMesh& mesh, bool features) {
  std::vector<EdgeId> edges;
  if (features) {
    auto f = find_feature_edges(mesh);
    REQUIRE(f.ok());
    edges = f->edges;
  } else {
    auto extrema = find_extrema(mesh);
    REQUIRE(extrema.ok());
    auto seam = compute_seam(mesh, *extrema, {});
    REQUIRE(seam.ok());
    edges = all_cut_edges(*seam);
  }
  auto cut = cut_along_edges(mesh, edges);
  REQUIRE(cut.ok());
  REQUIRE(check_is_disc(cut->mesh).ok());
  return cut->mesh;
}

double mesh_area(const HalfedgeMesh& m) {
  double a = 0;
  for (const Triangle& t : m.triangles()) {
    a += 0.5 * (m.position(VertexId(t[1])) - m.position(VertexId(t[0])))
                   .cross(m.position(VertexId(t[2])) - m.position(VertexId(t[0])))
                   .norm();
  }
  return a;
}

double uv_area(const HalfedgeMesh& m, const VertexData<Vec2>& uv) {
  double a = 0;
  for (const Triangle& t : m.triangles()) {
    const Vec2 e1 = uv.raw()[t[1]] - uv.raw()[t[0]];
    const Vec2 e2 = uv.raw()[t[2]] - uv.raw()[t[0]];
    a += 0.5 * std::abs(e1.x() * e2.y() - e1.y() * e2.x());
  }
  return a;
}

}  // namespace

TEST_CASE("three meshes in one atlas: float32 UVs in the unit square, one density, nothing covered twice") {
  const HalfedgeMesh hand = disc_of(seam::test_data::load_cgal_halfedge("hand"), false);
  const HalfedgeMesh elephant = disc_of(seam::test_data::load_cgal_halfedge("elephant"), false);
  const HalfedgeMesh cube = disc_of(fx::build_fixture(fx::voxel_surface({{0, 0, 0}, {1, 0, 0}})), true);
  std::vector<UvResult> maps;
  for (const HalfedgeMesh* m : {&hand, &elephant, &cube}) {
    auto r = parameterize(*m);
    REQUIRE(r.ok());
    maps.push_back(std::move(*r));
  }
  const std::vector<AtlasMesh> members{{hand, maps[0].uv}, {elephant, maps[1].uv}, {cube, maps[2].uv}};
  const PackOptions options{.texture_size = 2048, .margin_px = 8};
  auto atlas = pack_atlas(members, options);
  REQUIRE(atlas.ok());
  CHECK(atlas->charts == 1 + 1 + 6);
  REQUIRE(atlas->uv.size() == 3);
  CHECK(atlas->overlap_area == 0);
  CHECK(atlas->between_charts_area == 0);
  CHECK(atlas->density_ratio == doctest::Approx(1.0).epsilon(1e-4));

  std::vector<Vec2> all_uv;
  std::vector<Triangle> all_tris;
  double stored_area = 0;
  double density[3];
  const HalfedgeMesh* meshes[3] = {&hand, &elephant, &cube};
  for (std::size_t m = 0; m < 3; ++m) {
    const VertexData<Vec2>& uv = atlas->uv[m];
    REQUIRE(uv.size() == meshes[m]->num_vertices());
    for (const Vec2& p : uv) {
      CHECK(p.minCoeff() >= 0.5 * options.margin_px / options.texture_size - 1e-6);
      CHECK(p.maxCoeff() <= 1.0);
      CHECK(static_cast<double>(static_cast<float>(p.x())) == p.x());
      CHECK(static_cast<double>(static_cast<float>(p.y())) == p.y());
    }
    const double a = uv_area(*meshes[m], uv);
    stored_area += a;
    density[m] = std::sqrt(a / mesh_area(*meshes[m]));
    const auto base = static_cast<std::uint32_t>(all_uv.size());
    all_uv.insert(all_uv.end(), uv.begin(), uv.end());
    for (const Triangle& t : meshes[m]->triangles()) all_tris.push_back({base + t[0], base + t[1], base + t[2]});
    // Per mesh: still no flip, and the chart's shape (distortion) is unchanged by packing.
    const Distortion d = measure_distortion(*meshes[m], uv);
    CHECK(d.flipped == 0);
    CHECK(d.angle == doctest::Approx(maps[m].distortion.angle).epsilon(1e-3));
  }
  CHECK(density[0] == doctest::Approx(density[1]).epsilon(1e-4));
  CHECK(density[0] == doctest::Approx(density[2]).epsilon(1e-4));
  CHECK(atlas->coverage == doctest::Approx(stored_area).epsilon(1e-4));
  const seam::atlas_test::RasterCount raster = seam::atlas_test::rasterize(all_uv, all_tris, 2048);
  CHECK(raster.twice == 0);
  CHECK(raster.covered > 0);
}

TEST_CASE("pack_atlas refuses members it cannot pack") {
  const HalfedgeMesh closed = fx::build_fixture(fx::icosphere(1));
  VertexData<Vec2> uv(closed.num_vertices(), Vec2::Zero());
  std::vector<AtlasMesh> members{{closed, uv}};
  auto r = pack_atlas(members);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == ErrorCode::kTopologyViolation);
  VertexData<Vec2> short_uv(3, Vec2::Zero());
  std::vector<AtlasMesh> wrong{{closed, short_uv}};
  CHECK(pack_atlas(wrong).error().code == ErrorCode::kInvalidArgument);
  auto empty = pack_atlas(std::span<const AtlasMesh>{});
  REQUIRE(empty.ok());
  CHECK(empty->charts == 0);
}

}  // namespace seam_atlas_test
