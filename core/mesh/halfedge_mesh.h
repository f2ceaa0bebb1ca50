// Immutable index-based half-edge mesh with implicit twins, built by a validating builder.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/error.h"
#include "core/mesh/types.h"

namespace seam::core {

/// A manifold, consistently oriented triangle mesh in struct-of-arrays half-edge form.
///
/// Conventions:
/// - twin(h) = h ^ 1 and edge(h) = h >> 1; edge e owns half-edges 2e and 2e+1.
/// - Every half-edge has a tail (origin) vertex; head(h) = tail(twin(h)).
/// - Interior half-edges circulate their face counter-clockwise; boundary half-edges
///   (face(h) invalid) are explicit and their next/prev links form the boundary loops.
/// - vertex_halfedge(v) is an outgoing half-edge; for a boundary vertex it is the outgoing
///   boundary half-edge, so a rotation starting there visits every outgoing half-edge.
///   Isolated vertices (in no face) have an invalid vertex_halfedge.
/// - rotate_ccw(h) = twin(prev(h)) steps to the next outgoing half-edge around tail(h),
///   counter-clockwise seen from outside.
///
/// Built only by build_halfedge_mesh(); immutable afterwards, so algorithms take it const.
class HalfedgeMesh {
 public:
  HalfedgeMesh() = default;

  std::size_t num_vertices() const { return positions_.size(); }
  std::size_t num_halfedges() const { return tail_.size(); }
  std::size_t num_edges() const { return tail_.size() / 2; }
  std::size_t num_faces() const { return face_halfedge_.size(); }

  static HalfedgeId twin(HalfedgeId h) { return HalfedgeId(h.value() ^ 1u); }
  static EdgeId edge(HalfedgeId h) { return EdgeId(h.value() >> 1); }
  static HalfedgeId halfedge(EdgeId e, unsigned side = 0) { return HalfedgeId(2 * e.value() + side); }

  HalfedgeId next(HalfedgeId h) const { return next_[h.index()]; }
  HalfedgeId prev(HalfedgeId h) const { return prev_[h.index()]; }
  VertexId tail(HalfedgeId h) const { return tail_[h.index()]; }
  VertexId head(HalfedgeId h) const { return tail_[h.value() ^ 1u]; }
  FaceId face(HalfedgeId h) const { return face_[h.index()]; }
  bool is_boundary(HalfedgeId h) const { return !face_[h.index()].valid(); }
  bool is_boundary(EdgeId e) const { return is_boundary(halfedge(e, 0)) || is_boundary(halfedge(e, 1)); }
  HalfedgeId rotate_ccw(HalfedgeId h) const { return twin(prev(h)); }
  HalfedgeId rotate_cw(HalfedgeId h) const { return next(twin(h)); }

  HalfedgeId vertex_halfedge(VertexId v) const { return vertex_halfedge_[v.index()]; }
  bool is_isolated(VertexId v) const { return !vertex_halfedge_[v.index()].valid(); }
  bool is_boundary(VertexId v) const {
    const HalfedgeId h = vertex_halfedge_[v.index()];
    return h.valid() && is_boundary(h);
  }
  HalfedgeId face_halfedge(FaceId f) const { return face_halfedge_[f.index()]; }

  const Vec3& position(VertexId v) const { return positions_[v.index()]; }
  std::span<const Vec3> positions() const { return positions_; }

  /// The three vertices of face f in counter-clockwise order.
  std::array<VertexId, 3> face_vertices(FaceId f) const {
    const HalfedgeId h = face_halfedge(f);
    return {tail(h), tail(next(h)), tail(prev(h))};
  }
  /// The half-edge from a to b, or invalid if a and b are not adjacent. O(valence of a).
  HalfedgeId find_halfedge(VertexId a, VertexId b) const;
  /// Euclidean length of edge e.
  double edge_length(EdgeId e) const;
  /// Number of outgoing half-edges (= incident edges) of v. O(valence).
  std::size_t valence(VertexId v) const;

  /// Calls f(h) for every outgoing half-edge of v, counter-clockwise, starting at
  /// vertex_halfedge(v). Does nothing for an isolated vertex.
  template <class F>
  void for_each_outgoing(VertexId v, F&& f) const {
    const HalfedgeId start = vertex_halfedge(v);
    if (!start.valid()) return;
    HalfedgeId h = start;
    do {
      f(h);
      h = rotate_ccw(h);
    } while (h != start);
  }

  /// The triangles as vertex index triples (the form the mesh was built from).
  std::vector<Triangle> triangles() const;

 private:
  friend struct HalfedgeMeshBuilder;  // build_halfedge_mesh's steps (halfedge_mesh.cpp)

  std::vector<Vec3> positions_;
  std::vector<HalfedgeId> next_;
  std::vector<HalfedgeId> prev_;
  std::vector<VertexId> tail_;
  std::vector<FaceId> face_;
  std::vector<HalfedgeId> vertex_halfedge_;
  std::vector<HalfedgeId> face_halfedge_;
};

/// Builds a half-edge mesh from positions and counter-clockwise triangles.
///
/// Errors (the message names the first offender, `elements` lists up to 8):
/// - kEmptyMesh: no triangles.
/// - kIndexOutOfRange: a triangle names a vertex >= positions.size() (elements: faces).
/// - kNonFinitePosition: a coordinate is NaN or Inf (elements: vertices).
/// - kDegenerateFace: a triangle repeats a vertex or has zero area (elements: faces).
/// - kNonManifoldEdge: an edge in three or more triangles (elements: vertex pairs a,b,...).
/// - kInconsistentOrientation: two triangles traverse an edge in the same direction
///   (elements: vertex pairs).
/// - kNonManifoldVertex: a vertex whose triangles form several fans (elements: vertices).
/// Vertices in no triangle are kept as isolated vertices.
/// Complexity: O(V + F) (a counting sort of the edge keys by smaller vertex); a vertex of
/// valence d > 32 adds O(d log d). Memory: 8 bytes per corner of scratch besides the mesh.
Result<HalfedgeMesh> build_halfedge_mesh(std::span<const Vec3> positions, std::span<const Triangle> triangles);

/// One use of an undirected edge by a triangle: corner 3t + k is the directed edge
/// t[k] -> t[k+1] of triangle t.
struct EdgeCorner {
  std::uint64_t key;     ///< (min vertex << 32) | max vertex: the undirected edge
  std::uint32_t corner;  ///< 3 * triangle + k
};

/// The 3 edge uses of every triangle whose indices are all < num_vertices (others are left
/// out), sorted by (key, corner): the uses of one undirected edge are adjacent and in corner
/// order. Exactly the order std::sort gives on (key, corner), computed as build_halfedge_mesh
/// groups its edges (a counting sort by the smaller vertex, an insertion sort per vertex), so
/// the edge grouping of repair and pinch-splitting code can share the builder's kernel.
/// Complexity: O(F + V) for bounded valence; a vertex of valence d > 32 costs O(d log d).
std::vector<EdgeCorner> sorted_edge_uses(std::span<const Triangle> triangles, std::size_t num_vertices);

/// Checks every connectivity invariant listed on HalfedgeMesh (twin/next/prev consistency,
/// faces are triangles, boundary loops closed, vertex half-edges outgoing, rotations cover
/// every outgoing half-edge). Returns kTopologyViolation naming the first broken one.
/// For tests and for verifying results built by other modules. O(n).
Status check_invariants(const HalfedgeMesh& mesh);

}  // namespace seam::core
