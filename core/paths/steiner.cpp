#include "core/paths/steiner.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numeric>
#include <tuple>
#include <set>
#include <thread>
#include <unordered_map>

namespace seam::core {

namespace {

Status validate_terminals(const HalfedgeMesh& mesh, std::span<const VertexId> terminals) {
  const std::size_t k = terminals.size();
  if (k < 2) return make_error(ErrorCode::kInvalidArgument, "shortest paths need at least two terminals");
  std::vector<VertexId> sorted(terminals.begin(), terminals.end());
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t i = 0; i < k; ++i) {
    if (!sorted[i].valid() || sorted[i].index() >= mesh.num_vertices()) {
      return make_error(ErrorCode::kInvalidArgument, "terminal vertex out of range", {sorted[i].value()});
    }
    if (i > 0 && sorted[i] == sorted[i - 1]) {
      return make_error(ErrorCode::kInvalidArgument, "terminal vertex given twice", {sorted[i].value()});
    }
  }
  return Ok{};
}

struct Candidate {
  double d;
  std::uint32_t i, j;  // i < j
  bool operator<(const Candidate& o) const { return std::tie(d, i, j) < std::tie(o.d, o.i, o.j); }
};

// Kruskal over terminal pairs: the accepted pairs in order (ties by index).
std::vector<std::array<std::uint32_t, 2>> kruskal(std::size_t k, std::vector<Candidate> candidates) {
  std::sort(candidates.begin(), candidates.end());
  std::vector<std::uint32_t> parent(k);
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::vector<std::array<std::uint32_t, 2>> mst;
  for (const Candidate& c : candidates) {
    if (c.d == ShortestPathTree::kUnreached) break;
    const std::uint32_t a = find(c.i), b = find(c.j);
    if (a == b) continue;
    parent[a] = b;
    mst.push_back({c.i, c.j});
  }
  return mst;
}

std::vector<HalfedgeId> reversed(std::span<const HalfedgeId> path) {
  std::vector<HalfedgeId> back(path.rbegin(), path.rend());
  for (auto& h : back) h = HalfedgeMesh::twin(h);
  return back;
}

}  // namespace

double TerminalPaths::dist(std::size_t i, std::size_t j) const {
  const std::size_t at = i * size() + j;
  if (std::isnan(distance_[at])) search_pair(std::min(i, j), std::max(i, j));
  return distance_[at];
}

const std::vector<HalfedgeId>& TerminalPaths::path_between(std::size_t i, std::size_t j) const {
  const std::size_t at = i * size() + j;
  if (std::isnan(distance_[at])) search_pair(std::min(i, j), std::max(i, j));
  return path_[at];
}

double TerminalPaths::lower_bound(std::size_t i, std::size_t j) const {
  const double known = distance_[i * size() + j];
  if (!std::isnan(known)) return known;
  if (!astar_) return 0.0;
  const auto positions = mesh_->positions();
  return (positions[terminals[i].index()] - positions[terminals[j].index()]).norm() * (1.0 - 1e-12);
}

void TerminalPaths::set(std::size_t i, std::size_t j, double d, std::vector<HalfedgeId> path) const {
  const std::size_t k = size();
  distance_[j * k + i] = d;
  path_[j * k + i] = reversed(path);
  distance_[i * k + j] = d;
  path_[i * k + j] = std::move(path);
}

void TerminalPaths::search_pair(std::size_t i, std::size_t j) const {
  SEAM_ASSERT(search_ != nullptr);  // a complete table knows every pair
  ++searches_;
  search_->reset();
  search_->add_source(terminals[i]);
  const VertexId target[] = {terminals[j]};
  // No cancel token: neither can fail. A* settles vertices with their exact distances too.
  if (astar_) {
    (void)search_->run_astar(terminals[j], mesh_->positions(), nearest_);
  } else {
    (void)search_->run(target);
  }
  // Every terminal this search settled is known now (settled distances are final).
  for (std::size_t other = 0; other < size(); ++other) {
    if (other == i || !std::isnan(distance_[i * size() + other]) || !search_->reached(terminals[other])) continue;
    set(i, other, search_->distance(terminals[other]), search_->path_to(*mesh_, terminals[other]));
  }
  if (std::isnan(distance_[i * size() + j])) set(i, j, ShortestPathTree::kUnreached, {});
}

