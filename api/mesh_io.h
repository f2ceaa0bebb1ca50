// OFF and OBJ readers (the command line and the tests accept these beside glTF).
#pragma once

#include <string>
#include <string_view>

#include "api/error.h"
#include "core/mesh/types.h"

namespace seam::api {

/// Parses an OFF file (OFF/COFF/NOFF headers, '#' comments, per-vertex colours ignored).
/// Polygons with more than three corners are fan-triangulated; vertex indices are kept as
/// in the file. Errors: kMalformedAsset with the line number (bad header, counts larger
/// than the data could hold, a non-number, an index out of range, a face with < 3 corners).
ApiResult<core::IndexedMesh> read_off(std::string_view text);

/// Parses the `v` and `f` lines of a Wavefront OBJ (1-based and negative indices, v/vt/vn
/// corners; other statements ignored). Polygons are fan-triangulated. Errors as read_off.
ApiResult<core::IndexedMesh> read_obj(std::string_view text);

/// Reads a file by extension (.off or .obj, case-insensitive). Errors: kMalformedAsset for
/// an unreadable file or unknown extension.
ApiResult<core::IndexedMesh> read_mesh_file(const std::string& path);

/// Writes an OFF file (used by tests and benchmarks to make inputs).
std::string write_off(const core::IndexedMesh& mesh);

}  // namespace seam::api
