#include "core/atlas/untangle.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <deque>
#include <numeric>

#include "core/atlas/overlap.h"
#include "core/atlas/predicates.h"
#include "core/timing.h"

namespace seam::core {

// Named, not anonymous: the core builds in unity batches, where anonymous namespaces of
// several files are one.
namespace untangle_detail {

constexpr std::uint32_t kNone = UINT32_MAX;

std::vector<int> orientations(const PackChart& chart) {
  std::vector<int> out;
  out.reserve(chart.triangles.size());
  for (const Triangle& t : chart.triangles) out.push_back(orient2d(chart.uv[t[0]], chart.uv[t[1]], chart.uv[t[2]]));
  return out;
}

// Each chart vertex as the lowest-numbered vertex at its UV point: an asset split along hard
// edges or old seams repeats its vertices (a flat-shaded wheel has three per face), and its
// triangles meet only through their points.
std::vector<std::uint32_t> point_ids(const PackChart& chart) {
  std::vector<std::uint32_t> all(chart.uv.size());
  std::iota(all.begin(), all.end(), 0u);
  return same_point_representatives(chart.uv, all);
}

// Each triangle's edges as {low point, high point, triangle}, sorted: uses of one edge are a run.
std::vector<std::array<std::uint32_t, 3>> edge_uses(const PackChart& chart, const std::vector<std::uint32_t>& point) {
  std::vector<std::array<std::uint32_t, 3>> uses;
  uses.reserve(3 * chart.triangles.size());
  for (std::uint32_t t = 0; t < chart.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const auto [a, b] = std::minmax(point[chart.triangles[t][k]], point[chart.triangles[t][(k + 1) % 3]]);
      uses.push_back({a, b, t});
    }
  }
  std::sort(uses.begin(), uses.end());
  return uses;
}

// Triangles sharing an edge (an unordered pair of UV points), compressed rows: neighbours of t
// are next[start[t] .. start[t + 1]), in order of (edge, triangle).
struct EdgeNeighbours {
  std::vector<std::uint32_t> start;
  std::vector<std::uint32_t> next;
};

EdgeNeighbours edge_neighbours(const PackChart& chart, const std::vector<std::uint32_t>& point) {
  const std::vector<std::array<std::uint32_t, 3>> uses = edge_uses(chart, point);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;  // (triangle, neighbour)
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    while (j < uses.size() && uses[j][0] == uses[i][0] && uses[j][1] == uses[i][1]) ++j;
    for (std::size_t x = i; x < j; ++x) {
      for (std::size_t y = i; y < j; ++y) {
        if (uses[x][2] != uses[y][2]) pairs.emplace_back(uses[x][2], uses[y][2]);
      }
    }
    i = j;
  }
  std::stable_sort(pairs.begin(), pairs.end(), [](const auto& p, const auto& q) { return p.first < q.first; });
  EdgeNeighbours out;
  out.start.assign(chart.triangles.size() + 1, 0);
  for (const auto& [t, u] : pairs) {
    ++out.start[t + 1];
    out.next.push_back(u);
  }
  std::partial_sum(out.start.begin(), out.start.end(), out.start.begin());
  return out;
}

// A bounding-volume hierarchy over all of the chart's triangles with area (built once; pieces
// only change which triangles count): median splits along the longer side, 4 triangles a
// leaf. A uniform grid would not do: `lscm` shrinks parts of a chart a thousandfold, and a
// grid cell there holds thousands of triangles.
class TriangleTree {
 public:
  TriangleTree(const PackChart& chart, const std::vector<int>& orient) : chart_(chart) {
    for (std::uint32_t t = 0; t < chart.triangles.size(); ++t) {
      if (orient[t] != 0) order_.push_back(t);
    }
    if (order_.empty()) return;
    nodes_.resize(1);
    build(0, 0, static_cast<std::uint32_t>(order_.size()));
  }

