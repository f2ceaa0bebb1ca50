#include "core/seam/tour.h"

#include <algorithm>
#include <limits>
#include <numeric>
#include <tuple>

#include "core/seam/tree_util.h"

namespace seam::core {

namespace {

// Algorithm 1's state: how often each half-edge is on the tour, so candidate tours can be
// checked by adding and removing pieces instead of rebuilding the set.
class IntersectionChecker {
 public:
  explicit IntersectionChecker(const HalfedgeMesh& mesh)
      : mesh_(mesh), count_(mesh.num_halfedges(), 0), vertex_stamp_(mesh.num_vertices(), 0) {}

  void add(std::span<const HalfedgeId> piece, int delta) {
    for (HalfedgeId h : piece) count_[h.index()] += delta;
  }

  // The inner loop of Algorithm 1 for the consecutive tour half-edges ei -> ej: sweep from
  // ei.Next around head(ei) (e = e.Twin.Next) until ej; any tour half-edge met means the
  // tour crosses or touches itself from the left (exterior) side here.
  bool sweep_hits(HalfedgeId ei, HalfedgeId ej) const {
    SEAM_ASSERT(mesh_.head(ei) == mesh_.tail(ej));
    const HalfedgeId first = mesh_.next(ei);
    HalfedgeId ek = first;
    while (ek != ej) {
      if (count_[ek.index()] > 0) return true;
      ek = mesh_.next(HalfedgeMesh::twin(ek));
      SEAM_ASSERT(ek != first);  // ej is outgoing at head(ei), so the sweep reaches it
    }
    return false;
  }

  // Algorithm 1 restricted to the turns at vertices stamped by mark_vertices(): the rest of
  // the tour is unchanged and only lost half-edges, so it cannot have become self-intersecting.
  template <class Seq>
  bool intersects_at_marked(const Seq& pieces_in_order) const {
    HalfedgeId prev;
    for (const auto* piece : pieces_in_order) {
      if (!piece->empty()) prev = piece->back();
    }
    if (!prev.valid()) return false;
    for (const auto* piece : pieces_in_order) {
      for (HalfedgeId h : *piece) {
        if (vertex_stamp_[mesh_.head(prev).index()] == stamp_ && sweep_hits(prev, h)) return true;
        prev = h;
      }
    }
    return false;
  }

  void mark_vertices(std::span<const HalfedgeId> path, VertexId endpoint) {
    ++stamp_;
    vertex_stamp_[endpoint.index()] = stamp_;
    for (HalfedgeId h : path) {
      vertex_stamp_[mesh_.tail(h).index()] = stamp_;
      vertex_stamp_[mesh_.head(h).index()] = stamp_;
    }
  }

