// render_uv_svg: the document is read back as XML-ish text (elements, attributes, numbers)
// and its geometry compared with the layout it came from.
#include "api/svg.h"

#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace seam_svg_test {

namespace {

using seam::api::render_uv_svg;
using seam::api::UvLayout;

struct Element {
  std::string name;
  std::map<std::string, std::string> attributes;
};

// Every start tag of the document with its attributes; checks that tags are balanced
// (a stack of open elements, self-closing ones popped at once) and attribute values quoted.
std::vector<Element> parse_tags(const std::string& doc) {
  std::vector<Element> out;
  std::vector<std::string> open;
  std::size_t at = 0;
  while ((at = doc.find('<', at)) != std::string::npos) {
    const auto end = doc.find('>', at);
    REQUIRE(end != std::string::npos);
    std::string tag = doc.substr(at + 1, end - at - 1);
    at = end + 1;
    if (tag.starts_with("?")) continue;
    if (tag.starts_with("/")) {
      REQUIRE_FALSE(open.empty());
      CHECK(open.back() == tag.substr(1));
      open.pop_back();
      continue;
    }
    const bool self_closing = tag.ends_with("/");
    if (self_closing) tag.pop_back();
    Element e;
    std::size_t i = tag.find_first_of(" \n");
    e.name = tag.substr(0, i);
    while (i != std::string::npos && i < tag.size()) {
      const auto eq = tag.find('=', i);
      if (eq == std::string::npos) break;
      const std::string key = tag.substr(tag.find_first_not_of(" \n", i), eq - tag.find_first_not_of(" \n", i));
      REQUIRE(tag[eq + 1] == '"');
      const auto close = tag.find('"', eq + 2);
      REQUIRE(close != std::string::npos);
      e.attributes[key] = tag.substr(eq + 2, close - eq - 2);
      i = close + 1;
    }
    if (!self_closing) open.push_back(e.name);
    out.push_back(std::move(e));
  }
  CHECK(open.empty());
  return out;
}

std::vector<double> numbers(const std::string& text) {
  std::string s = text;
  for (char& c : s) {
    if (c == ',' || c == 'M' || c == 'L') c = ' ';
  }
  std::istringstream in(s);
  std::vector<double> out;
  double x = 0;
  while (in >> x) out.push_back(x);
  return out;
}

std::vector<Element> named(const std::vector<Element>& all, const std::string& name) {
  std::vector<Element> out;
  for (const auto& e : all) {
    if (e.name == name) out.push_back(e);
  }
  return out;
}

// Two charts: a unit quad of two triangles on the left, one triangle on the right whose
// vertices are its own (as a cut leaves them). The seam runs along the quad's right side.
UvLayout two_charts() {
  return UvLayout{.name = "duck <body> & \"wing\"",
                  .uv = {{0.0, 0.0}, {0.5, 0.0}, {0.5, 1.0}, {0.0, 1.0}, {0.6, 0.0}, {1.0, 0.0}, {0.6, 0.5}},
                  .triangles = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}},
                  .seam_edges = {{1, 2}, {4, 6}}};
}

}  // namespace

TEST_CASE("svg: one polygon per triangle at the layout's coordinates, v flipped") {
  const auto svg = render_uv_svg({two_charts()}, {.size_px = 100});
  REQUIRE(svg.ok());
  const auto tags = parse_tags(svg.value());
  const auto polygons = named(tags, "polygon");
  REQUIRE(polygons.size() == 3);
  const auto layout = two_charts();
  for (std::size_t f = 0; f < polygons.size(); ++f) {
    const auto xy = numbers(polygons[f].attributes.at("points"));
    REQUIRE(xy.size() == 6);
    for (int k = 0; k < 3; ++k) {
      const auto& uv = layout.uv[layout.triangles[f][k]];
      CHECK(xy[2 * k] == doctest::Approx(uv[0] * 100));
      CHECK(xy[2 * k + 1] == doctest::Approx((1 - uv[1]) * 100));
    }
  }
}

TEST_CASE("svg: charts get their own colours, triangles of one chart share theirs") {
  const auto svg = render_uv_svg({two_charts()});
  REQUIRE(svg.ok());
  const auto polygons = named(parse_tags(svg.value()), "polygon");
  REQUIRE(polygons.size() == 3);
  CHECK(polygons[0].attributes.at("fill") == polygons[1].attributes.at("fill"));
  CHECK(polygons[0].attributes.at("fill") != polygons[2].attributes.at("fill"));
}

TEST_CASE("svg: seam edges are segments between their UV points") {
  const auto svg = render_uv_svg({two_charts()}, {.size_px = 10});
  REQUIRE(svg.ok());
  const auto paths = named(parse_tags(svg.value()), "path");
  REQUIRE(paths.size() == 1);
  CHECK(paths[0].attributes.at("class") == "seam");
  const auto& d = paths[0].attributes.at("d");
  CHECK(std::count(d.begin(), d.end(), 'M') == 2);
  CHECK(numbers(d) == std::vector<double>{5, 10, 5, 0, 6, 10, 6, 5});
}

