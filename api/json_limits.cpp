#include "api/json_limits.h"

namespace seam::api {
namespace {

using nlohmann::json;

// nlohmann's own DOM builder with a depth gate in front: returning false from a SAX event
// stops the parser at once, so a value deeper than the limit is never built (and a 100 MB
// body of '[' costs one pass up to the 65th bracket, not a 100 MB tree).
class DepthLimitedBuilder {
 public:
  DepthLimitedBuilder(json& root, int max_depth) : dom_(root, /*allow_exceptions=*/false), max_depth_(max_depth) {}

  bool null() { return dom_.null(); }
  bool boolean(bool v) { return dom_.boolean(v); }
  bool number_integer(json::number_integer_t v) { return dom_.number_integer(v); }
  bool number_unsigned(json::number_unsigned_t v) { return dom_.number_unsigned(v); }
  bool number_float(json::number_float_t v, const json::string_t& s) { return dom_.number_float(v, s); }
  bool string(json::string_t& v) { return dom_.string(v); }
  bool binary(json::binary_t& v) { return dom_.binary(v); }
  bool key(json::string_t& v) { return dom_.key(v); }
  bool start_object(std::size_t n) { return enter() && dom_.start_object(n); }
  bool end_object() {
    --depth_;
    return dom_.end_object();
  }
  bool start_array(std::size_t n) { return enter() && dom_.start_array(n); }
  bool end_array() {
    --depth_;
    return dom_.end_array();
  }
  bool parse_error(std::size_t position, const std::string& /*last_token*/, const nlohmann::detail::exception& e) {
    error_position_ = position;
    error_ = e.what();
    return false;
  }

  bool too_deep() const { return too_deep_; }
  std::size_t error_position() const { return error_position_; }
  const std::string& error() const { return error_; }

 private:
  bool enter() {
    if (++depth_ > max_depth_) too_deep_ = true;
    return !too_deep_;
  }

  nlohmann::detail::json_sax_dom_parser<json> dom_;
  int max_depth_;
  int depth_ = 0;
  bool too_deep_ = false;
  std::size_t error_position_ = 0;
  std::string error_;
};

// The SAX interface reports no position for the event that stopped it, so the error path
// finds the offending bracket again with a byte scan (strings skipped; the text up to that
// bracket was valid JSON, so the scan sees exactly the parser's nesting).
std::size_t offset_too_deep(std::string_view text, int max_depth) {
  int depth = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') ++i;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > max_depth) return i;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return text.size();
}

}  // namespace

ApiResult<json> parse_json_limited(std::string_view text, int max_depth) {
  json root;
  DepthLimitedBuilder builder(root, max_depth);
  const bool ok = json::sax_parse(text.data(), text.data() + text.size(), &builder);
  if (builder.too_deep()) {
    const std::size_t offset = offset_too_deep(text, max_depth);
    return make_api_error(ApiErrorCode::kMalformedRequest,
                          "JSON nested deeper than " + std::to_string(max_depth) + " levels at byte " +
                              std::to_string(offset),
                          {{"offset", offset}, {"max_depth", max_depth}});
  }
  if (!ok) {
    // nlohmann's message quotes the last token, which may be most of the body: keep its head.
    // Its byte position counts from 1; ours from 0, like every offset in our messages.
    const std::size_t offset = builder.error_position() > 0 ? builder.error_position() - 1 : 0;
    std::string reason = builder.error();
    if (reason.size() > 160) reason = reason.substr(0, 160) + "...";
    return make_api_error(ApiErrorCode::kMalformedRequest,
                          "not valid JSON at byte " + std::to_string(offset) + ": " + reason, {{"offset", offset}});
  }
  return root;
}

namespace {

std::string count_of(std::size_t n, const char* singular, const char* plural) {
  return std::to_string(n) + " " + (n == 1 ? singular : plural);
}

}  // namespace

std::string describe_json(const json& value) {
  switch (value.type()) {
    case json::value_t::array: return "an array of " + count_of(value.size(), "element", "elements");
    case json::value_t::object: return "an object of " + count_of(value.size(), "member", "members");
    case json::value_t::string:
      return "a string of " + count_of(value.get_ref<const std::string&>().size(), "byte", "bytes");
    case json::value_t::binary: return "binary data";
    case json::value_t::discarded: return "nothing";
    case json::value_t::null:
    case json::value_t::boolean:
    case json::value_t::number_integer:
    case json::value_t::number_unsigned:
    case json::value_t::number_float: return value.dump();  // scalars: short, and no recursion
  }
  return "a JSON value";
}

}  // namespace seam::api
