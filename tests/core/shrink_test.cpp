// Algorithm 3 (shrink_tour): the marks fill exactly the tour's interior, every piece's wave
// enters it, and the skeleton is exactly where two marks meet.
#include <doctest/doctest.h>

#include <set>
#include <vector>

#include "core/paths/steiner.h"
#include "core/seam/shrink.h"
#include "core/seam/tour.h"
#include "fixtures.h"
#include "skeleton_fixtures.h"

namespace seam_shrink_test {

using namespace seam::core;
namespace fx = seam::fixtures;

namespace {

HalfedgeMesh sphere(int levels) {
  const auto s = fx::icosphere(levels);
  return build_halfedge_mesh(s.positions, s.triangles).value();
}

// The faces on the right of the tour, flooded across every edge that is not on the tour.
std::vector<std::uint8_t> interior_faces(const HalfedgeMesh& mesh, const Tour& tour) {
  std::vector<std::uint8_t> on_tour(mesh.num_edges(), 0), inside(mesh.num_faces(), 0);
  std::vector<FaceId> stack;
  for (const auto& piece : tour.pieces) {
    for (HalfedgeId h : piece) on_tour[HalfedgeMesh::edge(h).index()] = 1;
  }
  for (const auto& piece : tour.pieces) {
    for (HalfedgeId h : piece) {
      const FaceId right = mesh.face(HalfedgeMesh::twin(h));
      if (!inside[right.index()]) inside[right.index()] = 1, stack.push_back(right);
    }
  }
  while (!stack.empty()) {
    const FaceId f = stack.back();
    stack.pop_back();
    HalfedgeId h = mesh.face_halfedge(f);
    for (int i = 0; i < 3; ++i, h = mesh.next(h)) {
      if (on_tour[HalfedgeMesh::edge(h).index()]) continue;
      const FaceId g = mesh.face(HalfedgeMesh::twin(h));
      if (!inside[g.index()]) inside[g.index()] = 1, stack.push_back(g);
    }
  }
  return inside;
}

}  // namespace

TEST_CASE("shrink_tour: a tour around one vertex's fan in two pieces meets along exactly two spokes") {
  const HalfedgeMesh mesh = sphere(2);
  const VertexId centre(0u);
  // The fan's outer half-edges a -> b have the fan face on their left; the tour runs their
  // twins b -> a, which keeps the fan on its right (the interior).
  std::vector<HalfedgeId> ring;
  std::vector<FaceId> fan;
  mesh.for_each_outgoing(centre, [&](HalfedgeId out) {
    ring.push_back(HalfedgeMesh::twin(mesh.next(out)));
    fan.push_back(mesh.face(out));
  });
  const std::size_t n = ring.size();
  REQUIRE(n >= 5);
  // The walk must be contiguous: order the twins so each ends where the next starts.
  Tour tour;
  tour.visits = {0, 1};
  std::vector<HalfedgeId> walk{ring[0]};
  while (walk.size() < n) {
    for (HalfedgeId h : ring) {
      if (mesh.tail(h) == mesh.head(walk.back()) && h != walk.front()) {
        walk.push_back(h);
        break;
      }
    }
  }
  REQUIRE(mesh.head(walk.back()) == mesh.tail(walk.front()));
  const std::size_t split = n / 2;
  tour.pieces = {std::vector<HalfedgeId>(walk.begin(), walk.begin() + split),
                 std::vector<HalfedgeId>(walk.begin() + split, walk.end())};
  auto shrunk = shrink_tour(mesh, tour);
  REQUIRE(shrunk.ok());
  // Every fan face takes the mark of its own tour edge; nothing outside is marked.
  std::set<std::uint32_t> fan_faces;
  for (std::size_t p = 0; p < 2; ++p) {
    for (HalfedgeId h : tour.pieces[p]) {
      const FaceId f = mesh.face(HalfedgeMesh::twin(h));
      fan_faces.insert(f.value());
      CHECK(shrunk->face_mark[f.index()] == static_cast<std::int32_t>(p));
    }
  }
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    if (!fan_faces.count(static_cast<std::uint32_t>(f))) CHECK(shrunk->face_mark[f] == -1);
  }
  // The skeleton: the spokes from the centre to the two vertices where the pieces change.
  std::vector<EdgeId> expected = {HalfedgeMesh::edge(mesh.find_halfedge(centre, mesh.tail(tour.pieces[0].front()))),
                                  HalfedgeMesh::edge(mesh.find_halfedge(centre, mesh.tail(tour.pieces[1].front())))};
  std::sort(expected.begin(), expected.end());
  CHECK(shrunk->skeleton == expected);
}

