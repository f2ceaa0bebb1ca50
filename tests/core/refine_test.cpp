#include <doctest/doctest.h>

#include <functional>
#include <map>
#include <random>
#include <set>

#include "core/seam/baselines.h"
#include "core/seam/refine.h"
#include "core/seam/skeleton.h"
#include "core/seam/straighten.h"
#include "core/paths/steiner.h"
#include "fixtures.h"
#include "tree_oracle.h"
#include "skeleton_fixtures.h"
#include "test_data.h"

namespace seam_refine_test {

using namespace seam::core;
namespace fx = seam::fixtures;

using seam::test_oracle::full_component_length;

namespace {

std::vector<VertexId> random_terminals(const HalfedgeMesh& mesh, std::size_t k, std::mt19937& rng) {
  std::vector<VertexId> terminals;
  while (terminals.size() < k) {
    const VertexId v(static_cast<std::uint32_t>(rng() % mesh.num_vertices()));
    if (std::find(terminals.begin(), terminals.end(), v) == terminals.end()) terminals.push_back(v);
  }
  return terminals;
}

// The paper's skeleton seam (no refinement, no improvement) through `terminals`.
SkeletonResult paper_skeleton(const SearchSurface& surface, const std::vector<VertexId>& terminals) {
  auto paths = compute_terminal_paths(surface, terminals, 1);
  REQUIRE(paths.ok());
  auto skeleton = skeleton_seam(surface, *paths, {.refine = false, .improve = false});
  REQUIRE(skeleton.ok());
  return std::move(skeleton).value();
}

}  // namespace

TEST_CASE("refine_tree on small terminal sets: a full component, never longer, never below the exact optimum") {
  const HalfedgeMesh mesh = seam::test_data::load_cgal_halfedge("hand");
  const SearchSurface surface(mesh);
  std::mt19937 rng(41);
  int shortened = 0;
  for (int trial = 0; trial < 8; ++trial) {
    const auto terminals = random_terminals(mesh, 3 + static_cast<std::size_t>(trial % 4), rng);
    CAPTURE(trial);
    const SkeletonResult skeleton = paper_skeleton(surface, terminals);
    const double before = full_component_length(mesh, skeleton.tree.edges, terminals);
    auto refined = refine_tree(surface, terminals, skeleton.tree.edges);
    REQUIRE(refined.ok());
    const RefineStats& stats = refined->stats;
    const double after = full_component_length(mesh, refined->edges, terminals);
    CHECK(after <= before + 1e-12);
    CHECK(stats.length_before == doctest::Approx(before));
    CHECK(stats.length_after == doctest::Approx(after));
    CHECK((stats.improvements > 0) == (after < before - 1e-12));
    auto optimal = optimal_seam(surface, terminals, 10);
    REQUIRE(optimal.ok());
    CHECK(optimal->length <= after + 1e-9);
    if (after < before - 1e-12) ++shortened;
    // Deterministic: the same input gives the same tree.
    auto again = refine_tree(surface, terminals, skeleton.tree.edges);
    REQUIRE(again.ok());
    CHECK(again->edges == refined->edges);
  }
  CHECK(shortened > 0);  // the paper's skeleton on random sets leaves room to refine
}

TEST_CASE("the star-tree fallback is a full component that refinement shortens") {
  const auto s = fx::spiky_sphere(3, fx::spread_directions(5));
  const HalfedgeMesh mesh = build_halfedge_mesh(s.soup.positions, s.soup.triangles).value();
  std::vector<VertexId> tips;
  for (auto t : s.tips) tips.push_back(VertexId(t));
  const SearchSurface surface(mesh);
  auto star = star_tree(surface, tips);
  REQUIRE(star.ok());
  const double star_length = full_component_length(mesh, *star, tips);
  auto refined = refine_tree(surface, tips, *star);
  REQUIRE(refined.ok());
  const double after = full_component_length(mesh, refined->edges, tips);
  CHECK(after < star_length);
  auto optimal = optimal_seam(surface, tips, 10);
  REQUIRE(optimal.ok());
  CHECK(optimal->length <= after + 1e-9);
}

TEST_CASE("refine_tree refuses a tree whose terminal is not a leaf") {
  const auto s = fx::spiky_sphere(2, fx::spread_directions(3));
  const HalfedgeMesh mesh = build_halfedge_mesh(s.soup.positions, s.soup.triangles).value();
  const SearchSurface surface(mesh);
  std::vector<VertexId> tips;
  for (auto t : s.tips) tips.push_back(VertexId(t));
  // Two edges at the first tip: it is not a leaf of this (path) tree.
  const VertexId t = tips[0];
  const HalfedgeId h0 = mesh.vertex_halfedge(t);
  const std::vector<EdgeId> edges = {HalfedgeMesh::edge(h0), HalfedgeMesh::edge(mesh.next(HalfedgeMesh::twin(h0)))};
  auto r = refine_tree(surface, tips, edges);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == ErrorCode::kInvalidArgument);
}

