#include <doctest/doctest.h>

#include "api/mesh_io.h"
#include "fixtures.h"

namespace seam_mesh_io_test {

using namespace seam;
using api::ApiErrorCode;

namespace {
ApiErrorCode off_error(const std::string& text) {
  auto r = api::read_off(text);
  REQUIRE_FALSE(r.ok());
  return r.error().code;
}
}  // namespace

TEST_CASE("OFF round trip keeps positions and triangles exactly") {
  const auto soup = fixtures::icosphere(2);
  core::IndexedMesh mesh{soup.positions, soup.triangles};
  auto back = api::read_off(api::write_off(mesh));
  REQUIRE(back.ok());
  CHECK(back->triangles == mesh.triangles);
  REQUIRE(back->positions.size() == mesh.positions.size());
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) CHECK(back->positions[i] == mesh.positions[i]);
}

TEST_CASE("OFF variants: comments, counts on the header line, colours, polygons") {
  const std::string text =
      "OFF 5 2 0 # header and counts on one line\n"
      "# a comment line\n"
      "0 0 0\n1 0 0\n1 1 0 255 0 0\n0 1 0\n0.5 2 0\n"
      "4 0 1 2 3   # a quad is fan-triangulated\n"
      "3 3 2 4 200 200 200\n";
  auto r = api::read_off(text);
  REQUIRE(r.ok());
  CHECK(r->positions.size() == 5);
  CHECK(r->triangles == std::vector<core::Triangle>{{0, 1, 2}, {0, 2, 3}, {3, 2, 4}});
}

TEST_CASE("hostile OFF input gets malformed_asset with the line, never a crash") {
  CHECK(off_error("") == ApiErrorCode::kMalformedAsset);
  CHECK(off_error("OFF\n") == ApiErrorCode::kMalformedAsset);
  CHECK(off_error("OFF\n3 1 0\n0 0 0\n1 0 0\n") == ApiErrorCode::kMalformedAsset);         // truncated
  CHECK(off_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n") == ApiErrorCode::kMalformedAsset);  // index
  CHECK(off_error("OFF\n3 1 0\n0 0 0\n1 0 x\n0 1 0\n3 0 1 2\n") == ApiErrorCode::kMalformedAsset);  // number
  CHECK(off_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n") == ApiErrorCode::kMalformedAsset);    // 2 corners
  CHECK(off_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 -1\n") == ApiErrorCode::kMalformedAsset);
  CHECK(off_error("4OFF\n1 0 0\n0 0 0 0\n") == ApiErrorCode::kMalformedAsset);
  // Counts far beyond what the bytes could hold are refused before allocating.
  auto huge = api::read_off("OFF\n2000000000 2000000000 0\n0 0 0\n");
  REQUIRE_FALSE(huge.ok());
  CHECK(huge.error().message.find("do not fit") != std::string::npos);
  auto line = api::read_off("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 9\n");
  REQUIRE_FALSE(line.ok());
  CHECK(line.error().details["line"] == 6);
}

TEST_CASE("OBJ: v/vt/vn corners, negative indices, polygons, hostile input refused") {
  const std::string text =
      "# cube corner\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n"
      "f 1/1/1 2/1/1 3/1/1 4/1/1\nf -4 -2 -1\n";
  auto r = api::read_obj(text);
  REQUIRE(r.ok());
  CHECK(r->triangles == std::vector<core::Triangle>{{0, 1, 2}, {0, 2, 3}, {0, 2, 3}});
  for (const char* bad : {"v 0 0\nf 1 1 1\n", "v 0 0 0\nf 1 2 3\n", "f 0 1 2\n", "v 0 0 0\n", "v 0 0 0\nf a b c\n"}) {
    CAPTURE(bad);
    auto e = api::read_obj(bad);
    REQUIRE_FALSE(e.ok());
    CHECK(e.error().code == ApiErrorCode::kMalformedAsset);
  }
}

TEST_CASE("read_mesh_file refuses unknown extensions and missing files") {
  auto missing = api::read_mesh_file("/nonexistent/x.off");
  REQUIRE_FALSE(missing.ok());
  CHECK(missing.error().code == ApiErrorCode::kMalformedAsset);
  auto ext = api::read_mesh_file(std::string(SEAM_SOURCE_DIR) + "/CMakeLists.txt");
  REQUIRE_FALSE(ext.ok());
  CHECK(ext.error().code == ApiErrorCode::kMalformedAsset);
}

TEST_CASE("every API error code has a snake_case name and the contract's status") {
  using C = ApiErrorCode;
  CHECK(api::http_status(C::kMalformedRequest) == 400);
  CHECK(api::http_status(C::kPayloadTooLarge) == 413);
  CHECK(api::http_status(C::kUnsupportedMediaType) == 415);
  CHECK(api::http_status(C::kNonManifoldEdge) == 422);
  CHECK(api::http_status(C::kExternalUri) == 422);
  CHECK(api::http_status(C::kTooManyTerminals) == 422);
  CHECK(api::http_status(C::kQueueFull) == 503);
  CHECK(api::http_status(C::kTimeout) == 504);
  CHECK(api::http_status(C::kInternal) == 500);
  const auto body = api::error_body(api::from_core(
      core::make_error(core::ErrorCode::kNonManifoldEdge, "edge (0, 1) is shared by three faces", {0, 1})));
  CHECK(body["error"]["code"] == "non_manifold_edge");
  CHECK(body["error"]["details"]["elements"] == nlohmann::json::array({0, 1}));
  CHECK(api::from_core(core::make_error(core::ErrorCode::kCancelled, "x")).code == C::kTimeout);
}

}  // namespace seam_mesh_io_test
