// A cache-friendly, canonical vertex numbering.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/mesh/types.h"

namespace seam::core {

/// The vertices sorted along a Z-order (Morton) curve: positions quantized to 21 bits per axis
/// in their bounding box, ascending by interleaved code, ties by (x, y, z), then by index.
/// Returns order[new] = old. Vertices close in space get close numbers, so graph searches
/// that walk the surface touch memory in nearly sequential order. The order depends on the
/// positions alone (not on the input order) unless two positions are identical.
/// Positions must be finite. Complexity: O(n) (a radix sort of the codes), plus O(k log k)
/// for each run of k vertices sharing a code.
std::vector<std::uint32_t> spatial_order(std::span<const Vec3> positions);

/// `t` rotated to start at its first smallest vertex, the winding kept: the canonical form of a
/// face before sort_triangles. O(1).
inline Triangle rotated_to_smallest(const Triangle& t) {
  std::size_t m = 0;
  if (t[1] < t[m]) m = 1;
  if (t[2] < t[m]) m = 2;
  return {t[m], t[(m + 1) % 3], t[(m + 2) % 3]};
}

/// Sorts `triangles` by their vertex triples (t[0], then t[1], then t[2]), equal triples kept
/// in their order: what std::stable_sort on the triples gives. Returns order[new] = old.
/// Preconditions: every index < num_vertices. Complexity: O(F + V) (a counting sort by t[0],
/// then an insertion sort per bucket); a vertex that is t[0] of d > 32 triangles adds
/// O(d log d). Memory: 12 bytes per triangle of scratch.
std::vector<std::uint32_t> sort_triangles(std::vector<Triangle>& triangles, std::size_t num_vertices);

}  // namespace seam::core