 private:
  const HalfedgeMesh& mesh_;
  std::vector<std::int32_t> count_;
  std::vector<std::uint32_t> vertex_stamp_;
  std::uint32_t stamp_ = 0;
};

std::size_t prev_index(std::size_t i, std::size_t n) { return (i + n - 1) % n; }
std::size_t next_index(std::size_t i, std::size_t n) { return (i + 1) % n; }

// True when replacing pieces [first, first + count) (cyclically) by `replacement` keeps the
// tour free of self-intersections. `replacement` starts at visits[first].
bool replacement_is_simple(IntersectionChecker& checker, const Tour& tour, std::size_t first, std::size_t count,
                           const std::vector<HalfedgeId>& replacement, VertexId start_vertex) {
  const std::size_t n = tour.visits.size();
  for (std::size_t c = 0; c < count; ++c) checker.add(tour.pieces[(first + c) % n], -1);
  checker.add(replacement, +1);
  checker.mark_vertices(replacement, start_vertex);
  std::vector<const std::vector<HalfedgeId>*> order;
  order.reserve(n - count + 1);
  for (std::size_t c = count; c < n; ++c) order.push_back(&tour.pieces[(first + c) % n]);
  order.push_back(&replacement);
  const bool bad = checker.intersects_at_marked(order);
  checker.add(replacement, -1);
  for (std::size_t c = 0; c < count; ++c) checker.add(tour.pieces[(first + c) % n], +1);
  return !bad;
}

}  // namespace

std::vector<HalfedgeId> Tour::halfedges() const {
  std::vector<HalfedgeId> all;
  for (const auto& piece : pieces) all.insert(all.end(), piece.begin(), piece.end());
  return all;
}

std::vector<std::array<std::uint32_t, 2>> terminal_mst(const TerminalPaths& paths) { return paths.mst; }

bool tour_self_intersects(const HalfedgeMesh& mesh, std::span<const HalfedgeId> walk) {
  if (walk.empty()) return false;
  IntersectionChecker checker(mesh);
  checker.add(walk, +1);
  for (std::size_t i = 0; i < walk.size(); ++i) {
    if (checker.sweep_hits(walk[i], walk[(i + 1) % walk.size()])) return true;
  }
  return false;
}

Result<Tour> mst_walk(const HalfedgeMesh& mesh, const TerminalPaths& paths, const CancelToken& cancel) {
  const std::size_t k = paths.size();
  if (k < 2) {
    return make_error(ErrorCode::kInvalidArgument, "the tour needs at least two terminals");
  }
  const auto mst = terminal_mst(paths);
  if (mst.size() + 1 != k) return make_error(ErrorCode::kInvalidArgument, "the terminals are not connected");

  // Merge the MST's paths into one tree of mesh edges; where shortest paths share edges or
  // cross, the walk around their union is what stays free of self-intersections.
  detail::UnionFind uf(mesh.num_vertices());
  std::vector<EdgeId> tree;
  for (const auto& [i, j] : mst) {
    const auto& path = paths.path_between(i, j);
    if (path.empty()) return make_error(ErrorCode::kInvalidArgument, "missing path between two terminals");
    for (HalfedgeId h : path) {
      if (uf.unite(mesh.tail(h).value(), mesh.head(h).value())) tree.push_back(HalfedgeMesh::edge(h));
    }
  }
  if (cancel.is_cancelled()) return cancelled_error("tour");
  tree = detail::prune_dangling(mesh, std::move(tree), paths.terminals);

  std::vector<std::uint8_t> in_tree(mesh.num_halfedges(), 0);
  for (EdgeId e : tree) {
    in_tree[HalfedgeMesh::halfedge(e, 0).index()] = 1;
    in_tree[HalfedgeMesh::halfedge(e, 1).index()] = 1;
  }
  HalfedgeId start;
  mesh.for_each_outgoing(paths.terminals[0], [&](HalfedgeId h) {
    if (!start.valid() && in_tree[h.index()]) start = h;
  });
  SEAM_ASSERT(start.valid());

  // Walk with the tree on the left: at each vertex take the first tree half-edge met when
  // sweeping clockwise from the incoming half-edge's next (the sweep of Algorithm 1), so the
  // sweep between consecutive tour half-edges never meets the tour.
  std::vector<HalfedgeId> walk;
  walk.reserve(2 * tree.size());
  HalfedgeId h = start;
  do {
    walk.push_back(h);
    HalfedgeId ek = mesh.next(h);
    while (!in_tree[ek.index()]) ek = mesh.next(HalfedgeMesh::twin(ek));
    h = ek;
  } while (h != start && walk.size() <= 2 * tree.size());
  SEAM_ASSERT(walk.size() == 2 * tree.size());

  std::vector<std::int32_t> terminal_of(mesh.num_vertices(), -1);
  for (std::size_t i = 0; i < k; ++i) terminal_of[paths.terminals[i].index()] = static_cast<std::int32_t>(i);
  Tour tour;
  for (std::size_t p = 0; p < walk.size(); ++p) {
    const std::int32_t t = terminal_of[mesh.tail(walk[p]).index()];
    if (t >= 0) {
      tour.visits.push_back(static_cast<std::uint32_t>(t));
      tour.pieces.emplace_back();
    }
    tour.pieces.back().push_back(walk[p]);
  }
  return tour;
}

Result<TourResult> remove_repeated_visits(const HalfedgeMesh& mesh, const TerminalPaths& paths, Tour tour,
                                          const CancelToken& cancel) {
  TourStats st;
  st.initial_visits = tour.visits.size();
  const std::size_t k = paths.size();
  std::vector<std::uint32_t> visit_count(k, 0);
  for (std::uint32_t t : tour.visits) ++visit_count[t];
  IntersectionChecker checker(mesh);
  for (const auto& piece : tour.pieces) checker.add(piece, +1);
  const std::vector<HalfedgeId> no_path;
  auto shortest = [&](std::uint32_t a, std::uint32_t b) -> const std::vector<HalfedgeId>& {
    return a == b ? no_path : paths.path_between(a, b);
  };
  auto distance = [&](std::uint32_t a, std::uint32_t b) { return a == b ? 0.0 : paths.dist(a, b); };

  std::size_t distinct = 0;
  for (std::uint32_t c : visit_count) distinct += c > 0 ? 1 : 0;
  while (tour.visits.size() > distinct) {
    if (cancel.is_cancelled()) return cancelled_error("tour");
    const std::size_t n = tour.visits.size();
    constexpr double kInf = std::numeric_limits<double>::infinity();
    std::size_t best = n;
    double best_priority = kInf;
    std::size_t forced = n;
    double forced_priority = kInf;
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t t = tour.visits[i];
      if (visit_count[t] < 2) continue;
      const std::size_t ip = prev_index(i, n);
      const std::uint32_t pre = tour.visits[ip];
      const std::uint32_t nxt = tour.visits[next_index(i, n)];
      const double priority = distance(pre, nxt);
      if (priority < forced_priority) forced_priority = priority, forced = i;
      if (priority >= best_priority) continue;  // cannot win; skip the intersection test
      if (!replacement_is_simple(checker, tour, ip, 2, shortest(pre, nxt), paths.terminals[pre])) {
        ++st.rejected_removals;
        continue;
      }
      best_priority = priority;
      best = i;
    }
    SEAM_ASSERT(forced < n);
    const bool is_forced = best == n;
    const std::size_t i = is_forced ? forced : best;
    // Rotate so the removed visit sits at index 1: Pre at 0, Next at 2.
    const std::size_t shift = prev_index(i, n);
    std::rotate(tour.visits.begin(), tour.visits.begin() + static_cast<std::ptrdiff_t>(shift), tour.visits.end());
    std::rotate(tour.pieces.begin(), tour.pieces.begin() + static_cast<std::ptrdiff_t>(shift), tour.pieces.end());
    const std::uint32_t pre = tour.visits[0];
    const std::uint32_t t = tour.visits[1];
    const std::uint32_t nxt = tour.visits[2 % n];
    checker.add(tour.pieces[0], -1);
    checker.add(tour.pieces[1], -1);
    if (is_forced) {
      // Keep the course: Pre's piece now runs through t to Next.
      ++st.forced_merges;
      tour.pieces[0].insert(tour.pieces[0].end(), tour.pieces[1].begin(), tour.pieces[1].end());
    } else {
      ++st.removals;
      tour.pieces[0] = shortest(pre, nxt);
    }
    checker.add(tour.pieces[0], +1);
    tour.visits.erase(tour.visits.begin() + 1);
    tour.pieces.erase(tour.pieces.begin() + 1);
    --visit_count[t];
    if (tour.pieces[0].empty()) {
      // Pre == Next: the loop through t is gone and the two visits of Pre become one.
      tour.pieces[0] = std::move(tour.pieces[1]);
      tour.visits.erase(tour.visits.begin() + 1);
      tour.pieces.erase(tour.pieces.begin() + 1);
      --visit_count[pre];
    }
  }

