// A stable LSD radix sort of records by an unsigned key, shared by the weld (hashes) and the
// Z-order numbering (Morton codes). Internal to core.
#pragma once

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace seam::core::detail {

/// Sorts `items` stably by key(item), an unsigned integer: passes of 11-bit digits from the
/// lowest, skipping those whose digit is the same in every record (the top bits of Morton
/// codes of a flat box, say). Equal keys keep their order, so records made in index order come
/// out as std::sort on (key, index) would give them. Preconditions: key(item) < 2^key_bits.
/// Complexity: O(n * key_bits / 11); one scratch copy of `items`.
template <class Item, class Key>
void radix_sort(std::vector<Item>& items, unsigned key_bits, Key key) {
  constexpr unsigned kDigitBits = 11;
  constexpr std::size_t kBuckets = std::size_t{1} << kDigitBits;
  const unsigned passes = (key_bits + kDigitBits - 1) / kDigitBits;
  const std::size_t n = items.size();
  if (n < 2) return;
  std::vector<std::array<std::uint32_t, kBuckets>> count(passes);
  for (auto& c : count) c.fill(0);
  const auto digit = [&](const Item& item, unsigned d) {
    return static_cast<std::size_t>((static_cast<std::uint64_t>(key(item)) >> (kDigitBits * d)) & (kBuckets - 1));
  };
  for (const Item& item : items) {
    for (unsigned d = 0; d < passes; ++d) ++count[d][digit(item, d)];
  }
  std::vector<Item> scratch(n);
  for (unsigned d = 0; d < passes; ++d) {
    if (count[d][digit(items[0], d)] == n) continue;  // one digit value: the pass changes nothing
    std::uint32_t sum = 0;
    for (std::uint32_t& c : count[d]) sum += std::exchange(c, sum);
    for (const Item& item : items) scratch[count[d][digit(item, d)]++] = item;
    items.swap(scratch);
  }
}

}  // namespace seam::core::detail
