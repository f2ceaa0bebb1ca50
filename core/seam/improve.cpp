#include "core/seam/improve.h"

#include <algorithm>
#include <cstdint>
#include <limits>

#include "core/paths/forest.h"
#include "core/paths/path_search.h"
#include "core/seam/straighten.h"
#include "core/seam/tree_util.h"

namespace seam::core {

namespace {

// A branch between two nodes (terminals or vertices of degree >= 3), from a to b.
struct KeyPath {
  std::vector<HalfedgeId> course;
  double length = 0.0;
  VertexId a, b;
};

// The current tree, its adjacency and key paths, and the moves tried on it. One per call.
class Improver {
 public:
  Improver(const SearchSurface& surface, std::span<const VertexId> terminals)
      : surface_(surface),
        mesh_(surface.mesh()),
        terminals_(terminals),
        search_(surface.graph()),
        is_terminal_(mesh_.num_vertices(), 0),
        local_(mesh_.num_vertices(), -1),
        removed_edge_(mesh_.num_edges(), 0) {
    for (VertexId t : terminals) is_terminal_[t.index()] = 1;
  }

  // Adopts `edges` as the current tree: adjacency, key paths (longest first), Steiner points.
  void index(std::vector<EdgeId> edges);
  // Removes the key paths `removed` (and the Steiner point `eliminated`, if valid) and rejoins
  // the parts; true (and the tree re-indexed) when that made the tree shorter.
  Result<bool> try_move(std::span<const std::size_t> removed, const CancelToken& cancel);

  std::size_t work() const { return work_; }
  void set_max_work(std::size_t max_work) { max_work_ = max_work; }
  const std::vector<EdgeId>& edges() const { return edges_; }
  double length() const { return length_; }
  const std::vector<KeyPath>& key_paths() const { return key_paths_; }
  const std::vector<VertexId>& steiner_points() const { return steiner_; }
  std::vector<std::size_t> paths_at(VertexId s) const {
    std::vector<std::size_t> at;
    for (std::size_t i = 0; i < key_paths_.size(); ++i) {
      if (key_paths_[i].a == s || key_paths_[i].b == s) at.push_back(i);
    }
    return at;
  }

 private:
  bool is_node(std::int32_t i) const {
    return is_terminal_[vertices_[static_cast<std::size_t>(i)].index()] || out_[static_cast<std::size_t>(i)].size() != 2;
  }
  KeyPath walk(HalfedgeId first) const;
  // Labels the tree vertices left after removing the marked edges by part; returns the count.
  std::size_t label_parts(std::vector<std::int32_t>& part, std::vector<std::uint8_t>& alive) const;
  Result<double> rejoin(std::size_t parts, const std::vector<std::int32_t>& part,
                        const std::vector<std::uint8_t>& alive, std::vector<std::uint8_t>& attachable,
                        double budget, std::vector<EdgeId>& added, const CancelToken& cancel);
  Result<double> junction(const std::vector<std::int32_t>& part, const std::vector<std::uint8_t>& alive,
                          const std::vector<std::uint8_t>& attachable, double budget, std::vector<EdgeId>& added,
                          const CancelToken& cancel);

