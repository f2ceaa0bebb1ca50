// Client JSON can nest as deep as it likes; the process must not care: depth is refused while
// parsing, before anything recursive (dump, copy, compare) walks the value, and invalid values
// are described, never dumped.
#include <doctest/doctest.h>

#include <string>

#include "api/json_limits.h"
#include "api/pipeline.h"

namespace seam_json_limits_test {

namespace {

using namespace seam::api;
using nlohmann::json;

std::string nested_arrays(std::size_t depth, const std::string& inner = "") {
  return std::string(depth, '[') + inner + std::string(depth, ']');
}

std::string nested_objects(std::size_t depth) {
  std::string s;
  for (std::size_t i = 0; i < depth; ++i) s += "{\"a\":";
  s += "1";
  s += std::string(depth, '}');
  return s;
}

// A value `depth` levels deep built by moves (no recursive copy), as a client's could be.
json deep_value(std::size_t depth) {
  json v = 1;
  for (std::size_t i = 0; i < depth; ++i) {
    json a = json::array();
    a.push_back(std::move(v));
    v = std::move(a);
  }
  return v;
}

}  // namespace

TEST_CASE("parse_json_limited accepts depth 64 and refuses 65 with the offending byte") {
  auto ok = parse_json_limited(nested_arrays(64, "7"));
  REQUIRE(ok.ok());
  // Depth 64 is safe to walk: dump it back.
  CHECK(ok->dump() == nested_arrays(64, "7"));
  REQUIRE(parse_json_limited(nested_objects(64)).ok());

  auto deep = parse_json_limited(nested_arrays(65));
  REQUIRE(!deep.ok());
  CHECK(deep.error().code == ApiErrorCode::kMalformedRequest);
  CHECK(http_status(deep.error().code) == 400);
  CHECK(deep.error().message == "JSON nested deeper than 64 levels at byte 64");
  CHECK(deep.error().details["offset"] == 64);

  auto objects = parse_json_limited("  " + nested_objects(65));
  REQUIRE(!objects.ok());
  CHECK(objects.error().details["offset"] == 2 + 64 * 5);  // the 65th '{' of {"a":{"a":...

  // Brackets inside strings are not nesting.
  const std::string brackets = "[\"" + std::string(1000, '[') + "\\\"{{{\"]";
  auto in_string = parse_json_limited(brackets);
  REQUIRE(in_string.ok());
  CHECK((*in_string)[0].get<std::string>().size() == 1004);

  // A smaller limit works the same way.
  CHECK(parse_json_limited("[[1]]", 2).ok());
  CHECK(parse_json_limited("[[[1]]]", 2).error().details["offset"] == 2);
  CHECK(parse_json_limited("5", 0).ok());
}

TEST_CASE("parse_json_limited refuses 100,000 levels of arrays and objects without a crash") {
  for (const std::string& text : {nested_arrays(100'000), nested_objects(100'000),
                                  "{\"extrema\": " + nested_arrays(100'000, "1") + "}",
                                  std::string(100'000, '[')}) {  // unterminated too
    auto r = parse_json_limited(text);
    REQUIRE(!r.ok());
    CHECK(r.error().code == ApiErrorCode::kMalformedRequest);
    CHECK(r.error().message.find("JSON nested deeper than 64 levels at byte ") == 0);
  }
}

TEST_CASE("parse_json_limited reports invalid JSON with its offset and a bounded message") {
  for (const std::string& text : {std::string(""), std::string("{\"a\": }"), std::string("[1, 2] x"),
                                  std::string("{\"a\": tru"), "\"" + std::string(100'000, 'x')}) {
    CAPTURE(text.substr(0, 20));
    auto r = parse_json_limited(text);
    REQUIRE(!r.ok());
    CHECK(r.error().code == ApiErrorCode::kMalformedRequest);
    CHECK(r.error().message.find("not valid JSON at byte ") == 0);
    CHECK(r.error().message.size() < 300);  // the 100 KB unterminated string is not quoted back
    CHECK(r.error().details["offset"].get<std::size_t>() <= text.size());
  }
  CHECK(parse_json_limited("{\"a\": }").error().details["offset"] == 6);
}

TEST_CASE("describe_json names the type and size, never the content") {
  CHECK(describe_json(json::array({1, 2, 3})) == "an array of 3 elements");
  CHECK(describe_json(json::array({1})) == "an array of 1 element");
  CHECK(describe_json(json{{"a", 1}, {"b", 2}}) == "an object of 2 members");
  CHECK(describe_json(std::string(5000, 'x')) == "a string of 5000 bytes");
  CHECK(describe_json(-3) == "-3");
  CHECK(describe_json(1.5) == "1.5");
  CHECK(describe_json(true) == "true");
  CHECK(describe_json(nullptr) == "null");
  // 100,000 levels: described in O(1); dump() here would overflow the stack.
  CHECK(describe_json(deep_value(100'000)) == "an array of 1 element");
}

TEST_CASE("params_from_json describes an invalid deep value instead of dumping it") {
  json params = json::object();
  json list = json::array();
  list.push_back(deep_value(100'000));
  params["extrema"] = std::move(list);
  auto r = params_from_json(params);
  REQUIRE(!r.ok());
  CHECK(r.error().code == ApiErrorCode::kInvalidParameter);
  CHECK(r.error().message == "extrema: vertex indices must be non-negative integers below 2^32-1, got an array of 1 element");
  auto scalar = params_from_json(json{{"extrema", {-4}}});
  REQUIRE(!scalar.ok());
  CHECK(scalar.error().message.find("got -4") != std::string::npos);
}

}  // namespace seam_json_limits_test
