// Sub-meshes (submesh.h): extract_faces gives a valid mesh whose faces and vertices map back to
// the parent's (same corners, same orientation, same positions), with the documented numbering;
// cone_boundary_loops closes every boundary loop with one apex per loop, in topology order, and
// weighs exactly the apex edges 0; map_edges carries edges across a vertex map and drops the
// ones with no counterpart. Empty and full selections, and selections that are not a manifold,
// are covered.
#include "core/mesh/submesh.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <map>
#include <set>
#include <vector>

#include "core/mesh/topology.h"
#include "fixture_mesh.h"
#include "test_data.h"

namespace seam_submesh_test {

using namespace seam::core;
namespace fx = seam::fixtures;

namespace {

// A triangle as its corners rotated so the smallest comes first: equal for the same oriented
// triangle whatever corner it starts at.
std::array<std::uint32_t, 3> canonical(std::array<std::uint32_t, 3> t) {
  while (t[0] > t[1] || t[0] > t[2]) std::rotate(t.begin(), t.begin() + 1, t.end());
  return t;
}

std::array<std::uint32_t, 3> corners(const HalfedgeMesh& mesh, FaceId f) {
  const auto vs = mesh.face_vertices(f);
  return {vs[0].value(), vs[1].value(), vs[2].value()};
}

// Checks every documented property of extract_faces(parent, faces) against the parent.
void check_extraction(const HalfedgeMesh& parent, const std::vector<FaceId>& faces, const ComponentMesh& part) {
  REQUIRE(check_invariants(part.mesh).ok());
  // Faces keep the given order; vertices are exactly the ones the faces use, ascending.
  CHECK(part.face_to_parent == faces);
  REQUIRE(part.mesh.num_faces() == faces.size());
  std::set<std::uint32_t> used;
  for (FaceId f : faces) {
    for (VertexId v : parent.face_vertices(f)) used.insert(v.value());
  }
  REQUIRE(part.to_parent.size() == used.size());
  CHECK(part.mesh.num_vertices() == used.size());
  std::size_t k = 0;
  for (std::uint32_t v : used) CHECK(part.to_parent[k++].value() == v);
  // Every local face is its parent face, corner for corner up to rotation (same orientation),
  // and every local vertex sits where its parent vertex does.
  for (std::size_t f = 0; f < part.mesh.num_faces(); ++f) {
    auto local = corners(part.mesh, FaceId(f));
    for (auto& v : local) v = part.to_parent[v].value();
    CHECK(canonical(local) == canonical(corners(parent, part.face_to_parent[f])));
  }
  for (std::size_t v = 0; v < part.mesh.num_vertices(); ++v) {
    CHECK(part.mesh.position(VertexId(v)) == parent.position(part.to_parent[v]));
  }
  // The vertex map round-trips: parent -> local -> parent is the identity on used vertices.
  std::map<std::uint32_t, std::uint32_t> local_of;
  for (std::size_t v = 0; v < part.to_parent.size(); ++v) {
    CHECK(local_of.emplace(part.to_parent[v].value(), static_cast<std::uint32_t>(v)).second);
  }
  for (std::uint32_t v : used) CHECK(part.to_parent[local_of.at(v)].value() == v);
}

std::vector<FaceId> faces_of_component(const Topology& topology, std::uint32_t component) {
  std::vector<FaceId> faces;
  for (std::size_t f = 0; f < topology.face_component.size(); ++f) {
    if (topology.face_component[FaceId(f)] == component) faces.push_back(FaceId(f));
  }
  return faces;
}

// A vertex map for map_edges: identity on the first n vertices, invalid on the rest.
std::vector<VertexId> identity_map(std::size_t n, std::size_t size) {
  std::vector<VertexId> map(size, VertexId::invalid());
  for (std::size_t v = 0; v < n; ++v) map[v] = VertexId(v);
  return map;
}

std::vector<EdgeId> all_edges(const HalfedgeMesh& mesh) {
  std::vector<EdgeId> edges;
  for (std::size_t e = 0; e < mesh.num_edges(); ++e) edges.push_back(EdgeId(e));
  return edges;
}

// Checks every documented property of cone_boundary_loops(mesh).
void check_coned(const HalfedgeMesh& mesh, const ConedMesh& coned) {
  REQUIRE(check_invariants(coned.mesh).ok());
  const Topology before = compute_topology(mesh);
  const Topology after = compute_topology(coned.mesh);
  const std::size_t loops = before.boundary_loops.size();
  // Closed, one apex per loop after the original vertices, which keep their ids and positions.
  CHECK(after.boundary_loops.empty());
  CHECK(coned.num_original_vertices == mesh.num_vertices());
  REQUIRE(coned.apexes.size() == loops);
  CHECK(coned.mesh.num_vertices() == mesh.num_vertices() + loops);
  for (std::size_t k = 0; k < loops; ++k) CHECK(coned.apexes[k].index() == mesh.num_vertices() + k);
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
    CHECK(coned.mesh.position(VertexId(v)) == mesh.position(VertexId(v)));
    CHECK_FALSE(coned.is_apex(VertexId(v)));
  }
  // Every original triangle survives with its orientation, plus one cone triangle per
  // boundary edge.
  std::size_t boundary_edges = 0;
  for (const auto& loop : before.boundary_loops) boundary_edges += loop.size();
  CHECK(coned.mesh.num_faces() == mesh.num_faces() + boundary_edges);
  std::set<std::array<std::uint32_t, 3>> coned_faces;
  for (std::size_t f = 0; f < coned.mesh.num_faces(); ++f)
    coned_faces.insert(canonical(corners(coned.mesh, FaceId(f))));
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) CHECK(coned_faces.count(canonical(corners(mesh, FaceId(f)))) == 1);
  // Apex k is joined to exactly the vertices of Topology's loop k, by triangles of nonzero
  // area, at half the loop's mean radius from its centroid.
  for (std::size_t k = 0; k < loops; ++k) {
    std::set<std::uint32_t> loop_vertices;
    Vec3 centroid = Vec3::Zero();
    for (HalfedgeId h : before.boundary_loops[k]) {
      loop_vertices.insert(mesh.tail(h).value());
      centroid += mesh.position(mesh.tail(h));
    }
    centroid /= static_cast<double>(before.boundary_loops[k].size());
    double radius = 0;
    for (HalfedgeId h : before.boundary_loops[k]) radius += (mesh.position(mesh.tail(h)) - centroid).norm();
    radius /= static_cast<double>(before.boundary_loops[k].size());
    std::set<std::uint32_t> ring;
    coned.mesh.for_each_outgoing(coned.apexes[k], [&](HalfedgeId h) { ring.insert(coned.mesh.head(h).value()); });
    CHECK(ring == loop_vertices);
    CHECK((coned.mesh.position(coned.apexes[k]) - centroid).norm() == doctest::Approx(0.5 * radius));
  }
  for (std::size_t f = mesh.num_faces(); f < coned.mesh.num_faces(); ++f) {
    const auto c = corners(coned.mesh, FaceId(f));
    const Vec3& a = coned.mesh.position(VertexId(c[0]));
    const Vec3 n = (coned.mesh.position(VertexId(c[1])) - a).cross(coned.mesh.position(VertexId(c[2])) - a);
    CHECK(n.norm() > 0);
  }
  // Weights: 0 exactly on edges at an apex, the Euclidean length elsewhere.
  REQUIRE(coned.edge_weights.size() == coned.mesh.num_edges());
  for (std::size_t e = 0; e < coned.mesh.num_edges(); ++e) {
    const HalfedgeId h = HalfedgeMesh::halfedge(EdgeId(e));
    const VertexId a = coned.mesh.tail(h);
    const VertexId b = coned.mesh.head(h);
    const bool at_apex = a.index() >= mesh.num_vertices() || b.index() >= mesh.num_vertices();
    CHECK(coned.is_virtual(EdgeId(e)) == at_apex);
    if (at_apex) {
      CHECK(coned.edge_weights[e] == 0.0);
    } else {
      CHECK(coned.edge_weights[e] == doctest::Approx((coned.mesh.position(a) - coned.mesh.position(b)).norm()));
    }
  }
  // Coning a loop caps a hole: every component keeps its genus and becomes closed.
  REQUIRE(after.components.size() == before.components.size());
  for (std::size_t c = 0; c < after.components.size(); ++c) {
    CHECK(after.components[c].genus == before.components[c].genus);
    CHECK(after.components[c].boundary_loops == 0);
  }
}

}  // namespace

