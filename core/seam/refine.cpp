#include "core/seam/refine.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <unordered_set>
#include <utility>

#include "core/paths/dreyfus_wagner.h"
#include "core/paths/path_search.h"
#include "core/seam/straighten.h"
#include "core/seam/tree_util.h"

namespace seam::core {

namespace {

// Dreyfus–Wagner (the shared kernel) on a region of the mesh, with port *sets*: port i may
// be joined at any vertex of its set (a loose subtree's non-terminal vertices, or a loose
// terminal alone).
class LocalSteiner {
 public:
  explicit LocalSteiner(const SearchSurface& surface) : graph_(surface.graph()) {
    local_of_.assign(surface.mesh().num_vertices(), -1);
  }

  // `region`: global vertices; `obstacle[i]`, `terminal[i]`, `port_mask[i]` per region vertex.
  // The minimum tree (its edges), or no tree when none costs less than `bound`. Every partial
  // tree of a tree cheaper than `bound` is itself cheaper (edge weights are positive), so the
  // kernel's branch-and-bound leaves the answer unchanged. No tree either when the kernel's
  // lower bound shows that none costs less than `target` (<= bound).
  Result<GroupSteinerTree> solve(std::span<const VertexId> region, const std::vector<std::uint8_t>& obstacle,
                                 const std::vector<std::uint8_t>& terminal, const std::vector<std::uint32_t>& port_mask,
                                 std::size_t ports, double bound, double target, const CancelToken& cancel) {
    const std::size_t n = region.size();
    for (std::size_t i = 0; i < n; ++i) local_of_[region[i].index()] = static_cast<std::int32_t>(i);
    // The region's edge graph: local heads, the mesh's half-edges.
    local_.offsets.assign(n + 1, 0);
    local_.head.clear();
    local_.weight.clear();
    local_.halfedge.clear();
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t v = region[i].value();
      for (std::uint32_t slot = graph_.offsets[v]; slot < graph_.offsets[v + 1]; ++slot) {
        const std::int32_t w = local_of_[graph_.head[slot].index()];
        if (w < 0) continue;
        local_.head.push_back(VertexId(static_cast<std::uint32_t>(w)));
        local_.weight.push_back(graph_.weight[slot]);
        local_.halfedge.push_back(graph_.halfedge[slot]);
      }
      local_.offsets[i + 1] = static_cast<std::uint32_t>(local_.head.size());
    }
    for (VertexId v : region) local_of_[v.index()] = -1;
    return kernel_.solve(local_,
                         GroupSteinerProblem{.ports = ports,
                                             .port_mask = port_mask,
                                             .obstacle = obstacle,
                                             .leaf_only = terminal,
                                             .root = VertexId(),
                                             .bound = bound,
                                             .target = target},
                         cancel);
  }

 private:
  const EdgeGraph& graph_;
  std::vector<std::int32_t> local_of_;
  EdgeGraph local_;
  DreyfusWagner kernel_;
};

// A piece's search region: the vertices within `reach` of the cut parts, in search order.
// It depends only on the cut (its vertices in order) and the reach, so a piece tried again
// with the same cut (after a move elsewhere in the tree) takes the region found before
// instead of searching again: the same vertices in the same order.
class Regions {
 public:
  Regions(const EdgeGraph& graph, bool reuse) : search_(graph), reuse_(reuse) {}

  struct Found {
    const std::vector<VertexId>* region = nullptr;  // null: more than max_region vertices
    bool searched = false;                          // false: known from an earlier search
  };
  Result<Found> find(const std::vector<VertexId>& sources, double reach, std::size_t max_region,
                     const CancelToken& cancel) {
    if (!reuse_) known_.clear();
    auto [it, inserted] = known_.try_emplace(Key{std::bit_cast<std::uint64_t>(reach), sources});
    if (!inserted) return Found{it->second ? &*it->second : nullptr, false};
    search_.reset();
    for (VertexId v : sources) search_.add_source(v);
    if (auto st = search_.run_limited(reach, max_region + 1, cancel); !st.ok()) {
      known_.erase(it);
      return st.take_error();
    }
    const auto settled = search_.settled();
    if (settled.size() <= max_region) it->second.emplace(settled.begin(), settled.end());
    return Found{it->second ? &*it->second : nullptr, true};
  }