  // Whether t's interior meets the interior of a triangle of piece `p` (piece_of).
  bool overlaps(std::uint32_t t, std::uint32_t p, const std::vector<std::uint32_t>& piece_of) const {
    if (nodes_.empty()) return false;
    const std::array<Vec2, 3> a = corners(t);
    const Vec2 lo = a[0].cwiseMin(a[1]).cwiseMin(a[2]);
    const Vec2 hi = a[0].cwiseMax(a[1]).cwiseMax(a[2]);
    std::uint32_t stack[64];
    int depth = 0;
    stack[depth++] = 0;
    while (depth > 0) {
      const Node& n = nodes_[stack[--depth]];
      if ((n.hi.array() < lo.array()).any() || (n.lo.array() > hi.array()).any()) continue;
      if (n.count == 0) {
        stack[depth++] = n.first;  // children at first, first + 1
        stack[depth++] = n.first + 1;
        continue;
      }
      for (std::uint32_t i = n.first; i < n.first + n.count; ++i) {
        const std::uint32_t u = order_[i];
        if (piece_of[u] == p && u != t && triangle_interiors_intersect(a, corners(u))) return true;
      }
    }
    return false;
  }

 private:
  struct Node {
    Vec2 lo, hi;
    std::uint32_t first = 0;  // leaf: into order_; inner: the left child (right = first + 1)
    std::uint32_t count = 0;  // triangles of a leaf; 0 for an inner node
  };

  std::array<Vec2, 3> corners(std::uint32_t t) const {
    const Triangle& tri = chart_.triangles[t];
    return {chart_.uv[tri[0]], chart_.uv[tri[1]], chart_.uv[tri[2]]};
  }

  // Fills node `id` (already allocated) over order_[begin, end); its children are allocated
  // side by side. Median splits halve the range, so the depth stays below 40 (stack of 64).
  void build(std::uint32_t id, std::uint32_t begin, std::uint32_t end) {
    Vec2 lo = Vec2::Constant(kInf);
    Vec2 hi = Vec2::Constant(-kInf);
    for (std::uint32_t i = begin; i < end; ++i) {
      for (const Vec2& q : corners(order_[i])) {
        lo = lo.cwiseMin(q);
        hi = hi.cwiseMax(q);
      }
    }
    nodes_[id].lo = lo;
    nodes_[id].hi = hi;
    if (end - begin <= 4) {
      nodes_[id].first = begin;
      nodes_[id].count = end - begin;
      return;
    }
    const int axis = hi.x() - lo.x() >= hi.y() - lo.y() ? 0 : 1;
    auto key = [&](std::uint32_t t) {
      const std::array<Vec2, 3> a = corners(t);
      return a[0][axis] + a[1][axis] + a[2][axis];
    };
    const std::uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                     [&](std::uint32_t x, std::uint32_t y) { return key(x) != key(y) ? key(x) < key(y) : x < y; });
    const auto left = static_cast<std::uint32_t>(nodes_.size());
    nodes_[id].first = left;
    nodes_.resize(nodes_.size() + 2);
    build(left, begin, mid);
    build(left + 1, mid, end);
  }

  const PackChart& chart_;
  std::vector<std::uint32_t> order_;
  std::vector<Node> nodes_;
};