  const SearchSurface& surface_;
  const HalfedgeMesh& mesh_;
  std::span<const VertexId> terminals_;
  PathSearch search_;
  std::vector<PathSearch> part_search_;  // one per part for junction(), made on first use
  std::vector<std::uint8_t> is_terminal_;
  std::vector<std::int32_t> local_;  // tree vertex -> index in vertices_, -1 off the tree
  std::vector<std::uint8_t> removed_edge_;
  std::vector<EdgeId> edges_;
  double length_ = 0.0;
  std::vector<VertexId> vertices_;
  std::vector<std::vector<HalfedgeId>> out_;
  std::vector<KeyPath> key_paths_;
  std::vector<VertexId> steiner_;
  std::size_t work_ = 0;  // vertices settled by all searches so far
  std::size_t max_work_ = SIZE_MAX;
  // What one search may still settle: the budget left (at least 1, so a search ends).
  std::size_t left() const { return work_ < max_work_ ? max_work_ - work_ : 1; }
};

void Improver::index(std::vector<EdgeId> edges) {
  for (VertexId v : vertices_) local_[v.index()] = -1;
  edges_ = std::move(edges);
  std::sort(edges_.begin(), edges_.end());
  length_ = surface_.length(edges_);
  vertices_ = std::move(detail::TreeVertices(mesh_, edges_).vertices);
  out_.assign(vertices_.size(), {});
  for (std::size_t i = 0; i < vertices_.size(); ++i) local_[vertices_[i].index()] = static_cast<std::int32_t>(i);
  for (EdgeId e : edges_) {
    const HalfedgeId h = HalfedgeMesh::halfedge(e);
    out_[static_cast<std::size_t>(local_[mesh_.tail(h).index()])].push_back(h);
    out_[static_cast<std::size_t>(local_[mesh_.head(h).index()])].push_back(HalfedgeMesh::twin(h));
  }
  key_paths_.clear();
  steiner_.clear();
  for (std::size_t i = 0; i < vertices_.size(); ++i) {
    if (!is_node(static_cast<std::int32_t>(i))) continue;
    if (!is_terminal_[vertices_[i].index()]) steiner_.push_back(vertices_[i]);
    for (HalfedgeId h : out_[i]) {
      KeyPath path = walk(h);
      if (path.a.value() < path.b.value()) key_paths_.push_back(std::move(path));
    }
  }
  // Longest first: the longest branches have the most to gain; ties by their ends' ids.
  std::sort(key_paths_.begin(), key_paths_.end(), [](const KeyPath& x, const KeyPath& y) {
    if (x.length != y.length) return x.length > y.length;
    return std::pair(x.a, x.b) < std::pair(y.a, y.b);
  });
}

KeyPath Improver::walk(HalfedgeId first) const {
  KeyPath path;
  path.a = mesh_.tail(first);
  HalfedgeId h = first;
  for (;;) {
    path.course.push_back(h);
    path.length += surface_.weight(HalfedgeMesh::edge(h));
    const std::int32_t x = local_[mesh_.head(h).index()];
    if (is_node(x)) break;
    const auto& out = out_[static_cast<std::size_t>(x)];
    h = out[0] == HalfedgeMesh::twin(h) ? out[1] : out[0];
  }
  path.b = mesh_.head(h);
  return path;
}

std::size_t Improver::label_parts(std::vector<std::int32_t>& part, std::vector<std::uint8_t>& alive) const {
  std::size_t parts = 0;
  std::vector<std::size_t> stack;
  for (std::size_t i = 0; i < vertices_.size(); ++i) {
    if (!alive[i] || part[i] >= 0) continue;
    part[i] = static_cast<std::int32_t>(parts);
    stack.push_back(i);
    while (!stack.empty()) {
      const std::size_t v = stack.back();
      stack.pop_back();
      for (HalfedgeId h : out_[v]) {
        if (removed_edge_[HalfedgeMesh::edge(h).index()]) continue;
        const auto w = static_cast<std::size_t>(local_[mesh_.head(h).index()]);
        if (alive[w] && part[w] < 0) {
          part[w] = static_cast<std::int32_t>(parts);
          stack.push_back(w);
        }
      }
    }
    ++parts;
  }
  return parts;
}

// Prim over the parts: starting from the smallest, repeatedly joins the nearest other part by
// a shortest path from any attachable vertex of the joined parts (or of the paths added so
// far) to an attachable vertex of another part, through no tree vertex. Returns the added
// length, or infinity when the parts cannot be joined within `budget`.
Result<double> Improver::rejoin(std::size_t parts, const std::vector<std::int32_t>& part,
                                const std::vector<std::uint8_t>& alive, std::vector<std::uint8_t>& attachable,
                                double budget, std::vector<EdgeId>& added, const CancelToken& cancel) {
  std::vector<std::size_t> size(parts, 0);
  for (std::size_t i = 0; i < vertices_.size(); ++i) {
    if (alive[i]) ++size[static_cast<std::size_t>(part[i])];
  }
  std::vector<std::uint8_t> joined(parts, 0);
  joined[static_cast<std::size_t>(std::min_element(size.begin(), size.end()) - size.begin())] = 1;
  std::vector<VertexId> new_vertices, targets;
  double used = 0.0;
  for (std::size_t step = 1; step < parts; ++step) {
    search_.reset();
    search_.clear_marks();
    targets.clear();
    for (std::size_t i = 0; i < vertices_.size(); ++i) {
      if (!alive[i]) continue;  // removed vertices are free for the new paths
      const VertexId v = vertices_[i];
      const bool in_joined = joined[static_cast<std::size_t>(part[i])] != 0;
      if (!attachable[i]) {
        search_.forbid(v);
      } else if (in_joined) {
        search_.add_source(v);
      } else {
        search_.block(v);
        targets.push_back(v);
      }
    }
    for (VertexId v : new_vertices) search_.add_source(v);
    const double room = budget - used;
    if (auto st = search_.run_to_nearest(targets, cancel, room, left()); !st.ok()) return st.take_error();
    const auto settled = search_.settled();
    work_ += settled.size();
    if (settled.empty()) return std::numeric_limits<double>::infinity();
    const VertexId reached = settled.back();
    const std::int32_t at = local_[reached.index()];
    if (at < 0 || !alive[static_cast<std::size_t>(at)] || joined[static_cast<std::size_t>(part[static_cast<std::size_t>(at)])] ||
        !attachable[static_cast<std::size_t>(at)]) {
      return std::numeric_limits<double>::infinity();  // the search ran out of budget first
    }
    used += search_.distance(reached);
    for (HalfedgeId h : search_.path_to(mesh_, reached)) {
      added.push_back(HalfedgeMesh::edge(h));
      const std::int32_t w = local_[mesh_.head(h).index()];
      if (w < 0 || !alive[static_cast<std::size_t>(w)]) new_vertices.push_back(mesh_.head(h));
    }
    joined[static_cast<std::size_t>(part[static_cast<std::size_t>(at)])] = 1;
    // A lone terminal that is now joined is a leaf: nothing more may attach to it.
    if (is_terminal_[reached.index()]) attachable[static_cast<std::size_t>(at)] = 0;
  }
  return used;
}

// Three parts: the exact best single junction (key-vertex relocation). One search per part,
// each from its attachable vertices, blocked by the other parts' attachable vertices and
// bounded by `budget`; the junction is the non-terminal vertex minimising the sum of the
// three distances (zero for its own part). Returns the sum, or infinity when over budget.
Result<double> Improver::junction(const std::vector<std::int32_t>& part, const std::vector<std::uint8_t>& alive,
                                  const std::vector<std::uint8_t>& attachable, double budget,
                                  std::vector<EdgeId>& added, const CancelToken& cancel) {
  while (part_search_.size() < 3) part_search_.emplace_back(surface_.graph());
  for (std::int32_t p = 0; p < 3; ++p) {
    PathSearch& search = part_search_[static_cast<std::size_t>(p)];
    search.reset();
    search.clear_marks();
    for (std::size_t i = 0; i < vertices_.size(); ++i) {
      if (!alive[i]) continue;
      if (!attachable[i]) {
        search.forbid(vertices_[i]);
      } else if (part[i] == p) {
        search.add_source(vertices_[i]);
      } else {
        search.block(vertices_[i]);
      }
    }
    // A search cut short by the work budget only narrows the junctions considered; the move
    // is still checked to shorten the tree.
    if (auto st = search.run_limited(budget, left(), cancel); !st.ok()) return st.take_error();
    work_ += search.settled().size();
  }
  double best = std::numeric_limits<double>::infinity();
  VertexId at;
  for (VertexId v : part_search_[0].settled()) {
    if (is_terminal_[v.index()]) continue;  // a junction there would make a terminal inner
    const double sum = part_search_[0].distance(v) + part_search_[1].distance(v) + part_search_[2].distance(v);
    if (sum < best || (sum == best && v < at)) {
      best = sum;
      at = v;
    }
  }
  if (!(best < budget)) return std::numeric_limits<double>::infinity();
  for (const PathSearch& search : part_search_) {
    for (HalfedgeId h : search.path_to(mesh_, at)) added.push_back(HalfedgeMesh::edge(h));
  }
  return best;
}

Result<bool> Improver::try_move(std::span<const std::size_t> removed, const CancelToken& cancel) {
  std::vector<std::uint8_t> alive(vertices_.size(), 1);
  double removed_length = 0.0;
  for (std::size_t p : removed) {
    const KeyPath& path = key_paths_[p];
    removed_length += path.length;
    for (std::size_t i = 0; i < path.course.size(); ++i) {
      removed_edge_[HalfedgeMesh::edge(path.course[i]).index()] = 1;
      if (i > 0) alive[static_cast<std::size_t>(local_[mesh_.tail(path.course[i]).index()])] = 0;
    }
  }
  // A vertex all of whose tree edges were removed and that is no terminal goes too (the
  // eliminated Steiner point).
  std::vector<std::uint8_t> attachable(vertices_.size(), 0);
  for (std::size_t i = 0; i < vertices_.size(); ++i) {
    if (!alive[i]) continue;
    std::size_t kept = 0;
    for (HalfedgeId h : out_[i]) kept += removed_edge_[HalfedgeMesh::edge(h).index()] ? 0 : 1;
    const bool terminal = is_terminal_[vertices_[i].index()] != 0;
    if (kept == 0 && !terminal) alive[i] = 0;
    attachable[i] = terminal ? kept == 0 : 1;
  }
  std::vector<std::int32_t> part(vertices_.size(), -1);
  const std::size_t parts = label_parts(part, alive);
  std::vector<EdgeId> added;
  const double slack = 1e-9 * (1.0 + removed_length);
  auto joined = parts == 3 ? junction(part, alive, attachable, removed_length - slack, added, cancel)
                           : rejoin(parts, part, alive, attachable, removed_length - slack, added, cancel);
  for (std::size_t p : removed) {
    for (HalfedgeId h : key_paths_[p].course) removed_edge_[HalfedgeMesh::edge(h).index()] = 0;
  }
  if (!joined.ok()) return joined.take_error();
  if (!(*joined < removed_length - slack)) return false;
  std::vector<EdgeId> gone;
  for (std::size_t p : removed) {
    for (HalfedgeId h : key_paths_[p].course) gone.push_back(HalfedgeMesh::edge(h));
  }
  std::sort(gone.begin(), gone.end());
  std::vector<EdgeId> candidate;
  for (EdgeId e : edges_) {
    if (!std::binary_search(gone.begin(), gone.end(), e)) candidate.push_back(e);
  }
  candidate.insert(candidate.end(), added.begin(), added.end());
  // Paths to one junction may share a stretch (a cycle) or leave a part's old end dangling.
  candidate = pruned_spanning_forest(mesh_, candidate, terminals_, surface_.edge_weights());
  const double length = surface_.length(candidate);
  if (!(length < length_ - slack) || !check_full_component_tree(mesh_, candidate, terminals_).ok()) return false;
  index(std::move(candidate));
  return true;
}

// One sweep: every key path (longest first), then every Steiner point with its key paths.
// After an accepted move the tree is re-indexed and the sweep goes on at the same position.
Result<bool> sweep(Improver& tree, const ImproveOptions& options, std::size_t max_work, ImproveStats& stats,
                   const CancelToken& cancel) {
  bool improved = false;
  auto out_of_budget = [&] {
    stats.budget_spent = stats.budget_spent || tree.work() > max_work;
    return stats.budget_spent || stats.path_exchanges + stats.vertex_eliminations >= options.max_moves;
  };
  for (std::size_t i = 0; i < tree.key_paths().size(); ++i) {
    if (out_of_budget()) return improved;
    const std::size_t one[] = {i};
    ++stats.moves_tried;
    SEAM_TRY(bool moved, tree.try_move(one, cancel));
    if (moved) ++stats.path_exchanges, improved = true;
  }
  for (std::size_t i = 0; i < tree.steiner_points().size(); ++i) {
    if (out_of_budget()) return improved;
    const std::vector<std::size_t> at = tree.paths_at(tree.steiner_points()[i]);
    if (at.size() < 3) continue;
    ++stats.moves_tried;
    SEAM_TRY(bool moved, tree.try_move(at, cancel));
    if (moved) ++stats.vertex_eliminations, improved = true;
  }
  return improved;
}

}  // namespace

Result<ImproveResult> improve_tree(const SearchSurface& surface, std::span<const VertexId> terminals,
                                   std::span<const EdgeId> edges, const ImproveOptions& options,
                                   const CancelToken& cancel) {
  const HalfedgeMesh& mesh = surface.mesh();
  if (auto valid = check_full_component_tree(mesh, edges, terminals); !valid.ok()) {
    return make_error(ErrorCode::kInvalidArgument,
                      "improve_tree needs a full-component tree: " + valid.error().message);
  }
  Improver tree(surface, terminals);
  tree.index(std::vector<EdgeId>(edges.begin(), edges.end()));
  ImproveResult result;
  result.stats.length_before = tree.length();
  std::size_t max_work = options.max_work > 0
                             ? static_cast<std::size_t>(options.max_work * static_cast<double>(mesh.num_vertices()))
                             : SIZE_MAX;
  if (options.max_settled > 0) max_work = std::min(max_work, options.max_settled);
  tree.set_max_work(max_work);
  for (int pass = 0; pass < options.max_passes; ++pass) {
    if (cancel.is_cancelled()) return cancelled_error("seam improvement");
    SEAM_TRY(bool improved, sweep(tree, options, max_work, result.stats, cancel));
    if (!improved || result.stats.budget_spent) break;
  }
  result.stats.settled = tree.work();
  result.stats.length_after = tree.length();
  result.edges = tree.edges();
  return result;
}

namespace {

// The shortest-path heuristic's searches as one growing search. After the first path (from
// terminals[0], which then becomes a leaf and no source), the sources are the tree's
// non-terminal vertices, and every later join only adds sources at distance 0: distances
// only shrink, so the search goes on from where it stopped instead of starting again. A
// vertex is expanded again only when a new source brings it closer; the settling order
// within a join is (distance, vertex), the order of a fresh search, so each join reaches the
// terminal a fresh search from the whole tree would (exact distances; a path may differ only
// between equally long ones).
class NearestTerminalGrowth {
 public:
  NearestTerminalGrowth(const SearchSurface& surface, std::span<const VertexId> terminals)
      : mesh_(surface.mesh()),
        graph_(surface.graph()),
        dist_(mesh_.num_vertices(), kUnreached),
        parent_(mesh_.num_vertices()),
        terminal_(mesh_.num_vertices(), 0),
        in_tree_(mesh_.num_vertices(), 0) {
    for (VertexId t : terminals) terminal_[t.index()] = 1;
  }

