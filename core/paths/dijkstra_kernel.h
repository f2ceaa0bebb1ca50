// The one Dijkstra loop of core/paths, core/seam and core/extrema: pop the nearest entry,
// decide whether it settles, relax its out-edges. What differs between the searches (where
// distances live, what ends a search, which vertices are closed, A* keys) is a small
// visitor; which heap orders the frontier is a template argument.
#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>
#include <span>
#include <utility>
#include <vector>

#include "core/cancel.h"
#include "core/error.h"
#include "core/paths/geodesic.h"
#include "core/paths/indexed_heap.h"

namespace seam::core {

/// A 4-ary min-heap of (key, vertex) with lazy deletion: a vertex may be pushed again with
/// a smaller key and its older entries are popped later and skipped by the visitor (stale).
/// Ties are ordered by vertex index, like IndexedHeap, so both settle vertices in one order.
/// Any min-heap over this total order pops the same sequence; four children per node make
/// the tree half as deep as a binary heap's, and a node's children share a cache line.
class LazyHeap {
 public:
  using Entry = std::pair<double, std::uint32_t>;

  bool empty() const { return heap_.empty(); }
  void clear() { heap_.clear(); }
  void push(double key, std::uint32_t v) {
    heap_.push_back(pack(key, v));
    sift_up(heap_.size() - 1, heap_.back());
  }
  Entry top() const { return unpack(heap_.front()); }
  Entry pop() {
    const Packed top = heap_.front();
    const Packed last = heap_.back();
    heap_.pop_back();
    if (!heap_.empty()) {
      // The hole at the root sinks to a leaf along the least children, then the last entry
      // rises from there: it usually belongs near the bottom, so this compares less than
      // sinking it from the root.
      std::size_t hole = 0;
      const std::size_t n = heap_.size();
      for (std::size_t first = 1; first < n; first = kArity * hole + 1) {
        const std::size_t end = std::min(first + kArity, n);
        std::size_t least = first;
        for (std::size_t c = first + 1; c < end; ++c) {
          if (heap_[c] < heap_[least]) least = c;
        }
        heap_[hole] = heap_[least];
        hole = least;
      }
      sift_up(hole, last);
    }
    return unpack(top);
  }
  /// Adds `delta(v)` to every key and restores the heap order (A* re-keying of sources).
  template <class Delta>
  void rekey(Delta&& delta) {
    for (auto& entry : heap_) {
      const auto [key, v] = unpack(entry);
      entry = pack(key + delta(v), v);
    }
    // Heap order by insertion, in place: entries [0, i) are a heap when entry i rises.
    for (std::size_t i = 1; i < heap_.size(); ++i) sift_up(i, heap_[i]);
  }

 private:
  static constexpr std::size_t kArity = 4;
  // (key, vertex) as one 128-bit integer whose unsigned order is the order by key, then
  // vertex (Entry's operator<, without its branches; ordered_bits, indexed_heap.h).
  __extension__ typedef unsigned __int128 Packed;
  static Packed pack(double key, std::uint32_t v) { return (Packed{ordered_bits(key)} << 32) | v; }
  static Entry unpack(Packed p) {
    return {from_ordered_bits(static_cast<std::uint64_t>(p >> 32)), static_cast<std::uint32_t>(p)};
  }

  // Places `entry` at hole i or above it.
  void sift_up(std::size_t i, Packed entry) {
    while (i > 0) {
      const std::size_t parent = (i - 1) / kArity;
      if (!(entry < heap_[parent])) break;
      heap_[i] = heap_[parent];
      i = parent;
    }
    heap_[i] = entry;
  }

  std::vector<Packed> heap_;
};

/// A sorted list of seed entries streamed in order alongside a LazyHeap of improvements:
/// a multi-source search with many sources (a Dreyfus-Wagner row after merging) pays a sort
/// instead of a heap push per source. Pops the smaller of the next seed and the heap's top
/// (ties: the heap's). `seeds` must be sorted and outlive this.
class SeededHeap {
 public:
  using Entry = LazyHeap::Entry;

