// The seam pipeline (paper §4.1): per connected component, open handles and extra boundary
// loops with a cut graph, make the remaining boundary one terminal by coning it, run the
// chosen method on the closed genus-0 surface, map the tree back and verify the cut.
//
// Documented choices:
// - Boundary terminal: every boundary loop of the (cut) component is closed by a virtual
//   apex joined by zero-weight edges (core/mesh/submesh.h). The apex is an ordinary terminal, so
//   "the whole boundary is one terminal, touched at one point" (§2) holds for skeleton and
//   optimal, whose terminals are leaves. The virtual edges are dropped; where the seam meets
//   the boundary, that boundary vertex is reported among the terminals. Real edges at the
//   boundary carry a penalty larger than any seam (see seam_on_component), so every method
//   meets the boundary with as few edges as possible: one, unless an extremum can only be
//   reached along the boundary. Lengths are always reported unpenalised.
// - An extremum already on the boundary of the (cut) component is on the cut: it is kept in
//   `extrema` and `terminals` but needs no seam, so it is not passed to the method.
// - Fewer than two terminals on a closed genus-0 component: the seam is the shortest path
//   from the extremum (or, with none, from one end of a double-sweep diameter) to the
//   vertex farthest from it along edges. That peels the surface along its longest axis,
//   which flattens with less distortion than a short slit; the far end becomes a terminal.
// - One open component with only its boundary terminal needs no seam (already a disc).
// - A one-edge seam on a closed component cannot be cut into a simplicial disc (a slit
//   between two vertices with one wedge each); it becomes the cheapest two-edge path
//   through a vertex opposite that edge, which keeps both ends leaves.
// - The mapped seam is reduced to a forest in which each tree touches the boundary at most
//   once (core/paths/forest.h with the boundary as one node): a path that grazes the boundary
//   would otherwise close a cycle with it and cut a piece off. With positive weights and no
//   ties this changes nothing.
#include "core/seam/seam.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/mesh/cut.h"
#include "core/mesh/cut_check.h"
#include "core/mesh/submesh.h"
#include "core/mesh/topology.h"
#include "core/paths/forest.h"
#include "core/paths/geodesic.h"
#include "core/paths/steiner.h"
#include "core/seam/baselines.h"
#include "core/seam/cut_graph.h"
#include "core/seam/skeleton.h"
#include "core/seam/tree_util.h"
#include "core/timing.h"

