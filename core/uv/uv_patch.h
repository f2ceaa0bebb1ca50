// One disc-shaped component of a mesh in compact local indexing, and the cotan operators the
// flattening methods (LSCM, BFF, ARAP) share.
#pragma once

#include <Eigen/SparseCore>
#include <cstdint>
#include <span>
#include <vector>

#include "core/cancel.h"
#include "core/error.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/topology.h"

namespace seam::core {

/// A topological disc with local vertex indices 0..n-1.
struct DiscPatch {
  std::vector<VertexId> to_mesh;       ///< local vertex -> vertex of the source mesh
  std::vector<Vec3> positions;         ///< per local vertex
  std::vector<Triangle> triangles;     ///< local indices, counter-clockwise seen from outside
  std::vector<FaceId> to_mesh_face;    ///< local triangle -> face of the source mesh
  std::vector<std::uint32_t> boundary; ///< the one boundary loop, counter-clockwise (interior on the left)

  std::size_t num_vertices() const { return positions.size(); }
};

/// Splits `mesh` into one DiscPatch per connected component (in the component order of
/// `topology`). Errors: kTopologyViolation if a component is not a disc (Euler characteristic
/// 1 and exactly one boundary loop); the message names the component and one of its faces.
/// O(V + F).
Result<std::vector<DiscPatch>> extract_disc_patches(const HalfedgeMesh& mesh, const Topology& topology);

/// The three corner angles of triangle t (at corners 0, 1, 2), in radians.
Vec3 corner_angles(const DiscPatch& patch, std::size_t t);

/// Cotangents of the three corner angles, clamped to [-kCotanClamp, kCotanClamp] so a sliver
/// cannot make the operators numerically singular, then made semi-definite
/// (`semi_definite_cotans`), so that every operator built from them stays so.
Vec3 corner_cotans(const DiscPatch& patch, std::size_t t);
inline constexpr double kCotanClamp = 1e5;

/// One triangle's cotangent weights with its Dirichlet energy made positive semi-definite:
/// a single negative weight is raised to -b c / (b + c) (b, c the other two) where it lies
/// below, and with two or three negative weights those become 0. True cotangents of a
/// triangle are returned unchanged (they lie 1 / (b + c) above the bound).
Vec3 semi_definite_cotans(Vec3 cot);

/// The positive semi-definite cotan Laplacian (Dirichlet energy 1/2 x^T L x):
/// L_ij = -(cot a_ij + cot b_ij)/2, L_ii = -sum_j L_ij. n x n, O(F).
Eigen::SparseMatrix<double> cotan_laplacian(const DiscPatch& patch);

/// The patch's vertex graph as the lower triangle of a symmetric pattern, diagonal included
/// (every value 1): the pattern the solvers of one chart share, for nested_dissection_order
/// (sparse_cholesky.h). n x n, O(n + F).
Eigen::SparseMatrix<double> vertex_graph_lower(const DiscPatch& patch);

/// Planar coordinates of triangle t's corners in an isometric frame of its plane
/// (corner 0 at the origin, corner 1 on the +x axis, corner 2 with y > 0).
std::array<Vec2, 3> local_triangle_frame(const DiscPatch& patch, std::size_t t);

}  // namespace seam::core

