// The weld stage of a primitive job: weld -> canonical numbering -> build (repair or split
// pinched vertices only where the builder refuses the soup) -> topology. Its own file so that
// bench/mesh_bench.cpp times the very code the service runs.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "api/error.h"
#include "api/gltf_reader.h"
#include "api/params.h"
#include "core/cancel.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/repair.h"
#include "core/mesh/topology.h"

namespace seam::api {

/// The mesh the core sees, numbered canonically: welded vertices along a Z-order curve of
/// their positions (canonical, and neighbours close in memory: Dijkstra runs ~40% faster than
/// in the input's order of a subdivided mesh, bench/mesh_bench.cpp), faces in order of their
/// (rotated) vertex triples. Vertex order, face order and vertex splits of the input then
/// cannot change the seam: GLB, split-vertex GLB and Draco (which reorders both) of one surface
/// give the same result.
struct Canonical {
  /// The soup handed to the builder; prepare_surface empties both once the mesh holds them.
  std::vector<core::Vec3> positions;
  std::vector<core::Triangle> triangles;
  std::vector<std::uint32_t> input_to_vertex;  ///< input vertex -> canonical vertex
  std::vector<std::uint32_t> vertex_to_input;  ///< canonical vertex -> smallest input index
  std::vector<std::uint32_t> face_to_input;    ///< canonical face -> input triangle
  std::vector<std::uint32_t> input_to_face;    ///< input triangle -> canonical face
  // After repair (or split_pinched): vertices beyond the welded ones are copies made by the
  // splits, and faces are the kept ones. face_to_input/input_to_face then speak of the mesh's
  // faces; an input triangle left out (degenerate) maps to kNoFace and is listed below.
  std::vector<std::uint32_t> vertex_to_welded;   ///< vertex -> the welded vertex it is or copies
  std::vector<std::uint8_t> reoriented;          ///< per mesh face: winding reversed by the repair
  std::vector<std::uint32_t> degenerate_inputs;  ///< input triangles left out of the topology
  std::size_t welded_vertices = 0;
  core::RepairCounts repairs;
};

/// Canonical::input_to_face of an input triangle left out of the topology.
inline constexpr std::uint32_t kNoFace = core::RepairedMesh::kNoFace;

/// Wall milliseconds of each step of prepare_surface; total is their sum (the job's
/// timings_ms.weld times the call around them).
struct SurfaceTimings {
  double weld = 0;          ///< core::weld_vertices
  double canonicalize = 0;  ///< Z-order vertices, rotated and sorted triangles, the maps
  double repair = 0;        ///< repair_mesh or split_pinched_vertices: 0 when the soup built as it is
  double build = 0;         ///< build_halfedge_mesh: both attempts when the first one refused
  double topology = 0;      ///< core::compute_topology
  double total = 0;
};

/// The surface the core sees: the canonical, repaired mesh and its topology.
struct Surface {
  Canonical canon;
  core::HalfedgeMesh mesh;
  core::Topology topology;
  std::size_t welded_vertices = 0;
  SurfaceTimings timings;
};

/// Welds `data.mesh` with params.weld_epsilon, numbers it canonically, and builds it. The soup
/// is built as it is first; only when the builder refuses it does params.repair run
/// core::repair_mesh on it (else core::split_pinched_vertices) before a second build. Both
/// are the identity on a soup the builder accepts, so the result is the one of always
/// repairing, at the cost of one refused build on defective input.
/// Errors name input elements: kNonFinitePosition, kDegenerateFace, kNonManifoldEdge,
/// kInconsistentOrientation and kNonManifoldVertex (repair: false), kInvalidParameter (weld
/// epsilon), kTimeout (cancelled during the weld), kEmptyMesh and kIndexOutOfRange (the
/// builder's, on input the reader should have refused), kInternal (a refusal the recount does
/// not find). Complexity: O(V + F) for bounded valence, plus repair_mesh's cost on a refusal.
ApiResult<Surface> prepare_surface(const PrimitiveData& data, const SeamParams& params, const core::CancelToken& cancel);

/// A core error whose `elements` name canonical vertices or faces, with them mapped to input
/// indices (details "vertices" or "faces"); other errors as from_core gives them.
ApiError map_core_error(const core::Error& error, const Canonical& canon, core::ErrorCode code);

}  // namespace seam::api
