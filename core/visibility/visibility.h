// What a camera sees of a surface, for seams placed where it does not look (the paper's §6 and
// Fig. 10: the triangle energy "defined in terms of visibility"). Ray casting against the mesh
// itself with Embree's BVH; no HTTP, no glTF.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "core/cancel.h"
#include "core/error.h"
#include "core/mesh/halfedge_mesh.h"

namespace seam::core {

struct VisibilityOptions {
  /// Directions in which orthographic cameras look (from infinity); need not be unit length
  /// (any finite magnitude, 1e-300 to 1e300, is scaled before normalising), must be finite
  /// and not exactly zero.
  std::vector<Vec3> views;
  /// Also measure each face's openness (ambient occlusion): the fraction of `ao_rays` rays in
  /// its cosine-weighted hemisphere that leave without hitting the mesh within `ao_distance`.
  bool ambient_occlusion = false;
  int ao_rays = 32;
  double ao_distance = 0.25;  ///< as a fraction of the bounding-box diagonal
  unsigned threads = 1;       ///< ray casting threads (the result does not depend on it)
};

struct Visibility {
  /// Per face: max over views of cos(angle between the face normal and the direction to the
  /// camera), 0 when back-facing or occluded by the mesh. 0..1; empty without views.
  FaceData<double> seen;
  /// Per face: the unoccluded fraction of its hemisphere, 0 (deep crevice) .. 1 (open);
  /// empty without ambient_occlusion.
  FaceData<double> openness;
  std::size_t rays = 0;
  double ms = 0;
};

/// Casts, for every face and view, one ray from the face's centroid towards the camera
/// (offset by 1e-5 of the diagonal), and with ambient_occlusion a fixed spiral of ao_rays
/// cosine-distributed directions per face. Deterministic. Zero-area faces are never seen and
/// count as open. Errors: kInvalidArgument (a non-finite or zero view, ao_rays outside 1..1024,
/// ao_distance not in (0, 10]), kSolverFailed (Embree could not build the scene), kCancelled.
/// Complexity: O(F log F) to build the BVH, O(F * (views + ao_rays) * log F) rays.
Result<Visibility> compute_visibility(const HalfedgeMesh& mesh, const VisibilityOptions& options,
                                      const CancelToken& cancel = CancelToken::none());

/// Per edge: the cost multiplier a seam along it pays. 1 + strength * seen (the larger of its
/// faces', so silhouette edges count as seen), times 1 + strength * openness (the smaller of
/// its faces') when openness is measured. Empty inputs contribute nothing. O(E).
std::vector<double> hiding_multipliers(const HalfedgeMesh& mesh, const Visibility& visibility, double strength);

}  // namespace seam::core
