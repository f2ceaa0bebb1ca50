#include "core/paths/path_search.h"

#include <algorithm>
#include <functional>

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

void PathSearch::touch(std::uint32_t v) {
  if (stamp_[v] == generation_) return;
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
    heap_.emplace_back(offset, i);
    std::push_heap(heap_.begin(), heap_.end(), std::greater<>());
  }
}

template <class Key>
void PathSearch::relax(std::uint32_t v, double d, Key&& key) {
  if (mark_[v] == kBlocked && !is_source_[v]) return;
  const auto& g = *graph_;
  for (std::uint32_t slot = g.offsets[v]; slot < g.offsets[v + 1]; ++slot) {
    const std::uint32_t w = g.head[slot].value();
    if (mark_[w] == kForbidden) continue;
    touch(w);
    if (settled_[w]) continue;
    const double nd = d + g.weight[slot];
    if (nd < dist_[w]) {
      dist_[w] = nd;
      parent_[w] = g.halfedge[slot];
      heap_.emplace_back(key(w, nd), w);
      std::push_heap(heap_.begin(), heap_.end(), std::greater<>());
    }
  }
}

Status PathSearch::run_impl(std::span<const VertexId> targets, double max_distance, bool nearest_only,
                            const CancelToken& cancel) {
  std::size_t targets_left = 0;
  for (VertexId t : targets) {
    if (!is_target_[t.index()]) ++targets_left;
    is_target_[t.index()] = 1;
  }
  if (nearest_only && targets_left > 1) targets_left = 1;
  auto clear_targets = [&] {
    for (VertexId t : targets) is_target_[t.index()] = 0;
  };
  std::uint32_t polls = 0;
  while (!heap_.empty()) {
    if (cancel.poll(polls)) {
      clear_targets();
      return cancelled_error("shortest-path search");
    }
    std::pop_heap(heap_.begin(), heap_.end(), std::greater<>());
    const auto [d, v] = heap_.back();
    heap_.pop_back();
    if (settled_[v] || d > dist_[v]) continue;
    if (d > max_distance) break;
    settled_[v] = 1;
    settled_order_.push_back(VertexId(v));
    if (settled_order_.size() >= max_settled_) break;
    if (is_target_[v] && --targets_left == 0) break;
    relax(v, d, [](std::uint32_t, double nd) { return nd; });
  }
  clear_targets();
  return Ok{};
}

Status PathSearch::run_astar(VertexId target, std::span<const Vec3> positions, const CancelToken& cancel) {
  // The heap holds (g + h, v); sources were pushed with h = 0, so re-key them first.
  const Vec3 goal = positions[target.index()];
  auto estimate = [&](std::uint32_t v) { return (positions[v] - goal).norm(); };
  for (auto& entry : heap_) entry.first += estimate(entry.second);
  std::make_heap(heap_.begin(), heap_.end(), std::greater<>());
  std::uint32_t polls = 0;
  const std::uint32_t t = target.value();
  while (!heap_.empty()) {
    if (cancel.poll(polls)) return cancelled_error("shortest-path search");
    std::pop_heap(heap_.begin(), heap_.end(), std::greater<>());
    const std::uint32_t v = heap_.back().second;
    heap_.pop_back();
    if (settled_[v]) continue;
    // With a consistent estimate the first pop of v carries its final distance.
    settled_[v] = 1;
    settled_order_.push_back(VertexId(v));
    if (v == t) break;
    relax(v, dist_[v], [&](std::uint32_t w, double nd) { return nd + estimate(w); });
  }
  return Ok{};
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