namespace seam::core {

/// The largest t such that no triangle with positive signed area at t = 0 reaches zero area on
/// [0, t) when every vertex moves by t * direction[v] (infinity if none ever does; triangles
/// already folded are ignored). Smith & Schaefer 2015's injective step bound. O(F).
double max_injective_step(const DiscPatch& patch, const std::vector<Vec2>& uv, const std::vector<Vec2>& direction);

/// Triangles of `patch` whose signed UV area is not positive.
std::size_t count_flipped(const DiscPatch& patch, const std::vector<Vec2>& uv);

/// Local repair of isolated folds: moves vertices of flipped triangles (and, in later rounds,
/// their neighbours) to the uniform average of their neighbours, or halfway there, whenever
/// that lowers the number of flipped triangles around the vertex and creates none. A vertex
/// inside the kernel of its one-ring polygon ends up unfolded; this is the untangling step of
/// mesh smoothing, applied only where the map folded. Returns the flipped count afterwards
/// (never more than before). O(rounds x affected area).
std::size_t repair_flips(const DiscPatch& patch, std::vector<Vec2>& uv, int rounds = 10);

/// Untangling by position: each interior corner of a folded triangle (and, from the second
/// round, its neighbours) moves to the point that maximises the smallest signed area of its
/// star (a linear program in the point; Freitag & Plassmann 2000's max-min untangling) when
/// that unfolds some of its star's triangles and folds none, or, for a star with nothing
/// folded, makes its thinnest triangle fatter. Where the star's kernel is not empty one move
/// unfolds it, and the fold count never rises. Folds left after half the rounds (stars whose
/// kernels are empty until a neighbour moves) get the second half with any move that raises
/// the star's smallest area. Boundary vertices never move. Returns the folded count afterwards.
/// With `min_area_2x` > 0, a triangle counts as folded when its doubled signed area is at most
/// that (fattening triangles thinner than a storage precision, e.g. float32's). O(rounds x (F +
/// affected vertices x degree^4)); vertices of degree above kUntangleMaxDegree stay where they are.
std::size_t untangle(const DiscPatch& patch, std::vector<Vec2>& uv, int rounds = 20, double min_area_2x = 0.0);
inline constexpr std::uint32_t kUntangleMaxDegree = 24;

/// Vertex -> incident triangles, CSR: the triangles of vertex v are
/// triangles[offset[v] .. offset[v + 1]).
struct VertexStars {
  std::vector<std::uint32_t> offset;
  std::vector<std::uint32_t> triangles;
};
/// O(V + F) over `triangles` whose corners are below num_vertices.
VertexStars vertex_stars(std::span<const Triangle> triangles, std::size_t num_vertices);
VertexStars vertex_stars(const DiscPatch& patch);

}  // namespace seam::core

namespace seam::core {

/// The grid stored UVs lie on: multiples of 2^-24 in [0,1]. Each is a float32, and so is its
/// 1 - v (a texture space whose v runs down, as glTF's, stores 1 - v): the flip is exact, and
/// what is measured on these values is what ships. Float32 itself is finer below 1/2, where 1 - v would
/// round a second time (a chart measured overlap-free overlapped itself after the flip: arap on
/// defects.glb, 6e-10 of the atlas).
inline constexpr double kUvGrid = 0x1p-24;

/// `x` clamped to [0,1] and rounded to the nearest multiple of kUvGrid (ties away from zero).
double to_uv_grid(double x);

/// Counts of the storage step (see round_to_float32 and restore_turns).
struct Float32Rounding {
  std::size_t degenerate = 0;  ///< turned the wanted way before rounding, not after, before nudging
  std::size_t remaining = 0;   ///< of those, still not turned the wanted way after nudging
};

/// Restores, after a rounding to the grid, the turn the triangles had before it: a triangle t
/// with want[t] != 0 whose signed area on `uv` is not strictly of want[t]'s sign gets a corner
/// moved to a nearby grid point (staying in [0,1]) when that restores it without losing the
/// wanted turn of any other triangle at the moved vertex: first the eight neighbours one
/// kUvGrid step away (corners in order, moves x-major from (-1, -1)), then the rings 2, 3 and
/// 4 steps away, for a corner of a sliver thinner than the grid (fuzz finding F19). Triangles
/// with want[t] == 0 are free. `uv` lies on the grid and stays there. O(F) when nothing is
/// turned, plus O(V + F) for the vertex stars when something is. The pack step calls it after
/// placing charts.
Float32Rounding restore_turns(std::span<const Triangle> triangles, std::span<const double> want, std::vector<Vec2>& uv);

/// Rounds `uv` (already fitted into [0,1]^2) to the grid (kUvGrid: float32 values whose 1 - v
/// is float32 too) in place. A triangle that was positive before but rounds to zero or negative
/// area gets its corners nudged to neighbouring grid points (restore_turns, wanting every
/// positive triangle positive). O(V + F).
Float32Rounding round_to_float32(const DiscPatch& patch, std::vector<Vec2>& uv);

}  // namespace seam::core
