// The UV layout of cut primitives as an SVG document, like a DCC's "export UV layout"
// (API.md v2, `output: "svg"`): every triangle outlined and filled with its chart's colour,
// the seam edges marked, the unit square drawn. Pure: no I/O, no global state.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "api/error.h"

namespace seam::api {

/// One primitive's new UV set, in the numbering of the cut primitive.
struct UvLayout {
  std::string name;                                      ///< shown in a <title>; escaped
  std::vector<std::array<double, 2>> uv;                 ///< #V by 2, (u, v) with v up
  std::vector<std::array<std::uint32_t, 3>> triangles;   ///< #F by 3, indices into uv
  /// Seam edges as pairs of indices into uv: both sides of the cut, each a segment in UV
  /// space (an edge of the cut primitive whose ends are copies made by the cut).
  std::vector<std::array<std::uint32_t, 2>> seam_edges;
};

struct SvgOptions {
  double size_px = 1024;        ///< the unit square's side in SVG user units (> 0)
  double line_px = 0.5;         ///< triangle outline width (> 0)
  double seam_line_px = 2.0;    ///< seam edge width (> 0)
};

/// Renders the layouts into one SVG 1.1 document: one <g class="primitive"> per layout,
/// holding a <title> with its name, one <polygon class="triangle"> per triangle (coloured by
/// chart: triangles connected through shared UV vertices) and one <path class="seam"> with a
/// segment per seam edge; a <rect class="unit-square"> shows [0,1]². u maps to x, v to
/// size_px·(1 − v), so the layout looks as in a DCC's UV editor. The viewBox covers the unit
/// square and every UV point, with a margin of 2% of size_px.
/// Errors: kInvalidParameter for options that are not finite and positive; kInternal naming
/// the layout and element for an index out of range or a non-finite UV (the pipeline's bug,
/// not the client's input). O(V + F + seam edges) time and output size.
ApiResult<std::string> render_uv_svg(const std::vector<UvLayout>& layouts, const SvgOptions& options = {});

/// The edges of `triangles` that only one triangle uses, as index pairs (smaller first, in
/// order of first use): on a cut primitive, the chart boundaries, i.e. both sides of every
/// seam edge plus the surface's own boundary. A UvLayout's seam_edges when the caller has no
/// finer list. O(F log F).
std::vector<std::array<std::uint32_t, 2>> boundary_edges(const std::vector<std::array<std::uint32_t, 3>>& triangles);

/// Escapes text for an XML attribute or text node (&, <, >, ", ' ); invalid UTF-8 bytes (one
/// U+FFFD each), control characters other than tab and newline, and U+FFFE and U+FFFF (one
/// U+FFFD per code point) become U+FFFD, so the result holds only XML 1.0 characters.
std::string xml_escape(const std::string& text);

}  // namespace seam::api
