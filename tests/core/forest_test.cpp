// pruned_spanning_forest: against a Kruskal and a leaf-peeling written here (same edges,
// exactly), against an exhaustive search over every edge subset on small graphs (minimum
// weight), and on the documented properties: a forest, leaves only at kept or merged vertices,
// every pair of kept vertices still connected, the merged set touched as one node.
#include "core/paths/forest.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <functional>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <vector>

#include "fixture_mesh.h"

namespace seam_forest_test {

using namespace seam::core;
namespace fx = seam::fixtures;

namespace {

constexpr std::int64_t kSuper = -1;  // the node all merged vertices become

struct Oracle {
  const HalfedgeMesh& mesh;
  std::vector<double> weights;  // empty: Euclidean
  std::set<std::uint32_t> merged;

  double weight(EdgeId e) const {
    if (!weights.empty()) return weights[e.index()];
    const HalfedgeId h = HalfedgeMesh::halfedge(e);
    return (mesh.position(mesh.head(h)) - mesh.position(mesh.tail(h))).norm();
  }
  std::int64_t node(VertexId v) const {
    return merged.count(v.value()) ? kSuper : static_cast<std::int64_t>(v.value());
  }
  std::pair<std::int64_t, std::int64_t> ends(EdgeId e) const {
    const HalfedgeId h = HalfedgeMesh::halfedge(e);
    return {node(mesh.tail(h)), node(mesh.head(h))};
  }

  // Textbook Kruskal over (weight, edge id) with a map-based union-find.
  std::vector<EdgeId> kruskal(const std::vector<EdgeId>& edges) const {
    std::set<std::pair<double, std::uint32_t>> order;
    for (EdgeId e : edges) order.insert({weight(e), e.value()});
    std::map<std::int64_t, std::int64_t> parent;
    std::function<std::int64_t(std::int64_t)> find = [&](std::int64_t x) {
      if (!parent.count(x)) parent[x] = x;
      return parent[x] == x ? x : parent[x] = find(parent[x]);
    };
    std::vector<EdgeId> out;
    for (const auto& [w, id] : order) {
      const auto [a, b] = ends(EdgeId(id));
      const auto ra = find(a), rb = find(b);
      if (ra == rb) continue;
      parent[ra] = rb;
      out.push_back(EdgeId(id));
    }
    return out;
  }

  // Removes, one at a time until none is left, an edge at a leaf node that is neither kept
  // nor the merged node.
  std::vector<EdgeId> peel(std::vector<EdgeId> forest, const std::set<std::uint32_t>& keep) const {
    for (bool changed = true; changed;) {
      changed = false;
      std::map<std::int64_t, int> degree;
      for (EdgeId e : forest) {
        const auto [a, b] = ends(e);
        ++degree[a];
        ++degree[b];
      }
      for (auto it = forest.begin(); it != forest.end(); ++it) {
        const auto [a, b] = ends(*it);
        auto removable = [&](std::int64_t n) {
          return n != kSuper && degree[n] == 1 && !keep.count(static_cast<std::uint32_t>(n));
        };
        if (removable(a) || removable(b)) {
          forest.erase(it);
          changed = true;
          break;
        }
      }
    }
    std::sort(forest.begin(), forest.end());
    return forest;
  }

  // Connected components of an edge set over nodes (merged vertices as one node): each node
  // touched mapped to the smallest node of its component, so equal maps mean equal partitions.
  std::map<std::int64_t, std::int64_t> components(const std::vector<EdgeId>& edges) const {
    std::map<std::int64_t, std::int64_t> parent;
    std::function<std::int64_t(std::int64_t)> find = [&](std::int64_t x) {
      if (!parent.count(x)) parent[x] = x;
      return parent[x] == x ? x : parent[x] = find(parent[x]);
    };
    for (EdgeId e : edges) {
      const auto [a, b] = ends(e);
      parent[find(a)] = find(b);
    }
    std::map<std::int64_t, std::int64_t> smallest;  // root -> smallest node
    for (const auto& entry : parent) {
      const std::int64_t r = find(entry.first);
      auto [it, inserted] = smallest.try_emplace(r, entry.first);
      if (!inserted) it->second = std::min(it->second, entry.first);
    }
    std::map<std::int64_t, std::int64_t> label;
    for (const auto& entry : parent) label[entry.first] = smallest.at(find(entry.first));
    return label;
  }