TEST_CASE("submesh: extracting one component of a two-component mesh maps faces and vertices back") {
  const HalfedgeMesh mesh =
      fx::build_fixture(fx::join(fx::icosphere(1), fx::translated(fx::torus(12, 6), Vec3(5, 0, 0))));
  const Topology topology = compute_topology(mesh);
  REQUIRE(topology.components.size() == 2);
  for (std::uint32_t c = 0; c < 2; ++c) {
    CAPTURE(c);
    const std::vector<FaceId> faces = faces_of_component(topology, c);
    auto part = extract_faces(mesh, faces);
    REQUIRE(part.ok());
    check_extraction(mesh, faces, *part);
    // The part is that component alone, with its counts and genus.
    const Topology own = compute_topology(part->mesh);
    REQUIRE(own.components.size() == 1);
    CHECK(own.components[0].vertices == topology.components[c].vertices);
    CHECK(own.components[0].edges == topology.components[c].edges);
    CHECK(own.components[0].genus == topology.components[c].genus);
  }
}

TEST_CASE("submesh: a full selection reproduces the mesh, in any face order") {
  const HalfedgeMesh mesh = fx::build_fixture(fx::open_cylinder(10, 4));
  std::vector<FaceId> faces;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) faces.push_back(FaceId(f));
  auto same = extract_faces(mesh, faces);
  REQUIRE(same.ok());
  check_extraction(mesh, faces, *same);
  CHECK(same->mesh.triangles() == mesh.triangles());  // identity vertex map, same face order
  std::reverse(faces.begin(), faces.end());
  auto reversed = extract_faces(mesh, faces);
  REQUIRE(reversed.ok());
  check_extraction(mesh, faces, *reversed);
  CHECK(reversed->mesh.num_edges() == mesh.num_edges());
  CHECK(compute_topology(reversed->mesh).boundary_loops.size() == 2);
}

