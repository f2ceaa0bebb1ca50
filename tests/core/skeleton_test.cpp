#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <random>
#include <set>

#include "core/seam/shrink.h"
#include "core/seam/skeleton.h"
#include "core/seam/skeleton_trace.h"
#include "core/paths/steiner.h"
#include "core/seam/straighten.h"
#include "core/seam/tour.h"
#include "fixtures.h"
#include "skeleton_fixtures.h"
#include "test_data.h"

namespace seam_skeleton_test {

using namespace seam::core;
namespace fx = seam::fixtures;

namespace {

TerminalPaths require_paths(const SearchSurface& surface, const std::vector<VertexId>& terminals) {
  auto paths = compute_terminal_paths(surface, terminals, 1);
  REQUIRE(paths.ok());
  return std::move(paths).value();
}

// A mesh, its search surface and its terminals' paths; built in place (the surface refers to
// the mesh), so a Setup is neither copied nor moved.
struct Setup {
  Setup(HalfedgeMesh m, const std::vector<VertexId>& terminals, std::vector<double> weights = {})
      : mesh(std::move(m)), surface(mesh, std::move(weights)), paths(require_paths(surface, terminals)) {}
  Setup(const Setup&) = delete;
  Setup& operator=(const Setup&) = delete;

  HalfedgeMesh mesh;
  SearchSurface surface;  // empty weights: Euclidean
  TerminalPaths paths;
};

Setup spiky(int spikes, int levels = 3) {
  const auto s = fx::spiky_sphere(levels, fx::spread_directions(spikes));
  std::vector<VertexId> terminals;
  for (auto t : s.tips) terminals.push_back(VertexId(t));
  return Setup(build_halfedge_mesh(s.soup.positions, s.soup.triangles).value(), terminals);
}

double weight_of(const Setup& s, EdgeId e) {
  const auto weights = s.surface.edge_weights();
  return weights.empty() ? s.mesh.edge_length(e) : weights[e.index()];
}

// Independent of the module under test: the edges form one tree containing every terminal,
// every terminal has degree 1 and no other vertex is a leaf.
void require_full_component_tree(const Setup& s, const SteinerTree& tree) {
  REQUIRE_FALSE(tree.edges.empty());
  std::map<std::uint32_t, int> degree;
  std::map<std::uint32_t, std::uint32_t> parent;
  std::function<std::uint32_t(std::uint32_t)> find = [&](std::uint32_t x) {
    if (!parent.count(x)) parent[x] = x;
    return parent[x] == x ? x : parent[x] = find(parent[x]);
  };
  double length = 0;
  for (EdgeId e : tree.edges) {
    REQUIRE(e.index() < s.mesh.num_edges());
    const HalfedgeId h = HalfedgeMesh::halfedge(e);
    const auto a = s.mesh.tail(h).value(), b = s.mesh.head(h).value();
    ++degree[a];
    ++degree[b];
    const auto ra = find(a), rb = find(b);
    REQUIRE_MESSAGE(ra != rb, "the seam has a cycle");
    parent[ra] = rb;
    length += weight_of(s, e);
  }
  CHECK(degree.size() == tree.edges.size() + 1);  // connected, given acyclic
  std::set<std::uint32_t> terminals;
  for (VertexId t : s.paths.terminals) {
    terminals.insert(t.value());
    CHECK_MESSAGE(degree[t.value()] == 1, "terminal " << t.value() << " is not a leaf");
  }
  for (const auto& [v, d] : degree) {
    if (!terminals.count(v)) CHECK_MESSAGE(d >= 2, "dangling non-terminal " << v);
    if (d >= 3 && !terminals.count(v)) {
      CHECK(std::binary_search(tree.steiner_points.begin(), tree.steiner_points.end(), VertexId(v)));
    }
  }
  CHECK(tree.length == doctest::Approx(length).epsilon(1e-9));
}

// Sheffer's baseline computed here: the union of the shortest paths along the terminal MST.
double mst_seam_length(const Setup& s) {
  std::set<std::uint32_t> edges;
  for (const auto& [i, j] : terminal_mst(s.paths)) {
    for (HalfedgeId h : s.paths.path_between(i, j)) edges.insert(HalfedgeMesh::edge(h).value());
  }
  double total = 0;
  for (auto e : edges) total += weight_of(s, EdgeId(e));
  return total;
}

SkeletonResult run(const Setup& s, const SkeletonOptions& options = {}, SkeletonTrace* trace = nullptr) {
  auto r = skeleton_seam_traced(s.surface, s.paths, options, trace);
  REQUIRE_MESSAGE(r.ok(), (r.ok() ? "" : r.error().message));
  return std::move(r).value();
}

}  // namespace

TEST_CASE("skeleton seam on spiky spheres: a full-component tree, deterministic, shorter than MST") {
  for (int spikes : {3, 4, 5, 6, 8, 12}) {
    CAPTURE(spikes);
    const Setup s = spiky(spikes);
    SkeletonTrace trace;
    const auto result = run(s, {}, &trace);
    require_full_component_tree(s, result.tree);
    CHECK_FALSE(trace.fallback);
    CHECK(trace.tour.visits.size() == s.paths.size());
    CHECK_FALSE(trace.raw_skeleton.empty());
    // The refinement never lengthens the seam.
    CHECK(result.tree.length <= result.stats.length_before_refine + 1e-9);
    const double mst = mst_seam_length(s);
    MESSAGE("spikes " << spikes << ": skeleton " << result.tree.length << " (before refine "
                      << result.stats.length_before_refine << "), MST seam " << mst);
    const auto again = run(s);
    CHECK(again.tree.edges == result.tree.edges);
  }
}

TEST_CASE("Algorithm 3's raw skeleton reaches every terminal and straightening keeps terminals off paths") {
  const Setup s = spiky(6);
  auto built = build_tour(s.mesh, s.paths);
  REQUIRE(built.ok());
  const Tour& tour = built->tour;
  auto shrunk = shrink_tour(s.mesh, tour);
  REQUIRE(shrunk.ok());
  std::set<std::uint32_t> skeleton_vertices;
  for (EdgeId e : shrunk->skeleton) {
    skeleton_vertices.insert(s.mesh.tail(HalfedgeMesh::halfedge(e)).value());
    skeleton_vertices.insert(s.mesh.head(HalfedgeMesh::halfedge(e)).value());
  }
  for (VertexId t : s.paths.terminals) CHECK(skeleton_vertices.count(t.value()) == 1);
  // Marks only flow to the interior (right-hand side): faces left of every tour half-edge
  // that are not also right of one stay unmarked, and every piece's wave reaches some face.
  std::set<std::int32_t> marks(shrunk->face_mark.begin(), shrunk->face_mark.end());
  for (std::size_t i = 0; i < tour.pieces.size(); ++i) CHECK(marks.count(static_cast<std::int32_t>(i)) == 1);

  auto topo = skeleton_topology(s.surface, shrunk->skeleton, s.paths.terminals);
  REQUIRE(topo.ok());
  auto straightened = straighten_topology(s.surface, *topo);
  REQUIRE(straightened.ok());
  const TreeTopology& straight = straightened->topology;
  std::set<std::uint32_t> node_vertices;
  for (VertexId v : straight.nodes) node_vertices.insert(v.value());
  for (std::size_t l = 0; l < straight.links.size(); ++l) {
    const auto& path = straight.paths[l];
    REQUIRE_FALSE(path.empty());
    CHECK(s.mesh.tail(path.front()) == straight.nodes[straight.links[l][0]]);
    CHECK(s.mesh.head(path.back()) == straight.nodes[straight.links[l][1]]);
    for (std::size_t i = 0; i + 1 < path.size(); ++i) CHECK(node_vertices.count(s.mesh.head(path[i]).value()) == 0);
  }
  // Branches do not cross or touch: their inner vertices are pairwise disjoint.
  std::set<std::uint32_t> inner;
  for (const auto& path : straight.paths) {
    for (std::size_t i = 0; i + 1 < path.size(); ++i) CHECK(inner.insert(s.mesh.head(path[i]).value()).second);
  }
  // Straightening does not lengthen the skeleton's branches.
  CHECK(topology_length(s.surface, straight) <= topology_length(s.surface, *topo) + 1e-9);
  CHECK(check_full_component_tree(s.mesh, topology_edges(straight), s.paths.terminals).ok());
}

TEST_CASE("two terminals: the seam is their shortest path") {
  const auto soup = fx::icosphere(3);
  const Setup s(build_halfedge_mesh(soup.positions, soup.triangles).value(), {VertexId(3u), VertexId(400u)});
  const auto result = run(s);
  require_full_component_tree(s, result.tree);
  CHECK(result.tree.length == doctest::Approx(s.paths.dist(0, 1)).epsilon(1e-12));
}

TEST_CASE("degenerate terminal sets: adjacent terminals, clusters, random sets never break the tree") {
  const auto soup = fx::icosphere(2);
  const HalfedgeMesh mesh = build_halfedge_mesh(soup.positions, soup.triangles).value();
  // Three mutually adjacent terminals (one face) and a far one.
  const auto face = mesh.face_vertices(FaceId(0u));
  VertexId far(0u);
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
    if ((mesh.position(VertexId(v)) - mesh.position(face[0])).norm() >
        (mesh.position(far) - mesh.position(face[0])).norm()) {
      far = VertexId(v);
    }
  }
  {
    const Setup s(mesh, {face[0], face[1], face[2], far});
    require_full_component_tree(s, run(s).tree);
  }
  {
    // A whole vertex ring as terminals: every path must leave through the gaps.
    std::vector<VertexId> ring;
    mesh.for_each_outgoing(VertexId(0u), [&](HalfedgeId h) {
      if (ring.size() < 4) ring.push_back(mesh.head(h));
    });
    ring.push_back(far);
    const Setup s(mesh, ring);
    require_full_component_tree(s, run(s).tree);
  }
  std::mt19937 rng(7);
  for (int trial = 0; trial < 60; ++trial) {
    const std::size_t k = 3 + rng() % 8;
    std::set<std::uint32_t> picked;
    while (picked.size() < k) picked.insert(static_cast<std::uint32_t>(rng() % mesh.num_vertices()));
    std::vector<VertexId> terminals;
    for (auto v : picked) terminals.push_back(VertexId(v));
    CAPTURE(trial);
    const Setup s(mesh, terminals);
    for (bool refine : {false, true}) require_full_component_tree(s, run(s, {.refine = refine}).tree);
  }
}

