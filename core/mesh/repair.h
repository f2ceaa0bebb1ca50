// Repair before building: what DCC tools and scanners export (fins, flipped patches, faces that
// collapse when welded, pinched vertices) becomes a soup that build_halfedge_mesh accepts.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/mesh/types.h"

namespace seam::core {

/// What repair_mesh did, in counts (API.md "Whole assets", `repairs`).
struct RepairCounts {
  std::size_t non_manifold_edges = 0;  ///< input edges in three or more faces, split into sheets
  std::size_t reoriented_faces = 0;    ///< faces whose winding was reversed to agree with their sheet
  std::size_t split_off_faces = 0;     ///< faces detached (own vertices): non-orientable conflicts, leftovers
  std::size_t degenerate_faces = 0;    ///< faces left out: a repeated vertex or exactly zero area
  std::size_t pinched_vertices = 0;    ///< vertices split into one copy per fan (as split_pinched_vertices)
};

/// The repaired soup and the maps back to the input.
struct RepairedMesh {
  /// The input positions, followed by copies made by the splits.
  std::vector<Vec3> positions;
  /// The kept faces in input order (degenerate ones left out), over `positions`; a reoriented
  /// face has its corners 1 and 2 swapped.
  std::vector<Triangle> triangles;
  std::vector<std::uint32_t> vertex_source;  ///< vertex -> the input vertex it is or copies
  std::vector<std::uint32_t> face_source;    ///< face -> input face
  std::vector<std::uint8_t> reoriented;      ///< per face: 1 when its winding was reversed
  /// Input face -> face, or kNoFace for a face left out (listed in `degenerate_faces`).
  std::vector<std::uint32_t> input_to_face;
  std::vector<std::uint32_t> degenerate_faces;  ///< input faces left out, ascending
  RepairCounts counts;

  static constexpr std::uint32_t kNoFace = 0xffffffffu;
};

/// Repairs a welded triangle soup so that it builds as a manifold, consistently oriented mesh:
/// 1. faces that repeat a vertex or have exactly zero area (the builder's kDegenerateFace
///    test) are left out;
/// 2. at an edge of three or more faces the faces are unglued, and every vertex gets one copy
///    per fan of faces glued through two-face edges, so sheets that meet only along the edge
///    separate while a sheet that is connected around both ends (a sphere under a fin) stays
///    whole; a face still on an edge of three or more faces after that is split off;
/// 3. per sheet (faces joined through two-face edges) the orientation that keeps most faces
///    as they are wins (ties: the lowest face's), the others are reversed; in a non-orientable
///    sheet one face per conflicting edge (the higher id) is split off;
/// 4. pinched vertices are split per fan, as split_pinched_vertices does.
/// Faces naming a vertex >= positions.size() are kept untouched (the builder reports them).
/// The result depends only on the input (no hashing, no threads). Never fails: on input the
/// builder accepts (apart from pinched vertices) it changes nothing but pinched vertices.
/// Complexity: O(F log F).
RepairedMesh repair_mesh(std::span<const Vec3> positions, std::span<const Triangle> triangles);

}  // namespace seam::core
