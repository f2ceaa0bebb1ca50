// Repair: every fixture of broken input builds afterwards (validating builder, invariants,
// consistent orientation), the counts say what was done, and every input face is kept
// (mapped, with the same corners up to winding) or reported as degenerate.
#include <doctest/doctest.h>

#include <algorithm>
#include <set>

#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/repair.h"
#include "core/mesh/split_pinched.h"
#include "core/mesh/topology.h"
#include "fixtures.h"

namespace seam_repair_test {

using namespace seam::core;
namespace fx = seam::fixtures;

namespace {

// Builds the repaired soup and checks what must hold for any input.
HalfedgeMesh check_repaired(const fx::Soup& in, const RepairedMesh& r) {
  auto built = build_halfedge_mesh(r.positions, r.triangles);
  REQUIRE_MESSAGE(built.ok(), (built.ok() ? "" : built.error().message));
  REQUIRE(check_invariants(*built).ok());
  REQUIRE(r.vertex_source.size() == r.positions.size());
  for (std::size_t v = 0; v < r.positions.size(); ++v) {
    REQUIRE(r.vertex_source[v] < in.positions.size());
    CHECK(r.positions[v] == in.positions[r.vertex_source[v]]);
  }
  REQUIRE(r.face_source.size() == r.triangles.size());
  REQUIRE(r.reoriented.size() == r.triangles.size());
  REQUIRE(r.input_to_face.size() == in.triangles.size());
  std::size_t kept = 0, reoriented = 0;
  for (std::uint32_t f = 0; f < in.triangles.size(); ++f) {
    const std::uint32_t g = r.input_to_face[f];
    const bool dropped = std::binary_search(r.degenerate_faces.begin(), r.degenerate_faces.end(), f);
    CHECK(dropped == (g == RepairedMesh::kNoFace));  // kept or reported, never both, never lost
    if (dropped) continue;
    ++kept;
    REQUIRE(r.face_source[g] == f);
    // The same corners through vertex_source: in order, or reversed when reoriented.
    Triangle back;
    for (int k = 0; k < 3; ++k) back[k] = r.vertex_source[r.triangles[g][k]];
    if (r.reoriented[g]) std::swap(back[1], back[2]), ++reoriented;
    CHECK(back == in.triangles[f]);
  }
  CHECK(kept + r.degenerate_faces.size() == in.triangles.size());
  CHECK(r.counts.degenerate_faces == r.degenerate_faces.size());
  CHECK(r.counts.reoriented_faces == reoriented);
  return std::move(built).value();
}

std::size_t count(const std::vector<std::uint8_t>& flags) { return static_cast<std::size_t>(std::count(flags.begin(), flags.end(), 1)); }

}  // namespace

TEST_CASE("a clean mesh comes back unchanged, with nothing counted") {
  const fx::Soup in = fx::torus();
  const RepairedMesh r = repair_mesh(in.positions, in.triangles);
  check_repaired(in, r);
  CHECK(r.triangles == in.triangles);
  CHECK(r.positions.size() == in.positions.size());
  CHECK(r.counts.non_manifold_edges == 0);
  CHECK(r.counts.reoriented_faces == 0);
  CHECK(r.counts.split_off_faces == 0);
  CHECK(r.counts.degenerate_faces == 0);
  CHECK(r.counts.pinched_vertices == 0);
}

TEST_CASE("a bowtie: the pinched vertex is split exactly as split_pinched_vertices splits it") {
  const fx::Soup in = fx::bowtie();
  const RepairedMesh r = repair_mesh(in.positions, in.triangles);
  check_repaired(in, r);
  const PinchSplit split = split_pinched_vertices(in.positions, in.triangles);
  CHECK(r.counts.pinched_vertices == 1);
  CHECK(r.triangles == split.triangles);
  CHECK(r.vertex_source == split.source);
}

TEST_CASE("a flipped patch on a sphere is reversed back: one closed genus-0 surface, the patch counted") {
  const fx::Soup good = fx::icosphere(2);
  const fx::Soup in = fx::sphere_with_flipped_patch(2, 0.7);
  std::size_t patch = 0;
  for (std::size_t f = 0; f < in.triangles.size(); ++f) patch += in.triangles[f] != good.triangles[f];
  REQUIRE(patch > 3);
  REQUIRE(2 * patch < in.triangles.size());
  REQUIRE(build_halfedge_mesh(in.positions, in.triangles).error().code == ErrorCode::kInconsistentOrientation);
  const RepairedMesh r = repair_mesh(in.positions, in.triangles);
  const HalfedgeMesh mesh = check_repaired(in, r);
  CHECK(r.counts.reoriented_faces == patch);
  CHECK(r.counts.split_off_faces == 0);
  CHECK(r.triangles == good.triangles);  // the majority's winding, i.e. the sphere's own
  const Topology t = compute_topology(mesh);
  CHECK(t.components.size() == 1);
  CHECK(t.boundary_loops.empty());
  CHECK(t.total_genus() == 0);
}

TEST_CASE("the flipped tetrahedron: one face reversed, closed") {
  const fx::Soup in = fx::flipped_tetrahedron();
  const RepairedMesh r = repair_mesh(in.positions, in.triangles);
  const HalfedgeMesh mesh = check_repaired(in, r);
  CHECK(r.counts.reoriented_faces == 1);
  CHECK(r.reoriented[3] == 1);
  CHECK(compute_topology(mesh).boundary_loops.empty());
}

TEST_CASE("three faces on one edge (fin): the edge is split into sheets") {
  const fx::Soup in = fx::fin();
  REQUIRE(build_halfedge_mesh(in.positions, in.triangles).error().code == ErrorCode::kNonManifoldEdge);
  const RepairedMesh r = repair_mesh(in.positions, in.triangles);
  const HalfedgeMesh mesh = check_repaired(in, r);
  CHECK(r.counts.non_manifold_edges == 1);
  CHECK(r.counts.pinched_vertices == 0);  // the split vertices are the edge's own
  CHECK(r.triangles.size() == 3);
  // Nothing joins the three faces but the edge: three single-triangle sheets.
  CHECK(compute_topology(mesh).components.size() == 3);
}

TEST_CASE("a fin on a closed sphere: the sphere stays closed and whole, the fin is its own sheet") {
  const fx::Soup in = fx::sphere_with_fin(1);
  const RepairedMesh r = repair_mesh(in.positions, in.triangles);
  const HalfedgeMesh mesh = check_repaired(in, r);
  CHECK(r.counts.non_manifold_edges == 1);
  CHECK(r.counts.split_off_faces == 0);
  CHECK(r.positions.size() == in.positions.size() + 2);  // the fin's two corners on the edge
  const Topology t = compute_topology(mesh);
  REQUIRE(t.components.size() == 2);
  const std::size_t sphere = t.face_component[FaceId(std::size_t{0})];
  CHECK(t.components[sphere].faces == in.triangles.size() - 1);
  CHECK(t.components[sphere].boundary_loops == 0);
  CHECK(t.components[sphere].genus == 0);
  CHECK(t.components[1 - sphere].faces == 1);
}

TEST_CASE("several sheets on one edge: books of 3 to 6 pages, two tetrahedra on one edge") {
  for (int pages = 3; pages <= 6; ++pages) {
    CAPTURE(pages);
    const fx::Soup in = fx::book(pages);
    const RepairedMesh r = repair_mesh(in.positions, in.triangles);
    const HalfedgeMesh mesh = check_repaired(in, r);
    CHECK(r.counts.non_manifold_edges == 1);
    CHECK(compute_topology(mesh).components.size() == static_cast<std::size_t>(pages));
  }
  const fx::Soup in = fx::tetrahedra_on_one_edge();
  REQUIRE(build_halfedge_mesh(in.positions, in.triangles).error().code == ErrorCode::kNonManifoldEdge);
  const RepairedMesh r = repair_mesh(in.positions, in.triangles);
  const HalfedgeMesh mesh = check_repaired(in, r);
  CHECK(r.counts.non_manifold_edges == 1);
  CHECK(r.counts.reoriented_faces == 0);
  const Topology t = compute_topology(mesh);
  REQUIRE(t.components.size() == 2);
  for (const auto& c : t.components) {
    CHECK(c.faces == 4);
    CHECK(c.boundary_loops == 0);
    CHECK(c.genus == 0);
  }
}

TEST_CASE("faces degenerate after welding are left out and reported, the rest builds") {
  fx::Soup in = fx::icosphere(1);
  const std::size_t sphere_faces = in.triangles.size();
  in.triangles.push_back({3, 7, 7});  // a repeated vertex (two input vertices welded into one)
  in.positions.push_back((in.positions[0] + in.positions[1]) / 2);
  const auto mid = static_cast<std::uint32_t>(in.positions.size() - 1);
  in.positions.push_back(in.positions[0] * 2 - in.positions[1]);  // on the line through 0 and 1
  in.triangles.push_back({0, mid, mid + 1});  // zero area: collinear
  in.triangles.push_back({5, 5, 5});
  const RepairedMesh r = repair_mesh(in.positions, in.triangles);
  const HalfedgeMesh mesh = check_repaired(in, r);
  CHECK(r.counts.degenerate_faces == 3);
  CHECK(r.degenerate_faces == std::vector<std::uint32_t>{static_cast<std::uint32_t>(sphere_faces),
                                                          static_cast<std::uint32_t>(sphere_faces + 1),
                                                          static_cast<std::uint32_t>(sphere_faces + 2)});
  CHECK(r.triangles.size() == sphere_faces);
  CHECK(mesh.is_isolated(VertexId(mid)));  // only in a left-out face: kept, in no face
  CHECK(compute_topology(mesh).boundary_loops.empty());
}

TEST_CASE("a Moebius strip cannot be oriented: a conflicting face is split off, the rest is consistent") {
  const fx::Soup in = fx::moebius(12);
  REQUIRE(build_halfedge_mesh(in.positions, in.triangles).error().code == ErrorCode::kInconsistentOrientation);
  const RepairedMesh r = repair_mesh(in.positions, in.triangles);
  const HalfedgeMesh mesh = check_repaired(in, r);
  CHECK(r.counts.split_off_faces == 1);
  CHECK(r.counts.reoriented_faces > 0);
  // The strip minus one triangle is an orientable disc; the split-off triangle is its own sheet.
  const Topology t = compute_topology(mesh);
  CHECK(t.components.size() == 2);
  CHECK(t.euler_characteristic() == 2);
}

TEST_CASE("everything at once: fin, flipped patch and degenerate faces on one sphere") {
  fx::Soup in = fx::sphere_with_fin(2);
  const fx::Soup flipped = fx::sphere_with_flipped_patch(2, 0.7);
  std::size_t patch = 0;
  for (std::size_t f = 0; f < flipped.triangles.size(); ++f) {
    patch += flipped.triangles[f] != in.triangles[f];
    in.triangles[f] = flipped.triangles[f];
  }
  in.triangles.push_back({2, 9, 2});
  const RepairedMesh r = repair_mesh(in.positions, in.triangles);
  const HalfedgeMesh mesh = check_repaired(in, r);
  CHECK(r.counts.non_manifold_edges == 1);
  CHECK(r.counts.degenerate_faces == 1);
  CHECK(r.counts.reoriented_faces >= patch);
  CHECK(r.counts.reoriented_faces <= patch + 1);  // the fin's one face may be reversed too
  CHECK(count(r.reoriented) == r.counts.reoriented_faces);
  const Topology t = compute_topology(mesh);
  CHECK(t.components.size() == 2);
}

}  // namespace seam_repair_test