TEST_CASE("refine_tree equals the exact optimum when one piece holds the whole tree (3-4 terminals)") {
  // With 3 terminals the one Steiner point, and with 4 the two adjacent ones, make a piece
  // whose branches are the whole tree; with a reach that cuts them entirely and a region that
  // is the whole mesh, the local problem is the global one, so the result must be the
  // Dreyfus-Wagner optimum (an independent solve on the whole graph).
  const auto sphere = fx::icosphere(3);
  const HalfedgeMesh mesh = build_halfedge_mesh(sphere.positions, sphere.triangles).value();
  const SearchSurface surface(mesh);
  std::mt19937 rng(7);
  int whole_pieces = 0;
  for (int trial = 0; trial < 12; ++trial) {
    const auto terminals = random_terminals(mesh, 3 + static_cast<std::size_t>(trial % 2), rng);
    CAPTURE(trial);
    const SkeletonResult skeleton = paper_skeleton(surface, terminals);
    // Only trees with the full topology (k - 2 Steiner points of degree 3) are one piece.
    if (skeleton.tree.steiner_points.size() + 2 != terminals.size()) continue;
    ++whole_pieces;
    const RefineOptions options{.max_ports = 5, .max_region = mesh.num_vertices(), .max_work = SIZE_MAX, .reach = 100.0};
    auto refined = refine_tree(surface, terminals, skeleton.tree.edges, options);
    REQUIRE(refined.ok());
    auto optimal = optimal_seam(surface, terminals, 10);
    REQUIRE(optimal.ok());
    CHECK(full_component_length(mesh, refined->edges, terminals) == doctest::Approx(optimal->length).epsilon(1e-9));
  }
  CHECK(whole_pieces >= 4);
}

TEST_CASE("the forced star-tree fallback: flagged, a full component, refined and moved towards the optimum") {
  const HalfedgeMesh mesh = seam::test_data::load_cgal_halfedge("hand");
  const SearchSurface surface(mesh);
  std::mt19937 rng(3);
  for (int trial = 0; trial < 4; ++trial) {
    const auto terminals = random_terminals(mesh, 4 + static_cast<std::size_t>(trial), rng);
    CAPTURE(trial);
    auto paths = compute_terminal_paths(surface, terminals, 1);
    REQUIRE(paths.ok());
    auto plain = skeleton_seam(surface, *paths, {.refine = false, .improve = false, .paper_steps = false});
    auto refined = skeleton_seam(surface, *paths, {.refine = true, .improve = true, .paper_steps = false});
    REQUIRE(plain.ok());
    REQUIRE(refined.ok());
    CHECK(plain->stats.fallback);
    CHECK(refined->stats.fallback);
    // The star tree as returned is star_tree's, and a full component.
    auto star = star_tree(surface, terminals);
    REQUIRE(star.ok());
    const double star_length = full_component_length(mesh, *star, terminals);
    CHECK(full_component_length(mesh, plain->tree.edges, terminals) == doctest::Approx(star_length));
    const double after = full_component_length(mesh, refined->tree.edges, terminals);
    CHECK(after <= star_length + 1e-12);
    auto optimal = optimal_seam(surface, terminals, 10);
    REQUIRE(optimal.ok());
    CHECK(optimal->length <= after + 1e-9);
  }
}

TEST_CASE("refine_tree's shortcuts (lower-bound skips, reused regions) leave every result unchanged") {
  // The plain run (shortcuts off) solves every local problem and searches every region: an
  // independent oracle for the skips, which must give the same tree, move for move.
  const HalfedgeMesh mesh = seam::test_data::load_cgal_halfedge("hand");
  const SearchSurface surface(mesh);
  std::mt19937 rng(97);
  std::size_t ruled_out = 0, saved_searches = 0;
  for (int trial = 0; trial < 10; ++trial) {
    const auto terminals = random_terminals(mesh, 4 + static_cast<std::size_t>(trial % 6), rng);
    CAPTURE(trial);
    const SkeletonResult skeleton = paper_skeleton(surface, terminals);
    RefineOptions plain_options;
    plain_options.shortcuts = false;
    auto plain = refine_tree(surface, terminals, skeleton.tree.edges, plain_options);
    auto fast = refine_tree(surface, terminals, skeleton.tree.edges);
    REQUIRE(plain.ok());
    REQUIRE(fast.ok());
    CHECK(fast->edges == plain->edges);
    CHECK(fast->stats.length_after == plain->stats.length_after);
    CHECK(fast->stats.improvements == plain->stats.improvements);
    CHECK(fast->stats.pieces_solved == plain->stats.pieces_solved);
    CHECK(plain->stats.pieces_ruled_out == 0);
    CHECK(fast->stats.region_searches <= plain->stats.region_searches);
    ruled_out += fast->stats.pieces_ruled_out;
    saved_searches += plain->stats.region_searches - fast->stats.region_searches;
  }
  CHECK(ruled_out > 0);
  CHECK(saved_searches > 0);
}

}  // namespace seam_refine_test
