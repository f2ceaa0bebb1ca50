#include <doctest/doctest.h>

#include <algorithm>
#include <map>
#include <vector>

#include "core/seam/tree_util.h"
#include "fixture_mesh.h"

namespace seam_tree_util_test {

using namespace seam::core;
using namespace seam::core::detail;
namespace fx = seam::fixtures;

namespace {

// A walk from vertex 0 along first out-going half-edges, never revisiting a vertex.
std::vector<HalfedgeId> simple_walk(const HalfedgeMesh& mesh, std::size_t steps) {
  std::vector<HalfedgeId> path;
  std::vector<std::uint8_t> seen(mesh.num_vertices(), 0);
  VertexId v(0u);
  seen[0] = 1;
  while (path.size() < steps) {
    HalfedgeId next;
    mesh.for_each_outgoing(v, [&](HalfedgeId h) {
      if (!next.valid() && !seen[mesh.head(h).index()]) next = h;
    });
    REQUIRE(next.valid());
    path.push_back(next);
    v = mesh.head(next);
    seen[v.index()] = 1;
  }
  return path;
}

}  // namespace

TEST_CASE("TreeVertices: sorted vertices, each edge's ends by index, and each vertex's ends") {
  const HalfedgeMesh mesh = fx::build_fixture(fx::icosphere(2));
  const std::vector<HalfedgeId> walk = simple_walk(mesh, 12);
  std::vector<EdgeId> edges;
  for (HalfedgeId h : walk) edges.push_back(HalfedgeMesh::edge(h));
  std::reverse(edges.begin(), edges.end());  // not in vertex order
  const TreeVertices tree(mesh, edges);
  REQUIRE(tree.size() == edges.size() + 1);
  CHECK(std::is_sorted(tree.vertices.begin(), tree.vertices.end()));
  std::map<std::uint32_t, std::uint32_t> degree;  // by tree index, counted from the mesh
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const HalfedgeId h = HalfedgeMesh::halfedge(edges[i]);
    CHECK(tree.vertices[tree.ends[2 * i]] == mesh.tail(h));
    CHECK(tree.vertices[tree.ends[2 * i + 1]] == mesh.head(h));
    CHECK(tree.index(mesh.tail(h)) == tree.ends[2 * i]);
    ++degree[tree.ends[2 * i]];
    ++degree[tree.ends[2 * i + 1]];
  }
  const TreeVertices::Incidence incidence = tree.incidence();
  REQUIRE(incidence.offsets.size() == tree.size() + 1);
  for (std::uint32_t v = 0; v < tree.size(); ++v) {
    CHECK(incidence.degree(v) == degree[v]);
    for (std::uint32_t k = incidence.offsets[v]; k < incidence.offsets[v + 1]; ++k) {
      CHECK(tree.ends[incidence.slots[k]] == v);
      if (k > incidence.offsets[v]) CHECK(incidence.slots[k - 1] < incidence.slots[k]);
    }
  }
}

TEST_CASE("prune_dangling: a chain off the path between two terminals goes, the path stays") {
  const HalfedgeMesh mesh = fx::build_fixture(fx::icosphere(2));
  const std::vector<HalfedgeId> walk = simple_walk(mesh, 10);
  std::vector<EdgeId> edges;
  for (HalfedgeId h : walk) edges.push_back(HalfedgeMesh::edge(h));
  // Terminals at vertex 0 and after 6 steps: the last 4 edges dangle beyond the second.
  const std::vector<VertexId> terminals = {mesh.tail(walk[0]), mesh.head(walk[5])};
  const std::vector<EdgeId> kept = prune_dangling(mesh, edges, terminals);
  CHECK(kept == std::vector<EdgeId>(edges.begin(), edges.begin() + 6));
  // With the far end a terminal as well nothing dangles.
  const std::vector<VertexId> ends = {mesh.tail(walk[0]), mesh.head(walk.back())};
  CHECK(prune_dangling(mesh, edges, ends) == edges);
}

}  // namespace seam_tree_util_test
