// Helpers for the glTF tests: hand-built assets, the Khronos validator, temp files.
#pragma once

#include <doctest/doctest.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/gltf_writer.h"

namespace seam::test_gltf {

using nlohmann::json;

template <class T>
void append(std::vector<std::uint8_t>& bin, const std::vector<T>& values) {
  const auto* p = reinterpret_cast<const std::uint8_t*>(values.data());
  bin.insert(bin.end(), p, p + values.size() * sizeof(T));
  while (bin.size() % 4) bin.push_back(0);
}

/// A unit quad (4 vertices, 2 triangles) as GLB JSON + BIN: accessor 0 POSITION (float),
/// accessor 1 indices (u16), bufferView 0 positions (48 bytes), bufferView 1 indices (12).
inline std::pair<json, std::vector<std::uint8_t>> quad_asset() {
  std::vector<std::uint8_t> bin;
  append(bin, std::vector<float>{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0});
  append(bin, std::vector<std::uint16_t>{0, 1, 2, 0, 2, 3});
  json j = {{"asset", {{"version", "2.0"}}},
            {"scene", 0},
            {"scenes", {{{"nodes", {0}}}}},
            {"nodes", {{{"mesh", 0}}}},
            {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}}}},
            {"accessors",
             {{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"},
               {"min", {0, 0, 0}}, {"max", {1, 1, 0}}},
              {{"bufferView", 1}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}}}},
            {"bufferViews", {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 48}},
                             {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 12}}}},
            {"buffers", {{{"byteLength", bin.size()}}}}};
  return {j, bin};
}

inline std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("seam_api_test_" + std::to_string(::getpid()) + "_" + name)).string();
}

inline void write_file(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

/// Runs tests/validate_gltf.js (the Khronos glTF-Validator) on `glb`; returns the number of
/// errors it reports and puts its output in `report`. Fails the test with the install
/// command when the validator is not installed.
inline int validator_errors(const std::string& glb, std::string& report, const std::string& name = "asset.glb") {
  const std::string tests_dir = std::string(SEAM_SOURCE_DIR) + "/tests";
  if (!std::filesystem::exists(tests_dir + "/node_modules/gltf-validator")) {
    FAIL("the glTF validator is not installed: run `npm install --prefix " << tests_dir << "`");
  }
  const std::string path = temp_path(name);
  write_file(path, glb);
  const std::string command = "node '" + tests_dir + "/validate_gltf.js' '" + path + "' 2>&1";
  FILE* pipe = ::popen(command.c_str(), "r");
  REQUIRE(pipe != nullptr);
  report.clear();
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe) != nullptr) report += buffer;
  const int status = ::pclose(pipe);
  std::filesystem::remove(path);
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (code > 100) FAIL("validator failed to run: " << report);
  return code;
}

}  // namespace seam::test_gltf