 private:
  using Key = std::pair<std::uint64_t, std::vector<VertexId>>;
  PathSearch search_;
  bool reuse_;
  std::map<Key, std::optional<std::vector<VertexId>>> known_;
};

// Pieces of the tree: every Steiner node, and every pair of adjacent Steiner nodes.
std::vector<std::vector<std::uint32_t>> pieces_of(const TreeTopology& t) {
  std::vector<std::vector<std::uint32_t>> pieces;
  for (std::uint32_t s = static_cast<std::uint32_t>(t.num_terminals); s < t.nodes.size(); ++s) pieces.push_back({s});
  for (const auto& link : t.links) {
    if (link[0] >= t.num_terminals && link[1] >= t.num_terminals) pieces.push_back({link[0], link[1]});
  }
  return pieces;
}

struct Branch {
  std::size_t link;
  bool internal;                   // between two nodes of the piece
  std::vector<HalfedgeId> course;  // from the outer end towards the piece
  double length;
};

struct PieceBranches {
  std::vector<Branch> branches;
  double longest = 0.0;
};

// The branches at a piece, each oriented from its outer end towards the piece.
PieceBranches branches_at(const SearchSurface& surface, const TreeTopology& topo,
                          const std::vector<std::uint32_t>& piece) {
  auto in_piece = [&](std::uint32_t node) { return std::find(piece.begin(), piece.end(), node) != piece.end(); };
  PieceBranches out;
  for (std::size_t l = 0; l < topo.links.size(); ++l) {
    const auto& link = topo.links[l];
    const bool a_in = in_piece(link[0]), b_in = in_piece(link[1]);
    if (!a_in && !b_in) continue;
    Branch br{l, a_in && b_in, topo.paths[l], 0.0};
    if (a_in && !b_in) {
      std::reverse(br.course.begin(), br.course.end());
      for (auto& h : br.course) h = HalfedgeMesh::twin(h);
    }
    br.length = surface.path_length(br.course);
    out.longest = std::max(out.longest, br.length);
    out.branches.push_back(std::move(br));
  }
  return out;
}

struct PieceCut {
  std::vector<VertexId> ports;             // where the cut branches now end
  std::vector<VertexId> removed_vertices;  // the cut parts' vertices (the region's sources)
  double removed_length = 0.0;
};

// Cuts each branch loose up to `reach` from the piece (internal branches entirely), stamping
// the removed edges with `stamp`.
PieceCut cut_branches(const SearchSurface& surface, const std::vector<Branch>& branches, double reach,
                      std::vector<std::uint32_t>& removed_stamp, std::uint32_t stamp) {
  const HalfedgeMesh& mesh = surface.mesh();
  PieceCut out;
  for (const auto& br : branches) {
    // Keep the outer part of the branch: edges whose far end is more than `reach` from the
    // piece along the branch.
    double from_piece = br.length;
    std::size_t cut = 0;  // course[cut..] is removed
    if (!br.internal) {
      while (cut < br.course.size() && from_piece > reach) {
        from_piece -= surface.weight(HalfedgeMesh::edge(br.course[cut]));
        ++cut;
      }
      // `cut` edges leave the outer end; stop one short if that already is within reach.
      if (cut > 0 && from_piece < reach) --cut;
      out.ports.push_back(cut == 0 ? mesh.tail(br.course.front()) : mesh.head(br.course[cut - 1]));
    }
    if (cut < br.course.size()) out.removed_vertices.push_back(mesh.tail(br.course[cut]));
    for (std::size_t i = cut; i < br.course.size(); ++i) {
      removed_stamp[HalfedgeMesh::edge(br.course[i]).index()] = stamp;
      out.removed_length += surface.weight(HalfedgeMesh::edge(br.course[i]));
      out.removed_vertices.push_back(mesh.head(br.course[i]));
    }
  }
  return out;
}

struct PieceRegion {
  PieceCut cut;
  const std::vector<VertexId>* region = nullptr;  // null: too large at every reach tried
};

// Cuts the branches and takes the region around the cut parts; where the region would be too
// large, cuts less (the reach halved, up to 4 times) so a piece costs a bounded amount of work:
// the piece takes the largest reach options.reach * longest * 2^-a, a = 0..4, whose region
// fits. A smaller reach cuts a part of each branch's cut part and searches less far from it,
// so its region lies inside the larger reach's: whether a region fits is monotone in a, and
// the search starts at `hint` (the previous piece's a, which it updates) and walks to the
// first fitting a from there, which finds the same a as trying 0, 1, ... in turn. At 1.25M
// faces pieces mostly settle at a = 3, and each reach that does not fit costs a search of
// max_region vertices. The kept cut stamps its removed edges with the current `stamp`.
Result<PieceRegion> piece_region(const SearchSurface& surface, const std::vector<Branch>& branches, double longest,
                                 const RefineOptions& options, Regions& regions,
                                 std::vector<std::uint32_t>& removed_stamp, std::uint32_t& stamp, int& hint,
                                 RefineStats& st, const CancelToken& cancel) {
  constexpr int kReaches = 5;
  auto at = [&](int a) -> Result<PieceRegion> {
    const double reach = std::ldexp(options.reach * longest, -a);  // exact: halving, a times
    PieceRegion out;
    out.cut = cut_branches(surface, branches, reach, removed_stamp, ++stamp);
    SEAM_TRY(const Regions::Found found, regions.find(out.cut.removed_vertices, reach, options.max_region, cancel));
    st.region_searches += found.searched ? 1 : 0;
    out.region = found.region;
    return out;
  };
  int a = std::clamp(hint, 0, kReaches - 1);
  SEAM_TRY(PieceRegion out, at(a));
  if (out.region) {
    while (a > 0) {
      SEAM_TRY(PieceRegion larger, at(a - 1));
      if (!larger.region) {
        SEAM_TRY(out, at(a));  // known from the search above: only the stamp is renewed
        break;
      }
      out = std::move(larger);
      --a;
    }
  } else {
    while (!out.region && a + 1 < kReaches) {
      SEAM_TRY(out, at(++a));
    }
  }
  hint = a;
  return out;
}

struct LocalProblem {
  std::vector<std::uint8_t> obstacle;   // per region vertex: terminal or on the rest of the tree
  std::vector<std::uint8_t> terminal;   // per region vertex
  std::vector<std::uint32_t> port_mask; // per region vertex: the loose subtree it may join
};

// The local problem on `region`: the rest of the tree falls into one subtree per port; a loose
// subtree may be joined at any non-terminal vertex, a loose terminal that is its whole
// subtree only as itself (it stays a leaf). `in_rest` is scratch (all zero before and after).
LocalProblem local_problem(const HalfedgeMesh& mesh, const std::vector<EdgeId>& rest,
                           const std::vector<VertexId>& ports, std::span<const VertexId> region,
                           const std::vector<std::uint8_t>& is_terminal, std::vector<std::uint8_t>& in_rest) {
  // Union-find over the rest's vertices only, through a compact index.
  const detail::TreeVertices rest_index(mesh, rest, ports);
  const std::vector<VertexId>& rest_vertices = rest_index.vertices;
  auto compact = [&](VertexId v) { return rest_index.index(v); };
  detail::UnionFind uf(rest_vertices.size());
  for (EdgeId e : rest) {
    uf.unite(compact(mesh.tail(HalfedgeMesh::halfedge(e))), compact(mesh.head(HalfedgeMesh::halfedge(e))));
  }
  for (VertexId v : rest_vertices) in_rest[v.index()] = 1;
  std::vector<std::int32_t> port_of_root(rest_vertices.size(), -1);
  for (std::size_t i = 0; i < ports.size(); ++i) port_of_root[uf.find(compact(ports[i]))] = static_cast<std::int32_t>(i);
  LocalProblem out{std::vector<std::uint8_t>(region.size()), std::vector<std::uint8_t>(region.size()),
                   std::vector<std::uint32_t>(region.size(), 0)};
  for (std::size_t i = 0; i < region.size(); ++i) {
    const VertexId v = region[i];
    out.terminal[i] = is_terminal[v.index()];
    out.obstacle[i] = out.terminal[i] || in_rest[v.index()];
    if (!in_rest[v.index()]) continue;
    const std::int32_t port = port_of_root[uf.find(compact(v))];
    if (port >= 0 && (!out.terminal[i] || ports[static_cast<std::size_t>(port)] == v)) out.port_mask[i] = 1u << port;
  }
  for (VertexId v : rest_vertices) in_rest[v.index()] = 0;
  return out;
}

// `rest` joined by the local tree's edges, sorted; a subtree joined before its cut end leaves
// that end dangling, which is pruned.
std::vector<EdgeId> rejoined(const HalfedgeMesh& mesh, std::vector<EdgeId> rest, std::span<const HalfedgeId> joining,
                             std::span<const VertexId> terminals) {
  for (HalfedgeId h : joining) rest.push_back(HalfedgeMesh::edge(h));
  std::sort(rest.begin(), rest.end());
  rest.erase(std::unique(rest.begin(), rest.end()), rest.end());
  rest = detail::prune_dangling(mesh, std::move(rest), terminals);
  std::sort(rest.begin(), rest.end());
  return rest;
}

// A 64-bit fingerprint of a local problem (its region in search order, each vertex's obstacle
// flag and port mask, and the length to beat); terminals are obstacles without a port, so
// they are covered. A collision can only skip a piece, never make the tree longer.
std::uint64_t problem_key(std::span<const VertexId> region, const std::vector<std::uint8_t>& obstacle,
                          const std::vector<std::uint32_t>& port_mask, double bound) {
  std::uint64_t h = 0x9e3779b97f4a7c15ull ^ std::bit_cast<std::uint64_t>(bound);
  auto mix = [&h](std::uint64_t x) {
    h ^= x + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
    h *= 0xff51afd7ed558ccdull;
  };
  for (std::size_t i = 0; i < region.size(); ++i) {
    mix((std::uint64_t{region[i].value()} << 32) | (std::uint64_t{port_mask[i]} << 1) | obstacle[i]);
  }
  return h;
}

// What trying one piece came to.
enum class PieceOutcome {
  kNoMove,      // skipped, or no shorter tree through it
  kOverBudget,  // solving it would exceed max_work: refinement stops
  kShorter,     // `tree` is shorter than the current one
};

struct PieceMove {
  PieceOutcome outcome = PieceOutcome::kNoMove;
  std::vector<EdgeId> tree;  // kShorter: the new tree, sorted
  double length = 0.0;       // kShorter: its length
};

// What the pieces of every pass share: the scratch arrays, the regions found so far, the
// work done and the local problems known to have no cheaper tree.
class PieceRefiner {
 public:
  PieceRefiner(const SearchSurface& surface, std::span<const VertexId> terminals, const RefineOptions& options)
      : surface_(surface),
        mesh_(surface.mesh()),
        terminals_(terminals),
        options_(options),
        is_terminal_(mesh_.num_vertices(), 0),
        regions_(surface.graph(), options.shortcuts),
        solver_(surface),
        removed_stamp_(mesh_.num_edges(), 0),
        in_rest_(mesh_.num_vertices(), 0) {
    for (VertexId t : terminals) is_terminal_[t.index()] = 1;
  }

