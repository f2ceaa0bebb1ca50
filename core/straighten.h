// Turning the shrunk tour's skeleton into the seam: its tree structure (terminals as leaves,
// Steiner points inside), straightening each branch into a shortest path (§4.4), relocating
// Steiner points (our refinement), and the checks and fallback that keep the result a
// full-component Steiner tree whatever the mesh.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/cancel.h"
#include "core/error.h"
#include "core/geodesic.h"
#include "core/halfedge_mesh.h"

namespace seam::core {

/// A full-component tree as nodes joined by mesh paths. nodes[0..num_terminals) are the
/// terminals (leaves), the rest Steiner points (non-terminal vertices of degree >= 3).
/// links[i] joins nodes links[i][0] and links[i][1] along paths[i] (half-edges from the
/// first node's vertex to the second's).
struct TreeTopology {
  std::vector<VertexId> nodes;
  std::size_t num_terminals = 0;
  std::vector<std::array<std::uint32_t, 2>> links;
  std::vector<std::vector<HalfedgeId>> paths;
};

/// OK when `edges` form one tree that contains every terminal, in which every terminal is
/// a leaf (or, with two terminals, an end of the one path) and no other vertex is a leaf.
/// Errors: kTopologyViolation naming the first offending vertex. O(|edges| + V).
Status check_full_component_tree(const HalfedgeMesh& mesh, std::span<const EdgeId> edges,
                                 std::span<const VertexId> terminals);

/// The fallback that always works when any full-component tree exists: the shortest-path
/// tree from one centre vertex to every terminal, with terminals blocked so that no path
/// passes through one. The centre minimises the sum of those distances among the vertices
/// nearest to each terminal's paths. Errors: kInvalidArgument (no tree with every
/// terminal a leaf exists, e.g. a terminal whose neighbours are all terminals),
/// kCancelled. Complexity: O(k E log V).
Result<std::vector<EdgeId>> star_tree(const HalfedgeMesh& mesh, const EdgeGraph& graph,
                                      std::span<const VertexId> terminals,
                                      const CancelToken& cancel = CancelToken::none());

/// The sorted, unique edges of all paths of `topology`.
std::vector<EdgeId> topology_edges(const TreeTopology& topology);

}  // namespace seam::core