TEST_CASE("a boundary coned to a virtual vertex: terminals on the boundary, next to the cone") {
  // A disc closed by a cone vertex with zero-weight edges, as compute_seam prepares it.
  auto soup = fx::disc(6, 16);
  const auto cone = static_cast<std::uint32_t>(soup.positions.size());
  soup.positions.emplace_back(0, 0, -0.5);
  const std::uint32_t outer0 = 1 + 5 * 16;
  for (std::uint32_t k = 0; k < 16; ++k) {
    soup.triangles.push_back({outer0 + (k + 1) % 16, outer0 + k, cone});
  }
  HalfedgeMesh mesh = build_halfedge_mesh(soup.positions, soup.triangles).value();
  REQUIRE(check_invariants(mesh).ok());
  std::vector<double> weights(mesh.num_edges());
  for (std::size_t e = 0; e < mesh.num_edges(); ++e) {
    const HalfedgeId h = HalfedgeMesh::halfedge(EdgeId(e));
    const bool virtual_edge = mesh.tail(h).value() == cone || mesh.head(h).value() == cone;
    weights[e] = virtual_edge ? 0.0 : mesh.edge_length(EdgeId(e));
  }
  // Extrema: the centre, an inner-ring vertex, and a boundary vertex (adjacent to the cone).
  const Setup s(mesh, {VertexId(cone), VertexId(0u), VertexId(1u + 2 * 16 + 4), VertexId(outer0 + 9)}, weights);
  for (bool refine : {false, true}) {
    const auto result = run(s, {.refine = refine});
    require_full_component_tree(s, result.tree);
  }
}

