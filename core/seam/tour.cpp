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

// The visit Algorithm 2 removes next, and how.
struct Removal {
  std::size_t visit = 0;  // index in Tour::visits
  bool forced = false;    // no shortcut keeps the tour simple: the pieces around it are merged
};

// Algorithm 2's state while it removes repeated visits: the tour, how often it visits each
// terminal, and the half-edge counts of the intersection test, kept in step with the tour.
class VisitRemoval {
 public:
  VisitRemoval(const HalfedgeMesh& mesh, const TerminalPaths& paths, Tour tour)
      : paths_(paths), tour_(std::move(tour)), visit_count_(paths.size(), 0), checker_(mesh) {
    stats_.initial_visits = tour_.visits.size();
    for (std::uint32_t t : tour_.visits) ++visit_count_[t];
    for (const auto& piece : tour_.pieces) checker_.add(piece, +1);
    for (std::uint32_t c : visit_count_) distinct_ += c > 0 ? 1 : 0;
  }

  bool has_repeated_visits() const { return tour_.visits.size() > distinct_; }

  // The repeated visit whose shortcut Pre -> Next is shortest among those that keep the tour
  // simple (the first visit on ties); if none does, the one with the shortest shortcut,
  // forced. Candidates are taken in order of a lower bound on their shortcut that runs no
  // search (TerminalPaths::lower_bound), and once the bound passes the best shortcut found
  // the rest cannot win, so their pairs are not searched (camel x64, k = 16: 30 -> 25 A*
  // searches of the on-demand paths, the tour 330 -> 277 ms).
  Removal choose() {
    const std::size_t n = tour_.visits.size();
    struct Candidate {
      double bound;
      std::size_t visit;
      bool operator<(const Candidate& o) const { return std::tie(bound, visit) < std::tie(o.bound, o.visit); }
    };
    std::vector<Candidate> candidates;
    for (std::size_t i = 0; i < n; ++i) {
      if (visit_count_[tour_.visits[i]] < 2) continue;
      const auto [pre, nxt] = ends(i);
      candidates.push_back({pre == nxt ? 0.0 : paths_.lower_bound(pre, nxt), i});
    }
    SEAM_ASSERT(!candidates.empty());
    std::sort(candidates.begin(), candidates.end());
    std::size_t best = n;
    double best_priority = kInf;
    for (const Candidate& c : candidates) {
      if (c.bound > best_priority) break;
      const auto [pre, nxt] = ends(c.visit);
      const double priority = distance(pre, nxt);
      // An unreachable pair (infinite) never wins; ties go to the first visit.
      if (!(priority < kInf) || std::tie(priority, c.visit) >= std::tie(best_priority, best)) continue;
      if (!replacement_is_simple(checker_, tour_, prev_index(c.visit, n), 2, shortest(pre, nxt),
                                 paths_.terminals[pre])) {
        ++stats_.rejected_removals;
        continue;
      }
      best_priority = priority;
      best = c.visit;
    }
    if (best < n) return Removal{.visit = best, .forced = false};
    const auto shortcut = [&](const Candidate& c) {
      const auto [pre, nxt] = ends(c.visit);
      return std::make_pair(distance(pre, nxt), c.visit);
    };
    const auto forced = std::min_element(candidates.begin(), candidates.end(),
                                         [&](const Candidate& a, const Candidate& b) { return shortcut(a) < shortcut(b); });
    return Removal{.visit = forced->visit, .forced = true};
  }

