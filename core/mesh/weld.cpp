#include "core/mesh/weld.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <string>
#include <unordered_map>
#include <utility>

#include "core/mesh/radix_sort.h"
#include "core/seam/tree_util.h"

namespace seam::core {
namespace {

std::uint64_t cell_key(std::int64_t x, std::int64_t y, std::int64_t z) {
  // 21 bits per axis; collisions between far cells only cost extra distance checks.
  const auto m = [](std::int64_t v) { return static_cast<std::uint64_t>(v) & 0x1fffffu; };
  return (m(x) << 42) | (m(y) << 21) | m(z);
}

// The welded vertices from root[i] <= i, the smallest input index welded with i: numbered in
// order of their roots. input_to_welded is rewritten from `root` in place, which works because
// a root is numbered before any later member reads its number.
WeldResult number_by_root(std::span<const Vec3> positions, std::vector<std::uint32_t> root) {
  WeldResult result;
  const std::size_t n = positions.size();
  std::size_t welded = 0;
  for (std::uint32_t i = 0; i < n; ++i) welded += root[i] == i;
  result.positions.reserve(welded);
  result.welded_to_input.reserve(welded);
  result.input_to_welded = std::move(root);
  std::vector<std::uint32_t>& map = result.input_to_welded;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (map[i] != i) {
      map[i] = map[map[i]];
      continue;
    }
    map[i] = static_cast<std::uint32_t>(result.welded_to_input.size());
    result.welded_to_input.push_back(i);
    result.positions.push_back(positions[i]);
  }
  return result;
}

std::uint64_t bits(double x) {
  x += 0.0;  // folds -0.0 into +0.0
  std::uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

std::uint64_t mix(std::uint64_t h) {  // splitmix64 finaliser
  h ^= h >> 30;
  h *= 0xbf58476d1ce4e5b9ULL;
  h ^= h >> 27;
  h *= 0x94d049bb133111ebULL;
  return h ^ (h >> 31);
}

// epsilon 0. Records (32-bit hash of the exact bit pattern, index) are radix-sorted by hash:
// 8-byte records in three passes stream through memory where a hash table would miss the cache
// once per vertex. Within a run of equal hashes the records are in index order (the sort is
// stable), so the first record at each distinct position is its smallest index; positions are
// compared exactly, so a collision never welds.
Result<WeldResult> weld_exact(std::span<const Vec3> positions, const CancelToken& cancel) {
  struct Hashed {
    std::uint32_t hash;
    std::uint32_t index;
  };
  const std::size_t n = positions.size();
  std::vector<Hashed> hashed(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    const Vec3& p = positions[i];
    hashed[i] = {static_cast<std::uint32_t>(mix(bits(p.x()) ^ mix(bits(p.y()) ^ mix(bits(p.z())))) >> 32), i};
  }
  detail::radix_sort(hashed, 32, [](const Hashed& h) { return h.hash; });
  std::vector<std::uint32_t> root(n);
  std::vector<std::uint32_t> firsts;  // the first index at each distinct position of the run
  std::uint32_t polls = 0;
  for (std::size_t begin = 0; begin < n;) {
    if (cancel.poll(polls)) return cancelled_error("welding");
    std::size_t end = begin + 1;
    while (end < n && hashed[end].hash == hashed[begin].hash) ++end;
    firsts.clear();
    for (std::size_t k = begin; k < end; ++k) {
      const std::uint32_t i = hashed[k].index;
      const auto same = std::find_if(firsts.begin(), firsts.end(), [&](std::uint32_t j) {
        return positions[i].x() == positions[j].x() && positions[i].y() == positions[j].y() &&
               positions[i].z() == positions[j].z();
      });
      if (same != firsts.end()) {
        root[i] = *same;
      } else {
        root[i] = i;
        firsts.push_back(i);
      }
    }
    begin = end;
  }
  return number_by_root(positions, std::move(root));
}

// epsilon > 0: a grid of cell size epsilon, so any pair within epsilon lies in the same or
// adjacent cells; pairs unite toward the smaller index, so a set's root is its smallest.
Result<WeldResult> weld_grid(std::span<const Vec3> positions, double epsilon, const CancelToken& cancel) {
  const std::size_t n = positions.size();
  detail::UnionFind sets(n);
  std::uint32_t polls = 0;
  const double inv = 1.0 / epsilon;
  const double eps2 = epsilon * epsilon;
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
  std::vector<std::uint32_t> root(n);
  for (std::uint32_t i = 0; i < n; ++i) root[i] = sets.find(i);
  return number_by_root(positions, std::move(root));
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
  return options.epsilon == 0.0 ? weld_exact(positions, cancel) : weld_grid(positions, options.epsilon, cancel);
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