TEST_CASE("submesh: a patch of a closed surface comes out as a disc with one boundary loop") {
  const HalfedgeMesh mesh = fx::build_fixture(fx::icosphere(2));
  // The faces with every corner above z = 0.5: a spherical cap.
  std::vector<FaceId> faces;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    bool above = true;
    for (VertexId v : mesh.face_vertices(FaceId(f))) above = above && mesh.position(v).z() > 0.5;
    if (above) faces.push_back(FaceId(f));
  }
  REQUIRE(faces.size() > 4);
  REQUIRE(faces.size() < mesh.num_faces());
  auto part = extract_faces(mesh, faces);
  REQUIRE(part.ok());
  check_extraction(mesh, faces, *part);
  const Topology own = compute_topology(part->mesh);
  REQUIRE(own.components.size() == 1);
  CHECK(own.components[0].euler_characteristic == 1);
  CHECK(own.components[0].boundary_loops == 1);
}

TEST_CASE("submesh: every component of a real mesh extracts to a valid mesh, and together they cover it") {
  const HalfedgeMesh mesh = seam::test_data::load_cgal_halfedge("elephant");
  const Topology topology = compute_topology(mesh);
  std::vector<std::uint8_t> seen(mesh.num_faces(), 0);
  for (std::uint32_t c = 0; c < topology.components.size(); ++c) {
    const std::vector<FaceId> faces = faces_of_component(topology, c);
    auto part = extract_faces(mesh, faces);
    REQUIRE(part.ok());
    check_extraction(mesh, faces, *part);
    for (FaceId f : part->face_to_parent) {
      CHECK(seen[f.index()] == 0);
      seen[f.index()] = 1;
    }
  }
  CHECK(std::count(seen.begin(), seen.end(), 1) == static_cast<std::ptrdiff_t>(mesh.num_faces()));
}

TEST_CASE("submesh: an empty selection is kEmptyMesh, faces meeting at a vertex only are kNonManifoldVertex") {
  const HalfedgeMesh mesh = fx::build_fixture(fx::icosphere(1));
  auto empty = extract_faces(mesh, {});
  REQUIRE_FALSE(empty.ok());
  CHECK(empty.error().code == ErrorCode::kEmptyMesh);
  // Two faces around one vertex that share no edge: a bowtie once cut out.
  const VertexId centre(0u);
  std::vector<FaceId> fan;
  mesh.for_each_outgoing(centre, [&](HalfedgeId h) { fan.push_back(mesh.face(h)); });
  REQUIRE(fan.size() >= 5);
  const std::vector<FaceId> bowtie = {fan[0], fan[2]};
  std::set<std::uint32_t> shared;
  for (VertexId v : mesh.face_vertices(bowtie[0])) shared.insert(v.value());
  int common = 0;
  for (VertexId v : mesh.face_vertices(bowtie[1])) common += static_cast<int>(shared.count(v.value()));
  REQUIRE(common == 1);
  auto pinched = extract_faces(mesh, bowtie);
  REQUIRE_FALSE(pinched.ok());
  CHECK(pinched.error().code == ErrorCode::kNonManifoldVertex);
}

