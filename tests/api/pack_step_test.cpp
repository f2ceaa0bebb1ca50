// The atlas step's choice of texture (api::atlas_options): the caller's sizes hold as given;
// left at their defaults, a group of more charts than the margins leave room for packs into a
// larger texture instead of failing after all its flattening. And the safety net after
// placing: a group whose layout overlaps is untangled on its placed UVs and packed again.
#include "api/pack_step.h"

#include <doctest/doctest.h>

#include <cmath>

#include "api/params.h"
#include "core/atlas/overlap.h"
#include "core/uv/uv_patch.h"

namespace seam_pack_step_test {

using namespace seam::api;

TEST_CASE("atlas_options keeps the defaults while the margins fit, then doubles the texture to fit") {
  const auto params = params_from_json(nlohmann::json::object());
  REQUIRE(params.ok());
  const PackParams& pack = params->pack;
  REQUIRE(!pack.sized_by_caller);
  auto fits = atlas_options(pack, 65535);  // 65,535 x 4^2 < 1024^2
  REQUIRE(fits.ok());
  CHECK(fits->texture_size == 1024);
  CHECK(fits->margin_px == 4);
  CHECK(fits->rotate);
  // 65,536 charts' margins cover 1024^2 exactly; at 2048 they cover a quarter.
  auto grown = atlas_options(pack, 65536);
  REQUIRE(grown.ok());
  CHECK(grown->texture_size == 2048);
  CHECK(grown->margin_px == 4);
  // One more chart than a quarter of 2048^2 holds: 4096.
  auto again = atlas_options(pack, 65537);
  REQUIRE(again.ok());
  CHECK(again->texture_size == 4096);
  // Past what 65,536 px hold at the default margin (2^28 charts): the 400, naming the size.
  auto refused = atlas_options(pack, std::size_t{1} << 28);
  REQUIRE(!refused.ok());
  CHECK(refused.error().code == ApiErrorCode::kInvalidParameter);
  CHECK(refused.error().details.at("parameter") == "pack.texture_size");
}

TEST_CASE("atlas_options holds the caller's texture_size or margin_px as given") {
  for (const char* given : {R"({"pack": {"texture_size": 1024}})", R"({"pack": {"margin_px": 4}})"}) {
    CAPTURE(given);
    const auto params = params_from_json(nlohmann::json::parse(given));
    REQUIRE(params.ok());
    CHECK(params->pack.sized_by_caller);
    CHECK(atlas_options(params->pack, 65535).ok());
    auto refused = atlas_options(params->pack, 65536);
    REQUIRE(!refused.ok());
    CHECK(refused.error().code == ApiErrorCode::kInvalidParameter);
    CHECK(refused.error().details.at("charts") == 65536);
    CHECK(refused.error().message.find("use texture_size above") != std::string::npos);
  }
  // pack: true is the default object, and its sizes are the defaults.
  const auto on = params_from_json(nlohmann::json::parse(R"({"pack": true})"));
  REQUIRE(on.ok());
  CHECK(!on->pack.sized_by_caller);
}

TEST_CASE("pack_uv_sets untangles and packs again a group whose placed layout overlaps") {
  // A fan of five counter-clockwise triangles around vertex 0 whose rim turns 450 degrees: one
  // chart, no triangle flipped, the fifth over the first. Its flattening reported neither
  // (as when only the placement's rounding makes two triangles meet), so the first packing
  // keeps it whole and the measurement finds the overlap.
  PrimitiveResult r;
  r.cut.uv.push_back({0.5f, 0.5f});
  for (int k = 0; k <= 5; ++k) {
    const double a = k * 1.5707963267948966;
    r.cut.uv.push_back({static_cast<float>(seam::core::to_uv_grid(0.5 + 0.4 * std::cos(a))),
                        static_cast<float>(seam::core::to_uv_grid(0.5 + 0.4 * std::sin(a)))});
  }
  // Output frame (v down): counter-clockwise as the asset shows it is clockwise here.
  for (std::uint32_t k = 1; k <= 5; ++k) r.cut.triangles.push_back({0, k + 1, k});
  for (std::uint32_t v = 0; v < r.cut.uv.size(); ++v) r.cut.source_vertex.push_back(v);
  r.chart.assign(r.cut.uv.size(), 0);
  r.chart_area = {1.0};
  r.summary = {{"uv", {{"flipped", 0}, {"overlap_area", 0.0}}}};
  GltfDocument doc;
  doc.json = {{"meshes", {{{"primitives", {nlohmann::json::object()}}}}}};
  const std::vector<PackMember> members{{0, 0, &r}};
  auto packed = pack_uv_sets(doc, members, PackParams{}, seam::core::CancelToken::none());
  REQUIRE(packed.ok());
  const PackOutcome& out = packed->front();
  CHECK(out.overlap_area == 0.0);
  CHECK(out.flipped == 0);
  CHECK(out.untangle.charts == 1);
  CHECK(out.charts == 1 + out.untangle.pieces_added);
  CHECK(out.charts >= 2);
  REQUIRE(r.cut.triangles.size() == 5);
  // Measured independently on what ships: no two triangles share area, every UV on the grid.
  std::vector<seam::core::Vec2> uv;
  for (const auto& p : r.cut.uv) {
    CHECK(seam::core::to_uv_grid(p[0]) == p[0]);
    CHECK(seam::core::to_uv_grid(p[1]) == p[1]);
    uv.emplace_back(p[0], p[1]);
  }
  auto overlap = seam::core::find_overlaps(uv, r.cut.triangles);
  REQUIRE(overlap.ok());
  CHECK_FALSE(overlap->overlaps);
  // The duplicated vertices on the new cut copy their source.
  for (std::size_t v = 0; v < r.cut.source_vertex.size(); ++v) CHECK(r.cut.source_vertex[v] < 7);
}

}  // namespace seam_pack_step_test