  bool over_budget() const { return work_ > options_.max_work; }

  // Cuts the branches at `piece` loose and re-joins the loose subtrees by the minimum tree
  // over the region around them; a move when that makes `current` shorter and keeps it a
  // full-component tree.
  Result<PieceMove> try_piece(const TreeTopology& topo, const std::vector<std::uint32_t>& piece,
                              const std::vector<EdgeId>& current, double current_length, RefineStats& st,
                              const CancelToken& cancel) {
    const auto [branches, longest] = branches_at(surface_, topo, piece);
    ++st.pieces_tried;
    // The ports (one per branch not inside the piece) do not depend on the reach.
    const auto outer = static_cast<std::size_t>(
        std::count_if(branches.begin(), branches.end(), [](const Branch& br) { return !br.internal; }));
    if (outer < 2 || outer > options_.max_ports) return PieceMove{};
    SEAM_TRY(const PieceRegion cut_region, piece_region(surface_, branches, longest, options_, regions_, removed_stamp_,
                                                        stamp_, reach_hint_, st, cancel));
    const PieceCut& piece_cut = cut_region.cut;
    const std::vector<VertexId>* found = cut_region.region;
    const std::vector<VertexId>& ports = piece_cut.ports;
    const double removed_length = piece_cut.removed_length;
    if (!found) return PieceMove{};
    // The rest of the tree falls into one subtree per port.
    std::vector<EdgeId> rest;
    for (EdgeId e : current) {
      if (removed_stamp_[e.index()] != stamp_) rest.push_back(e);
    }
    const std::span<const VertexId> region(*found);
    const LocalProblem problem = local_problem(mesh_, rest, ports, region, is_terminal_, in_rest_);
    const auto& [obstacle, terminal, port_mask] = problem;
    // The same local problem (region, obstacles, ports, length to beat) that had no
    // cheaper tree before has none now: later passes only solve pieces near a change.
    const std::uint64_t key = problem_key(region, obstacle, port_mask, removed_length);
    if (no_gain_.count(key)) {
      ++st.pieces_reused;
      return PieceMove{};
    }
    work_ += region.size() << ports.size();
    if (work_ > options_.max_work) return PieceMove{.outcome = PieceOutcome::kOverBudget};
    ++st.pieces_solved;
    st.solved_vertices += region.size();
    // A move needs a tree cheaper than removed_length - slack. Where the kernel's lower bound
    // shows that none is (with a margin far above the rounding of a sum of edge weights),
    // the full solve would also have found nothing: the same piece is skipped, exactly.
    const double slack = 1e-9 * (1.0 + removed_length);
    const double target = options_.shortcuts ? removed_length - slack + 1e-11 * (1.0 + removed_length)
                                             : std::numeric_limits<double>::infinity();
    auto joined = solver_.solve(region, obstacle, terminal, port_mask, ports.size(), removed_length, target, cancel);
    if (!joined.ok()) return joined.take_error();
    st.pieces_ruled_out += joined->target_ruled_out ? 1 : 0;
    if (!(joined->cost < removed_length - slack)) {
      no_gain_.insert(key);
      return PieceMove{};
    }
    std::vector<EdgeId> candidate = rejoined(mesh_, std::move(rest), joined->halfedges, terminals_);
    const double length = surface_.length(candidate);
    if (!(length < current_length - 1e-9 * (1.0 + current_length)) ||
        !check_full_component_tree(mesh_, candidate, terminals_).ok()) {
      return PieceMove{};
    }
    return PieceMove{.outcome = PieceOutcome::kShorter, .tree = std::move(candidate), .length = length};
  }