Result<TerminalPaths> compute_terminal_paths(const SearchSurface& surface, std::span<const VertexId> terminals,
                                             unsigned threads, const CancelToken& cancel) {
  const HalfedgeMesh& mesh = surface.mesh();
  const EdgeGraph& graph = surface.graph();
  if (auto st = validate_terminals(mesh, terminals); !st.ok()) return st.take_error();
  const std::size_t k = terminals.size();
  TerminalPaths result;
  result.terminals.assign(terminals.begin(), terminals.end());
  result.distance_.assign(k * k, ShortestPathTree::kUnreached);
  result.path_.assign(k * k, {});

  // Each worker takes source terminals from a shared counter and writes only row i, so
  // the output does not depend on scheduling.
  std::atomic<std::size_t> next{0};
  std::vector<Error> errors(k);
  std::vector<std::uint8_t> failed(k, 0);
  // Distances are symmetric, so the search from terminal i only has to settle terminals
  // i+1..k-1 (rows j < i are mirrored below) and the last terminal needs no search: about
  // half the work of k full searches, since each stops once its later terminals are settled.
  auto work = [&] {
    for (std::size_t i = next++; i + 1 < k; i = next++) {
      const VertexId source[] = {terminals[i]};
      const std::span<const VertexId> later = terminals.subspan(i + 1);
      auto tree = dijkstra(graph, source, {.targets = later}, cancel);
      if (!tree.ok()) {
        errors[i] = tree.take_error();
        failed[i] = 1;
        continue;
      }
      result.distance_[i * k + i] = 0.0;
      for (std::size_t j = i + 1; j < k; ++j) {
        result.distance_[i * k + j] = tree->distance[terminals[j].index()];
        result.path_[i * k + j] = trace_path(mesh, *tree, terminals[j]);
      }
    }
  };
  const unsigned wanted = threads != 0 ? threads : std::max(1u, std::thread::hardware_concurrency());
  const unsigned n = static_cast<unsigned>(std::min<std::size_t>(k - 1, wanted));
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < n; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  for (std::size_t i = 0; i < k; ++i) {
    if (failed[i]) return errors[i];
  }
  result.distance_[(k - 1) * k + (k - 1)] = 0.0;
  // Use the lower-index row's path for both directions so i->j and j->i are the same edges.
  std::vector<Candidate> pairs;
  pairs.reserve(k * (k - 1) / 2);
  for (std::uint32_t i = 0; i < k; ++i) {
    for (std::uint32_t j = i + 1; j < k; ++j) {
      result.set(i, j, result.distance_[i * k + j], std::move(result.path_[i * k + j]));
      pairs.push_back({result.distance_[i * k + j], i, j});
    }
  }
  result.mst = kruskal(k, std::move(pairs));
  return result;
}

Result<TerminalPaths> terminal_paths_on_demand(const SearchSurface& surface, std::span<const VertexId> terminals,
                                               const CancelToken& cancel) {
  const HalfedgeMesh& mesh = surface.mesh();
  const EdgeGraph& graph = surface.graph();
  const bool euclidean = surface.euclidean();
  if (auto st = validate_terminals(mesh, terminals); !st.ok()) return st.take_error();
  const std::size_t k = terminals.size();
  // One search from all terminals (the workspace the pair searches reuse afterwards); each
  // vertex's region is its nearest terminal, carried down the search tree in settle order.
  auto search = std::make_shared<PathSearch>(graph);
  search->reset();
  for (VertexId t : terminals) search->add_source(t);
  if (auto st = search->run({}, PathSearch::kUnreached, cancel); !st.ok()) return st.take_error();
  constexpr std::uint32_t kNoRegion = VertexId::kInvalidValue;
  std::vector<std::uint32_t> region(graph.num_vertices(), kNoRegion);
  for (std::uint32_t i = 0; i < k; ++i) region[terminals[i].index()] = i;
  for (VertexId v : search->settled()) {
    if (const HalfedgeId p = search->parent(v); p.valid()) region[v.index()] = region[mesh.tail(p).index()];
  }
  // Per terminal pair, the cheapest edge between their regions (first in vertex and slot
  // order on ties, so the result is deterministic).
  std::vector<Candidate> best(k * k, Candidate{ShortestPathTree::kUnreached, 0, 0});
  std::vector<std::uint32_t> best_slot(k * k, 0);
  for (std::uint32_t u = 0; u < graph.num_vertices(); ++u) {
    const std::uint32_t su = region[u];
    if (su == kNoRegion) continue;
    const double du = search->distance(VertexId(u));
    for (std::uint32_t slot = graph.offsets[u]; slot < graph.offsets[u + 1]; ++slot) {
      const std::uint32_t v = graph.head[slot].value();
      const std::uint32_t sv = region[v];
      if (sv == kNoRegion || su >= sv) continue;  // each crossing once, from the lower region
      const double d = du + graph.weight[slot] + search->distance(VertexId(v));
      Candidate& c = best[su * k + sv];
      if (d < c.d) c = {d, su, sv}, best_slot[su * k + sv] = slot;
    }
  }
  std::vector<Candidate> proposals;
  for (const Candidate& c : best) {
    if (c.d != ShortestPathTree::kUnreached) proposals.push_back(c);
  }
  TerminalPaths result;
  result.terminals.assign(terminals.begin(), terminals.end());
  result.distance_.assign(k * k, std::numeric_limits<double>::quiet_NaN());
  result.path_.assign(k * k, {});
  for (std::size_t i = 0; i < k; ++i) result.distance_[i * k + i] = 0.0;
  result.mst = kruskal(k, std::move(proposals));
  // An MST pair's proposal is a shortest path (Mehlhorn's lemma): source i to u, u -> v,
  // v back to source j.
  for (const auto& [i, j] : result.mst) {
    const std::uint32_t slot = best_slot[i * k + j];
    std::vector<HalfedgeId> path = search->path_to(mesh, mesh.tail(graph.halfedge[slot]));
    path.push_back(graph.halfedge[slot]);
    const std::vector<HalfedgeId> back = reversed(search->path_to(mesh, graph.head[slot]));
    path.insert(path.end(), back.begin(), back.end());
    result.set(i, j, best[i * k + j].d, std::move(path));
  }
  result.mesh_ = &mesh;
  if (euclidean) {
    result.nearest_.assign(graph.num_vertices(), 0.0);
    for (VertexId v : search->settled()) result.nearest_[v.index()] = search->distance(v);
  }
  result.search_ = std::move(search);
  result.astar_ = euclidean;
  return result;
}