  // Tightening: the part of a shortest tour between two terminals is their shortest path
  // (§4.2); pieces that are still walk segments become one where that keeps the tour simple.
  const std::size_t n = tour.visits.size();
  for (std::size_t i = 0; i < n && n >= 2; ++i) {
    const std::uint32_t a = tour.visits[i];
    const std::uint32_t b = tour.visits[next_index(i, n)];
    const auto& sp = shortest(a, b);
    if (sp == tour.pieces[i]) continue;
    if (!replacement_is_simple(checker, tour, i, 1, sp, paths.terminals[a])) continue;
    checker.add(tour.pieces[i], -1);
    tour.pieces[i] = sp;
    checker.add(tour.pieces[i], +1);
    ++st.tightened;
  }
  // Start at the lowest terminal index so equal inputs give identical tours.
  const auto first = std::min_element(tour.visits.begin(), tour.visits.end()) - tour.visits.begin();
  std::rotate(tour.visits.begin(), tour.visits.begin() + first, tour.visits.end());
  std::rotate(tour.pieces.begin(), tour.pieces.begin() + first, tour.pieces.end());
  return TourResult{std::move(tour), st};
}

Result<TourResult> build_tour(const HalfedgeMesh& mesh, const TerminalPaths& paths, const CancelToken& cancel) {
  SEAM_TRY(Tour walk, mst_walk(mesh, paths, cancel));
  return remove_repeated_visits(mesh, paths, std::move(walk), cancel);
}

}  // namespace seam::core
