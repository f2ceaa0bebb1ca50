// Real meshes from CGAL's data (fetched by scripts/fetch-test-data.sh into .cache/data).
#pragma once

#include <doctest/doctest.h>

#include <filesystem>
#include <string>

#include "api/mesh_io.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/weld.h"

namespace seam::test_data {

inline std::string cgal_mesh_path(const std::string& name) {
  return std::string(SEAM_TEST_DATA_DIR) + "/meshes/" + name + ".off";
}

/// Loads CGAL's `name`.off as an indexed mesh. Fails the test (with the command to run) if
/// the cache is missing: the test command fetches it first.
inline core::IndexedMesh load_cgal(const std::string& name) {
  const std::string path = cgal_mesh_path(name);
  if (!std::filesystem::exists(path)) {
    FAIL("missing " << path << ": run scripts/fetch-test-data.sh");
  }
  auto mesh = api::read_mesh_file(path);
  REQUIRE_MESSAGE(mesh.ok(), (mesh.ok() ? "" : mesh.error().message));
  return std::move(mesh).value();
}

/// Loads, welds exactly and builds the half-edge mesh of CGAL's `name`.off.
inline core::HalfedgeMesh load_cgal_halfedge(const std::string& name) {
  const auto soup = load_cgal(name);
  auto weld = core::weld_vertices(soup.positions, {});
  REQUIRE(weld.ok());
  const auto tris = core::remap_triangles(soup.triangles, weld->input_to_welded);
  auto mesh = core::build_halfedge_mesh(weld->positions, tris);
  REQUIRE_MESSAGE(mesh.ok(), (mesh.ok() ? "" : mesh.error().message));
  return std::move(mesh).value();
}

}  // namespace seam::test_data