TEST_CASE("submesh: a face selected twice is refused with the builder's error, not built") {
  const HalfedgeMesh mesh = fx::build_fixture(fx::icosphere(0));
  const FaceId face(0u);
  // Alone twice: each of its edges is run twice in the same direction.
  auto alone = extract_faces(mesh, std::vector<FaceId>{face, face});
  REQUIRE_FALSE(alone.ok());
  CHECK(alone.error().code == ErrorCode::kInconsistentOrientation);
  // Twice next to a neighbour: their shared edge is in three triangles.
  const FaceId neighbour = mesh.face(HalfedgeMesh::twin(mesh.face_halfedge(face)));
  auto crowded = extract_faces(mesh, std::vector<FaceId>{face, neighbour, face});
  REQUIRE_FALSE(crowded.ok());
  CHECK(crowded.error().code == ErrorCode::kNonManifoldEdge);
}

TEST_CASE("submesh: coning an open cylinder closes both loops into a sphere") {
  const HalfedgeMesh mesh = fx::build_fixture(fx::open_cylinder(12, 3));
  auto coned = cone_boundary_loops(mesh);
  REQUIRE(coned.ok());
  check_coned(mesh, *coned);
  CHECK(coned->apexes.size() == 2);
  CHECK(compute_topology(coned->mesh).components[0].euler_characteristic == 2);
}

TEST_CASE("submesh: coning a flat disc lifts its apex off the plane") {
  const HalfedgeMesh mesh = fx::build_fixture(fx::disc(3, 8));
  auto coned = cone_boundary_loops(mesh);
  REQUIRE(coned.ok());
  check_coned(mesh, *coned);
  REQUIRE(coned->apexes.size() == 1);
  // Centroid at the origin, mean radius 1: the apex is half a radius along the normal (+-z).
  const Vec3 apex = coned->mesh.position(coned->apexes[0]);
  CHECK(apex.head<2>().norm() < 1e-12);
  CHECK(std::abs(apex.z()) == doctest::Approx(0.5));
}

TEST_CASE("submesh: coning several components with several loops gives one apex per loop in topology order") {
  const fx::Soup soup = fx::join(fx::join(fx::disc(2, 8), fx::translated(fx::open_cylinder(8, 2), Vec3(4, 0, 0))),
                                 fx::translated(fx::icosphere(1), Vec3(-4, 0, 0)));
  const HalfedgeMesh mesh = fx::build_fixture(soup);
  auto coned = cone_boundary_loops(mesh);
  REQUIRE(coned.ok());
  check_coned(mesh, *coned);
  CHECK(coned->apexes.size() == 3);
}

TEST_CASE("submesh: coning a real mesh with holes closes every hole") {
  const HalfedgeMesh mesh = seam::test_data::load_cgal_halfedge("mech-holes-shark");
  REQUIRE(compute_topology(mesh).boundary_loops.size() >= 2);
  auto coned = cone_boundary_loops(mesh);
  REQUIRE(coned.ok());
  check_coned(mesh, *coned);
}

TEST_CASE("submesh: a closed mesh comes back from coning unchanged, with its edge lengths as weights") {
  const HalfedgeMesh mesh = fx::build_fixture(fx::torus(10, 5));
  auto coned = cone_boundary_loops(mesh);
  REQUIRE(coned.ok());
  check_coned(mesh, *coned);
  CHECK(coned->apexes.empty());
  CHECK(coned->mesh.triangles() == mesh.triangles());
  CHECK(coned->mesh.num_edges() == mesh.num_edges());
}

