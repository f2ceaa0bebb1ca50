#include "core/seam/straighten.h"

#include <algorithm>
#include <numeric>
#include <optional>
#include <string>
#include <utility>

#include "core/paths/path_search.h"
#include "core/seam/tree_util.h"

namespace seam::core {

using detail::prune_dangling;
using detail::TreeVertices;
using detail::UnionFind;

Status check_full_component_tree(const HalfedgeMesh& mesh, std::span<const EdgeId> edges,
                                 std::span<const VertexId> terminals) {
  if (edges.empty()) return make_error(ErrorCode::kTopologyViolation, "the seam tree has no edges");
  const std::size_t nv = mesh.num_vertices();
  // Edges are checked in order: an edge out of range is reported where it stands, after any
  // cycle closed before it.
  const auto bad =
      std::find_if(edges.begin(), edges.end(), [&](EdgeId e) { return !e.valid() || e.index() >= mesh.num_edges(); });
  // The tree's vertices, sorted: degrees and the union-find are indexed by them, not by the
  // mesh's vertices (the refinement and the moves check every candidate tree).
  const TreeVertices tree(mesh, edges.first(static_cast<std::size_t>(bad - edges.begin())));
  std::vector<std::uint32_t> degree(tree.size(), 0);
  UnionFind uf(tree.size());
  for (auto it = edges.begin(); it != edges.end(); ++it) {
    const EdgeId e = *it;
    if (it == bad) return make_error(ErrorCode::kTopologyViolation, "seam edge out of range", {e.value()});
    const auto i = static_cast<std::size_t>(it - edges.begin());
    const std::uint32_t a = tree.ends[2 * i];
    const std::uint32_t b = tree.ends[2 * i + 1];
    ++degree[a];
    ++degree[b];
    if (!uf.unite(a, b)) {
      return make_error(ErrorCode::kTopologyViolation,
                        "the seam has a cycle through edge " + std::to_string(e.value()) + " (or repeats it)",
                        {e.value()});
    }
  }
  for (VertexId t : terminals) {
    if (!t.valid() || t.index() >= nv) {
      return make_error(ErrorCode::kTopologyViolation, "terminal out of range", {t.value()});
    }
    const std::uint32_t d = tree.contains(t) ? degree[tree.index(t)] : 0;
    if (d != 1) {
      return make_error(
          ErrorCode::kTopologyViolation,
          "terminal " + std::to_string(t.value()) + " has degree " + std::to_string(d) + " in the seam, not 1 (a leaf)",
          {t.value()});
    }
  }
  std::vector<VertexId> sorted_terminals(terminals.begin(), terminals.end());
  std::sort(sorted_terminals.begin(), sorted_terminals.end());
  const std::uint32_t root =
      uf.find(tree.index(terminals.empty() ? mesh.tail(HalfedgeMesh::halfedge(edges[0])) : terminals[0]));
  for (std::uint32_t i = 0; i < tree.size(); ++i) {
    const std::uint32_t v = tree.vertices[i].value();
    if (uf.find(i) != root) {
      return make_error(ErrorCode::kTopologyViolation,
                        "the seam is not connected: vertex " + std::to_string(v) + " is apart", {v});
    }
    if (degree[i] == 1 && !std::binary_search(sorted_terminals.begin(), sorted_terminals.end(), tree.vertices[i])) {
      return make_error(ErrorCode::kTopologyViolation,
                        "vertex " + std::to_string(v) + " is a dangling leaf that is not a terminal", {v});
    }
  }
  return Ok{};
}

Result<std::vector<EdgeId>> star_tree(const SearchSurface& surface, std::span<const VertexId> terminals,
                                      const CancelToken& cancel) {
  const HalfedgeMesh& mesh = surface.mesh();
  const std::size_t nv = mesh.num_vertices();
  const std::size_t k = terminals.size();
  if (k < 2) return make_error(ErrorCode::kInvalidArgument, "a seam tree needs at least two terminals");
  PathSearch search(surface.graph());
  for (VertexId t : terminals) search.block(t);
  // Sum of terminal-avoiding distances from every terminal; the centre must be reached by all.
  std::vector<double> sum(nv, 0.0);
  std::vector<std::uint32_t> count(nv, 0);
  for (VertexId t : terminals) {
    search.reset();
    search.add_source(t);
    if (auto st = search.run({}, PathSearch::kUnreached, cancel); !st.ok()) return st.take_error();
    for (VertexId v : search.settled()) {
      sum[v.index()] += search.distance(v);
      ++count[v.index()];
    }
  }
  VertexId centre;
  for (std::size_t v = 0; v < nv; ++v) {
    if (count[v] != k || search.is_blocked(VertexId(v))) continue;
    if (!centre.valid() || sum[v] < sum[centre.index()]) centre = VertexId(v);
  }
  if (!centre.valid()) {
    if (k == 2 && mesh.find_halfedge(terminals[0], terminals[1]).valid()) {
      return std::vector<EdgeId>{HalfedgeMesh::edge(mesh.find_halfedge(terminals[0], terminals[1]))};
    }
    return make_error(ErrorCode::kInvalidArgument,
                      "no seam tree with every terminal a leaf exists: no vertex reaches every terminal "
                      "without passing through another terminal");
  }
  search.reset();
  search.add_source(centre);
  if (auto st = search.run(terminals, PathSearch::kUnreached, cancel); !st.ok()) return st.take_error();
  std::vector<EdgeId> edges;
  for (VertexId t : terminals) {
    for (HalfedgeId h : search.path_to(mesh, t)) edges.push_back(HalfedgeMesh::edge(h));
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return prune_dangling(mesh, std::move(edges), terminals);
}

namespace {

std::vector<HalfedgeId> reversed(const std::vector<HalfedgeId>& path) {
  std::vector<HalfedgeId> r(path.rbegin(), path.rend());
  for (auto& h : r) h = HalfedgeMesh::twin(h);
  return r;
}

}  // namespace

double topology_length(const SearchSurface& surface, const TreeTopology& topology) {
  return surface.length(topology_edges(topology));
}

namespace {

// A spanning forest of the skeleton, lightest edges first (a cycle loses its heaviest edge),
// and of it only the pieces that touch a terminal. `pieces` is the forest's union-find, which
// joining the pieces goes on extending.
struct TerminalForest {
  std::vector<EdgeId> edges;
  UnionFind pieces;
};

TerminalForest terminal_forest(const SearchSurface& surface, std::span<const EdgeId> skeleton_edges,
                               std::span<const VertexId> terminals) {
  const HalfedgeMesh& mesh = surface.mesh();
  const std::size_t nv = mesh.num_vertices();
  std::vector<EdgeId> sorted(skeleton_edges.begin(), skeleton_edges.end());
  std::sort(sorted.begin(), sorted.end(), [&](EdgeId a, EdgeId b) {
    const double wa = surface.weight(a);
    const double wb = surface.weight(b);
    return wa != wb ? wa < wb : a < b;
  });
  UnionFind uf(nv);
  std::vector<EdgeId> forest;
  for (EdgeId e : sorted) {
    const HalfedgeId h = HalfedgeMesh::halfedge(e);
    if (uf.unite(mesh.tail(h).value(), mesh.head(h).value())) forest.push_back(e);
  }
  std::vector<std::uint8_t> root_has_terminal(nv, 0);
  for (VertexId t : terminals) root_has_terminal[uf.find(t.value())] = 1;
  std::vector<EdgeId> kept;
  for (EdgeId e : forest) {
    if (root_has_terminal[uf.find(mesh.tail(HalfedgeMesh::halfedge(e)).value())]) kept.push_back(e);
  }
  return TerminalForest{std::move(kept), std::move(uf)};
}

// Joins the forest's other pieces (and terminals the skeleton missed) to the piece of
// terminal 0, one nearest piece at a time, by terminal-avoiding shortest paths.
Result<std::vector<EdgeId>> join_to_first_terminal(const SearchSurface& surface, std::span<const VertexId> terminals,
                                                   const std::vector<std::int32_t>& terminal_of, TerminalForest forest,
                                                   const CancelToken& cancel) {
  const HalfedgeMesh& mesh = surface.mesh();
  const std::size_t nv = mesh.num_vertices();
  const std::size_t k = terminals.size();
  UnionFind& uf = forest.pieces;
  std::vector<EdgeId>& kept = forest.edges;
  // Made on the first piece to join: a tree that is already whole (every call from the
  // refinement) needs no search state, which is several arrays of the mesh's size.
  std::optional<PathSearch> search;
  std::vector<std::uint8_t> seen(nv, 0);
  std::vector<VertexId> seen_list;
  for (int guard = 0; guard < static_cast<int>(k); ++guard) {
    const std::uint32_t main_root = uf.find(terminals[0].value());
    std::vector<VertexId> sources;
    std::vector<VertexId> targets;
    for (VertexId v : seen_list) seen[v.index()] = 0;
    seen_list.clear();
    auto consider = [&](VertexId v) {
      if (seen[v.index()]) return;
      seen[v.index()] = 1;
      seen_list.push_back(v);
      if (uf.find(v.value()) == main_root) {
        // A terminal must stay a leaf, so a joining path may start at one only if it is
        // alone in its piece (then it is the piece).
        if (terminal_of[v.index()] < 0 || kept.empty()) sources.push_back(v);
      } else {
        targets.push_back(v);
      }
    };
    for (EdgeId e : kept) {
      consider(mesh.tail(HalfedgeMesh::halfedge(e)));
      consider(mesh.head(HalfedgeMesh::halfedge(e)));
    }
    for (VertexId t : terminals) consider(t);
    if (targets.empty()) break;
    if (sources.empty()) sources.push_back(terminals[0]);
    if (!search) {
      search.emplace(surface.graph());
      for (VertexId t : terminals) search->block(t);
    }
    search->reset();
    for (VertexId v : sources) search->add_source(v);
    if (auto st = search->run_to_nearest(targets, cancel); !st.ok()) return st.take_error();
    VertexId hit;
    for (VertexId v : targets) {
      if (search->reached(v) && (!hit.valid() || search->distance(v) < search->distance(hit))) hit = v;
    }
    if (!hit.valid()) {
      return make_error(ErrorCode::kTopologyViolation, "the skeleton cannot be joined to every terminal");
    }
    for (HalfedgeId h : search->path_to(mesh, hit)) {
      if (uf.unite(mesh.tail(h).value(), mesh.head(h).value())) kept.push_back(HalfedgeMesh::edge(h));
    }
  }
  return std::move(kept);
}

// The tree as nodes and branches, before inner terminals are made leaves; `node_of` gives
// each tree vertex's node index (by `tree`'s index; -1: not a node).
struct WalkedTopology {
  TreeTopology topology;
  TreeVertices tree;
  std::vector<std::int32_t> node_of;
};

// Nodes: terminals first, then vertices of degree >= 3; branches are walked between them.
// The tree's adjacency is indexed by its own vertices (sorted), not by the mesh's: each
// vertex's out-going half-edges (from TreeVertices::incidence), in half-edge order.
WalkedTopology walk_branches(const HalfedgeMesh& mesh, std::span<const EdgeId> tree,
                             std::span<const VertexId> terminals) {
  const std::size_t k = terminals.size();
  WalkedTopology walked{TreeTopology{}, TreeVertices(mesh, tree), {}};
  const TreeVertices& index = walked.tree;
  const std::size_t n = index.size();
  struct Out {
    HalfedgeId h;        // out of the vertex
    std::uint32_t slot;  // its end's slot in index.ends: edge slot / 2, the far end ends[slot ^ 1]
    bool operator<(const Out& o) const { return h < o.h; }
  };
  const TreeVertices::Incidence incidence = index.incidence();
  const std::vector<std::uint32_t>& offsets = incidence.offsets;
  std::vector<Out> out(incidence.slots.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    const std::uint32_t s = incidence.slots[i];
    const HalfedgeId h = HalfedgeMesh::halfedge(tree[s / 2]);
    out[i] = {s % 2 == 0 ? h : HalfedgeMesh::twin(h), s};
  }
  for (std::size_t v = 0; v < n; ++v) std::sort(out.begin() + offsets[v], out.begin() + offsets[v + 1]);
  TreeTopology& topo = walked.topology;
  std::vector<std::int32_t>& node_of = walked.node_of;
  topo.num_terminals = k;
  node_of.assign(n, -1);
  for (std::size_t i = 0; i < k; ++i) {
    topo.nodes.push_back(terminals[i]);
    if (index.contains(terminals[i])) node_of[index.index(terminals[i])] = static_cast<std::int32_t>(i);
  }
  for (std::size_t v = 0; v < n; ++v) {
    if (node_of[v] < 0 && incidence.degree(static_cast<std::uint32_t>(v)) >= 3) {
      node_of[v] = static_cast<std::int32_t>(topo.nodes.size());
      topo.nodes.push_back(index.vertices[v]);
    }
  }
  std::vector<std::uint8_t> used(tree.size(), 0);  // walked edges, by place in `tree`
  for (std::uint32_t a = 0; a < topo.nodes.size(); ++a) {
    if (!index.contains(topo.nodes[a])) continue;  // a terminal the tree misses: no branch
    const std::uint32_t from = index.index(topo.nodes[a]);
    for (std::uint32_t slot = offsets[from]; slot < offsets[from + 1]; ++slot) {
      if (used[out[slot].slot / 2]) continue;
      std::vector<HalfedgeId> path;
      Out step = out[slot];
      std::uint32_t w;
      while (true) {
        used[step.slot / 2] = 1;
        path.push_back(step.h);
        w = index.ends[step.slot ^ 1u];
        if (node_of[w] >= 0) break;
        SEAM_ASSERT(incidence.degree(w) == 2);
        const Out& first = out[offsets[w]];
        step = first.slot / 2 == step.slot / 2 ? out[offsets[w] + 1] : first;
      }
      topo.links.push_back({a, static_cast<std::uint32_t>(node_of[w])});
      topo.paths.push_back(std::move(path));
    }
  }
  return walked;
}

// A terminal inside the tree hangs off a new Steiner node on its first non-terminal
// neighbour along one of its branches; its other branches are re-routed to that node.
Result<TreeTopology> hang_inner_terminals(const HalfedgeMesh& mesh, std::span<const VertexId> terminals,
                                          const std::vector<std::int32_t>& terminal_of, WalkedTopology walked) {
  const std::size_t k = terminals.size();
  TreeTopology& topo = walked.topology;
  std::vector<std::int32_t>& node_of = walked.node_of;
  for (std::uint32_t t = 0; t < k; ++t) {
    std::vector<std::size_t> incident;
    for (std::size_t l = 0; l < topo.links.size(); ++l) {
      if (topo.links[l][0] == t || topo.links[l][1] == t) incident.push_back(l);
    }
    if (incident.size() <= 1) continue;
    for (std::size_t l : incident) {
      if (topo.links[l][1] == t) {
        std::swap(topo.links[l][0], topo.links[l][1]);
        topo.paths[l] = reversed(topo.paths[l]);
      }
    }
    std::size_t chosen = incident.size();
    for (std::size_t c = 0; c < incident.size(); ++c) {
      const auto& path = topo.paths[incident[c]];
      if (!path.empty() && terminal_of[mesh.head(path.front()).index()] < 0) {
        chosen = c;
        break;
      }
    }
    if (chosen == incident.size()) {
      return make_error(ErrorCode::kTopologyViolation,
                        "terminal " + std::to_string(terminals[t].value()) +
                            " lies between other terminals and cannot be made a leaf",
                        {terminals[t].value()});
    }
    const std::size_t l0 = incident[chosen];
    const VertexId u = mesh.head(topo.paths[l0].front());
    const std::uint32_t at = walked.tree.index(u);
    std::uint32_t s;
    if (node_of[at] >= 0) {
      s = static_cast<std::uint32_t>(node_of[at]);
    } else {
      s = static_cast<std::uint32_t>(topo.nodes.size());
      topo.nodes.push_back(u);
      node_of[at] = static_cast<std::int32_t>(s);
      std::vector<HalfedgeId> rest(topo.paths[l0].begin() + 1, topo.paths[l0].end());
      topo.links.push_back({s, topo.links[l0][1]});
      topo.paths.push_back(std::move(rest));
      topo.links[l0][1] = s;
      topo.paths[l0].resize(1);
    }
    for (std::size_t l : incident) {
      if (l == l0) continue;
      topo.links[l][0] = s;
      topo.paths[l].clear();  // no course yet: straighten_topology routes it
    }
  }
  return std::move(topo);
}

}  // namespace

Result<TreeTopology> skeleton_topology(const SearchSurface& surface, std::span<const EdgeId> skeleton_edges,
                                       std::span<const VertexId> terminals, const CancelToken& cancel) {
  const HalfedgeMesh& mesh = surface.mesh();
  // A full-component tree (the refinement's tree after every move) is its own skeleton: the
  // spanning forest keeps all of it, no piece is joined, nothing is pruned and no terminal is
  // inner, so only its branches are walked (the same topology: walk_branches does not depend
  // on the order of the edges), without the steps' work of the mesh's size.
  if (check_full_component_tree(mesh, skeleton_edges, terminals).ok()) {
    return std::move(walk_branches(mesh, skeleton_edges, terminals).topology);
  }
  const std::size_t nv = mesh.num_vertices();
  const std::size_t k = terminals.size();
  std::vector<std::int32_t> terminal_of(nv, -1);
  for (std::size_t i = 0; i < k; ++i) terminal_of[terminals[i].index()] = static_cast<std::int32_t>(i);

  // Keep the skeleton's pieces that touch a terminal, then join them (and terminals the
  // skeleton missed) to the piece of terminal 0.
  SEAM_TRY(std::vector<EdgeId> kept,
           join_to_first_terminal(surface, terminals, terminal_of, terminal_forest(surface, skeleton_edges, terminals),
                                  cancel));
  kept = prune_dangling(mesh, std::move(kept), terminals);
  return hang_inner_terminals(mesh, terminals, terminal_of, walk_branches(mesh, kept, terminals));
}

Result<StraightenResult> straighten_topology(const SearchSurface& surface, const TreeTopology& topology,
                                             const CancelToken& cancel) {
  const HalfedgeMesh& mesh = surface.mesh();
  StraightenStats st;
  const std::size_t nl = topology.links.size();
  st.branches = nl;
  // Shorter branches first; branches without a course first of all (they must be routed).
  std::vector<std::size_t> order(nl);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::vector<double> len(nl);
  for (std::size_t l = 0; l < nl; ++l) {
    len[l] = topology.paths[l].empty() ? -1.0 : surface.path_length(topology.paths[l]);
  }
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return len[a] < len[b]; });

