// Stable sorting of the short runs a bucket pass leaves (a vertex's corners or triangles).
#pragma once

#include <algorithm>

namespace seam::core {

/// Sorts [first, last) stably by `less`: by insertion up to 32 elements (a vertex's few
/// corners or triangles), by std::stable_sort beyond. Empty and one-element runs are left
/// as they are without forming an iterator past `last`.
template <class It, class Less>
void stable_sort_small(It first, It last, Less less) {
  if (last - first > 32) {
    std::stable_sort(first, last, less);
    return;
  }
  if (last - first < 2) return;
  for (It i = first + 1; i != last; ++i) {
    auto item = std::move(*i);
    It j = i;
    for (; j != first && less(item, *(j - 1)); --j) *j = std::move(*(j - 1));
    *j = std::move(item);
  }
}

}  // namespace seam::core