  SeededHeap(std::span<const Entry> seeds, LazyHeap& heap) : seeds_(seeds), heap_(heap) {}
  bool empty() const { return next_ >= seeds_.size() && heap_.empty(); }
  void push(double key, std::uint32_t v) { heap_.push(key, v); }
  Entry pop() {
    if (heap_.empty() || (next_ < seeds_.size() && seeds_[next_] < heap_.top())) return seeds_[next_++];
    return heap_.pop();
  }

 private:
  std::span<const Entry> seeds_;
  std::size_t next_ = 0;
  LazyHeap& heap_;
};

/// What a visitor decides for a popped entry.
enum class SettleAction : std::uint8_t {
  kExpand,  ///< v is settled: relax its out-edges
  kSkip,    ///< stale entry, or settled but closed (blocked): pop the next one
  kStop,    ///< the search is over (target reached, beyond a limit); the heap is left as is
};

namespace detail {
inline std::pair<std::uint32_t, double> pop_min(IndexedHeap& heap) {
  const std::uint32_t v = heap.pop();
  return {v, heap.key(v)};
}
// Heaps whose pop() returns a (key, vertex) entry: LazyHeap, SeededHeap.
template <class Heap>
std::pair<std::uint32_t, double> pop_min(Heap& heap) {
  const auto [key, v] = heap.pop();
  return {v, key};
}
}  // namespace detail

/// Runs the search until `heap` is empty or the visitor stops it. The visitor provides
///   SettleAction settle(std::uint32_t v, double key): v was popped with `key`;
///   double distance(std::uint32_t v): v's settled distance (read after kExpand);
///   std::uint32_t graph_vertex(std::uint32_t v): v's vertex in `graph` (v's own index space
///     may differ, e.g. a component's local numbering);
///   void relax(std::uint32_t v, std::uint32_t w, double nd, std::uint32_t slot): the edge
///     graph.head[slot] = w (a vertex of `graph`) out of v offers w the distance nd; the
///     visitor compares, records and pushes;
///   optionally bool enters(std::uint32_t w): false skips the edge before its weight is read
///     (PathSearch: forbidden or already settled w), which saves the weight load where most
///     neighbours are settled.
/// Out-edges are relaxed in slot order. `cancel` is polled once per popped entry (stale ones
/// included) through `polls`. Errors: kCancelled (message names `what`).
template <class Heap, class Visitor>
Status run_dijkstra(const EdgeGraph& graph, Heap& heap, Visitor& visitor, const CancelToken& cancel,
                    const char* what, std::uint32_t& polls) {
  while (!heap.empty()) {
    if (cancel.poll(polls)) return cancelled_error(what);
    const auto [v, key] = detail::pop_min(heap);
    const SettleAction action = visitor.settle(v, key);
    if (action == SettleAction::kStop) break;
    if (action == SettleAction::kSkip) continue;
    const double d = visitor.distance(v);
    const std::uint32_t gv = visitor.graph_vertex(v);
    for (std::uint32_t slot = graph.offsets[gv]; slot < graph.offsets[gv + 1]; ++slot) {
      const std::uint32_t w = graph.head[slot].value();
      if constexpr (requires { visitor.enters(w); }) {
        if (!visitor.enters(w)) continue;
      }
      visitor.relax(v, w, d + graph.weight[slot], slot);
    }
  }
  return Ok{};
}

/// The same with a poll counter that starts at zero for this search. Errors: kCancelled.
template <class Heap, class Visitor>
Status run_dijkstra(const EdgeGraph& graph, Heap& heap, Visitor& visitor, const CancelToken& cancel,
                    const char* what) {
  std::uint32_t polls = 0;
  return run_dijkstra(graph, heap, visitor, cancel, what, polls);
}

}  // namespace seam::core