  PathSearch search(surface.graph());
  for (int attempt = 0; attempt < 4; ++attempt) {
    TreeTopology result = topology;
    search.clear_marks();
    for (VertexId v : topology.nodes) search.block(v);
    std::size_t failed = nl;
    st.kept = 0;
    for (std::size_t l : order) {
      if (cancel.is_cancelled()) return cancelled_error("skeleton straightening");
      const VertexId a = topology.nodes[topology.links[l][0]];
      const VertexId b = topology.nodes[topology.links[l][1]];
      search.reset();
      search.add_source(a);
      const VertexId target[] = {b};
      // With Euclidean weights the straight-line distance guides the search (A*), which
      // visits a narrow band around the branch instead of a ball.
      auto s = surface.euclidean() ? search.run_astar(b, mesh.positions(), cancel)
                                   : search.run(target, PathSearch::kUnreached, cancel);
      if (!s.ok()) return s.take_error();
      std::vector<HalfedgeId> path;
      if (search.reached(b)) {
        path = search.path_to(mesh, b);
      } else {
        // No disjoint shortest path: keep the old course if no placed branch took its vertices.
        const auto& old = topology.paths[l];
        bool free = !old.empty();
        for (std::size_t i = 0; free && i + 1 < old.size(); ++i) free = !search.is_blocked(mesh.head(old[i]));
        if (!free) {
          failed = l;
          break;
        }
        path = old;
        ++st.kept;
      }
      for (std::size_t i = 0; i + 1 < path.size(); ++i) search.block(mesh.head(path[i]));
      result.paths[l] = std::move(path);
    }
    if (failed == nl) {
      search.clear_marks();
      return StraightenResult{std::move(result), st};
    }
    ++st.retries;
    order.erase(std::find(order.begin(), order.end(), failed));
    order.insert(order.begin(), failed);
  }
  return make_error(ErrorCode::kTopologyViolation,
                    "no branch layout keeps the straightened seam a tree with every terminal a leaf");
}

std::vector<EdgeId> topology_edges(const TreeTopology& topology) {
  std::vector<EdgeId> edges;
  for (const auto& path : topology.paths) {
    for (HalfedgeId h : path) edges.push_back(HalfedgeMesh::edge(h));
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

}  // namespace seam::core
