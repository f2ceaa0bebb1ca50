// Turning the shrunk tour's skeleton into the seam: its tree structure (terminals as leaves,
// Steiner points inside), straightening each branch into a shortest path (§4.4), and the
// checks and fallback that keep the result a full-component Steiner tree whatever the mesh.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/cancel.h"
#include "core/error.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/paths/search_surface.h"

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
/// Errors: kTopologyViolation naming the first offending vertex. O(|edges| log |edges|).
Status check_full_component_tree(const HalfedgeMesh& mesh, std::span<const EdgeId> edges,
                                 std::span<const VertexId> terminals);

/// The fallback that always works when any full-component tree exists: the shortest-path
/// tree from one centre vertex to every terminal, with terminals blocked so that no path
/// passes through one. The centre minimises the sum of those distances among the vertices
/// nearest to each terminal's paths. Errors: kInvalidArgument (no tree with every
/// terminal a leaf exists, e.g. a terminal whose neighbours are all terminals),
/// kCancelled. Complexity: O(k E log V).
Result<std::vector<EdgeId>> star_tree(const SearchSurface& surface, std::span<const VertexId> terminals,
                                      const CancelToken& cancel = CancelToken::none());

/// The structure of a skeleton (Algorithm 3's output, any edge set): keeps a spanning tree
/// of the part touching terminals, prunes non-terminal leaves, and where a terminal is
/// not a leaf, hangs it off a new Steiner node placed on its first neighbour so that the
/// terminal becomes a leaf (its other branches are left without a course, for
/// straighten_topology to route). Pieces of the skeleton that do not touch each other, and
/// terminals it misses, are joined by terminal-avoiding shortest paths (one search each).
/// Errors: kTopologyViolation (a terminal cannot be made a leaf), kCancelled.
/// O(|edges| log |edges| + V), plus one search per joined piece.
Result<TreeTopology> skeleton_topology(const SearchSurface& surface, std::span<const EdgeId> skeleton_edges,
                                       std::span<const VertexId> terminals,
                                       const CancelToken& cancel = CancelToken::none());

struct StraightenStats {
  std::size_t branches = 0;
  std::size_t kept = 0;     ///< branches left on their previous course (no disjoint shortest path)
  std::size_t retries = 0;  ///< restarts with a blocked branch placed first
};

struct StraightenResult {
  TreeTopology topology;  ///< same nodes and links, every branch re-routed (or kept)
  StraightenStats stats;
};

/// §4.4: keeps terminals and Steiner points fixed and replaces every branch by a shortest
/// path that passes through no other node and shares no vertex with the other branches,
/// so the result stays a tree with every terminal a leaf. Shorter branches are placed
/// first; a branch with no such path keeps its previous course when that is still
/// disjoint; a branch that is blocked entirely is placed first in a new attempt (up to 3).
/// A branch without a previous course (empty path) must be routed.
/// Errors: kTopologyViolation (no disjoint course for some branch), kCancelled.
/// Complexity: O(b E log V) worst case, b = number of branches; each search stops at its
/// target, so typically far less.
Result<StraightenResult> straighten_topology(const SearchSurface& surface, const TreeTopology& topology,
                                             const CancelToken& cancel = CancelToken::none());

/// The sorted, unique edges of all paths of `topology`.
std::vector<EdgeId> topology_edges(const TreeTopology& topology);

/// Sum of `surface`'s weights of topology_edges(topology).
double topology_length(const SearchSurface& surface, const TreeTopology& topology);

}  // namespace seam::core
