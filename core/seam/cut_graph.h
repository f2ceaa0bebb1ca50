// A short cut graph: the edges that open a surface of genus g with b boundary loops into one
// disc (the paper's §4.1 preprocessing, which delegates it to Gu et al.'s initial seam).
#pragma once

#include <vector>

#include "core/cancel.h"
#include "core/error.h"
#include "core/mesh/halfedge_mesh.h"

namespace seam::core {

/// Computes, for every connected component of `mesh` with genus > 0 or more than one boundary
/// loop, a cut graph: a set of edges such that cutting along them leaves that component one
/// topological disc. Components that are already a disc or a sphere get no edges.
///
/// The method (documented choice): close every boundary loop with a virtual apex joined by
/// zero-weight edges, so each loop is a single point; build a shortest-path tree T from a root
/// (the apex of the component's first boundary loop, else its smallest vertex); take a maximum
/// spanning tree C of the dual graph over the edges not in T, where edge uv weighs the length
/// of its loop d(u) + |uv| + d(v) (tree-cotree with Erickson–Whittlesey's greedy weights, so
/// the 2g leftover edges close the greedy, i.e. shortest, system of loops through the root);
/// keep T plus the leftover edges, repeatedly prune vertices of degree one that are not apexes
/// (which keeps exactly the 2g loops and the shortest-path-tree paths joining every boundary
/// loop to them), and drop the virtual edges. Erickson–Har-Peled show that minimising over
/// every root gives an O(log^2 g) approximation; one root is used here to stay near-linear.
///
/// Preconditions: `mesh` came from build_halfedge_mesh. Errors: kCancelled; those of
/// build_halfedge_mesh through cone_boundary_loops only if the precondition is broken.
/// Complexity: O(E log V). Output sorted, unique, no boundary edges.
Result<std::vector<EdgeId>> compute_cut_graph(const HalfedgeMesh& mesh,
                                              const CancelToken& cancel = CancelToken::none());

}  // namespace seam::core