  // Makes v (a vertex now on the tree) a source at distance 0.
  void add_source(VertexId v) {
    dist_[v.index()] = 0.0;
    parent_[v.index()] = HalfedgeId();
    heap_.push(0.0, v.value());
  }
  // Forgets every distance (after the first path, whose start stops being a source).
  void restart() {
    std::fill(dist_.begin(), dist_.end(), kUnreached);
    heap_.clear();
  }
  void mark_in_tree(VertexId v) { in_tree_[v.index()] = 1; }
  bool in_tree(VertexId v) const { return in_tree_[v.index()] != 0; }
  bool is_terminal(VertexId v) const { return terminal_[v.index()] != 0; }

  // Runs until the nearest terminal not on the tree is settled (invalid: none is reachable,
  // or `work` reached `max_work`). `expand_terminal` may expand one terminal (the first source).
  Result<VertexId> grow(VertexId expand_terminal, std::size_t& work, std::size_t max_work, const CancelToken& cancel) {
    VertexId reached;
    Visitor visitor{*this, expand_terminal.valid() ? expand_terminal.value() : kNone, reached, work, max_work};
    if (auto st = run_dijkstra(graph_, heap_, visitor, cancel, "nearest-terminal tree"); !st.ok()) {
      return st.take_error();
    }
    return work >= max_work ? VertexId() : reached;
  }
  // The path from the tree to `v`, in order (v's parents back to a source).
  std::vector<HalfedgeId> path_to(VertexId v) const {
    std::vector<HalfedgeId> path;
    for (HalfedgeId h = parent_[v.index()]; h.valid(); h = parent_[mesh_.tail(h).index()]) path.push_back(h);
    std::reverse(path.begin(), path.end());
    return path;
  }

