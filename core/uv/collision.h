// Global injectivity for a moving flattening: the largest step before the boundary of a chart
// touches itself (Smith & Schaefer 2015, "Bijective Parameterization with Free Boundaries",
// §4: the exact collision step bound for boundary vertex-edge pairs).
#pragma once

#include <vector>

#include "core/uv/uv_patch.h"

namespace seam::core {

struct CollisionStep {
  double step = 0;                 ///< the bound (<= t_max); t_max when nothing collides
  std::size_t candidate_pairs = 0; ///< vertex-edge pairs whose swept boxes met (tested exactly)
  bool limited = false;            ///< some pair collides before t_max
  /// Local ids of the vertices of every pair that collides before t_max (the boundary vertex
  /// and the edge's endpoints), sorted, unique.
  std::vector<std::uint32_t> colliding;
  /// Every pair that collides before t_max: boundary vertex, the edge's endpoints (local ids,
  /// the edge from a to b along the loop) and the contact time; in the grid's pair order.
  struct Contact {
    std::uint32_t vertex = 0;
    std::uint32_t a = 0;
    std::uint32_t b = 0;
    double time = 0;
  };
  std::vector<Contact> contacts;
};

/// The largest t in (0, t_max] such that, when every vertex moves by t' * direction[v] for
/// t' in [0, t), no boundary vertex touches a boundary edge not incident to it. A locally
/// injective map of a disc whose boundary stays a simple curve stays globally injective, so
/// together with max_injective_step (no triangle degenerates) this keeps a bijective map
/// bijective along the step. Per pair the contact time is the smallest root of a quadratic
/// (the vertex collinear with the moving edge) at which the vertex lies on the segment.
/// With `gap` > 0 the vertex must also stay `gap` away from the edge's line where it faces the
/// segment (the line offset by gap towards the vertex, at the edge's start length), so that
/// rounding the result (e.g. to float32) cannot close the last gap; a vertex already closer
/// than `gap` counts as colliding at t = 0 when it moves closer at first order, and else when
/// it would come closer than half its present distance (the edge may turn towards it).
/// Candidate pairs come from a uniform grid over the boxes swept on [0, t_max].
/// Preconditions: uv and direction have one entry per patch vertex; t_max > 0 finite.
/// Complexity: O(B + P) for B boundary vertices and P candidate pairs (O(B) when the swept
/// boxes are small against the chart).
CollisionStep max_collision_free_step(const DiscPatch& patch, const std::vector<Vec2>& uv,
                                      const std::vector<Vec2>& direction, double t_max, double gap = 0);

/// Whether the boundary loop of the chart (as placed by `uv`) is a simple closed curve:
/// no two non-adjacent boundary edges meet, and adjacent ones meet only at their common vertex.
/// Decided with the exact orient2d. O(B log B) typical (grid), O(B^2) worst.
bool boundary_is_simple(const DiscPatch& patch, const std::vector<Vec2>& uv);

}  // namespace seam::core