TEST_CASE("svg: the unit square, a viewBox that covers it and every UV, escaped names") {
  UvLayout outside = two_charts();
  outside.uv[5] = {1.5, -0.25};  // beyond [0,1]²: the view must still show it
  const auto svg = render_uv_svg({outside}, {.size_px = 100});
  REQUIRE(svg.ok());
  const auto tags = parse_tags(svg.value());
  const auto root = named(tags, "svg");
  REQUIRE(root.size() == 1);
  CHECK(root[0].attributes.at("xmlns") == "http://www.w3.org/2000/svg");
  const auto box = numbers(root[0].attributes.at("viewBox"));
  REQUIRE(box.size() == 4);
  // x from 0 to 150, y from 0 (v = 1) to 125 (v = -0.25), 2 units of margin.
  CHECK(box[0] == doctest::Approx(-2));
  CHECK(box[1] == doctest::Approx(-2));
  CHECK(box[2] == doctest::Approx(154));
  CHECK(box[3] == doctest::Approx(129));
  const auto rects = named(tags, "rect");
  REQUIRE(rects.size() == 1);
  CHECK(rects[0].attributes.at("width") == "100");
  CHECK(rects[0].attributes.at("height") == "100");
  CHECK(svg.value().find("<title>duck &lt;body&gt; &amp; &quot;wing&quot;</title>") != std::string::npos);
  CHECK(svg.value().find("<body>") == std::string::npos);
}

TEST_CASE("svg: one group per primitive") {
  UvLayout second = two_charts();
  second.name = "second";
  const auto svg = render_uv_svg({two_charts(), second});
  REQUIRE(svg.ok());
  const auto tags = parse_tags(svg.value());
  CHECK(named(tags, "g").size() == 2);
  CHECK(named(tags, "polygon").size() == 6);
  CHECK(named(tags, "title").size() == 2);
}

TEST_CASE("svg: an empty list is the unit square alone") {
  const auto svg = render_uv_svg({});
  REQUIRE(svg.ok());
  const auto tags = parse_tags(svg.value());
  CHECK(named(tags, "polygon").empty());
  CHECK(named(tags, "rect").size() == 1);
}

TEST_CASE("svg: indices out of range and non-finite UVs are the pipeline's bug (internal)") {
  UvLayout bad_triangle = two_charts();
  bad_triangle.triangles[2][1] = 7;
  auto svg = render_uv_svg({two_charts(), bad_triangle});
  REQUIRE_FALSE(svg.ok());
  CHECK(svg.error().code == seam::api::ApiErrorCode::kInternal);
  CHECK(svg.error().message.find("UV layout 1: triangle 2 names UV 7 of 7") != std::string::npos);

  UvLayout bad_seam = two_charts();
  bad_seam.seam_edges[0][0] = 70;
  svg = render_uv_svg({bad_seam});
  REQUIRE_FALSE(svg.ok());
  CHECK(svg.error().message.find("seam edge 0") != std::string::npos);

  UvLayout nan = two_charts();
  nan.uv[3][1] = std::nan("");
  svg = render_uv_svg({nan});
  REQUIRE_FALSE(svg.ok());
  CHECK(svg.error().message.find("UV 3 is not finite") != std::string::npos);

  svg = render_uv_svg({two_charts()}, {.size_px = 0});
  REQUIRE_FALSE(svg.ok());
  CHECK(svg.error().code == seam::api::ApiErrorCode::kInvalidParameter);
}

TEST_CASE("xml_escape: markup characters, control bytes and invalid UTF-8") {
  using seam::api::xml_escape;
  CHECK(xml_escape("a<b>&'\"") == "a&lt;b&gt;&amp;&apos;&quot;");
  CHECK(xml_escape("caf\xC3\xA9 \xE2\x82\xAC") == "caf\xC3\xA9 \xE2\x82\xAC");  // kept
  CHECK(xml_escape(std::string("x\x01y", 3)) == "x\xEF\xBF\xBDy");
  CHECK(xml_escape("\xFF\xC3") == "\xEF\xBF\xBD\xEF\xBF\xBD");
  CHECK(xml_escape("\xED\xA0\x80") == "\xEF\xBF\xBD\xEF\xBF\xBD\xEF\xBF\xBD");  // a UTF-16 surrogate
}

