#include "api/base64.h"

#include <array>
#include <cstdint>

namespace seam::api {
namespace {

constexpr std::string_view kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

constexpr std::array<std::int8_t, 256> kValue = [] {
  std::array<std::int8_t, 256> t{};
  t.fill(-1);
  for (std::size_t i = 0; i < kAlphabet.size(); ++i) t[static_cast<unsigned char>(kAlphabet[i])] = static_cast<std::int8_t>(i);
  return t;
}();

bool is_space(unsigned char c) { return c == ' ' || c == '\n' || c == '\r' || c == '\t'; }

}  // namespace

std::string Base64Error::describe() const {
  switch (kind) {
    case Kind::kBadCharacter: return "unexpected character at offset " + std::to_string(offset);
    case Kind::kTruncated: return "truncated (length " + std::to_string(symbols) + " symbols)";
  }
  return "invalid";
}

core::Result<std::string, Base64Error> decode_base64(std::string_view text) {
  std::string out;
  out.reserve(text.size() / 4 * 3 + 3);
  std::uint32_t acc = 0;
  int bits = 0;
  std::size_t padding = 0;
  std::size_t symbols = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (is_space(c)) continue;
    if (c == '=') {
      ++padding;
      continue;
    }
    // Data after padding, or a character outside the alphabet, is corrupt input, not noise.
    if (padding > 0 || kValue[c] < 0) return Base64Error{Base64Error::Kind::kBadCharacter, i, symbols};
    ++symbols;
    acc = (acc << 6) | static_cast<std::uint32_t>(kValue[c]);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<char>((acc >> bits) & 0xFFu));
    }
  }
  if (symbols % 4 == 1 || padding > 2 || (padding > 0 && (symbols + padding) % 4 != 0)) {
    return Base64Error{Base64Error::Kind::kTruncated, text.size(), symbols};
  }
  return out;
}

std::string encode_base64(std::string_view bytes) {
  // Sized once and written by index: appending a character at a time checks the capacity
  // per character, which costs several times the table lookups on a GLB of tens of MB.
  std::string out((bytes.size() + 2) / 3 * 4, '=');
  auto byte = [&](std::size_t i) { return static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[i])); };
  char* o = out.data();
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3, o += 4) {
    const std::uint32_t v = (byte(i) << 16) | (byte(i + 1) << 8) | byte(i + 2);
    o[0] = kAlphabet[(v >> 18) & 63];
    o[1] = kAlphabet[(v >> 12) & 63];
    o[2] = kAlphabet[(v >> 6) & 63];
    o[3] = kAlphabet[v & 63];
  }
  if (i < bytes.size()) {
    const bool two = i + 1 < bytes.size();
    const std::uint32_t v = (byte(i) << 16) | (two ? byte(i + 1) << 8 : 0);
    o[0] = kAlphabet[(v >> 18) & 63];
    o[1] = kAlphabet[(v >> 12) & 63];
    if (two) o[2] = kAlphabet[(v >> 6) & 63];  // o[3] (and o[2] with one byte) stay '='
  }
  return out;
}

}  // namespace seam::api