  bool is_forest(const std::vector<EdgeId>& edges) const {
    std::set<std::int64_t> nodes;
    for (EdgeId e : edges) {
      const auto [a, b] = ends(e);
      if (a == b) return false;
      nodes.insert(a);
      nodes.insert(b);
    }
    std::set<std::int64_t> roots;
    for (const auto& [n, r] : components(edges)) roots.insert(r);
    return edges.size() + roots.size() == nodes.size();  // acyclic: E = V - components
  }

  bool connected(const std::map<std::int64_t, std::int64_t>& comp, std::int64_t a, std::int64_t b) const {
    if (a == b) return true;
    auto ia = comp.find(a), ib = comp.find(b);
    return ia != comp.end() && ib != comp.end() && ia->second == ib->second;
  }
};

// Every documented property of `out` = pruned_spanning_forest(edges, keep, ...) that does not
// depend on tie-breaking.
void check_properties(const Oracle& oracle, const std::vector<EdgeId>& edges, const std::vector<VertexId>& keep,
                      const std::vector<EdgeId>& out) {
  CHECK(std::is_sorted(out.begin(), out.end()));
  CHECK(std::adjacent_find(out.begin(), out.end()) == out.end());
  const std::set<EdgeId> given(edges.begin(), edges.end());
  for (EdgeId e : out) CHECK(given.count(e) == 1);
  CHECK(oracle.is_forest(out));
  // No dangling branch: every leaf node is kept or the merged node.
  std::set<std::uint32_t> kept;
  for (VertexId v : keep) kept.insert(v.value());
  std::map<std::int64_t, int> degree;
  for (EdgeId e : out) {
    const auto [a, b] = oracle.ends(e);
    ++degree[a];
    ++degree[b];
  }
  for (const auto& [n, d] : degree) {
    if (d == 1 && n != kSuper) CHECK_MESSAGE(kept.count(static_cast<std::uint32_t>(n)) == 1, "dangling leaf " << n);
  }
  // Kept vertices (and the merged node) connected in the input stay connected.
  const auto before = oracle.components(edges);
  const auto after = oracle.components(out);
  std::vector<std::int64_t> terminals;
  for (VertexId v : keep) terminals.push_back(oracle.node(v));
  if (!oracle.merged.empty()) terminals.push_back(kSuper);
  for (std::int64_t a : terminals) {
    for (std::int64_t b : terminals) {
      if (oracle.connected(before, a, b)) CHECK_MESSAGE(oracle.connected(after, a, b), a << " and " << b << " split");
    }
  }
}

// One weight per edge of `mesh`, uniform in [low, high).
std::vector<double> random_weights(const HalfedgeMesh& mesh, double low, double high, std::mt19937& rng) {
  std::uniform_real_distribution<double> uniform(low, high);
  std::vector<double> weights(mesh.num_edges());
  for (double& w : weights) w = uniform(rng);
  return weights;
}

double total_weight(const std::vector<EdgeId>& edges, const std::vector<double>& weights) {
  double total = 0;
  for (EdgeId e : edges) total += weights[e.index()];
  return total;
}

std::vector<EdgeId> random_edges(const HalfedgeMesh& mesh, std::size_t count, std::mt19937& rng) {
  std::vector<EdgeId> all;
  for (std::size_t e = 0; e < mesh.num_edges(); ++e) all.push_back(EdgeId(e));
  std::shuffle(all.begin(), all.end(), rng);
  all.resize(std::min(count, all.size()));
  return all;
}

}  // namespace

TEST_CASE("forest: keeping every vertex gives the minimum spanning forest, equal to brute force over all subsets") {
  const HalfedgeMesh mesh = fx::build_fixture(fx::icosphere(0));
  std::mt19937 rng(7);
  for (int trial = 0; trial < 12; ++trial) {
    CAPTURE(trial);
    const std::vector<double> weights = random_weights(mesh, 0.5, 2.0, rng);
    const std::vector<EdgeId> edges = random_edges(mesh, 10 + trial % 5, rng);
    std::vector<VertexId> keep;
    for (std::size_t v = 0; v < mesh.num_vertices(); ++v) keep.push_back(VertexId(v));
    const Oracle oracle{mesh, weights, {}};
    const std::vector<EdgeId> out = pruned_spanning_forest(mesh, edges, keep, weights);
    check_properties(oracle, edges, keep, out);
    // Spanning: the same components as the input edges.
    CHECK(oracle.components(out) == oracle.components(edges));
    // Minimum: no acyclic subset with the same components weighs less.
    double best = std::numeric_limits<double>::infinity();
    const auto target = oracle.components(edges);
    std::set<std::int64_t> labels;
    for (const auto& entry : target) labels.insert(entry.second);
    const std::size_t forest_size = target.size() - labels.size();
    for (std::uint32_t mask = 0; mask < (1u << edges.size()); ++mask) {
      if (static_cast<std::size_t>(std::popcount(mask)) != forest_size) continue;  // nodes - components edges
      std::vector<EdgeId> subset;
      for (std::size_t i = 0; i < edges.size(); ++i) {
        if (mask & (1u << i)) subset.push_back(edges[i]);
      }
      if (!oracle.is_forest(subset) || oracle.components(subset) != target) continue;
      best = std::min(best, total_weight(subset, weights));
    }
    CHECK(total_weight(out, weights) == doctest::Approx(best).epsilon(1e-12));
  }
}

TEST_CASE("forest: equals Kruskal then leaf peeling written in the test, with random keep sets") {
  const HalfedgeMesh mesh = fx::build_fixture(fx::icosphere(2));
  std::mt19937 rng(11);
  for (int trial = 0; trial < 30; ++trial) {
    CAPTURE(trial);
    const std::vector<double> weights = random_weights(mesh, 0.1, 1.0, rng);
    const std::vector<EdgeId> edges = random_edges(mesh, 40 + 10 * (trial % 10), rng);
    std::vector<VertexId> keep;
    std::set<std::uint32_t> keep_set;
    for (int k = 0; k < 1 + trial % 6; ++k) {
      const VertexId v(static_cast<std::uint32_t>(rng() % mesh.num_vertices()));
      keep.push_back(v);
      keep_set.insert(v.value());
    }
    const Oracle oracle{mesh, weights, {}};
    const std::vector<EdgeId> out = pruned_spanning_forest(mesh, edges, keep, weights);
    CHECK(out == oracle.peel(oracle.kruskal(edges), keep_set));
    check_properties(oracle, edges, keep, out);
  }
}

TEST_CASE("forest: without weights it uses Euclidean lengths, and breaks ties by edge id") {
  // The torus grid has many edges of equal length: ties decide the tree.
  const HalfedgeMesh mesh = fx::build_fixture(fx::torus(8, 5));
  std::mt19937 rng(3);
  for (int trial = 0; trial < 10; ++trial) {
    CAPTURE(trial);
    const std::vector<EdgeId> edges = random_edges(mesh, 60, rng);
    const std::vector<VertexId> keep = {VertexId(static_cast<std::uint32_t>(rng() % mesh.num_vertices())),
                                        VertexId(static_cast<std::uint32_t>(rng() % mesh.num_vertices())),
                                        VertexId(static_cast<std::uint32_t>(rng() % mesh.num_vertices()))};
    const std::set<std::uint32_t> keep_set = {keep[0].value(), keep[1].value(), keep[2].value()};
    const Oracle euclidean{mesh, {}, {}};
    const std::vector<EdgeId> out = pruned_spanning_forest(mesh, edges, keep);
    CHECK(out == euclidean.peel(euclidean.kruskal(edges), keep_set));
    // All weights equal: Kruskal by edge id alone.
    const std::vector<double> ones(mesh.num_edges(), 1.0);
    const Oracle flat{mesh, ones, {}};
    CHECK(pruned_spanning_forest(mesh, edges, keep, ones) == flat.peel(flat.kruskal(edges), keep_set));
  }
}

TEST_CASE("forest: merged vertices act as one node that every tree reaches once") {
  // A disc with its whole boundary merged: edges along the boundary close cycles through the
  // merged node, so none survives, and each kept interior vertex hangs off the boundary.
  const HalfedgeMesh mesh = fx::build_fixture(fx::disc(5, 12));
  std::vector<VertexId> boundary;
  std::set<std::uint32_t> merged;
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
    if (mesh.is_boundary(VertexId(v))) {
      boundary.push_back(VertexId(v));
      merged.insert(static_cast<std::uint32_t>(v));
    }
  }
  REQUIRE(boundary.size() == 12);
  std::vector<EdgeId> edges;
  for (std::size_t e = 0; e < mesh.num_edges(); ++e) edges.push_back(EdgeId(e));
  std::mt19937 rng(5);
  for (int trial = 0; trial < 10; ++trial) {
    CAPTURE(trial);
    const std::vector<double> weights = random_weights(mesh, 0.1, 1.0, rng);
    std::vector<VertexId> keep;
    std::set<std::uint32_t> keep_set;
    while (keep.size() < 3) {
      const VertexId v(static_cast<std::uint32_t>(rng() % mesh.num_vertices()));
      if (merged.count(v.value()) || keep_set.count(v.value())) continue;
      keep.push_back(v);
      keep_set.insert(v.value());
    }
    const Oracle oracle{mesh, weights, merged};
    const std::vector<EdgeId> out = pruned_spanning_forest(mesh, edges, keep, weights, boundary);
    CHECK(out == oracle.peel(oracle.kruskal(edges), keep_set));
    check_properties(oracle, edges, keep, out);
    REQUIRE_FALSE(out.empty());
    for (EdgeId e : out) {
      const auto [a, b] = oracle.ends(e);
      CHECK_FALSE((a == kSuper && b == kSuper));  // no edge between two merged vertices
    }
    // One tree: every kept vertex reaches the merged node.
    const auto comp = oracle.components(out);
    for (VertexId v : keep) CHECK(oracle.connected(comp, oracle.node(v), kSuper));
    // Without the merge the boundary vertices are ordinary nodes again.
    const std::vector<EdgeId> unmerged = pruned_spanning_forest(mesh, edges, keep, weights);
    const Oracle plain{mesh, weights, {}};
    CHECK(unmerged == plain.peel(plain.kruskal(edges), keep_set));
  }
}

