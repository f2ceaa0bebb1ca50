// A cache-friendly, canonical vertex numbering.
#pragma once

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

}  // namespace seam::core
