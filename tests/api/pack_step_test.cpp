// The atlas step's choice of texture (api::atlas_options): the caller's sizes hold as given;
// left at their defaults, a group of more charts than the margins leave room for packs into a
// larger texture instead of failing after all its flattening.
#include "api/pack_step.h"

#include <doctest/doctest.h>

#include "api/params.h"

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

}  // namespace seam_pack_step_test