 private:
  static constexpr double kUnreached = std::numeric_limits<double>::infinity();

  struct Visitor {
    NearestTerminalGrowth& g;
    std::uint32_t expand_terminal;
    VertexId& reached;
    std::size_t& work;
    std::size_t max_work;

    SettleAction settle(std::uint32_t v, double key) {
      if (key > g.dist_[v]) return SettleAction::kSkip;  // stale
      if (g.terminal_[v] && v != expand_terminal) {
        if (g.in_tree_[v]) return SettleAction::kSkip;  // a joined terminal stays a leaf
        reached = VertexId(v);
        return SettleAction::kStop;  // the nearest terminal not yet joined
      }
      return ++work >= max_work ? SettleAction::kStop : SettleAction::kExpand;
    }
    double distance(std::uint32_t v) const { return g.dist_[v]; }
    static std::uint32_t graph_vertex(std::uint32_t v) { return v; }
    bool enters(std::uint32_t w) const { return !(g.terminal_[w] && g.in_tree_[w]); }
    void relax(std::uint32_t, std::uint32_t w, double nd, std::uint32_t slot) {
      if (nd < g.dist_[w]) {
        g.dist_[w] = nd;
        g.parent_[w] = g.graph_.halfedge[slot];
        g.heap_.push(nd, w);
      }
    }
  };