SteinerTree make_steiner_tree(const HalfedgeMesh& mesh, std::span<const EdgeId> edges,
                              std::span<const VertexId> terminals, std::span<const double> edge_weights) {
  SteinerTree tree;
  tree.edges.assign(edges.begin(), edges.end());
  std::sort(tree.edges.begin(), tree.edges.end());
  tree.edges.erase(std::unique(tree.edges.begin(), tree.edges.end()), tree.edges.end());

  std::unordered_map<std::uint32_t, std::vector<HalfedgeId>> incident;  // vertex -> outgoing tree half-edges
  for (EdgeId e : tree.edges) {
    tree.length += edge_weights.empty() ? mesh.edge_length(e) : edge_weights[e.index()];
    const HalfedgeId h = HalfedgeMesh::halfedge(e);
    incident[mesh.tail(h).value()].push_back(h);
    incident[mesh.head(h).value()].push_back(HalfedgeMesh::twin(h));
  }
  std::set<std::uint32_t> is_terminal;
  for (VertexId t : terminals) is_terminal.insert(t.value());
  auto is_node = [&](std::uint32_t v) { return is_terminal.count(v) || incident[v].size() != 2; };
  for (const auto& [v, hs] : incident) {
    if (hs.size() >= 3 && !is_terminal.count(v)) tree.steiner_points.push_back(VertexId(v));
  }
  std::sort(tree.steiner_points.begin(), tree.steiner_points.end());

  // Walk each branch from a node along degree-2 vertices; visit nodes in id order so the
  // branch list is deterministic. A cycle of degree-2 vertices (not a tree) is skipped.
  std::vector<std::uint32_t> nodes;
  for (const auto& [v, hs] : incident) {
    if (is_node(v)) nodes.push_back(v);
  }
  std::sort(nodes.begin(), nodes.end());
  std::set<std::uint32_t> used_edges;
  for (std::uint32_t v : nodes) {
    auto outgoing = incident[v];
    std::sort(outgoing.begin(), outgoing.end());
    for (HalfedgeId start : outgoing) {
      if (used_edges.count(HalfedgeMesh::edge(start).value())) continue;
      std::vector<HalfedgeId> branch;
      HalfedgeId h = start;
      while (true) {
        used_edges.insert(HalfedgeMesh::edge(h).value());
        branch.push_back(h);
        const std::uint32_t w = mesh.head(h).value();
        if (is_node(w)) break;
        const auto& hs = incident[w];
        const HalfedgeId back = HalfedgeMesh::twin(h);
        h = hs[0] == back ? hs[1] : hs[0];
      }
      tree.branches.push_back(std::move(branch));
    }
  }
  return tree;
}

}  // namespace seam::core
