// Exact 2D predicates for the atlas checks (overlap detection, packing tests): orientation,
// and which UV vertices are one point.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/mesh/types.h"

namespace seam::core {

/// The sign (+1, 0, -1) of the orientation of (a, b, c): +1 when c lies strictly left of the
/// directed line a->b (counter-clockwise triangle), 0 when the three points are collinear,
/// -1 when right. Exact for every finite double input: a floating-point filter (Shewchuk
/// 1997's error bound ccwerrboundA) answers almost always; otherwise the determinant is
/// evaluated exactly as a floating-point expansion (two-sum, FMA two-product). O(1).
int orient2d(const Vec2& a, const Vec2& b, const Vec2& c);

/// One vertex for each point: out[v] is the lowest index among `vertices` (indices into uv)
/// whose coordinates equal v's exactly (-0 equals 0); out[v] = v for every v not listed (so
/// an empty list changes nothing). A mesh split along hard edges or seams repeats its vertices, and with this map
/// their edges are one segment (boundary and outline tests). O(n log n), n = vertices listed.
std::vector<std::uint32_t> same_point_representatives(std::span<const Vec2> uv,
                                                      std::span<const std::uint32_t> vertices);

}  // namespace seam::core