  const HalfedgeMesh& mesh_;
  const EdgeGraph& graph_;
  std::vector<double> dist_;
  std::vector<HalfedgeId> parent_;
  std::vector<std::uint8_t> terminal_;
  std::vector<std::uint8_t> in_tree_;
  LazyHeap heap_;
};

}  // namespace

Result<std::vector<EdgeId>> nearest_terminal_tree(const SearchSurface& surface, std::span<const VertexId> terminals,
                                                  const CancelToken& cancel, std::size_t max_settled) {
  if (terminals.size() < 2) return make_error(ErrorCode::kInvalidArgument, "needs at least two terminals");
  const HalfedgeMesh& mesh = surface.mesh();
  NearestTerminalGrowth growth(surface, terminals);
  growth.mark_in_tree(terminals[0]);
  growth.add_source(terminals[0]);
  std::vector<EdgeId> edges;
  std::size_t work = 0;
  for (std::size_t joined = 1; joined < terminals.size(); ++joined) {
    SEAM_TRY(VertexId reached, growth.grow(joined == 1 ? terminals[0] : VertexId(), work, max_settled, cancel));
    if (work >= max_settled) return std::vector<EdgeId>{};  // out of budget
    if (!reached.valid()) return make_error(ErrorCode::kInvalidArgument, "a terminal cannot be joined as a leaf");
    const std::vector<HalfedgeId> path = growth.path_to(reached);
    // After the first path terminals[0] is a leaf: the search starts again from that path.
    if (joined == 1) growth.restart();
    for (HalfedgeId h : path) {
      edges.push_back(HalfedgeMesh::edge(h));
      for (VertexId w : {mesh.tail(h), mesh.head(h)}) {
        if (growth.in_tree(w)) continue;
        growth.mark_in_tree(w);
        if (!growth.is_terminal(w)) growth.add_source(w);
      }
    }
  }
  std::sort(edges.begin(), edges.end());
  if (auto valid = check_full_component_tree(mesh, edges, terminals); !valid.ok()) {
    return make_error(ErrorCode::kInvalidArgument, "nearest-terminal tree: " + valid.error().message);
  }
  return edges;
}

}  // namespace seam::core