// Greedy growth of the pieces (see untangle_charts): each piece's triangles, ascending, the
// pieces in order of their first triangle.
Result<std::vector<std::vector<std::uint32_t>>> grow_pieces(const PackChart& chart, const std::vector<int>& orient,
                                                            const std::vector<std::uint32_t>& point,
                                                            const CancelToken& cancel) {
  const EdgeNeighbours adjacent = edge_neighbours(chart, point);
  const std::size_t n = chart.triangles.size();
  const TriangleTree tree(chart, orient);
  std::vector<std::uint32_t> piece_of(n, kNone);
  std::vector<std::uint32_t> refused_by(n, kNone);  // a piece only grows, so a refusal stands
  std::vector<std::vector<std::uint32_t>> parts;
  std::vector<int> turns;  // per piece: its seed's orientation (0: degenerate triangles only)
  std::uint32_t poll = 0;
  std::deque<std::uint32_t> queue;
  // Seeds: non-degenerate triangles in index order, then what is left (degenerate only).
  for (int pass = 0; pass < 2; ++pass) {
    for (std::uint32_t seed = 0; seed < n; ++seed) {
      if (piece_of[seed] != kNone || (pass == 0 && orient[seed] == 0)) continue;
      const auto p = static_cast<std::uint32_t>(parts.size());
      parts.emplace_back();
      turns.push_back(orient[seed]);
      queue.assign(1, seed);
      piece_of[seed] = p;
      while (!queue.empty()) {
        if (cancel.poll(poll)) return cancelled_error("untangle_charts");
        const std::uint32_t t = queue.front();
        queue.pop_front();
        parts[p].push_back(t);
        for (std::uint32_t i = adjacent.start[t]; i < adjacent.start[t + 1]; ++i) {
          const std::uint32_t u = adjacent.next[i];
          if (piece_of[u] != kNone || refused_by[u] == p) continue;
          const bool fits = orient[u] == 0 || (orient[u] == turns[p] && !tree.overlaps(u, p, piece_of));
          if (!fits) {
            refused_by[u] = p;
            continue;
          }
          piece_of[u] = p;
          queue.push_back(u);
        }
      }
      std::sort(parts[p].begin(), parts[p].end());
    }
  }
  std::sort(parts.begin(), parts.end(), [](const auto& a, const auto& b) { return a.front() < b.front(); });
  return parts;
}

}  // namespace untangle_detail

Result<UntangleResult> untangle_charts(std::span<const PackChart> charts, const CancelToken& cancel) {
  namespace ud = untangle_detail;
  const auto start = StageClock::now();
  if (Status valid = validate_pack_charts(charts); !valid.ok()) return valid.take_error();
  UntangleResult result;
  for (std::size_t c = 0; c < charts.size(); ++c) {
    if (cancel.is_cancelled()) return cancelled_error("untangle_charts");
    const PackChart& chart = charts[c];
    const std::vector<int> orient = ud::orientations(chart);
    bool tangled = std::any_of(orient.begin(), orient.end(), [](int o) { return o < 0; });
    if (!tangled) {
      auto overlap = find_overlaps(chart.uv, chart.triangles, {}, cancel);
      if (!overlap.ok()) return overlap.take_error();
      tangled = overlap->overlaps;
    }
    if (std::all_of(orient.begin(), orient.end(), [](int o) { return o == 0; })) {
      return make_error(ErrorCode::kInvalidArgument, "untangle: chart " + std::to_string(c) + " has zero UV area");
    }
    std::vector<std::vector<std::uint32_t>> parts(1, std::vector<std::uint32_t>(chart.triangles.size()));
    std::iota(parts[0].begin(), parts[0].end(), 0u);
    std::vector<std::uint32_t> point;
    if (tangled) {
      point = ud::point_ids(chart);
      auto grown = ud::grow_pieces(chart, orient, point, cancel);
      if (!grown.ok()) return grown.take_error();
      parts = std::move(grown).value();
      ++result.charts_untangled;
      result.pieces_added += parts.size() - 1;
    }
    ChartPieces out = chart_pieces(chart, c, parts, point);
    result.cut_length += out.cut_length;
    for (ChartPiece& piece : out.pieces) {
      // A piece's triangles all turn one way, or have no area: the first one with area says.
      const auto turning = std::find_if(piece.chart_triangles.begin(), piece.chart_triangles.end(),
                                        [&](std::uint32_t t) { return orient[t] != 0; });
      piece.mirrored = turning != piece.chart_triangles.end() && orient[*turning] < 0;
      if (piece.mirrored) {
        ++result.pieces_mirrored;
        result.unflipped +=
            static_cast<std::size_t>(std::count_if(piece.chart_triangles.begin(), piece.chart_triangles.end(),
                                                   [&](std::uint32_t t) { return orient[t] < 0; }));
      }
      result.pieces.push_back(std::move(piece));
    }
  }
  result.ms = ms_since(start);
  return result;
}

}  // namespace seam::core