namespace seam::core {

const char* seam_method_name(SeamMethod method) {
  switch (method) {
    case SeamMethod::kSkeleton:
      return "skeleton";
    case SeamMethod::kMst:
      return "mst";
    case SeamMethod::kGreedy:
      return "greedy";
    case SeamMethod::kOptimal:
      return "optimal";
  }
  return "skeleton";
}

namespace {

struct ComponentSeam {
  bool exact = true;                    // the tree is a minimum one for its terminals
  std::vector<EdgeId> seam_edges;       // in the input mesh
  std::vector<EdgeId> cut_graph_edges;  // in the input mesh
  std::vector<VertexId> extra_terminals;  // boundary touch points and added far ends
};

// Farthest vertex from `source` along edges (ties: smallest id).
Result<VertexId> farthest_vertex(const EdgeGraph& graph, VertexId source, const CancelToken& cancel) {
  const VertexId sources[] = {source};
  SEAM_TRY(ShortestPathTree tree, dijkstra(graph, sources, {}, cancel));
  VertexId best = source;
  double best_distance = 0;
  for (std::size_t v = 0; v < tree.distance.size(); ++v) {
    if (tree.reached(VertexId(v)) && tree.distance[v] > best_distance) {
      best_distance = tree.distance[v];
      best = VertexId(v);
    }
  }
  return best;
}

Result<std::vector<EdgeId>> shortest_path_edges(const SearchSurface& work, VertexId from, VertexId to,
                                                const CancelToken& cancel) {
  const VertexId sources[] = {from};
  const VertexId targets[] = {to};
  SEAM_TRY(ShortestPathTree tree, dijkstra(work.graph(), sources, {.targets = targets}, cancel));
  if (!tree.reached(to)) {
    return make_error(ErrorCode::kInvalidArgument, "no path between terminals " + std::to_string(from.value()) +
                                                       " and " + std::to_string(to.value()));
  }
  std::vector<EdgeId> edges;
  for (HalfedgeId h : trace_path(work.mesh(), tree, to)) edges.push_back(HalfedgeMesh::edge(h));
  return edges;
}

struct MethodTree {
  std::vector<EdgeId> edges;
  bool exact = false;
};

// Whether the skeleton method should return the exact optimum (SeamOptions::exact_budget).
bool exact_is_cheap(const SeamOptions& options, std::size_t terminals, std::size_t vertices) {
  if (options.method != SeamMethod::kSkeleton || !options.refine || terminals > options.optimal_max_terminals ||
      terminals > 30) {
    return false;
  }
  const double rows = static_cast<double>(std::size_t{1} << (terminals - 1));
  return rows * static_cast<double>(vertices) <= options.exact_budget;
}

// The exact seam within SeamOptions::exact_budget. From 6 terminals the skeleton with the
// global moves (no local refinement) first gives an upper bound, and Dreyfus–Wagner bounded
// by it drops every state that cannot beat it: at 8 terminals on 10k-30k faces that took the
// stage from 31-52x to 26-37x the paper's seam; with fewer terminals (<= 16 rows) the bound
// costs more than it saves (seam_quality_bench --speed).
Result<MethodTree> exact_tree(const SearchSurface& work, std::span<const VertexId> terminals,
                              const SeamOptions& options, SeamStats& stats, const CancelToken& cancel) {
  if (terminals.size() < 6) {
    const auto start = StageClock::now();
    auto exact = optimal_seam(work, terminals, options.optimal_max_terminals, cancel);
    stats.method_ms += ms_since(start);
    if (!exact.ok()) return exact.take_error();
    ++stats.exact_components;
    return MethodTree{std::move(exact->edges), true};
  }
  auto start = StageClock::now();
  SEAM_TRY(TerminalPaths paths, terminal_paths_on_demand(work, terminals, cancel));
  stats.paths_ms += ms_since(start);
  start = StageClock::now();
  SEAM_TRY(SkeletonResult skeleton,
           skeleton_seam(work, paths, SkeletonOptions{.refine = false, .improve = true}, cancel));
  const double bound = skeleton.tree.length * (1.0 + 1e-9) + 1e-12;
  auto exact = optimal_seam(work, terminals, options.optimal_max_terminals, cancel, bound);
  stats.method_ms += ms_since(start);
  if (!exact.ok()) {
    // Too large a table: the heuristic tree stands, not claimed optimal.
    if (exact.error().code == ErrorCode::kCancelled) return exact.take_error();
    return MethodTree{std::move(skeleton.tree.edges), false};
  }
  ++stats.exact_components;
  // Nothing below the (raised) bound: the heuristic tree is itself a minimum one.
  if (exact->edges.empty()) return MethodTree{std::move(skeleton.tree.edges), true};
  return MethodTree{std::move(exact->edges), true};
}

// Whether a tree with every terminal a leaf exists on `graph`: for three or more terminals,
// some part of the graph without terminals must touch all of them (a tiny closed part whose
// every vertex is an extremum has none). O(V + E).
bool leaf_tree_exists(const EdgeGraph& graph, std::span<const VertexId> terminals) {
  if (terminals.size() < 3) return true;
  const std::size_t nv = graph.num_vertices();
  std::vector<std::uint32_t> terminal_of(nv, kNone);
  for (std::uint32_t i = 0; i < terminals.size(); ++i) terminal_of[terminals[i].index()] = i;
  detail::UnionFind parts(nv);
  for (std::uint32_t v = 0; v < nv; ++v) {
    for (std::uint32_t slot = graph.offsets[v]; slot < graph.offsets[v + 1]; ++slot) {
      const std::uint32_t w = graph.head[slot].value();
      if (terminal_of[v] == kNone && terminal_of[w] == kNone) parts.unite(v, w);
    }
  }
  // Per part, the terminals it touches, counted once each (the last terminal that counted).
  std::vector<std::uint32_t> touched(nv, 0);
  std::vector<std::uint32_t> last(nv, kNone);
  for (std::uint32_t i = 0; i < terminals.size(); ++i) {
    const std::uint32_t t = terminals[i].value();
    for (std::uint32_t slot = graph.offsets[t]; slot < graph.offsets[t + 1]; ++slot) {
      const std::uint32_t w = graph.head[slot].value();
      if (terminal_of[w] != kNone) continue;
      const std::uint32_t part = parts.find(w);
      if (last[part] == i) continue;
      last[part] = i;
      if (++touched[part] == terminals.size()) return true;
    }
  }
  return false;
}

// The tree on `work` (a closed genus-0 surface) for `terminals` by the chosen method.
Result<MethodTree> run_method(const SearchSurface& work, std::span<const VertexId> terminals,
                              const SeamOptions& options, SeamStats& stats, const CancelToken& cancel) {
  if (options.method == SeamMethod::kOptimal && terminals.size() > options.optimal_max_terminals) {
    Error error = make_error(ErrorCode::kTooManyTerminals,
                             "the optimal method takes at most " + std::to_string(options.optimal_max_terminals) +
                                 " terminals per component, this component has " + std::to_string(terminals.size()) +
                                 "; use the skeleton method or fewer extrema");
    error.values = {{"count", terminals.size()}, {"limit", options.optimal_max_terminals}};
    return error;
  }
  if (terminals.size() == 2) {
    // §4.1: two terminals, the seam is their shortest path (the same for every method).
    auto start = StageClock::now();
    SEAM_TRY(auto edges, shortest_path_edges(work, terminals[0], terminals[1], cancel));
    stats.paths_ms += ms_since(start);
    return MethodTree{std::move(edges), true};
  }
  SteinerTree tree;
  if ((options.method == SeamMethod::kSkeleton || options.method == SeamMethod::kOptimal) &&
      !leaf_tree_exists(work.graph(), terminals)) {
    // No tree has every terminal a leaf: the MST seam, with terminals inside it, still opens
    // the part to a disc (not minimal, not leaf-only: `exact` false).
    auto start = StageClock::now();
    SEAM_TRY(TerminalPaths paths, terminal_paths_on_demand(work, terminals, cancel));
    SEAM_TRY(tree, mst_seam(work, paths, cancel));
    stats.method_ms += ms_since(start);
    return MethodTree{std::move(tree.edges), false};
  }
  if (exact_is_cheap(options, terminals.size(), work.mesh().num_vertices())) {
    auto exact = exact_tree(work, terminals, options, stats, cancel);
    // A table above optimal_seam's memory cap: the heuristic below decides.
    if (exact.ok() || exact.error().code != ErrorCode::kTooManyTerminals) return exact;
  }
  if (options.method == SeamMethod::kSkeleton || options.method == SeamMethod::kMst) {
    auto start = StageClock::now();
    SEAM_TRY(TerminalPaths paths, terminal_paths_on_demand(work, terminals, cancel));
    stats.paths_ms += ms_since(start);
    start = StageClock::now();
    if (options.method == SeamMethod::kSkeleton) {
      SEAM_TRY(SkeletonResult skeleton, skeleton_seam(work, paths,
                                                      SkeletonOptions{.refine = options.refine && options.local_refine,
                                                                      .improve = options.refine && options.improve,
                                                                      .threads = options.threads},
                                                      cancel));
      tree = std::move(skeleton.tree);
    } else {
      SEAM_TRY(tree, mst_seam(work, paths, cancel));
    }
    stats.method_ms += ms_since(start);
  } else {
    auto start = StageClock::now();
    if (options.method == SeamMethod::kGreedy) {
      SEAM_TRY(tree, greedy_seam(work, terminals, cancel));
    } else {
      SEAM_TRY(tree, optimal_seam(work, terminals, options.optimal_max_terminals, cancel));
    }
    stats.method_ms += ms_since(start);
  }
  return MethodTree{std::move(tree.edges), options.method == SeamMethod::kOptimal};
}

// The cheapest two-edge path a-w-b replacing the single edge e on a closed surface.
std::vector<EdgeId> widen_single_edge(const HalfedgeMesh& mesh, EdgeId e) {
  const HalfedgeId h = HalfedgeMesh::halfedge(e);
  const VertexId a = mesh.tail(h);
  const VertexId b = mesh.head(h);
  std::vector<EdgeId> best;
  double best_length = ShortestPathTree::kUnreached;
  for (HalfedgeId side : {h, HalfedgeMesh::twin(h)}) {
    if (mesh.is_boundary(side)) continue;
    const VertexId w = mesh.tail(mesh.prev(side));
    const HalfedgeId aw = mesh.find_halfedge(a, w);
    const HalfedgeId wb = mesh.find_halfedge(w, b);
    const double length = mesh.edge_length(HalfedgeMesh::edge(aw)) + mesh.edge_length(HalfedgeMesh::edge(wb));
    if (length < best_length) {
      best_length = length;
      best = {HalfedgeMesh::edge(aw), HalfedgeMesh::edge(wb)};
    }
  }
  std::sort(best.begin(), best.end());
  return best;
}

// The component as the methods see it: its own mesh (the input itself when it is the only
// one), opened into a disc by its cut graph, and the disc's boundary loops coned. Each layer
// is reached through the ones below it, so every result maps back to the input.
struct ComponentSurface {
  const HalfedgeMesh& mesh;      // the input
  bool whole = false;            // the component is the whole input: nothing extracted
  bool needs_cut_graph = false;  // handles or extra boundary loops
  bool has_boundary = false;     // the disc has a boundary, closed by cones
  ComponentMesh extracted;
  std::vector<EdgeId> cut_graph_edges;  // in the input mesh
  CutMesh cut;
  ConedMesh coned;

