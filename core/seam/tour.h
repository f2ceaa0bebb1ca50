// The skeleton seam's first step (§4.2): a directed, non-self-intersecting tour through all
// terminals, from the MST of the terminal graph (Kruskal), walked around in half-edge order
// (Fig. 6(b)), with repeated visits removed by Algorithm 2 and tested by Algorithm 1.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/cancel.h"
#include "core/error.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/paths/steiner.h"

namespace seam::core {

/// A closed directed walk on the mesh's half-edges through terminal visits.
/// visits[i] is an index into TerminalPaths::terminals; pieces[i] is the half-edge path from
/// visits[i] to visits[(i + 1) % n]. The region on the right of the walk is its interior.
struct Tour {
  std::vector<std::uint32_t> visits;
  std::vector<std::vector<HalfedgeId>> pieces;

  /// All half-edges in walk order (pieces concatenated).
  std::vector<HalfedgeId> halfedges() const;
};

struct TourStats {
  std::size_t initial_visits = 0;     ///< visits in the walk around the MST
  std::size_t removals = 0;           ///< repeated visits removed (Algorithm 2)
  std::size_t rejected_removals = 0;  ///< candidate removals refused: the tour would self-intersect
  std::size_t forced_merges = 0;      ///< every candidate refused: the visit was dropped, course kept
  std::size_t tightened = 0;          ///< pieces afterwards replaced by the shortest path
};

struct TourResult {
  Tour tour;
  TourStats stats;
};

/// The MST of the terminal distance graph (TerminalPaths::mst: Kruskal's, ties by index).
/// Returns k - 1 pairs (i < j) in the order Kruskal accepted them. O(k).
std::vector<std::array<std::uint32_t, 2>> terminal_mst(const TerminalPaths& paths);

/// Algorithm 1: true when the closed walk `walk` self-intersects, i.e. at some vertex the
/// sweep from the incoming half-edge's next, around the vertex to the outgoing half-edge,
/// meets another half-edge of the walk. Precondition: walk is closed and contiguous
/// (head of each half-edge = tail of the next; SEAM_ASSERT). O(|walk| * valence + H).
bool tour_self_intersects(const HalfedgeMesh& mesh, std::span<const HalfedgeId> walk);

/// The walk around the MST (Fig. 6(b)): the MST's shortest paths are merged into one tree of
/// mesh edges (an edge closing a cycle is skipped, dangling non-terminal ends are pruned)
/// and walked around, always taking the first tree half-edge clockwise from the incoming
/// half-edge's next, so the tree lies on the left and the walk never self-intersects.
/// Starts at terminal 0. Errors: kInvalidArgument (paths missing), kCancelled. O(V + L).
Result<Tour> mst_walk(const HalfedgeMesh& mesh, const TerminalPaths& paths,
                      const CancelToken& cancel = CancelToken::none());

/// Algorithm 2 on `tour`: while a terminal is visited more than once, remove the visit whose
/// neighbours Pre and Next have the shortest path between them, replacing Pre -> t -> Next by
/// that path, among the removals that keep the tour free of self-intersections (Algorithm 1,
/// checked at the vertices the new path touches). If every removal is refused, the visit with
/// the shortest Pre -> Next path is dropped without changing the course (forced merge).
/// Afterwards each piece that is not a shortest path is replaced by one where that keeps the
/// tour simple (tightening). Errors: kCancelled. O(k^2 L) for tour length L.
Result<TourResult> remove_repeated_visits(const HalfedgeMesh& mesh, const TerminalPaths& paths, Tour tour,
                                          const CancelToken& cancel = CancelToken::none());

/// mst_walk followed by remove_repeated_visits: every terminal visited exactly once.
/// Errors: kInvalidArgument (fewer than two terminals, terminals not connected by the MST,
/// or a path between two MST neighbours missing), kCancelled.
Result<TourResult> build_tour(const HalfedgeMesh& mesh, const TerminalPaths& paths,
                              const CancelToken& cancel = CancelToken::none());

}  // namespace seam::core
