// JSON from clients, read so that no input can crash the process (API.md "Limits that hold on
// every framing"). nlohmann's parser is iterative, and so is its destructor (3.11), but dump(),
// copies and comparisons recurse once per nesting level: 60,000 levels in a 120 KB body
// overflow the stack. So depth is refused while parsing, before anything walks the value, and
// invalid values are described in error messages, never serialised.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "api/error.h"

namespace seam::api {

/// The deepest nesting accepted anywhere in client JSON: the top-level array or object is
/// level 1, so `[[1]]` has depth 2. Scalars at the top level have depth 0.
inline constexpr int kMaxJsonDepth = 64;

/// Parses `text` as one JSON value (RFC 8259, no comments, nothing but whitespace after it),
/// counting nesting while parsing (a SAX handler in front of nlohmann's DOM builder) and
/// stopping at the first array or object deeper than `max_depth`, before the deeper value
/// is built. The returned value is then safe to dump, copy and compare.
/// Errors: kMalformedRequest "JSON nested deeper than 64 levels at byte N" (details.offset:
/// the 0-based byte offset of the opening bracket that is one level too deep;
/// details.max_depth), or "not valid JSON at byte N: ..." (details.offset).
/// Complexity: O(bytes) time; the stack use does not depend on the input.
ApiResult<nlohmann::json> parse_json_limited(std::string_view text, int max_depth = kMaxJsonDepth);

/// A short description of a value for error messages, never the value itself when it could
/// be large: "an array of 3 elements", "an object of 2 members", "a string of 12 bytes";
/// numbers, booleans and null as their JSON text ("-3", "1.5", "true", "null").
/// O(1) (and no recursion), whatever the value's size or depth.
std::string describe_json(const nlohmann::json& value);

}  // namespace seam::api