TEST_CASE("shrink_tour on a real tour: marks fill the interior, skeleton exactly where two marks meet") {
  for (int spikes : {3, 5, 7}) {
    CAPTURE(spikes);
    const auto s = fx::spiky_sphere(3, fx::spread_directions(spikes));
    const HalfedgeMesh mesh = build_halfedge_mesh(s.soup.positions, s.soup.triangles).value();
    const SearchSurface surface(mesh);
    std::vector<VertexId> terminals;
    for (auto t : s.tips) terminals.push_back(VertexId(t));
    auto paths = compute_terminal_paths(surface, terminals, 1);
    REQUIRE(paths.ok());
    auto built = build_tour(mesh, *paths);
    REQUIRE(built.ok());
    const Tour& tour = built->tour;
    auto shrunk = shrink_tour(mesh, tour);
    REQUIRE(shrunk.ok());
    const auto inside = interior_faces(mesh, tour);
    std::vector<std::uint8_t> on_tour_face(mesh.num_faces(), 0);
    for (const auto& piece : tour.pieces) {
      for (HalfedgeId h : piece) on_tour_face[mesh.face(h).index()] = on_tour_face[mesh.face(HalfedgeMesh::twin(h)).index()] = 1;
    }
    // A face with tour half-edges takes the majority of its half-edges' marks, which an
    // outside face with two tour half-edges may hold too: only the others are compared.
    for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
      CAPTURE(f);
      if (!on_tour_face[f]) CHECK((shrunk->face_mark[f] >= 0) == (inside[f] != 0));
      if (inside[f]) CHECK(shrunk->face_mark[f] >= 0);
    }
    // Where neither face touches the tour, an edge is on the skeleton exactly when its two
    // faces carry different marks.
    const std::set<EdgeId> skeleton(shrunk->skeleton.begin(), shrunk->skeleton.end());
    for (std::size_t e = 0; e < mesh.num_edges(); ++e) {
      const HalfedgeId h = HalfedgeMesh::halfedge(EdgeId(e));
      const FaceId a = mesh.face(h), b = mesh.face(HalfedgeMesh::twin(h));
      if (on_tour_face[a.index()] || on_tour_face[b.index()]) continue;
      CAPTURE(e);
      CHECK(skeleton.count(EdgeId(e)) == (shrunk->face_mark[a.index()] != shrunk->face_mark[b.index()] ? 1u : 0u));
    }
    // Every piece's wave enters the interior: each mark appears on some face.
    std::set<std::int32_t> marks(shrunk->face_mark.begin(), shrunk->face_mark.end());
    for (std::size_t piece = 0; piece < tour.pieces.size(); ++piece) CHECK(marks.count(static_cast<std::int32_t>(piece)) == 1);
  }
}

TEST_CASE("shrink_tour reports cancellation") {
  const HalfedgeMesh mesh = sphere(5);  // enough half-edges for the token to be polled
  std::vector<HalfedgeId> ring;
  mesh.for_each_outgoing(VertexId(0u), [&](HalfedgeId out) { ring.push_back(HalfedgeMesh::twin(mesh.next(out))); });
  Tour tour;
  tour.visits = {0};
  tour.pieces = {ring};
  CancelToken token;
  token.cancel();
  auto r = shrink_tour(mesh, tour, token);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == ErrorCode::kCancelled);
}

}  // namespace seam_shrink_test
