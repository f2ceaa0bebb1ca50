#include <doctest/doctest.h>

#include <algorithm>
#include <numeric>
#include <set>

#include "core/paths/steiner.h"
#include "core/seam/tour.h"
#include "fixtures.h"
#include "skeleton_fixtures.h"
#include "tree_oracle.h"

namespace seam_tour_test {

using namespace seam::core;
namespace fx = seam::fixtures;

namespace {

struct Setup {
  HalfedgeMesh mesh;
  TerminalPaths paths;  // a complete table: it keeps no reference to the mesh or its graph
};

Setup spiky(int spikes, int levels = 3) {
  const auto s = fx::spiky_sphere(levels, fx::spread_directions(spikes));
  Setup out{build_halfedge_mesh(s.soup.positions, s.soup.triangles).value(), {}};
  std::vector<VertexId> terminals;
  for (auto t : s.tips) terminals.push_back(VertexId(t));
  out.paths = compute_terminal_paths(SearchSurface(out.mesh), terminals, 1).value();
  return out;
}

// Prim's algorithm on the complete terminal graph: the reference MST weight.
double prim_weight(const TerminalPaths& paths) {
  return seam::test_oracle::prim_mst_weight(paths.size(), [&](std::size_t u, std::size_t v) { return paths.dist(u, v); });
}

void check_contiguous_closed(const HalfedgeMesh& mesh, const std::vector<HalfedgeId>& walk) {
  REQUIRE_FALSE(walk.empty());
  for (std::size_t i = 0; i < walk.size(); ++i) {
    CHECK(mesh.head(walk[i]) == mesh.tail(walk[(i + 1) % walk.size()]));
  }
}

}  // namespace

TEST_CASE("terminal MST: Kruskal spans the terminals with Prim's weight") {
  for (int spikes : {3, 5, 8}) {
    const Setup s = spiky(spikes);
    const auto mst = terminal_mst(s.paths);
    REQUIRE(mst.size() == s.paths.size() - 1);
    double weight = 0;
    std::vector<std::size_t> comp(s.paths.size());
    std::iota(comp.begin(), comp.end(), 0);
    for (const auto& [i, j] : mst) {
      CHECK(i < j);
      weight += s.paths.dist(i, j);
      const auto ci = comp[i], cj = comp[j];
      CHECK(ci != cj);  // no cycle
      for (auto& c : comp) c = c == cj ? ci : c;
    }
    CHECK(weight == doctest::Approx(prim_weight(s.paths)).epsilon(1e-12));
  }
}

TEST_CASE("the walk around the MST goes in half-edge order and does not self-intersect") {
  for (int spikes : {3, 6, 9}) {
    const Setup s = spiky(spikes);
    auto walk = mst_walk(s.mesh, s.paths);
    REQUIRE(walk.ok());
    const auto halfedges = walk->halfedges();
    check_contiguous_closed(s.mesh, halfedges);
    // Around a tree: every tree edge is walked once in each direction.
    std::set<std::uint32_t> seen;
    for (HalfedgeId h : halfedges) CHECK(seen.insert(h.value()).second);
    for (HalfedgeId h : halfedges) CHECK(seen.count(HalfedgeMesh::twin(h).value()) == 1);
    CHECK(halfedges.size() == 2 * (seen.size() / 2));
    // Half-edge order: the next tour half-edge is the first walk half-edge met sweeping from
    // the incoming half-edge's next around its head (Fig. 6(b)).
    for (std::size_t i = 0; i < halfedges.size(); ++i) {
      HalfedgeId ek = s.mesh.next(halfedges[i]);
      while (!seen.count(ek.value())) ek = s.mesh.next(HalfedgeMesh::twin(ek));
      CHECK(ek == halfedges[(i + 1) % halfedges.size()]);
    }
    CHECK_FALSE(tour_self_intersects(s.mesh, halfedges));
    // Every terminal is visited, leaves once and inner tree nodes more often.
    std::set<std::uint32_t> visited(walk->visits.begin(), walk->visits.end());
    CHECK(visited.size() == s.paths.size());
    CHECK(walk->visits.size() >= s.paths.size());
  }
}

TEST_CASE("Algorithm 1 tells a crossing from a simple loop") {
  const auto soup = fx::icosphere(2);
  const HalfedgeMesh mesh = build_halfedge_mesh(soup.positions, soup.triangles).value();
  // A valence-6 vertex v and its ring n0..n5 counter-clockwise.
  VertexId v;
  for (std::size_t i = 0; i < mesh.num_vertices() && !v.valid(); ++i) {
    if (mesh.valence(VertexId(i)) == 6) v = VertexId(i);
  }
  REQUIRE(v.valid());
  std::vector<VertexId> ring;
  mesh.for_each_outgoing(v, [&](HalfedgeId h) { ring.push_back(mesh.head(h)); });
  REQUIRE(ring.size() == 6);
  auto he = [&](VertexId a, VertexId b) {
    const HalfedgeId h = mesh.find_halfedge(a, b);
    REQUIRE(h.valid());
    return h;
  };
  // n0 -> v -> n3 -> n2 -> n1 -> v -> n4 -> n5 -> n0: passes v twice, crossing itself.
  const std::vector<HalfedgeId> crossing = {he(ring[0], v), he(v, ring[3]), he(ring[3], ring[2]),
                                            he(ring[2], ring[1]), he(ring[1], v), he(v, ring[4]),
                                            he(ring[4], ring[5]), he(ring[5], ring[0])};
  check_contiguous_closed(mesh, crossing);
  CHECK(tour_self_intersects(mesh, crossing));
  // n0 -> v -> n3 -> n4 -> n5 -> n0 is a simple loop, in either direction.
  std::vector<HalfedgeId> loop = {he(ring[0], v), he(v, ring[3]), he(ring[3], ring[4]), he(ring[4], ring[5]),
                                  he(ring[5], ring[0])};
  CHECK_FALSE(tour_self_intersects(mesh, loop));
  std::vector<HalfedgeId> back;
  for (auto it = loop.rbegin(); it != loop.rend(); ++it) back.push_back(HalfedgeMesh::twin(*it));
  CHECK_FALSE(tour_self_intersects(mesh, back));
}

TEST_CASE("Algorithm 2: the tour visits every terminal exactly once, without self-intersection") {
  for (int spikes : {3, 4, 6, 8, 12}) {
    CAPTURE(spikes);
    const Setup s = spiky(spikes);
    auto built = build_tour(s.mesh, s.paths);
    REQUIRE(built.ok());
    const Tour& tour = built->tour;
    const TourStats& stats = built->stats;
    std::vector<std::uint32_t> sorted = tour.visits;
    std::sort(sorted.begin(), sorted.end());
    std::vector<std::uint32_t> all(s.paths.size());
    std::iota(all.begin(), all.end(), 0u);
    CHECK(sorted == all);
    REQUIRE(tour.pieces.size() == tour.visits.size());
    for (std::size_t i = 0; i < tour.visits.size(); ++i) {
      REQUIRE_FALSE(tour.pieces[i].empty());
      CHECK(s.mesh.tail(tour.pieces[i].front()) == s.paths.terminals[tour.visits[i]]);
      CHECK(s.mesh.head(tour.pieces[i].back()) ==
            s.paths.terminals[tour.visits[(i + 1) % tour.visits.size()]]);
    }
    const auto halfedges = tour.halfedges();
    check_contiguous_closed(s.mesh, halfedges);
    CHECK_FALSE(tour_self_intersects(s.mesh, halfedges));
    CHECK(stats.initial_visits - stats.removals - stats.forced_merges >= s.paths.size());
    // Deterministic.
    auto again = build_tour(s.mesh, s.paths);
    REQUIRE(again.ok());
    CHECK(again->tour.visits == tour.visits);
    CHECK(again->tour.pieces == tour.pieces);
  }
}

}  // namespace seam_tour_test
