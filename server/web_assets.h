// Files seamd serves from memory: the viewer page at GET / with its script and stylesheet
// (web/, bundled with three.js by esbuild at build time) and the OpenAPI document
// (api/openapi.json). CMake embeds them into a generated source (server/web_assets.cmake), so the
// binary needs no files and no network at run time.
#pragma once

#include <span>
#include <string_view>

namespace seam::server {

struct WebAsset {
  std::string_view path;          ///< the route, e.g. "/" or "/viewer.js"
  std::string_view content_type;  ///< the Content-Type header to send
  std::string_view body;          ///< the file's bytes, exactly
};

/// Every embedded file (generated at build time). Static storage; never empty: without
/// Node.js at configure time "/" is a page saying that the viewer was not built.
std::span<const WebAsset> web_asset_table();

/// True when the viewer was bundled (Node.js and web/node_modules were there at configure
/// time); false when "/" is the page that says it was not built.
bool viewer_built();

/// The embedded file served at `path`, or nullptr. O(number of files).
const WebAsset* find_web_asset(std::string_view path);

}  // namespace seam::server