TEST_CASE("cancellation is reported") {
  const Setup s = spiky(5);
  CancelToken token;
  token.cancel();
  auto r = skeleton_seam(s.surface, s.paths, {}, token);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == ErrorCode::kCancelled);
}

TEST_CASE("invalid input is refused") {
  const Setup s = spiky(3);
  TerminalPaths one = s.paths;
  one.terminals.resize(1);
  CHECK(skeleton_seam(s.surface, one).error().code == ErrorCode::kInvalidArgument);
  TerminalPaths beyond = s.paths;  // terminals of a larger mesh
  beyond.terminals[0] = VertexId(static_cast<std::uint32_t>(s.mesh.num_vertices() + 5));
  CHECK(skeleton_seam(s.surface, beyond).error().code == ErrorCode::kInvalidArgument);
}

TEST_CASE("real CGAL meshes (hand, camel): full-component tree, lengths against the MST seam") {
  for (const std::string name : {"hand", "camel"}) {
    for (std::size_t count : {5u, 8u}) {
      CAPTURE(name);
      CAPTURE(count);
      HalfedgeMesh mesh = seam::test_data::load_cgal_halfedge(name);
      const EdgeGraph graph = build_edge_graph(mesh);
      const auto extrema = fx::farthest_point_extrema(mesh, graph, count);
      const Setup s(std::move(mesh), extrema);
      SkeletonTrace trace;
      const auto start = std::chrono::steady_clock::now();
      const auto result = run(s, {}, &trace);
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      require_full_component_tree(s, result.tree);
      CHECK_FALSE(trace.fallback);
      const double mst = mst_seam_length(s);
      MESSAGE(name << " k=" << count << ": skeleton " << result.tree.length << " (paper's steps "
                   << result.stats.length_before_refine << "), MST seam " << mst << ", ratio "
                   << result.tree.length / mst << ", " << ms << " ms (tour " << result.stats.tour_ms << ", shrink "
                   << result.stats.shrink_ms << ", straighten " << result.stats.straighten_ms << ", refine "
                   << result.stats.refine_ms << ", pieces " << trace.refine_stats.pieces_tried << ", moves "
                   << trace.refine_stats.improvements << ")");
    }
  }
}

}  // namespace seam_skeleton_test
