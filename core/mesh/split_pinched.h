// Repair before building: a vertex where several fans of triangles meet only at that vertex
// (a "pinched" or bowtie vertex, common in scans and in CGAL's cow) becomes one vertex per fan.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/mesh/types.h"

namespace seam::core {

struct PinchSplit {
  /// The input positions, followed by one copy for every fan beyond a vertex's first.
  std::vector<Vec3> positions;
  /// The input triangles, with the corners of every extra fan moved to that fan's copy.
  std::vector<Triangle> triangles;
  /// Vertex -> the input vertex it is (identity on 0..n-1, the pinched vertex for a copy).
  std::vector<std::uint32_t> source;
  /// Input vertices that had more than one fan.
  std::size_t pinched_vertices = 0;
};

/// Splits every pinched vertex of the triangle soup into one vertex per fan. Two triangles at
/// a vertex v are in one fan when they are linked through triangles that share an edge at v.
/// The fan holding v's lowest corner (3 * triangle + corner) keeps v; the others get copies,
/// numbered in order of v and then of the fan's lowest corner, so the result depends only on
/// the input. Nothing else changes: positions, face order and corner order stay, and the
/// builder still reports non-manifold edges, degenerate faces and out-of-range indices
/// (triangles with an index >= positions.size() are left as they are).
/// Complexity: O(F log F).
PinchSplit split_pinched_vertices(std::span<const Vec3> positions, std::span<const Triangle> triangles);

/// No fan: the corner's triangle is skipped (split_corner_fans).
inline constexpr std::uint32_t kNoFan = 0xffffffffu;

/// The splitting step shared by split_pinched_vertices and repair_mesh: `fan_root[c]` names
/// the fan of corner c = 3t + k (kNoFan: leave the corner). Per vertex, the fan holding its
/// lowest corner keeps it; every other fan gets a copy appended to `positions` and `source`
/// (source[copy] = source[v]), numbered by vertex and then by the fan's lowest corner, and
/// its corners move to the copy. Returns the vertices that were split, in increasing order.
/// Preconditions: fan_root.size() == 3 * triangles.size(); corners with a fan index vertices
/// < positions.size() == source.size(). Complexity: O(F + V) (a counting sort of the corners by
/// vertex, then an insertion sort by fan per vertex); a vertex of d > 32 corners adds O(d log d).
std::vector<std::uint32_t> split_corner_fans(std::vector<Vec3>& positions, std::vector<std::uint32_t>& source,
                                             std::vector<Triangle>& triangles, std::span<const std::uint32_t> fan_root);

}  // namespace seam::core
