// Request decoding without HTTP: media types, Accept negotiation, the JSON form.
#include "api/base64.h"
#include "server/request.h"

#include <doctest/doctest.h>

namespace seam_request_test {

using seam::api::ApiErrorCode;
using seam::api::AssetKind;
using namespace seam::server;

TEST_CASE("media types and Accept negotiation") {
  CHECK(media_type(" Model/GLTF-Binary ; charset=x") == "model/gltf-binary");
  CHECK(media_type("") == "");
  CHECK(asset_kind_for_media_type("model/gltf-binary") == AssetKind::kGlb);
  CHECK(asset_kind_for_media_type("model/gltf+json") == AssetKind::kGltfJson);
  CHECK(asset_kind_for_media_type("application/octet-stream") == AssetKind::kAuto);
  CHECK(!asset_kind_for_media_type("text/plain").has_value());
  CHECK(!asset_kind_for_media_type("").has_value());

  CHECK(accepts_glb("model/gltf-binary"));
  CHECK(accepts_glb("application/json;q=0.5, model/gltf-binary"));
  CHECK(accepts_glb("model/gltf-binary;q=0.9"));
  CHECK(!accepts_glb("model/gltf-binary;q=0"));
  CHECK(!accepts_glb("*/*"));
  CHECK(!accepts_glb("application/json"));
  CHECK(!accepts_glb(""));
  CHECK(!accepts_glb("model/gltf-binary; q=0.000"));
  CHECK(!accepts_glb("model/gltf-binary;Q=0"));
  CHECK(accepts_glb("model/gltf-binary;q=nonsense"));  // an unparsable q is the default, 1

  CHECK(accept_quality("application/json;q=0.5", "application/json") == 0.5);
  CHECK(accept_quality("text/html, application/json", "application/json") == 1.0);
  CHECK(!accept_quality("*/*", "application/json").has_value());
}

TEST_CASE("choose_output: an explicit output wins, Accept chooses without one") {
  using seam::api::OutputFormat;
  seam::api::SeamParams none;
  CHECK(*choose_output(none, "") == OutputFormat::kJson);
  CHECK(*choose_output(none, "*/*") == OutputFormat::kJson);
  CHECK(*choose_output(none, "model/gltf-binary") == OutputFormat::kGlb);
  CHECK(*choose_output(none, "image/svg+xml") == OutputFormat::kSvg);
  CHECK(*choose_output(none, "image/svg+xml, model/gltf-binary") == OutputFormat::kGlb);
  CHECK(*choose_output(none, "image/svg+xml;q=0") == OutputFormat::kJson);
  CHECK(*choose_output(none, "application/json;q=0, image/svg+xml") == OutputFormat::kSvg);
  CHECK(choose_output(none, "application/json;q=0").error().code == ApiErrorCode::kNotAcceptable);
  CHECK(choose_output(none, "application/json;q=0, image/svg+xml;q=0").error().code == ApiErrorCode::kNotAcceptable);

  for (const auto& [given, accept] :
       {std::pair{"json", "model/gltf-binary"}, std::pair{"glb", "image/svg+xml"},
        std::pair{"svg", "model/gltf-binary"}, std::pair{"json", "application/json;q=0"}}) {
    CAPTURE(given);
    CAPTURE(accept);
    auto params = seam::api::params_from_json({{"output", given}});
    REQUIRE(params.ok());
    CHECK(params->output_given);
    auto chosen = choose_output(*params, accept);
    REQUIRE(chosen.ok());
    CHECK(*chosen == params->output);
  }
}

TEST_CASE("the JSON request form") {
  auto ok = parse_json_request(R"({"mesh":{"glb_base64":")" + seam::api::encode_base64("glTF....") + R"("},"method":"mst"})");
  REQUIRE(ok.ok());
  CHECK(ok->asset == "glTF....");
  CHECK(ok->params.method == seam::core::SeamMethod::kMst);

  auto gltf = parse_json_request(R"({"mesh":{"gltf":{"asset":{"version":"2.0"}}}})");
  REQUIRE(gltf.ok());
  CHECK(gltf->kind == AssetKind::kGltfJson);
  CHECK(nlohmann::json::parse(gltf->asset)["asset"]["version"] == "2.0");

  struct Bad {
    const char* body;
    ApiErrorCode code;
  };
  for (const auto& b : {Bad{"", ApiErrorCode::kMalformedRequest}, Bad{"[1,2]", ApiErrorCode::kMalformedRequest},
                        Bad{R"({"extrema":[1]})", ApiErrorCode::kMalformedRequest},
                        Bad{R"({"mesh":{}})", ApiErrorCode::kMalformedRequest},
                        Bad{R"({"mesh":{"glb_base64":"Zg==","gltf":{}}})", ApiErrorCode::kMalformedRequest},
                        Bad{R"({"mesh":{"glb_base64":12}})", ApiErrorCode::kMalformedRequest},
                        Bad{R"({"mesh":{"gltf":"x"}})", ApiErrorCode::kMalformedRequest},
                        Bad{R"({"mesh":{"glb_base64":"Zg=="},"nonsense":1})", ApiErrorCode::kInvalidParameter}}) {
    CAPTURE(b.body);
    auto r = parse_json_request(b.body);
    REQUIRE(!r.ok());
    CHECK(r.error().code == b.code);
  }
  CHECK(parse_params_part("").ok());
  CHECK(parse_params_part("  ").ok());
  CHECK(parse_params_part("[]").error().code == ApiErrorCode::kMalformedRequest);
}

TEST_CASE("JSON nested 100,000 deep is a 400 in every request entry point, and depth 64 is accepted") {
  const std::string deep = std::string(100'000, '[') + std::string(100'000, ']');
  std::string deep_objects;
  for (int i = 0; i < 100'000; ++i) deep_objects += "{\"a\":";
  deep_objects += "1" + std::string(100'000, '}');
  const std::string b64 = R"("glb_base64":")" + seam::api::encode_base64("glTF....") + "\"";
  struct Case {
    const char* where;
    std::string text;
    bool params_part;
  };
  for (const auto& c : {Case{"params part, top level", deep, true},
                        Case{"params part, objects", deep_objects, true},
                        Case{"params part, in extrema", R"({"extrema":)" + deep + "}", true},
                        Case{"params part, in extrema.include", R"({"extrema":{"include":)" + deep + "}}", true},
                        Case{"JSON body, top level", deep, false},
                        Case{"JSON body, objects", deep_objects, false},
                        Case{"JSON body, in extrema", "{\"mesh\":{" + b64 + R"(},"extrema":)" + deep + "}", false},
                        Case{"JSON body, in mesh.gltf",
                             R"({"mesh":{"gltf":{"asset":{"version":"2.0"},"extras":)" + deep + "}}}", false}}) {
    CAPTURE(c.where);
    auto error = c.params_part ? parse_params_part(c.text).error() : parse_json_request(c.text).error();
    CHECK(error.code == ApiErrorCode::kMalformedRequest);
    CHECK(seam::api::http_status(error.code) == 400);
    CHECK(error.message.find("JSON nested deeper than 64 levels at byte ") != std::string::npos);
  }

  // Depth exactly 64 in all (the body's object is level 1), refused at 65.
  auto body_of_depth = [](int depth) {
    // {"mesh":{"gltf":{"asset":{...},"extras": <depth - 3 levels of arrays>}}}
    const std::size_t n = static_cast<std::size_t>(depth - 3);
    return R"({"mesh":{"gltf":{"asset":{"version":"2.0"},"extras":)" + std::string(n, '[') + std::string(n, ']') +
           "}}}";
  };
  auto at_64 = parse_json_request(body_of_depth(64));
  REQUIRE_MESSAGE(at_64.ok(), (at_64.ok() ? "" : at_64.error().message));
  CHECK(at_64->kind == AssetKind::kGltfJson);
  CHECK(nlohmann::json::parse(at_64->asset)["asset"]["version"] == "2.0");
  CHECK(parse_json_request(body_of_depth(65)).error().code == ApiErrorCode::kMalformedRequest);
  // A params part of depth 64 parses; what it holds is then a parameter error, not a crash.
  const std::string params_64 = R"({"extrema":)" + std::string(63, '[') + std::string(63, ']') + "}";
  CHECK(parse_params_part(params_64).error().code == ApiErrorCode::kInvalidParameter);
  const std::string params_65 = R"({"extrema":)" + std::string(64, '[') + std::string(64, ']') + "}";
  CHECK(parse_params_part(params_65).error().code == ApiErrorCode::kMalformedRequest);
}

TEST_CASE("multipart: part names other than one mesh and at most one params are a 400 naming the part") {
  const SeamRequestParts ok{.content_type = "multipart/form-data; boundary=x",
                            .mesh = FormPart{"glTF", ""},
                            .params = FormPart{"{}", ""},
                            .part_names = {"mesh", "params"}};
  CHECK(decode_seam_request(ok).ok());
  struct Bad {
    std::vector<std::string> names;
    const char* part;
  };
  for (const auto& b : {Bad{{"mesh", "parms"}, "parms"}, Bad{{"mesh", "params", "params"}, "params"},
                        Bad{{"mesh", "mesh"}, "mesh"}, Bad{{"mesh", std::string(300, 'x')}, ""}}) {
    CAPTURE(b.names.back().substr(0, 20));
    SeamRequestParts parts = ok;
    parts.part_names = b.names;
    auto r = decode_seam_request(parts);
    REQUIRE(!r.ok());
    CHECK(r.error().code == ApiErrorCode::kMalformedRequest);
    const auto part = r.error().details["part"].get<std::string>();
    if (*b.part) CHECK(part == b.part);
    CHECK(part.size() <= 60);
  }
}

}  // namespace seam_request_test