  const HalfedgeMesh& sub() const { return whole ? mesh : extracted.mesh; }
  const HalfedgeMesh& disc() const { return needs_cut_graph ? cut.mesh : sub(); }
  const HalfedgeMesh& work() const { return has_boundary ? coned.mesh : disc(); }

  VertexId to_local(VertexId v) const {
    if (whole) return v;
    const auto it = std::lower_bound(extracted.to_parent.begin(), extracted.to_parent.end(), v);
    return VertexId(static_cast<std::uint32_t>(it - extracted.to_parent.begin()));
  }
  std::vector<EdgeId> sub_edges_to_mesh(const std::vector<EdgeId>& edges) const {
    return whole ? edges : map_edges(sub(), extracted.to_parent, mesh, edges);
  }
  VertexId disc_to_mesh(VertexId v) const {
    const VertexId s = needs_cut_graph ? cut.to_original[v] : v;
    return whole ? s : extracted.to_parent[s.index()];
  }
  std::vector<EdgeId> disc_edges_to_mesh(std::vector<EdgeId> disc_edges) const {
    std::vector<EdgeId> sub_edges;
    if (needs_cut_graph) {
      sub_edges = map_edges(disc(), cut.to_original.raw(), sub(), disc_edges);
    } else {
      sub_edges = std::move(disc_edges);
    }
    return sub_edges_to_mesh(sub_edges);
  }
};

// Extracts the component, opens it along its cut graph and cones the disc's boundary loops.
// (Coning only reads the disc, so it may come before the terminals are picked on it.)
Result<ComponentSurface> open_component(const HalfedgeMesh& mesh, const Topology& topo, std::uint32_t component,
                                        std::span<const FaceId> faces, const CancelToken& cancel) {
  const ComponentInfo& info = topo.components[component];
  ComponentSurface s{.mesh = mesh, .whole = topo.components.size() == 1};
  if (!s.whole) {
    SEAM_TRY(s.extracted, extract_faces(mesh, faces));
  }
  // Handles and extra boundary loops: cut graph first, then work on the cut disc.
  s.needs_cut_graph = info.genus > 0 || info.boundary_loops > 1;
  if (s.needs_cut_graph) {
    SEAM_TRY(std::vector<EdgeId> cut_graph, compute_cut_graph(s.sub(), cancel));
    s.cut_graph_edges = s.sub_edges_to_mesh(cut_graph);
    SEAM_TRY(s.cut, cut_along_edges(s.sub(), cut_graph));
  }
  s.has_boundary = s.needs_cut_graph || info.boundary_loops > 0;
  if (s.has_boundary) {
    SEAM_TRY(s.coned, cone_boundary_loops(s.disc()));
  }
  return s;
}

// Terminals on the disc: the extrema off its boundary, then the cones' apexes. The cut keeps
// the first wedge's vertex id, so a sub vertex is also a disc vertex; extrema on the disc's
// boundary are already on the cut.
std::vector<VertexId> disc_terminals(const ComponentSurface& s, std::span<const VertexId> extrema) {
  std::vector<VertexId> terminals;
  for (VertexId x : extrema) {
    const VertexId local = s.to_local(x);
    if (!s.disc().is_boundary(local)) terminals.push_back(local);
  }
  if (s.has_boundary) terminals.insert(terminals.end(), s.coned.apexes.begin(), s.coned.apexes.end());
  return terminals;
}

// The edge weights of `work` for the method (empty: Euclidean).
std::vector<double> method_edge_weights(const ComponentSurface& s, const SeamOptions& options) {
  const HalfedgeMesh& work = s.work();
  std::vector<double> penalized;
  if (!options.edge_costs.empty()) {
    // Each real edge weighs its length times its input edge's multiplier; virtual edges 0.
    penalized.assign(work.num_edges(), 0.0);
    for (std::size_t e = 0; e < work.num_edges(); ++e) {
      if (s.has_boundary && s.coned.is_virtual(EdgeId(e))) continue;
      const HalfedgeId h = HalfedgeMesh::halfedge(EdgeId(e));
      const HalfedgeId in = s.mesh.find_halfedge(s.disc_to_mesh(work.tail(h)), s.disc_to_mesh(work.head(h)));
      SEAM_ASSERT(in.valid());
      penalized[e] = work.edge_length(EdgeId(e)) * options.edge_costs[HalfedgeMesh::edge(in).index()];
    }
  }
  if (s.has_boundary) {
    // Every real edge at a boundary vertex costs P more, P above any tree's length: a tree
    // then first minimises how many edges meet the boundary (one: the apex's attachment, so
    // no path grazes the boundary and the boundary terminal is touched at one point by one
    // edge, §4.1), then its length. Without it a path between two extrema could run through
    // the zero-weight apex (a shortcut across the hole) or graze the boundary elsewhere.
    if (penalized.empty()) penalized = s.coned.edge_weights;
    double total = 1.0;
    for (double w : penalized) total += w;
    for (std::size_t e = 0; e < work.num_edges(); ++e) {
      if (s.coned.is_virtual(EdgeId(e))) continue;
      const HalfedgeId h = HalfedgeMesh::halfedge(EdgeId(e));
      if (s.disc().is_boundary(work.tail(h)) || s.disc().is_boundary(work.head(h))) penalized[e] += total;
    }
  }
  return penalized;
}

// A closed disc with fewer than two terminals: the extremum (or, with none, one end of a
// double-sweep diameter) and the vertex farthest from it, unless that is itself.
Result<std::vector<VertexId>> axis_terminals(const HalfedgeMesh& disc, std::vector<VertexId> terminals,
                                             const CancelToken& cancel) {
  const EdgeGraph graph = build_edge_graph(disc);
  VertexId first;
  if (terminals.empty()) {
    SEAM_TRY(first, farthest_vertex(graph, disc.tail(disc.face_halfedge(FaceId(0u))), cancel));
    terminals.push_back(first);
  }
  SEAM_TRY(VertexId far, farthest_vertex(graph, terminals[0], cancel));
  if (far != terminals[0]) terminals.push_back(far);
  return terminals;
}

struct DiscSeam {
  std::vector<EdgeId> edges;
  bool widened = false;  // a single edge became two: no longer a minimum tree
};

// The method's tree back on the disc: virtual edges dropped, then a forest that touches the
// boundary once per tree; a single edge on a closed disc is widened.
DiscSeam seam_on_disc(const ComponentSurface& s, std::span<const VertexId> terminals, std::vector<EdgeId> work_edges) {
  const HalfedgeMesh& disc = s.disc();
  const HalfedgeMesh& work = s.work();
  std::vector<EdgeId> disc_edges;
  std::vector<VertexId> keep;
  if (s.has_boundary) {
    std::vector<VertexId> to_disc(work.num_vertices());
    for (std::size_t v = 0; v < work.num_vertices(); ++v) {
      to_disc[v] = s.coned.is_apex(VertexId(v)) ? VertexId() : VertexId(v);
    }
    disc_edges = map_edges(work, to_disc, disc, work_edges);
    for (VertexId t : terminals) {
      if (!s.coned.is_apex(t)) keep.push_back(t);
    }
  } else {
    disc_edges = std::move(work_edges);
    keep.assign(terminals.begin(), terminals.end());
  }
  std::vector<VertexId> boundary;
  if (s.has_boundary) {
    for (std::size_t v = 0; v < disc.num_vertices(); ++v) {
      if (disc.is_boundary(VertexId(v))) boundary.push_back(VertexId(v));
    }
  }
  DiscSeam out;
  out.edges = pruned_spanning_forest(disc, disc_edges, keep, {}, boundary);
  if (!s.has_boundary && out.edges.size() == 1) {
    out.edges = widen_single_edge(disc, out.edges[0]);
    out.widened = true;
  }
  return out;
}

// Where the seam reaches the boundary (in the input mesh): that point stands for the
// boundary terminal.
std::vector<VertexId> boundary_touch_points(const ComponentSurface& s, std::span<const EdgeId> disc_edges) {
  std::vector<VertexId> touch;
  for (EdgeId e : disc_edges) {
    for (unsigned side = 0; side < 2; ++side) {
      const VertexId v = s.disc().tail(HalfedgeMesh::halfedge(e, side));
      if (s.disc().is_boundary(v)) touch.push_back(s.disc_to_mesh(v));
    }
  }
  return touch;
}

Result<ComponentSeam> seam_on_component(const HalfedgeMesh& mesh, const Topology& topo, std::uint32_t component,
                                        std::span<const FaceId> faces, std::span<const VertexId> extrema,
                                        const SeamOptions& options, SeamStats& stats, const CancelToken& cancel) {
  ComponentSeam out;
  auto start = StageClock::now();
  SEAM_TRY(ComponentSurface surface, open_component(mesh, topo, component, faces, cancel));
  out.cut_graph_edges = std::move(surface.cut_graph_edges);
  std::vector<VertexId> terminals = disc_terminals(surface, extrema);
  std::vector<double> weights = method_edge_weights(surface, options);  // empty: Euclidean
  stats.preprocess_ms += ms_since(start);

  if (!surface.has_boundary && terminals.size() < 2) {
    start = StageClock::now();
    SEAM_TRY(terminals, axis_terminals(surface.disc(), std::move(terminals), cancel));
    for (std::size_t i = extrema.size() > 0 ? 1 : 0; i < terminals.size(); ++i) {
      out.extra_terminals.push_back(surface.disc_to_mesh(terminals[i]));
    }
    stats.paths_ms += ms_since(start);
  }
  stats.terminals += terminals.size();
  if (terminals.size() < 2) return out;  // an open disc with no extrema inside: no seam

  const SearchSurface work(surface.work(), std::move(weights));
  SEAM_TRY(MethodTree method_tree, run_method(work, terminals, options, stats, cancel));
  out.exact = method_tree.exact;
  DiscSeam seam = seam_on_disc(surface, terminals, std::move(method_tree.edges));
  if (seam.widened) out.exact = false;  // the minimum (one edge) cannot be cut; its widening is not minimal
  if (surface.has_boundary) {
    const std::vector<VertexId> touch = boundary_touch_points(surface, seam.edges);
    out.extra_terminals.insert(out.extra_terminals.end(), touch.begin(), touch.end());
  }
  out.seam_edges = surface.disc_edges_to_mesh(std::move(seam.edges));
  return out;
}

// The extrema in input order without repeats. Errors: kIndexOutOfRange naming the first
// extremum that is no vertex of a face.
Result<std::vector<VertexId>> distinct_extrema(const HalfedgeMesh& mesh, std::span<const VertexId> extrema) {
  const std::size_t nv = mesh.num_vertices();
  std::vector<VertexId> distinct;
  std::vector<char> seen(nv, 0);  // not a search of `distinct`: thousands of parts bring thousands of extrema
  for (VertexId x : extrema) {
    if (!x.valid() || x.index() >= nv) {
      return make_error(ErrorCode::kIndexOutOfRange,
                        "extremum " + std::to_string(x.value()) + " is out of range (the mesh has " +
                            std::to_string(nv) + " vertices)",
                        {x.value()});
    }
    if (mesh.is_isolated(x)) {
      return make_error(ErrorCode::kIndexOutOfRange,
                        "extremum " + std::to_string(x.value()) + " is an isolated vertex (in no face)", {x.value()});
    }
    if (!seen[x.index()]) distinct.push_back(x);
    seen[x.index()] = 1;
  }
  return distinct;
}

// Errors: kInvalidArgument unless edge_costs is empty or one finite positive cost per edge.
Status check_edge_costs(const HalfedgeMesh& mesh, const SeamOptions& options) {
  if (options.edge_costs.empty()) return Ok{};
  if (options.edge_costs.size() != mesh.num_edges()) {
    return make_error(ErrorCode::kInvalidArgument, "edge_costs has " + std::to_string(options.edge_costs.size()) +
                                                       " values for " + std::to_string(mesh.num_edges()) + " edges");
  }
  for (std::size_t e = 0; e < options.edge_costs.size(); ++e) {
    const double c = options.edge_costs[e];
    if (!(c > 0) || !std::isfinite(c)) {
      return make_error(
          ErrorCode::kInvalidArgument,
          "edge cost " + std::to_string(c) + " of edge " + std::to_string(e) + " is not finite and positive",
          {static_cast<std::uint32_t>(e)});
    }
  }
  return Ok{};
}

// Faces bucketed by component once, so many small parts cost O(F) in total, not O(C F).
// Empty with a single component (it is the whole mesh).
std::vector<std::vector<FaceId>> faces_by_component(const HalfedgeMesh& mesh, const Topology& topo) {
  std::vector<std::vector<FaceId>> component_faces(topo.components.size() > 1 ? topo.components.size() : 0);
  if (topo.components.size() > 1) {
    for (std::size_t c = 0; c < topo.components.size(); ++c) component_faces[c].reserve(topo.components[c].faces);
    for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
      component_faces[topo.face_component[FaceId(f)]].push_back(FaceId(f));
    }
  }
  return component_faces;
}

// Each branch of the tree as its chain of vertices, from its first half-edge's tail.
std::vector<std::vector<VertexId>> branch_chains(const HalfedgeMesh& mesh, const SteinerTree& tree) {
  std::vector<std::vector<VertexId>> chains;
  for (const auto& branch : tree.branches) {
    std::vector<VertexId> chain;
    chain.reserve(branch.size() + 1);
    chain.push_back(mesh.tail(branch.front()));
    for (HalfedgeId h : branch) chain.push_back(mesh.head(h));
    chains.push_back(std::move(chain));
  }
  return chains;
}

template <class T>
void sort_unique(std::vector<T>& values) {
  std::sort(values.begin(), values.end());
  values.erase(std::unique(values.begin(), values.end()), values.end());
}

}  // namespace

