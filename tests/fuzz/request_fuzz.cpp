// libFuzzer target for the request layer of POST /seam without HTTP (server/request.h,
// api/params.cpp, api/json_limits.cpp). The first input byte picks the entry point, the rest
// is its input:
//   'J'  parse_json_request (form 2: {"mesh": {"glb_base64"|"gltf"}, ...parameters})
//   'P'  parse_params_part (form 1's params part)
//   'Q'  parse_query_params on a query string, split at '&' and the first '=' and ordered by
//        key as cpp-httplib's Request::params (a multimap) hands it to the server
//   'B'  decode_base64 / encode_base64
//   'M'  media_type, asset_kind_for_media_type, accepts_glb
// any other byte maps to one of them (byte % 5), so mutations of the selector are not wasted.
//
// Properties, each a __builtin_trap when violated:
// - no exception escapes (the request layer reports errors as values);
// - every error has the contract's code for its input (400 kMalformedRequest or
//   kInvalidParameter) and renders as the server renders it, api::error_text(e), as valid
//   JSON (so valid UTF-8, whatever bytes the message quotes) of at most 2 KiB: invalid values
//   are described, never dumped (the longest bodies quote a 60-byte key three times, every
//   byte a 6-byte \u escape);
// - accepted parameters are in range: mesh and primitive below 2^31, vertex indices below
//   2^32 - 1, positions and numbers finite, weld_epsilon and min_protrusion >= 0;
// - a decoded glb_base64 re-encodes and decodes to the same bytes; a decoded mesh.gltf is a
//   JSON object within the depth limit again;
// - encode_base64 then decode_base64 gives back any bytes; the encoding has the expected
//   length and alphabet;
// - media_type is idempotent, lower-case and without parameters.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "api/base64.h"
#include "api/json_limits.h"
#include "tests/fuzz/tolerate.h"
#include "server/request.h"

namespace {

using seam::api::ApiError;
using seam::api::ApiErrorCode;
using seam::api::SeamParams;

void check(bool property) {
  if (!property) __builtin_trap();
}

// The error body as seamd sends it (api::error_text, which replaces bytes that are not
// UTF-8). It must be JSON again: valid UTF-8 (finding F1 was a throw here).
std::string rendered_error(const ApiError& error) {
  std::string text = seam::api::error_text(error);
  check(nlohmann::json::accept(text));
  return text;
}

void check_error(const ApiError& error) {
  static const bool verbose = std::getenv("SEAM_FUZZ_VERBOSE") != nullptr;  // for reading reproducers
  if (verbose) std::fprintf(stderr, "request_fuzz: %s\n", rendered_error(error).c_str());
  check(error.code == ApiErrorCode::kMalformedRequest || error.code == ApiErrorCode::kInvalidParameter);
  check(!error.message.empty());
  check(rendered_error(error).size() <= 2048);  // finding F4 (docs/fuzzing.md), fixed
}

void check_params(const SeamParams& p) {
  check(p.mesh < (1u << 31) && p.primitive < (1u << 31));
  check(std::isfinite(p.weld_epsilon) && p.weld_epsilon >= 0);
  for (const auto i : p.extrema.indices) check(i < std::numeric_limits<std::uint32_t>::max());
  for (const auto i : p.extrema.exclude) check(i < std::numeric_limits<std::uint32_t>::max());
  for (const auto& x : p.extrema.positions) check(std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]));
  check(std::isfinite(p.extrema.auto_options.min_protrusion) && p.extrema.auto_options.min_protrusion >= 0);
}

template <class T, class F>
void check_result(seam::api::ApiResult<T>& result, F&& on_value) {
  if (result.ok()) {
    on_value(*result);
  } else {
    check_error(result.error());
  }
}

void json_request(std::string_view body) {
  auto result = seam::server::parse_json_request(body);
  check_result(result, [](const seam::server::SeamRequest& r) {
    check_params(r.params);
    if (r.kind == seam::api::AssetKind::kGltfJson) {
      auto again = seam::api::parse_json_limited(r.asset);
      check(again.ok() && again->is_object());
    } else {
      check(r.kind == seam::api::AssetKind::kAuto);
      auto again = seam::api::decode_base64(seam::api::encode_base64(r.asset));
      check(again.ok() && *again == r.asset);
    }
  });
}

void params_part(std::string_view text) {
  auto result = seam::server::parse_params_part(text);
  check_result(result, check_params);
}

void query(std::string_view text) {
  std::multimap<std::string, std::string> params;
  std::size_t start = 0;
  while (start <= text.size()) {
    const auto amp = text.find('&', start);
    const auto item = text.substr(start, amp == std::string_view::npos ? std::string_view::npos : amp - start);
    const auto eq = item.find('=');
    params.emplace(std::string(item.substr(0, eq)), eq == std::string_view::npos ? std::string() : std::string(item.substr(eq + 1)));
    if (amp == std::string_view::npos) break;
    start = amp + 1;
  }
  const std::vector<std::pair<std::string, std::string>> list(params.begin(), params.end());
  auto result = seam::server::parse_query_params(list);
  check_result(result, check_params);
}

void base64(std::string_view bytes) {
  const std::string encoded = seam::api::encode_base64(bytes);
  check(encoded.size() == (bytes.size() + 2) / 3 * 4);
  for (const char c : encoded) check(std::isalnum(static_cast<unsigned char>(c)) || c == '+' || c == '/' || c == '=');
  auto round = seam::api::decode_base64(encoded);
  check(round.ok() && *round == bytes);

  auto decoded = seam::api::decode_base64(bytes);
  if (decoded.ok()) {
    const std::string& d = *decoded;
    check(d.size() <= bytes.size() / 4 * 3 + 3);
    auto again = seam::api::decode_base64(seam::api::encode_base64(d));
    check(again.ok() && *again == d);
  } else {
    check(decoded.error().offset <= bytes.size());
  }
}

void media(std::string_view text) {
  const std::string m = seam::server::media_type(text);
  check(seam::server::media_type(m) == m);
  check(m.find(';') == std::string::npos);
  for (const char c : m) check(!std::isupper(static_cast<unsigned char>(c)));
  const auto kind = seam::server::asset_kind_for_media_type(m);
  if (kind) check(m == "model/gltf-binary" || m == "model/gltf+json" || m == "application/octet-stream");
  const bool glb = seam::server::accepts_glb(text);
  if (glb) check(text.find('/') != std::string_view::npos);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string_view input(reinterpret_cast<const char*>(data) + 1, size - 1);
  static constexpr std::string_view kSelectors = "JPQBM";
  char selector = static_cast<char>(data[0]);
  if (kSelectors.find(selector) == std::string_view::npos) selector = kSelectors[data[0] % kSelectors.size()];
  try {
    switch (selector) {
      case 'J': json_request(input); break;
      case 'P': params_part(input); break;
      case 'Q': query(input); break;
      case 'B': base64(input); break;
      default: media(input); break;
    }
  } catch (...) {
    __builtin_trap();  // the request layer never throws
  }
  return 0;
}
