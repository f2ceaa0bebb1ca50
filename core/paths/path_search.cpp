#include "core/paths/path_search.h"

#include <algorithm>

namespace seam::core {

PathSearch::PathSearch(const EdgeGraph& graph)
    : graph_(&graph),
      nodes_(graph.num_vertices()),
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

void PathSearch::reset() {
  // A new generation unsets every record at once.
  settled_order_.clear();
  heap_.clear();
  generation_ += kGenerationStep;
  if (generation_ == 0) {
    std::fill(nodes_.begin(), nodes_.end(), Node{});
    generation_ = kGenerationStep;
  }
}

void PathSearch::add_source(VertexId v, double offset) {
  const std::uint32_t i = v.value();
  Node& n = touch(i);
  if (offset < n.dist) {
    n.dist = offset;
    n.parent = HalfedgeId();
    n.state |= kSource;
    heap_.push(offset, i);
  }
}

template <class OnSettle, class Key>
struct PathSearch::Visitor {
  PathSearch& search;
  OnSettle on_settle;
  Key key;

  SettleAction settle(std::uint32_t v, double popped_key) { return on_settle(v, popped_key); }
  double distance(std::uint32_t v) const { return search.nodes_[v].dist; }
  static std::uint32_t graph_vertex(std::uint32_t v) { return v; }
  bool enters(std::uint32_t w) {
    if (search.mark_[w] == kForbidden) return false;
    return !settled(search.touch(w));
  }
  void relax(std::uint32_t /*v*/, std::uint32_t w, double nd, std::uint32_t slot) {
    PathSearch& s = search;
    Node& n = s.nodes_[w];
    if (nd < n.dist) {
      n.dist = nd;
      n.parent = s.graph_->halfedge[slot];
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
    Node& n = nodes_[v];
    if (settled(n) || d > n.dist) return SettleAction::kSkip;  // stale entry
    if (d > max_distance) return SettleAction::kStop;
    n.state |= kSettled;
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
    Node& n = nodes_[v];
    if (settled(n)) return SettleAction::kSkip;
    // With a consistent estimate the first pop of v carries its final distance.
    n.state |= kSettled;
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
