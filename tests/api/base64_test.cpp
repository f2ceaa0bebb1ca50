// The one base64 codec (api/base64.h): every length round-trips, corrupt input is located.
#include "api/base64.h"

#include <doctest/doctest.h>

#include <random>

namespace seam_base64_test {

using namespace seam::api;

TEST_CASE("base64 round-trips every length and refuses corrupt input") {
  std::mt19937 rng(7);
  for (std::size_t n = 0; n < 70; ++n) {
    std::string bytes(n, '\0');
    for (auto& b : bytes) b = static_cast<char>(rng() & 0xFF);
    const auto text = encode_base64(bytes);
    CHECK(text.size() == (n + 2) / 3 * 4);
    auto back = decode_base64(text);
    REQUIRE(back.ok());
    CHECK(back.value() == bytes);
    // Unpadded and line-wrapped forms are accepted too.
    auto unpadded = text.substr(0, text.find('='));
    auto back2 = decode_base64(unpadded.substr(0, unpadded.size() / 2) + "\r\n" + unpadded.substr(unpadded.size() / 2));
    REQUIRE(back2.ok());
    CHECK(back2.value() == bytes);
  }
  CHECK(decode_base64("Zm9v").value() == "foo");
  for (const char* bad : {"Zm9v!", "Zm9vY", "Zg==Zg==", "Zg===", "Zm9v====", "Z"}) {
    CAPTURE(bad);
    auto r = decode_base64(bad);
    REQUIRE(!r.ok());
    CHECK(!r.error().describe().empty());
  }
}

TEST_CASE("base64 errors say where") {
  auto bad = decode_base64("Zm9v Zm!v");
  REQUIRE(!bad.ok());
  CHECK(bad.error().kind == Base64Error::Kind::kBadCharacter);
  CHECK(bad.error().offset == 7);
  CHECK(bad.error().describe() == "unexpected character at offset 7");
  auto cut = decode_base64("Zm9vZ");
  REQUIRE(!cut.ok());
  CHECK(cut.error().kind == Base64Error::Kind::kTruncated);
  CHECK(cut.error().symbols == 5);
}

}  // namespace seam_base64_test