TEST_CASE("submesh: map_edges carries edges through a vertex map and drops those without a counterpart") {
  const HalfedgeMesh mesh = fx::build_fixture(fx::open_cylinder(8, 3));
  auto coned_result = cone_boundary_loops(mesh);
  REQUIRE(coned_result.ok());
  const ConedMesh& coned = *coned_result;
  // Original -> coned and back: every original edge round-trips to itself.
  const std::vector<EdgeId> original = all_edges(mesh);
  const std::vector<VertexId> up = identity_map(mesh.num_vertices(), mesh.num_vertices());
  const std::vector<EdgeId> in_coned = map_edges(mesh, up, coned.mesh, original);
  CHECK(in_coned.size() == original.size());
  for (EdgeId e : in_coned) CHECK_FALSE(coned.is_virtual(e));
  const std::vector<VertexId> down = identity_map(mesh.num_vertices(), coned.mesh.num_vertices());
  CHECK(map_edges(coned.mesh, down, mesh, in_coned) == original);
  // Coned -> original over all edges: the apex edges have no counterpart and are dropped, the
  // others land on the edge with the same ends.
  const std::vector<EdgeId> back = map_edges(coned.mesh, down, mesh, all_edges(coned.mesh));
  CHECK(back == original);
  for (std::size_t e = 0; e < coned.mesh.num_edges(); ++e) {
    if (coned.is_virtual(EdgeId(e))) continue;
    const HalfedgeId h = HalfedgeMesh::halfedge(EdgeId(e));
    const HalfedgeId g = mesh.find_halfedge(coned.mesh.tail(h), coned.mesh.head(h));
    REQUIRE(g.valid());
    CHECK(map_edges(coned.mesh, down, mesh, std::vector<EdgeId>{EdgeId(e)}) ==
          std::vector<EdgeId>{HalfedgeMesh::edge(g)});
  }
  // Output sorted and unique whatever the input order and repetitions.
  std::vector<EdgeId> messy(original.rbegin(), original.rend());
  messy.insert(messy.end(), original.begin(), original.end());
  CHECK(map_edges(mesh, up, coned.mesh, messy) == in_coned);
  CHECK(map_edges(mesh, up, coned.mesh, {}).empty());
}

TEST_CASE("submesh: map_edges drops edges whose ends are not adjacent or collapse to one vertex") {
  const HalfedgeMesh mesh = fx::build_fixture(fx::disc(2, 8));
  const std::vector<EdgeId> edges = all_edges(mesh);
  // A rotation of the disc by one sector maps every edge to an edge; a shift of only the
  // boundary ring by one sector keeps the ring edges but breaks every spoke to the inner ring.
  auto shifted = [](std::uint32_t v, int ring_lo, int sectors) {
    if (static_cast<int>(v) < ring_lo) return v;
    const int r = (static_cast<int>(v) - 1) / sectors;
    const int k = (static_cast<int>(v) - 1) % sectors;
    return static_cast<std::uint32_t>(1 + r * sectors + (k + 1) % sectors);
  };
  std::vector<VertexId> rotate(mesh.num_vertices()), outer_only(mesh.num_vertices()), collapse(mesh.num_vertices());
  for (std::uint32_t v = 0; v < mesh.num_vertices(); ++v) {
    rotate[v] = VertexId(shifted(v, 1, 8));
    outer_only[v] = VertexId(shifted(v, 9, 8));
    collapse[v] = VertexId(0u);
  }
  // Oracle: an edge survives iff its mapped ends are distinct and adjacent in the mesh.
  for (const std::vector<VertexId>* map : {&rotate, &outer_only, &collapse}) {
    std::set<EdgeId> expected;
    for (EdgeId e : edges) {
      const HalfedgeId h = HalfedgeMesh::halfedge(e);
      const VertexId a = (*map)[mesh.tail(h).index()];
      const VertexId b = (*map)[mesh.head(h).index()];
      if (a == b) continue;
      const HalfedgeId g = mesh.find_halfedge(a, b);
      if (g.valid()) expected.insert(HalfedgeMesh::edge(g));
    }
    const std::vector<EdgeId> got = map_edges(mesh, *map, mesh, edges);
    CHECK(got == std::vector<EdgeId>(expected.begin(), expected.end()));
  }
  CHECK(map_edges(mesh, rotate, mesh, edges).size() == edges.size());
  CHECK(map_edges(mesh, collapse, mesh, edges).empty());
  const std::size_t kept = map_edges(mesh, outer_only, mesh, edges).size();
  CHECK(kept < edges.size());
  CHECK(kept >= 8 + 8 + 8);  // the inner ring's edges and spokes to the centre, the outer ring
}

}  // namespace seam_submesh_test