 private:
  const SearchSurface& surface_;
  const HalfedgeMesh& mesh_;
  std::span<const VertexId> terminals_;
  const RefineOptions& options_;
  std::vector<std::uint8_t> is_terminal_;
  Regions regions_;
  LocalSteiner solver_;
  std::vector<std::uint32_t> removed_stamp_;
  std::uint32_t stamp_ = 0;
  int reach_hint_ = 0;  // the halvings of the reach the last piece's region took (piece_region)
  std::vector<std::uint8_t> in_rest_;
  std::size_t work_ = 0;                       // region vertices times port subsets solved so far
  std::unordered_set<std::uint64_t> no_gain_;  // problem_key of local problems with no cheaper tree
};

}  // namespace

Result<RefineResult> refine_tree(const SearchSurface& surface, std::span<const VertexId> terminals,
                                 std::span<const EdgeId> edges, const RefineOptions& options,
                                 const CancelToken& cancel) {
  RefineStats st;
  if (auto valid = check_full_component_tree(surface.mesh(), edges, terminals); !valid.ok()) {
    return make_error(ErrorCode::kInvalidArgument, "refine_tree needs a full-component tree: " + valid.error().message);
  }
  std::vector<EdgeId> current(edges.begin(), edges.end());
  std::sort(current.begin(), current.end());
  double current_length = surface.length(current);
  st.length_before = current_length;
  if (options.max_ports > 20) return make_error(ErrorCode::kInvalidArgument, "max_ports above 20");

  PieceRefiner refiner(surface, terminals, options);
  for (int pass = 0; pass < options.max_passes; ++pass) {
    bool improved = false;
    std::size_t index = 0;
    std::size_t moves = 0;
    SEAM_TRY(TreeTopology topo, skeleton_topology(surface, current, terminals, cancel));
    auto pieces = pieces_of(topo);
    while (index < pieces.size() && moves < 4 * pieces.size() + 8) {
      if (cancel.is_cancelled()) return cancelled_error("seam refinement");
      SEAM_TRY(PieceMove move, refiner.try_piece(topo, pieces[index], current, current_length, st, cancel));
      ++index;
      if (move.outcome == PieceOutcome::kOverBudget) break;
      if (move.outcome == PieceOutcome::kNoMove) continue;
      current = std::move(move.tree);
      current_length = move.length;
      improved = true;
      ++st.improvements;
      ++moves;
      // The tree changed: list its pieces again and go on from the same position.
      SEAM_TRY(topo, skeleton_topology(surface, current, terminals, cancel));
      pieces = pieces_of(topo);
      --index;
    }
    if (!improved || refiner.over_budget()) break;
  }
  st.length_after = current_length;
  return RefineResult{std::move(current), st};
}

}  // namespace seam::core
