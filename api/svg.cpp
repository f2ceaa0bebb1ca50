#include "api/svg.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>

namespace seam::api {
namespace {

// Twelve distinguishable pastel fills, cycled over charts: a layout is read by its outlines,
// the fill only tells charts apart.
constexpr const char* kChartFills[] = {"#a6cee3", "#b2df8a", "#fb9a99", "#fdbf6f", "#cab2d6", "#ffff99",
                                       "#8dd3c7", "#bebada", "#80b1d3", "#fccde5", "#d9d9d9", "#ccebc5"};
constexpr std::size_t kChartFillCount = sizeof(kChartFills) / sizeof(kChartFills[0]);

// %.4f of size_px keeps 1e-4 px: far below what a texture of that size can show.
void append_number(std::string& out, double x) {
  char buf[32];
  const int n = std::snprintf(buf, sizeof buf, "%.4f", x);
  std::string_view s(buf, static_cast<std::size_t>(n));
  // Trailing zeros cost bytes in a document with millions of coordinates.
  while (s.size() > 1 && s.find('.') != std::string_view::npos && (s.back() == '0' || s.back() == '.')) {
    const bool dot = s.back() == '.';
    s.remove_suffix(1);
    if (dot) break;
  }
  if (s == "-0") s = "0";
  out += s;
}

std::size_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t x) {
  while (parent[x] != x) {
    parent[x] = parent[parent[x]];
    x = parent[x];
  }
  return x;
}

// Chart id per triangle: triangles that share a UV vertex are one chart (the cut duplicated
// the vertices along the seam, so charts share none). Ids are dense, in order of first use.
std::vector<std::uint32_t> chart_of_triangles(const UvLayout& layout) {
  std::vector<std::uint32_t> parent(layout.uv.size());
  std::iota(parent.begin(), parent.end(), 0u);
  for (const auto& t : layout.triangles) {
    const auto a = find_root(parent, t[0]);
    for (int k = 1; k < 3; ++k) parent[find_root(parent, t[k])] = static_cast<std::uint32_t>(a);
  }
  std::vector<std::uint32_t> id(layout.uv.size(), std::numeric_limits<std::uint32_t>::max());
  std::vector<std::uint32_t> chart;
  chart.reserve(layout.triangles.size());
  std::uint32_t next = 0;
  for (const auto& t : layout.triangles) {
    auto& c = id[find_root(parent, t[0])];
    if (c == std::numeric_limits<std::uint32_t>::max()) c = next++;
    chart.push_back(c);
  }
  return chart;
}

ApiError layout_bug(std::size_t layout, const std::string& what) {
  return make_api_error(ApiErrorCode::kInternal, "UV layout " + std::to_string(layout) + ": " + what,
                        {{"layout", layout}});
}

// Indices in range and coordinates finite; widens `lo`/`hi` to the layout's UV bounds.
ApiResult<core::Ok> check_layout(const UvLayout& l, std::size_t i, std::array<double, 2>& lo, std::array<double, 2>& hi) {
  for (std::size_t v = 0; v < l.uv.size(); ++v) {
    if (!std::isfinite(l.uv[v][0]) || !std::isfinite(l.uv[v][1])) {
      return layout_bug(i, "UV " + std::to_string(v) + " is not finite");
    }
    for (int k = 0; k < 2; ++k) {
      lo[k] = std::min(lo[k], l.uv[v][k]);
      hi[k] = std::max(hi[k], l.uv[v][k]);
    }
  }
  const auto n = l.uv.size();
  for (std::size_t f = 0; f < l.triangles.size(); ++f) {
    for (const auto c : l.triangles[f]) {
      if (c >= n) return layout_bug(i, "triangle " + std::to_string(f) + " names UV " + std::to_string(c) + " of " + std::to_string(n));
    }
  }
  for (std::size_t e = 0; e < l.seam_edges.size(); ++e) {
    for (const auto c : l.seam_edges[e]) {
      if (c >= n) return layout_bug(i, "seam edge " + std::to_string(e) + " names UV " + std::to_string(c) + " of " + std::to_string(n));
    }
  }
  return core::Ok{};
}

void append_point(std::string& out, const std::array<double, 2>& uv, double size) {
  append_number(out, uv[0] * size);
  out += ',';
  append_number(out, (1.0 - uv[1]) * size);
}

void append_layout(std::string& out, const UvLayout& l, const SvgOptions& o) {
  out += "<g class=\"primitive\"><title>";
  out += xml_escape(l.name);
  out += "</title>\n";
  const auto chart = chart_of_triangles(l);
  for (std::size_t f = 0; f < l.triangles.size(); ++f) {
    out += "<polygon class=\"triangle\" fill=\"";
    out += kChartFills[chart[f] % kChartFillCount];
    out += "\" points=\"";
    for (int k = 0; k < 3; ++k) {
      if (k) out += ' ';
      append_point(out, l.uv[l.triangles[f][k]], o.size_px);
    }
    out += "\"/>\n";
  }
  if (!l.seam_edges.empty()) {
    out += "<path class=\"seam\" d=\"";
    for (const auto& e : l.seam_edges) {
      out += 'M';
      append_point(out, l.uv[e[0]], o.size_px);
      out += 'L';
      append_point(out, l.uv[e[1]], o.size_px);
    }
    out += "\"/>\n";
  }
  out += "</g>\n";
}

}  // namespace