namespace {

// UTF-8 encoding of any value up to 0x10FFFF, surrogates included (which is invalid UTF-8).
std::string encode_utf8(std::uint32_t cp) {
  std::string out;
  if (cp < 0x80) {
    out += static_cast<char>(cp);
  } else if (cp < 0x800) {
    out += static_cast<char>(0xC0 | (cp >> 6));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  } else if (cp < 0x10000) {
    out += static_cast<char>(0xE0 | (cp >> 12));
    out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  } else {
    out += static_cast<char>(0xF0 | (cp >> 18));
    out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
    out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  }
  return out;
}

// Whether `text` is valid UTF-8 made only of XML 1.0 characters (the Char production:
// #x9 | #xA | #xD | [#x20-#xD7FF] | [#xE000-#xFFFD] | [#x10000-#x10FFFF]). An independent
// decoder, not xml_escape's.
bool only_xml_chars(const std::string& text) {
  const auto* s = reinterpret_cast<const unsigned char*>(text.data());
  for (std::size_t i = 0; i < text.size();) {
    std::uint32_t cp = s[i];
    std::size_t len = 1;
    if (cp >= 0xF0)
      len = 4, cp &= 0x07;
    else if (cp >= 0xE0)
      len = 3, cp &= 0x0F;
    else if (cp >= 0xC0)
      len = 2, cp &= 0x1F;
    else if (cp >= 0x80)
      return false;
    if (i + len > text.size()) return false;
    for (std::size_t k = 1; k < len; ++k) {
      if ((s[i + k] & 0xC0) != 0x80) return false;
      cp = (cp << 6) | (s[i + k] & 0x3F);
    }
    const std::size_t shortest = cp < 0x80 ? 1 : cp < 0x800 ? 2 : cp < 0x10000 ? 3 : 4;
    if (len != shortest) return false;  // overlong
    const bool ok = cp == 0x9 || cp == 0xA || cp == 0xD || (cp >= 0x20 && cp <= 0xD7FF) ||
                    (cp >= 0xE000 && cp <= 0xFFFD) || (cp >= 0x10000 && cp <= 0x10FFFF);
    if (!ok) return false;
    i += len;
  }
  return true;
}

}  // namespace

TEST_CASE("xml_escape: U+FFFE, U+FFFF and every other code point XML 1.0 forbids are replaced") {
  using seam::api::xml_escape;
  // A mesh named with U+FFFE or U+FFFF made the SVG not well-formed XML.
  CHECK(xml_escape("a\xEF\xBF\xBE"
                   "b\xEF\xBF\xBF"
                   "c") ==
        "a\xEF\xBF\xBD"
        "b\xEF\xBF\xBD"
        "c");
  CHECK(xml_escape("\xEF\xBF\xBD") == "\xEF\xBF\xBD");  // U+FFFD itself is allowed
  for (std::uint32_t cp = 0; cp <= 0x10FFFF; ++cp) {
    const std::string escaped = xml_escape("x" + encode_utf8(cp) + "y");
    if (!only_xml_chars(escaped)) {
      CAPTURE(cp);
      FAIL("not XML 1.0 characters only");
    }
  }
  // Broken sequences: truncated, overlong, beyond U+10FFFF, stray continuation bytes.
  for (const std::string bad : {"\xEF\xBF", "\xC0\x80", "\xE0\x80\x80", "\xF4\x90\x80\x80", "\xF8\x88\x80\x80\x80",
                                "\x80", "\xBF\xBE", "\xFE\xFF"}) {
    CHECK(only_xml_chars(xml_escape(bad)));
  }
}

TEST_CASE("svg: a name with code points XML forbids still gives a document of XML characters only") {
  UvLayout layout = two_charts();
  layout.name = std::string("body\xEF\xBF\xBE\xEF\xBF\xBF\x01\x1B\xFF\xED\xA0\x80", 16) + "<&>";
  const auto svg = render_uv_svg({layout});
  REQUIRE(svg.ok());
  CHECK(only_xml_chars(svg.value()));
  CHECK(svg.value().find("\xEF\xBF\xBE") == std::string::npos);
  CHECK(svg.value().find("\xEF\xBF\xBF") == std::string::npos);
  CHECK(svg.value().find("<title>body\xEF\xBF\xBD\xEF\xBF\xBD") != std::string::npos);
}

TEST_CASE("boundary_edges: edges used by one triangle, in order of first use") {
  using seam::api::boundary_edges;
  // The quad of two_charts(): its diagonal 0-2 is shared, the four sides are the boundary.
  const auto quad = boundary_edges({{0, 1, 2}, {0, 2, 3}});
  CHECK(quad == std::vector<std::array<std::uint32_t, 2>>{{0, 1}, {1, 2}, {2, 3}, {0, 3}});
  // A closed tetrahedron has none; an empty list has none.
  CHECK(boundary_edges({{0, 1, 2}, {0, 3, 1}, {1, 3, 2}, {2, 3, 0}}).empty());
  CHECK(boundary_edges({}).empty());
  // As seam_edges of a layout, they draw the chart outline.
  UvLayout layout = two_charts();
  layout.seam_edges = boundary_edges(layout.triangles);
  const auto svg = render_uv_svg({layout}, {.size_px = 10});
  REQUIRE(svg.ok());
  const auto paths = named(parse_tags(svg.value()), "path");
  REQUIRE(paths.size() == 1);
  const auto& d = paths[0].attributes.at("d");
  CHECK(std::count(d.begin(), d.end(), 'M') == 7);  // 4 quad sides + 3 triangle sides
}

}  // namespace seam_svg_test
