// Welding: merge coincident vertices so topology sees through UV/normal splits.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/cancel.h"
#include "core/error.h"
#include "core/mesh/types.h"

namespace seam::core {

struct WeldOptions {
  /// Vertices closer than this (Euclidean, model units) become one vertex, transitively.
  /// 0 merges only bit-identical positions (with -0.0 == +0.0). Must be finite and >= 0.
  double epsilon = 0.0;
};

/// The welded vertex set and the maps both ways.
struct WeldResult {
  std::vector<Vec3> positions;                ///< one per welded vertex: its representative's position
  std::vector<std::uint32_t> input_to_welded; ///< input vertex -> welded vertex
  std::vector<std::uint32_t> welded_to_input; ///< welded vertex -> its smallest input index
};

/// Welds `positions`. Welded vertices are numbered in order of their smallest input index,
/// so the result depends only on the input, not on hashing or threads.
/// Errors: kNonFinitePosition (elements: first offending input vertices), kInvalidArgument
/// (bad epsilon), kCancelled. Complexity: with epsilon 0, O(n) (a radix sort of 32-bit hashes
/// of the positions; only k distinct positions whose hashes collide cost O(k^2) comparisons);
/// with epsilon > 0, expected O(n log n) on a grid of
/// cell size epsilon (pathological clusters degrade to O(k^2) per cell).
Result<WeldResult> weld_vertices(std::span<const Vec3> positions, const WeldOptions& options,
                                 const CancelToken& cancel = CancelToken::none());

/// Rewrites triangles from input to welded indices. An index >= input_to_welded.size()
/// becomes VertexId::kInvalidValue, which build_halfedge_mesh reports as kIndexOutOfRange.
std::vector<Triangle> remap_triangles(std::span<const Triangle> triangles,
                                      std::span<const std::uint32_t> input_to_welded);

}  // namespace seam::core