std::vector<std::array<std::uint32_t, 2>> boundary_edges(const std::vector<std::array<std::uint32_t, 3>>& triangles) {
  // (edge, position of first use) sorted by edge: runs of one are boundary edges.
  std::vector<std::pair<std::array<std::uint32_t, 2>, std::size_t>> uses;
  uses.reserve(3 * triangles.size());
  for (const auto& t : triangles) {
    for (int k = 0; k < 3; ++k) {
      const auto a = t[k];
      const auto b = t[(k + 1) % 3];
      uses.push_back({{std::min(a, b), std::max(a, b)}, uses.size()});
    }
  }
  std::sort(uses.begin(), uses.end());
  std::vector<std::pair<std::size_t, std::array<std::uint32_t, 2>>> once;
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i + 1;
    while (j < uses.size() && uses[j].first == uses[i].first) ++j;
    if (j - i == 1) once.push_back({uses[i].second, uses[i].first});
    i = j;
  }
  std::sort(once.begin(), once.end());
  std::vector<std::array<std::uint32_t, 2>> out;
  out.reserve(once.size());
  for (const auto& [at, edge] : once) out.push_back(edge);
  return out;
}

std::string xml_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  const auto* s = reinterpret_cast<const unsigned char*>(text.data());
  const std::size_t n = text.size();
  for (std::size_t i = 0; i < n;) {
    const unsigned char c = s[i];
    if (c < 0x80) {
      switch (c) {
        case '&': out += "&amp;"; break;
        case '<': out += "&lt;"; break;
        case '>': out += "&gt;"; break;
        case '"': out += "&quot;"; break;
        case '\'': out += "&apos;"; break;
        default: out += (c < 0x20 && c != '\t' && c != '\n') ? std::string("\xEF\xBF\xBD") : std::string(1, static_cast<char>(c));
      }
      ++i;
      continue;
    }
    // A well-formed UTF-8 sequence is kept; anything else is one U+FFFD per byte.
    const std::size_t len = (c & 0xE0) == 0xC0 ? 2 : (c & 0xF0) == 0xE0 ? 3 : (c & 0xF8) == 0xF0 ? 4 : 0;
    bool ok = len != 0 && i + len <= n && c >= 0xC2 && c <= 0xF4;
    for (std::size_t k = 1; ok && k < len; ++k) ok = (s[i + k] & 0xC0) == 0x80;
    if (ok && len == 3) ok = !(c == 0xE0 && s[i + 1] < 0xA0) && !(c == 0xED && s[i + 1] >= 0xA0);
    if (ok && len == 4) ok = !(c == 0xF0 && s[i + 1] < 0x90) && !(c == 0xF4 && s[i + 1] >= 0x90);
    // U+FFFE and U+FFFF are well-formed UTF-8 but not XML 1.0 characters (its Char
    // production: #x9 | #xA | #xD | [#x20-#xD7FF] | [#xE000-#xFFFD] | [#x10000-#x10FFFF]);
    // surrogates were refused above, so these two are all that is left to exclude.
    const bool xml_char = !(ok && len == 3 && c == 0xEF && s[i + 1] == 0xBF && s[i + 2] >= 0xBE);
    if (ok && !xml_char) {
      out += "\xEF\xBF\xBD";
      i += len;
    } else if (ok) {
      out.append(text, i, len);
      i += len;
    } else {
      out += "\xEF\xBF\xBD";
      ++i;
    }
  }
  return out;
}

ApiResult<std::string> render_uv_svg(const std::vector<UvLayout>& layouts, const SvgOptions& options) {
  for (const double x : {options.size_px, options.line_px, options.seam_line_px}) {
    if (!std::isfinite(x) || x <= 0) {
      return make_api_error(ApiErrorCode::kInvalidParameter, "SVG sizes must be finite and positive");
    }
  }
  std::array<double, 2> lo{0.0, 0.0};
  std::array<double, 2> hi{1.0, 1.0};
  for (std::size_t i = 0; i < layouts.size(); ++i) {
    if (auto ok = check_layout(layouts[i], i, lo, hi); !ok.ok()) return ok.error();
  }
  const double s = options.size_px;
  const double margin = 0.02 * s;
  std::string out =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" viewBox=\"";
  // v is flipped: the top of the view is the largest v.
  append_number(out, lo[0] * s - margin);
  out += ' ';
  append_number(out, (1.0 - hi[1]) * s - margin);
  out += ' ';
  append_number(out, (hi[0] - lo[0]) * s + 2 * margin);
  out += ' ';
  append_number(out, (hi[1] - lo[1]) * s + 2 * margin);
  out += "\">\n<style>.triangle{stroke:#3c4655;stroke-width:";
  append_number(out, options.line_px);
  out += ";stroke-linejoin:round}.seam{fill:none;stroke:#e01010;stroke-width:";
  append_number(out, options.seam_line_px);
  out += ";stroke-linecap:round}.unit-square{fill:none;stroke:#888;stroke-width:1}</style>\n";
  out += "<rect class=\"unit-square\" x=\"0\" y=\"0\" width=\"";
  append_number(out, s);
  out += "\" height=\"";
  append_number(out, s);
  out += "\"/>\n";
  for (const auto& layout : layouts) append_layout(out, layout, options);
  out += "</svg>\n";
  return out;
}

}  // namespace seam::api