std::vector<EdgeId> all_cut_edges(const SeamResult& seam) {
  std::vector<EdgeId> all = seam.seam_edges;
  all.insert(all.end(), seam.cut_graph_edges.begin(), seam.cut_graph_edges.end());
  sort_unique(all);
  return all;
}

Result<SeamResult> compute_seam(const HalfedgeMesh& mesh, std::span<const VertexId> extrema, const SeamOptions& options,
                                const CancelToken& cancel) {
  const auto start = StageClock::now();
  const Topology topology = compute_topology(mesh);
  const double topology_ms = ms_since(start);
  SEAM_TRY(SeamResult result, compute_seam(mesh, topology, extrema, options, cancel));
  result.stats.preprocess_ms += topology_ms;
  return result;
}

Result<SeamResult> compute_seam(const HalfedgeMesh& mesh, const Topology& topo, std::span<const VertexId> extrema,
                                const SeamOptions& options, const CancelToken& cancel) {
  SeamResult result;
  SEAM_TRY(result.extrema, distinct_extrema(mesh, extrema));
  if (mesh.num_faces() == 0) return make_error(ErrorCode::kEmptyMesh, "the mesh has no faces");
  if (auto costs = check_edge_costs(mesh, options); !costs.ok()) return costs.take_error();
  if (auto own = check_topology_of(mesh, topo); !own.ok()) return own.take_error();

  std::vector<std::vector<VertexId>> per_component(topo.components.size());
  for (VertexId x : result.extrema) per_component[topo.vertex_component[x]].push_back(x);
  const std::vector<std::vector<FaceId>> component_faces = faces_by_component(mesh, topo);

  std::vector<VertexId> extra_terminals;
  result.optimal = true;
  for (std::uint32_t c = 0; c < topo.components.size(); ++c) {
    if (cancel.is_cancelled()) return cancelled_error("seam");
    SEAM_TRY(ComponentSeam part,
             seam_on_component(mesh, topo, c,
                               topo.components.size() > 1 ? std::span<const FaceId>(component_faces[c])
                                                          : std::span<const FaceId>(),
                               per_component[c], options, result.stats, cancel));
    result.optimal = result.optimal && part.exact;
    result.seam_edges.insert(result.seam_edges.end(), part.seam_edges.begin(), part.seam_edges.end());
    result.cut_graph_edges.insert(result.cut_graph_edges.end(), part.cut_graph_edges.begin(),
                                  part.cut_graph_edges.end());
    extra_terminals.insert(extra_terminals.end(), part.extra_terminals.begin(), part.extra_terminals.end());
  }
  sort_unique(result.seam_edges);
  sort_unique(result.cut_graph_edges);
  sort_unique(extra_terminals);
  result.terminals = result.extrema;
  std::vector<char> is_terminal(mesh.num_vertices(), 0);
  for (VertexId t : result.extrema) is_terminal[t.index()] = 1;
  for (VertexId t : extra_terminals) {
    if (!is_terminal[t.index()]) result.terminals.push_back(t);  // extra_terminals is sorted and unique
  }

  const SteinerTree summary = make_steiner_tree(mesh, result.seam_edges, result.terminals);
  result.steiner_points = summary.steiner_points;
  result.length = summary.length;
  result.branches = branch_chains(mesh, summary);
  for (EdgeId e : result.cut_graph_edges) result.cut_graph_length += mesh.edge_length(e);
  for (EdgeId e : result.seam_edges) {
    result.cost += mesh.edge_length(e) * (options.edge_costs.empty() ? 1.0 : options.edge_costs[e.index()]);
  }

  // The contract: seam plus cut graph opens every component into one disc. Checked here,
  // on the real cut, so a bug anywhere above is a typed error and not a wrong answer.
  const auto start = StageClock::now();
  const std::vector<EdgeId> all = all_cut_edges(result);
  // Counting wedges, edges and faces per part gives the same answer as building the cut mesh
  // (core/mesh/cut_check.h) at a fraction of the cost on large meshes.
  if (auto disc = check_cut_is_disc(mesh, all); !disc.ok()) {
    Error error = disc.take_error();
    error.code = ErrorCode::kTopologyViolation;
    error.message = "the seam does not open the mesh into discs: " + error.message;
    return error;
  }
  result.stats.preprocess_ms += ms_since(start);
  return result;
}

}  // namespace seam::core
