#include "core/mesh/weld.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numeric>
#include <string>
#include <unordered_map>
#include <utility>

namespace seam::core {
namespace {

// Union-find with union by smaller representative, so each set's root is its smallest
// input index: the representative the API contract asks for.
struct DisjointSets {
  std::vector<std::uint32_t> parent;
  explicit DisjointSets(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  std::uint32_t find(std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return;
    if (a < b) std::swap(a, b);
    parent[a] = b;
  }
};

// (key, index) pairs sorted by key, stably: an LSD radix sort, 8 passes of 8 bits, skipping
// the passes whose digit is the same in every key. Equal keys keep their index order, so the
// result is the one std::sort gives on (key, index) pairs with distinct ascending indices.
// O(n) time, one scratch copy.
struct KeyIndex {
  std::uint64_t key;
  std::uint32_t index;
};

void radix_sort_by_key(std::vector<KeyIndex>& items) {
  const std::size_t n = items.size();
  std::vector<std::array<std::uint32_t, 256>> count(8);
  for (auto& c : count) c.fill(0);
  for (const KeyIndex& item : items) {
    for (unsigned d = 0; d < 8; ++d) ++count[d][(item.key >> (8 * d)) & 0xffu];
  }
  std::vector<KeyIndex> scratch(n);
  for (unsigned d = 0; d < 8; ++d) {
    if (count[d][(items.empty() ? 0 : items[0].key >> (8 * d)) & 0xffu] == n) continue;  // one digit value
    std::uint32_t sum = 0;
    for (std::uint32_t& c : count[d]) sum += std::exchange(c, sum);
    for (const KeyIndex& item : items) scratch[count[d][(item.key >> (8 * d)) & 0xffu]++] = item;
    items.swap(scratch);
  }
}

std::uint64_t cell_key(std::int64_t x, std::int64_t y, std::int64_t z) {
  // 21 bits per axis; collisions between far cells only cost extra distance checks.
  const auto m = [](std::int64_t v) { return static_cast<std::uint64_t>(v) & 0x1fffffu; };
  return (m(x) << 42) | (m(y) << 21) | m(z);
}

WeldResult finish(std::span<const Vec3> positions, DisjointSets& sets) {
  WeldResult result;
  const std::size_t n = positions.size();
  result.input_to_welded.assign(n, 0);
  std::vector<std::uint32_t> root_to_welded(n, VertexId::kInvalidValue);
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t root = sets.find(i);
    if (root_to_welded[root] == VertexId::kInvalidValue) {
      // Roots are smallest members, and i increases: i == root the first time we see it.
      root_to_welded[root] = static_cast<std::uint32_t>(result.welded_to_input.size());
      result.welded_to_input.push_back(root);
      result.positions.push_back(positions[root]);
    }
    result.input_to_welded[i] = root_to_welded[root];
  }
  return result;
}

}  // namespace

Result<WeldResult> weld_vertices(std::span<const Vec3> positions, const WeldOptions& options,
                                 const CancelToken& cancel) {
  if (!std::isfinite(options.epsilon) || options.epsilon < 0.0) {
    return make_error(ErrorCode::kInvalidArgument, "weld epsilon must be a finite number >= 0");
  }
  std::vector<std::uint32_t> bad;
  for (std::size_t i = 0; i < positions.size() && bad.size() < 8; ++i) {
    if (!positions[i].allFinite()) bad.push_back(static_cast<std::uint32_t>(i));
  }
  if (!bad.empty()) {
    return make_error(ErrorCode::kNonFinitePosition,
                      "vertex " + std::to_string(bad[0]) + " has a NaN or infinite coordinate", bad);
  }
  const std::size_t n = positions.size();
  DisjointSets sets(n);
  std::uint32_t polls = 0;

  if (options.epsilon == 0.0) {
    // Sort (hash of the exact bit pattern, index) pairs: plain 128-bit keys sort several
    // times faster than coordinate triples. Equal positions have equal hashes; within a run
    // of equal hashes, positions are compared exactly, so a collision never welds.
    auto bits = [](double x) {
      x += 0.0;  // folds -0.0 into +0.0
      std::uint64_t b;
      std::memcpy(&b, &x, sizeof b);
      return b;
    };
    auto mix = [](std::uint64_t h) {  // splitmix64 finaliser
      h ^= h >> 30;
      h *= 0xbf58476d1ce4e5b9ULL;
      h ^= h >> 27;
      h *= 0x94d049bb133111ebULL;
      return h ^ (h >> 31);
    };
    std::vector<KeyIndex> keyed(n);
    for (std::uint32_t i = 0; i < n; ++i) {
      const Vec3& p = positions[i];
      keyed[i] = {mix(bits(p.x()) ^ mix(bits(p.y()) ^ mix(bits(p.z())))), i};
    }
    radix_sort_by_key(keyed);
    auto same = [&](std::uint32_t a, std::uint32_t b) {
      return positions[a].x() == positions[b].x() && positions[a].y() == positions[b].y() &&
             positions[a].z() == positions[b].z();
    };
    for (std::size_t begin = 0; begin < n;) {
      std::size_t end = begin + 1;
      while (end < n && keyed[end].key == keyed[begin].key) ++end;
      for (std::size_t i = begin + 1; i < end; ++i) {
        if (cancel.poll(polls)) return cancelled_error("welding");
        for (std::size_t j = begin; j < i; ++j) {
          if (same(keyed[i].index, keyed[j].index)) {
            sets.unite(keyed[i].index, keyed[j].index);
            break;
          }
        }
      }
      begin = end;
    }
    return finish(positions, sets);
  }

  // Grid of cell size epsilon: any pair within epsilon lies in the same or adjacent cells.
  const double inv = 1.0 / options.epsilon;
  const double eps2 = options.epsilon * options.epsilon;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid;
  grid.reserve(n);
  std::vector<std::array<std::int64_t, 3>> cells(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    for (int a = 0; a < 3; ++a) cells[i][a] = static_cast<std::int64_t>(std::floor(positions[i][a] * inv));
    grid[cell_key(cells[i][0], cells[i][1], cells[i][2])].push_back(i);
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    if (cancel.poll(polls)) return cancelled_error("welding");
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = grid.find(cell_key(cells[i][0] + dx, cells[i][1] + dy, cells[i][2] + dz));
          if (it == grid.end()) continue;
          for (std::uint32_t j : it->second) {
            if (j < i && (positions[i] - positions[j]).squaredNorm() < eps2) sets.unite(i, j);
          }
        }
      }
    }
  }
  return finish(positions, sets);
}

std::vector<Triangle> remap_triangles(std::span<const Triangle> triangles,
                                      std::span<const std::uint32_t> input_to_welded) {
  std::vector<Triangle> result(triangles.size());
  for (std::size_t f = 0; f < triangles.size(); ++f) {
    for (int i = 0; i < 3; ++i) {
      // An out-of-range index stays out of range so the mesh builder reports it.
      const std::uint32_t v = triangles[f][i];
      result[f][i] = v < input_to_welded.size() ? input_to_welded[v] : VertexId::kInvalidValue;
    }
  }
  return result;
}

}  // namespace seam::core
