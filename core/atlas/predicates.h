// Exact 2D orientation predicate for the atlas checks (overlap detection, packing tests).
#pragma once

#include "core/mesh/types.h"

namespace seam::core {

/// The sign (+1, 0, -1) of the orientation of (a, b, c): +1 when c lies strictly left of the
/// directed line a->b (counter-clockwise triangle), 0 when the three points are collinear,
/// -1 when right. Exact for every finite double input: a floating-point filter (Shewchuk
/// 1997's error bound ccwerrboundA) answers almost always; otherwise the determinant is
/// evaluated exactly as a floating-point expansion (two-sum, FMA two-product). O(1).
int orient2d(const Vec2& a, const Vec2& b, const Vec2& c);

}  // namespace seam::core
