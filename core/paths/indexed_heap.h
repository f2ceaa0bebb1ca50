// A 4-ary indexed min-heap of vertex indices with decrease-key, for the Dijkstra searches
// of core/paths/dijkstra_kernel.h that keep one distance array (geodesic.cpp, extrema.cpp).
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <vector>

namespace seam::core {

/// The bits of `key` as an unsigned integer that orders as the doubles do (NaN aside): the
/// sign bit flipped for keys >= 0, every bit flipped for negative ones; -0.0 counts as +0.0.
inline std::uint64_t ordered_bits(double key) {
  const std::uint64_t u = std::bit_cast<std::uint64_t>(key + 0.0);
  return u ^ ((u >> 63) ? ~std::uint64_t{0} : (std::uint64_t{1} << 63));
}
/// The key whose ordered_bits are `u`.
inline double from_ordered_bits(std::uint64_t u) {
  return std::bit_cast<double>((u >> 63) ? u ^ (std::uint64_t{1} << 63) : ~u);
}

// Keyed by an external distance array that the caller owns and updates before calling
// push_or_decrease. Compared with std::priority_queue and lazy deletion it holds each vertex
// at most once (V entries instead of up to E), which halves the memory traffic on large
// meshes; ties are ordered by index, so every search settles vertices in one deterministic
// order. A popped vertex may be pushed again (callers reuse one heap across searches).
class IndexedHeap {
 public:
  static constexpr std::uint32_t kNone = 0xffffffffu;

  IndexedHeap(const std::vector<double>& key, std::size_t size) : key_(key), position_(size, kNone) {}
  bool empty() const { return heap_.empty(); }
  /// The key the heap orders v by (the caller's distance array).
  double key(std::uint32_t v) const { return key_[v]; }

  /// Inserts v, or moves it up after its key decreased.
  void push_or_decrease(std::uint32_t v) {
    std::uint32_t i = position_[v];
    if (i == kNone) {
      i = static_cast<std::uint32_t>(heap_.size());
      heap_.emplace_back();
    }
    sift_up(i, pack(v));
  }

  std::uint32_t pop() {
    const std::uint32_t top = vertex(heap_[0]);
    position_[top] = kNone;
    const Packed last = heap_.back();
    heap_.pop_back();
    if (!heap_.empty()) sift_down(0, last);
    return top;
  }

 private:
  // Each entry carries its key: (key, vertex) as one 128-bit integer whose unsigned order is
  // the order by key, then index (ordered_bits), so comparisons read no distance array.
  __extension__ typedef unsigned __int128 Packed;
  Packed pack(std::uint32_t v) const { return (Packed{ordered_bits(key_[v])} << 32) | v; }
  static std::uint32_t vertex(Packed p) { return static_cast<std::uint32_t>(p); }

  void place(std::uint32_t i, Packed entry) {
    heap_[i] = entry;
    position_[vertex(entry)] = i;
  }
  void sift_up(std::uint32_t i, Packed entry) {
    while (i > 0) {
      const std::uint32_t parent = (i - 1) / 4;
      if (!(entry < heap_[parent])) break;
      place(i, heap_[parent]);
      i = parent;
    }
    place(i, entry);
  }
  void sift_down(std::uint32_t i, Packed entry) {
    const auto n = static_cast<std::uint32_t>(heap_.size());
    while (true) {
      const std::uint32_t first = 4 * i + 1;
      if (first >= n) break;
      std::uint32_t best = first;
      const std::uint32_t end = std::min(first + 4, n);
      for (std::uint32_t c = first + 1; c < end; ++c) {
        if (heap_[c] < heap_[best]) best = c;
      }
      if (!(heap_[best] < entry)) break;
      place(i, heap_[best]);
      i = best;
    }
    place(i, entry);
  }

  const std::vector<double>& key_;
  std::vector<std::uint32_t> position_;
  std::vector<Packed> heap_;
};

}  // namespace seam::core