TEST_CASE("forest: a path keeps exactly the stretch between kept vertices") {
  // Ring 1 of a disc is a cycle of 8 edges; take 7 of them as a path v1 - v2 - ... - v8.
  const HalfedgeMesh mesh = fx::build_fixture(fx::disc(2, 8));
  std::vector<EdgeId> path;
  for (std::uint32_t k = 1; k < 8; ++k) {
    const HalfedgeId h = mesh.find_halfedge(VertexId(k), VertexId(k + 1));
    REQUIRE(h.valid());
    path.push_back(HalfedgeMesh::edge(h));
  }
  auto sorted = [](std::vector<EdgeId> v) {
    std::sort(v.begin(), v.end());
    return v;
  };
  // Both ends kept: nothing to prune.
  CHECK(pruned_spanning_forest(mesh, path, std::vector<VertexId>{VertexId(1u), VertexId(8u)}) == sorted(path));
  // Kept at v3 and v6: only the edges v3..v6 stay.
  CHECK(pruned_spanning_forest(mesh, path, std::vector<VertexId>{VertexId(3u), VertexId(6u)}) ==
        sorted({path[2], path[3], path[4]}));
  // One kept vertex needs no edge; no kept vertex at all prunes everything.
  CHECK(pruned_spanning_forest(mesh, path, std::vector<VertexId>{VertexId(4u)}).empty());
  CHECK(pruned_spanning_forest(mesh, path, {}).empty());
  // A kept vertex off the edges changes nothing; the merged node counts as kept.
  CHECK(pruned_spanning_forest(mesh, path, std::vector<VertexId>{VertexId(0u)}).empty());
  CHECK(pruned_spanning_forest(mesh, path, std::vector<VertexId>{VertexId(3u)}, {},
                               std::vector<VertexId>{VertexId(6u)}) == sorted({path[2], path[3], path[4]}));
}

TEST_CASE("forest: empty input, repeated edges and input order do not change the result") {
  const HalfedgeMesh mesh = fx::build_fixture(fx::icosphere(1));
  CHECK(pruned_spanning_forest(mesh, {}, std::vector<VertexId>{VertexId(0u)}).empty());
  std::mt19937 rng(13);
  std::vector<EdgeId> edges = random_edges(mesh, 50, rng);
  const std::vector<VertexId> keep = {VertexId(0u), VertexId(5u), VertexId(9u), VertexId(20u)};
  const std::vector<EdgeId> once = pruned_spanning_forest(mesh, edges, keep);
  std::vector<EdgeId> twice = edges;
  twice.insert(twice.end(), edges.rbegin(), edges.rend());
  CHECK(pruned_spanning_forest(mesh, twice, keep) == once);
  std::shuffle(edges.begin(), edges.end(), rng);
  CHECK(pruned_spanning_forest(mesh, edges, keep) == once);
  check_properties(Oracle{mesh, {}, {}}, edges, keep, once);
}

}  // namespace seam_forest_test
