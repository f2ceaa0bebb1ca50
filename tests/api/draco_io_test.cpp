// Draco decoding of hostile payloads: what a payload claims (faces, points, attribute
// components and bytes) is refused before draco allocates by it, quickly and in little memory.
#include <doctest/doctest.h>

#include <chrono>
#include <cstdint>
#include <fstream>
#include <span>
#include <string>
#include <vector>

#include <draco/attributes/geometry_attribute.h>
#include <draco/core/draco_types.h>

#include "api/draco_io.h"
#include "api/gltf_writer.h"
#include "draco_payloads.h"
#include "fixtures.h"

namespace seam_draco_io_test {

namespace {

using namespace seam;
using namespace seam::api;
using namespace seam::test_draco;

// Peak resident memory since reset_peak_rss(), in MiB (Linux: clear_refs 5 resets VmHWM).
void reset_peak_rss() { std::ofstream("/proc/self/clear_refs") << "5"; }
double peak_rss_mib() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  }
  return 0;
}
double rss_mib() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  }
  return 0;
}

ApiResult<DracoMesh> decode(const std::vector<std::uint8_t>& bytes, const ReadLimits& limits = {}) {
  return decode_draco(std::span(bytes.data(), bytes.size()), limits);
}

}  // namespace

TEST_CASE("draco: 300 KB claiming 300k points of 255 float components is refused fast in little memory") {
  // The attack of issue 10: draco used to allocate and zero 300k * 255 * 4 bytes per copy
  // (+568 MB, 1.1 s) before failing on the missing values.
  const auto payload = sequential_payload(100'000, 300'000, {{draco::GeometryAttribute::GENERIC, draco::DT_FLOAT32, 255}});
  CHECK(payload.size() < 310'000);
  reset_peak_rss();
  const double before = rss_mib();
  const auto start = std::chrono::steady_clock::now();
  auto r = decode(payload);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double grown = peak_rss_mib() - before;
  MESSAGE("hostile Draco payload: " << payload.size() << " bytes refused in " << seconds * 1000 << " ms, peak RSS +"
                                    << grown << " MiB");
  REQUIRE(!r.ok());
  CHECK(r.error().code == ApiErrorCode::kMalformedAsset);
  CHECK(r.error().message == "Draco attribute 0 has 255 components (glTF allows 1 to 4)");
  CHECK(http_status(r.error().code) == 400);
  CHECK(seconds < 0.5);  // ~5 ms in Release: the 100k faces are read, nothing else
  CHECK(grown < 32);     // the faces (1.2 MB) and the point ids; never the attribute
}

TEST_CASE("draco: counts are checked against the limits before anything is decoded by them") {
  SUBCASE("more attribute bytes per point than 128") {
    std::vector<Attribute> many(9, {draco::GeometryAttribute::GENERIC, draco::DT_FLOAT32, 4});  // 144 bytes
    auto r = decode(sequential_payload(1000, 3000, many));
    REQUIRE(!r.ok());
    CHECK(r.error().code == ApiErrorCode::kMeshTooLarge);
    CHECK(r.error().message == "the Draco attributes take 144 bytes per point, more than the limit of 128");
    CHECK(r.error().details == nlohmann::json{{"count", 144}, {"limit", 128}});
    // 8 x 16 bytes is within the limit: the decoder goes on and fails on the missing values.
    many.resize(8);
    auto within = decode(sequential_payload(1000, 3000, many));
    REQUIRE(!within.ok());
    CHECK(within.error().code == ApiErrorCode::kMalformedAsset);
    CHECK(within.error().message.find("Draco decode failed") == 0);
  }
  SUBCASE("more faces than max_faces, sequential and edgebreaker") {
    ReadLimits limits;
    limits.max_faces = 999;
    auto r = decode(sequential_payload(1000, 3000, {{}}), limits);
    REQUIRE(!r.ok());
    CHECK(r.error().code == ApiErrorCode::kMeshTooLarge);
    CHECK(r.error().message == "the Draco mesh declares 1000 faces, more than the limit of 999");
    CHECK(r.error().details == nlohmann::json{{"count", 1000}, {"limit", 999}});
    // 100 million faces claimed in 215 bytes: refused before draco sizes its corner table.
    reset_peak_rss();
    const double before = rss_mib();
    auto e = decode(edgebreaker_header(100'000'000, 100'000'000));
    CHECK(peak_rss_mib() - before < 16);
    REQUIRE(!e.ok());
    CHECK(e.error().code == ApiErrorCode::kMeshTooLarge);
    CHECK(e.error().message == "the Draco mesh declares 100000000 faces, more than the limit of 5000000");
  }
  SUBCASE("more points than 3 per face or max_vertices") {
    auto r = decode(sequential_payload(1000, 3001, {{}}));
    REQUIRE(!r.ok());
    CHECK(r.error().code == ApiErrorCode::kMeshTooLarge);
    CHECK(r.error().message == "the Draco mesh declares 3001 points for 1000 faces (at most 3 per face and 20000000 in all)");
    CHECK(r.error().details == nlohmann::json{{"count", 3001}, {"limit", 3000}});
    auto eb = decode(edgebreaker_header(4'000'000, 1'000'000));
    REQUIRE(!eb.ok());
    CHECK(eb.error().code == ApiErrorCode::kMeshTooLarge);
    ReadLimits limits;
    limits.max_vertices = 2999;
    CHECK(decode(sequential_payload(1000, 3000, {{}}), limits).error().code == ApiErrorCode::kMeshTooLarge);
  }
  SUBCASE("an edgebreaker header within the limits reaches draco, which refuses the garbage") {
    auto r = decode(edgebreaker_header(30, 10));
    REQUIRE(!r.ok());
    CHECK(r.error().code == ApiErrorCode::kMalformedAsset);
  }
}

TEST_CASE("draco: honest meshes still decode, in both encodings, at the limits") {
  const auto sphere = fixtures::icosphere(2);
  const std::vector<AttributeArray> attributes = {
      make_float_attribute("POSITION", 3, [&] {
        std::vector<float> v;
        for (const auto& p : sphere.positions) {
          for (int c = 0; c < 3; ++c) v.push_back(static_cast<float>(p[c]));
        }
        return v;
      }())};
  for (bool preserve_order : {false, true}) {  // edgebreaker, then sequential
    CAPTURE(preserve_order);
    DracoEncodeOptions options;
    options.preserve_point_order = preserve_order;
    auto encoded = encode_draco(attributes, sphere.triangles, options);
    REQUIRE(encoded.ok());
    const std::vector<std::uint8_t> bytes(encoded->bytes.begin(), encoded->bytes.end());
    ReadLimits exact;
    exact.max_faces = sphere.triangles.size();
    auto decoded = decode(bytes, exact);
    REQUIRE_MESSAGE(decoded.ok(), (decoded.ok() ? "" : decoded.error().message));
    CHECK(decoded->triangles.size() == sphere.triangles.size());
    CHECK(decoded->num_points == sphere.positions.size());
    exact.max_faces = sphere.triangles.size() - 1;
    CHECK(decode(bytes, exact).error().code == ApiErrorCode::kMeshTooLarge);
  }
}

TEST_CASE("draco: attributes wider than the read limit still encode (our output), and are refused on input") {
  const auto sphere = fixtures::icosphere(1);
  std::vector<float> xyz, wide;
  for (const auto& p : sphere.positions) {
    for (int c = 0; c < 3; ++c) xyz.push_back(static_cast<float>(p[c]));
    for (int c = 0; c < 4; ++c) wide.push_back(static_cast<float>(c));
  }
  std::vector<AttributeArray> attributes = {make_float_attribute("POSITION", 3, xyz)};
  for (int i = 0; i < 8; ++i) attributes.push_back(make_float_attribute("_WIDE_" + std::to_string(i), 4, wide));
  // 12 + 8 * 16 = 140 bytes per point.
  auto encoded = encode_draco(attributes, sphere.triangles);
  REQUIRE_MESSAGE(encoded.ok(), (encoded.ok() ? "" : encoded.error().message));
  const std::vector<std::uint8_t> bytes(encoded->bytes.begin(), encoded->bytes.end());
  auto refused = decode(bytes);
  REQUIRE(!refused.ok());
  CHECK(refused.error().code == ApiErrorCode::kMeshTooLarge);
  CHECK(refused.error().message == "the Draco attributes take 140 bytes per point, more than the limit of 128");
  ReadLimits wider;
  wider.max_draco_bytes_per_point = 140;
  auto decoded = decode(bytes, wider);
  REQUIRE(decoded.ok());
  CHECK(decoded->attributes.size() == 9);
}

TEST_CASE("draco: a bool attribute is refused before draco converts it (gltf_fuzz reproducer)") {
  // A triangle whose generic attribute is DT_BOOL with the byte 0x02: draco's conversion
  // loads it as a C++ bool, which is undefined behaviour.
  const auto payload = sequential_payload(1, 3, {{draco::GeometryAttribute::GENERIC, draco::DT_BOOL, 1}});
  auto decoded = decode(payload);
  REQUIRE_FALSE(decoded.ok());
  CHECK(decoded.error().code == ApiErrorCode::kMalformedAsset);
  CHECK(decoded.error().message.find("bool") != std::string::npos);
  const std::string path = std::string(SEAM_SOURCE_DIR) + "/tests/fuzz/regressions/gltf/draco_bool_attribute.drc";
  std::ifstream in(path, std::ios::binary);
  REQUIRE(in);
  const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  auto reproducer = decode(bytes);
  CHECK_FALSE(reproducer.ok());
}

}  // namespace seam_draco_io_test