  void remove(Removal removal) {
    const std::size_t n = tour_.visits.size();
    // Rotate so the removed visit sits at index 1: Pre at 0, Next at 2.
    const std::size_t shift = prev_index(removal.visit, n);
    std::rotate(tour_.visits.begin(), tour_.visits.begin() + static_cast<std::ptrdiff_t>(shift), tour_.visits.end());
    std::rotate(tour_.pieces.begin(), tour_.pieces.begin() + static_cast<std::ptrdiff_t>(shift), tour_.pieces.end());
    const std::uint32_t pre = tour_.visits[0];
    const std::uint32_t t = tour_.visits[1];
    const std::uint32_t nxt = tour_.visits[2 % n];
    checker_.add(tour_.pieces[0], -1);
    checker_.add(tour_.pieces[1], -1);
    if (removal.forced) {
      // Keep the course: Pre's piece now runs through t to Next.
      ++stats_.forced_merges;
      tour_.pieces[0].insert(tour_.pieces[0].end(), tour_.pieces[1].begin(), tour_.pieces[1].end());
    } else {
      ++stats_.removals;
      tour_.pieces[0] = shortest(pre, nxt);
    }
    checker_.add(tour_.pieces[0], +1);
    tour_.visits.erase(tour_.visits.begin() + 1);
    tour_.pieces.erase(tour_.pieces.begin() + 1);
    --visit_count_[t];
    if (tour_.pieces[0].empty()) {
      // Pre == Next: the loop through t is gone and the two visits of Pre become one.
      tour_.pieces[0] = std::move(tour_.pieces[1]);
      tour_.visits.erase(tour_.visits.begin() + 1);
      tour_.pieces.erase(tour_.pieces.begin() + 1);
      --visit_count_[pre];
    }
  }

  // Tightening: the part of a shortest tour between two terminals is their shortest path
  // (§4.2); pieces that are still walk segments become one where that keeps the tour simple.
  void tighten() {
    const std::size_t n = tour_.visits.size();
    for (std::size_t i = 0; i < n && n >= 2; ++i) {
      const std::uint32_t a = tour_.visits[i];
      const std::uint32_t b = tour_.visits[next_index(i, n)];
      const auto& sp = shortest(a, b);
      if (sp == tour_.pieces[i]) continue;
      if (!replacement_is_simple(checker_, tour_, i, 1, sp, paths_.terminals[a])) continue;
      checker_.add(tour_.pieces[i], -1);
      tour_.pieces[i] = sp;
      checker_.add(tour_.pieces[i], +1);
      ++stats_.tightened;
    }
  }

  // The tour, started at the lowest terminal index so equal inputs give identical tours.
  TourResult finish() {
    const auto first = std::min_element(tour_.visits.begin(), tour_.visits.end()) - tour_.visits.begin();
    std::rotate(tour_.visits.begin(), tour_.visits.begin() + first, tour_.visits.end());
    std::rotate(tour_.pieces.begin(), tour_.pieces.begin() + first, tour_.pieces.end());
    return TourResult{std::move(tour_), stats_};
  }

 private:
  const std::vector<HalfedgeId>& shortest(std::uint32_t a, std::uint32_t b) const {
    return a == b ? no_path_ : paths_.path_between(a, b);
  }
  double distance(std::uint32_t a, std::uint32_t b) const { return a == b ? 0.0 : paths_.dist(a, b); }
  // The terminals visited before and after visit i.
  std::pair<std::uint32_t, std::uint32_t> ends(std::size_t i) const {
    const std::size_t n = tour_.visits.size();
    return {tour_.visits[prev_index(i, n)], tour_.visits[next_index(i, n)]};
  }

  const TerminalPaths& paths_;
  Tour tour_;
  std::vector<std::uint32_t> visit_count_;
  IntersectionChecker checker_;
  const std::vector<HalfedgeId> no_path_;
  std::size_t distinct_ = 0;  // terminals on the initial tour: the number of visits to reach
  TourStats stats_;
};

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
  VisitRemoval removal(mesh, paths, std::move(tour));
  while (removal.has_repeated_visits()) {
    if (cancel.is_cancelled()) return cancelled_error("tour");
    removal.remove(removal.choose());
  }
  removal.tighten();
  return removal.finish();
}

Result<TourResult> build_tour(const HalfedgeMesh& mesh, const TerminalPaths& paths, const CancelToken& cancel) {
  SEAM_TRY(Tour walk, mst_walk(mesh, paths, cancel));
  return remove_repeated_visits(mesh, paths, std::move(walk), cancel);
}

}  // namespace seam::core
