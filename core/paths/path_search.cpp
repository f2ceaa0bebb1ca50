#include "core/paths/path_search.h"

#include <algorithm>

namespace seam::core {

PathSearch::PathSearch(const EdgeGraph& graph)
    : graph_(&graph),
      dist_(graph.num_vertices(), kUnreached),
      parent_(graph.num_vertices()),
      stamp_(graph.num_vertices(), 0),
      settled_(graph.num_vertices(), 0),
      is_source_(graph.num_vertices(), 0),
      mark_(graph.num_vertices(), kFree),
      is_target_(graph.num_vertices(), 0) {}

void PathSearch::block(VertexId v) {
  if (mark_[v.index()] == kFree) marked_.push_back(v.value());
  mark_[v.index()] = kBlocked;
}

void PathSearch::forbid(VertexId v) {
  if (mark_[v.index()] == kFree) marked_.push_back(v.value());
  mark_[v.index()] = kForbidden;
}

void PathSearch::clear_marks() {
  for (std::uint32_t v : marked_) mark_[v] = kFree;
  marked_.clear();
}

void PathSearch::first_touch(std::uint32_t v) {
  stamp_[v] = generation_;
  dist_[v] = kUnreached;
  parent_[v] = HalfedgeId();
  settled_[v] = 0;
  is_source_[v] = 0;
  touched_.push_back(v);
}

void PathSearch::reset() {
  // A new generation invalidates every stamp at once; the flags that are read without a
  // stamp check are cleared through the touched list.
  for (std::uint32_t v : touched_) {
    settled_[v] = 0;
    is_source_[v] = 0;
  }
  touched_.clear();
  settled_order_.clear();
  heap_.clear();
  if (++generation_ == 0) {
    std::fill(stamp_.begin(), stamp_.end(), 0u);
    generation_ = 1;
  }
}

void PathSearch::add_source(VertexId v, double offset) {
  const std::uint32_t i = v.value();
  touch(i);
  if (offset < dist_[i]) {
    dist_[i] = offset;
    parent_[i] = HalfedgeId();
    is_source_[i] = 1;
    heap_.push(offset, i);
  }
}

template <class OnSettle, class Key>
struct PathSearch::Visitor {
  PathSearch& search;
  OnSettle on_settle;
  Key key;

  SettleAction settle(std::uint32_t v, double popped_key) { return on_settle(v, popped_key); }
  double distance(std::uint32_t v) const { return search.dist_[v]; }
  static std::uint32_t graph_vertex(std::uint32_t v) { return v; }
  bool enters(std::uint32_t w) {
    if (search.mark_[w] == kForbidden) return false;
    search.touch(w);
    return !search.settled_[w];
  }
  void relax(std::uint32_t /*v*/, std::uint32_t w, double nd, std::uint32_t slot) {
    PathSearch& s = search;
    if (nd < s.dist_[w]) {
      s.dist_[w] = nd;
      s.parent_[w] = s.graph_->halfedge[slot];
      s.heap_.push(key(w, nd), w);
    }
  }
};

Status PathSearch::run_impl(std::span<const VertexId> targets, double max_distance, bool nearest_only,
                            const CancelToken& cancel) {
  std::size_t targets_left = 0;
  for (VertexId t : targets) {
    if (!is_target_[t.index()]) ++targets_left;
    is_target_[t.index()] = 1;
  }
  if (nearest_only && targets_left > 1) targets_left = 1;
  auto on_settle = [&](std::uint32_t v, double d) {
    if (settled_[v] || d > dist_[v]) return SettleAction::kSkip;  // stale entry
    if (d > max_distance) return SettleAction::kStop;
    settled_[v] = 1;
    settled_order_.push_back(VertexId(v));
    if (settled_order_.size() >= max_settled_) return SettleAction::kStop;
    if (is_target_[v] && --targets_left == 0) return SettleAction::kStop;
    return expand_unless_blocked(v);
  };
  auto key = [](std::uint32_t, double nd) { return nd; };
  Visitor<decltype(on_settle), decltype(key)> visitor{*this, on_settle, key};
  Status status = run_dijkstra(*graph_, heap_, visitor, cancel, "shortest-path search");
  for (VertexId t : targets) is_target_[t.index()] = 0;
  return status;
}

Status PathSearch::run_astar(VertexId target, std::span<const Vec3> positions, std::span<const double> floor,
                             const CancelToken& cancel) {
  // The heap holds (g + h, v); sources were pushed with h = 0, so re-key them first.
  const Vec3 goal = positions[target.index()];
  auto estimate = [&](std::uint32_t v) {
    const double line = (positions[v] - goal).norm();
    return floor.empty() ? line : std::max(line, floor[v]);
  };
  heap_.rekey(estimate);
  const std::uint32_t t = target.value();
  auto on_settle = [&](std::uint32_t v, double) {
    if (settled_[v]) return SettleAction::kSkip;
    // With a consistent estimate the first pop of v carries its final distance.
    settled_[v] = 1;
    settled_order_.push_back(VertexId(v));
    if (v == t) return SettleAction::kStop;
    return expand_unless_blocked(v);
  };
  auto key = [&](std::uint32_t w, double nd) { return nd + estimate(w); };
  Visitor<decltype(on_settle), decltype(key)> visitor{*this, on_settle, key};
  return run_dijkstra(*graph_, heap_, visitor, cancel, "shortest-path search");
}

std::vector<HalfedgeId> PathSearch::path_to(const HalfedgeMesh& mesh, VertexId v) const {
  std::vector<HalfedgeId> path;
  if (!reached(v)) return path;
  VertexId x = v;
  for (HalfedgeId h = parent(x); h.valid(); h = parent(x)) {
    path.push_back(h);
    x = mesh.tail(h);
  }
  std::reverse(path.begin(), path.end());
  return path;
}

}  // namespace seam::core
