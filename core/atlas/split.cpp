#include "core/atlas/split.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numeric>
#include <tuple>

namespace seam::core {

namespace {

constexpr int kLines = 48;  // candidate cut lines per axis; those at 1/8..7/8 are tried
constexpr std::size_t kCandidates = 16;  // cuts of the best scores tried; the best fill wins

double area_of(const PackChart& chart, const Triangle& t) {
  const Vec2 e1 = chart.uv[t[1]] - chart.uv[t[0]];
  const Vec2 e2 = chart.uv[t[2]] - chart.uv[t[0]];
  return 0.5 * std::abs(cross2(e1, e2));
}

// A piece of a chart: indices of its triangles, and its UV area.
struct Piece {
  std::vector<std::uint32_t> triangles;
  double area = 0;
};

// The piece's vertices' UVs, each once.
std::vector<Vec2> points_of(const PackChart& chart, const Piece& piece) {
  std::vector<bool> seen(chart.uv.size(), false);
  std::vector<Vec2> points;
  for (std::uint32_t t : piece.triangles) {
    for (std::uint32_t v : chart.triangles[t]) {
      if (!seen[v]) points.push_back(chart.uv[v]);
      seen[v] = true;
    }
  }
  return points;
}

// UV area / area of the minimal enclosing rectangle.
double fill_of(const PackChart& chart, const Piece& piece) {
  const double rect = min_area_rect(convex_hull(points_of(chart, piece))).size.prod();
  return rect > 0 ? piece.area / rect : 1;
}

// A straight cut: triangles whose centroid's coordinate `axis` (in the frame rotated by
// `angle`) is below `at` go to one side.
struct Cut {
  double score = kInf;
  double angle = 0;
  int axis = 0;
  double at = 0;
};

// The cuts along one axis, scored by cross-section length / sqrt(smaller side's area).
void cuts_along(const PackChart& chart, const Piece& piece, const std::vector<Vec2>& q, double angle, int axis,
                std::vector<Cut>& cuts) {
  double lo = kInf;
  double hi = -kInf;
  for (std::uint32_t t : piece.triangles) {
    for (std::uint32_t v : chart.triangles[t]) {
      lo = std::min(lo, q[v][axis]);
      hi = std::max(hi, q[v][axis]);
    }
  }
  const double step = (hi - lo) / kLines;
  if (!(step > 0)) return;
  std::array<double, kLines + 1> length{};
  std::array<double, kLines + 1> below{};  // area of triangles whose centroid is below line k
  for (std::uint32_t t : piece.triangles) {
    const Triangle& tri = chart.triangles[t];
    const double centroid = (q[tri[0]][axis] + q[tri[1]][axis] + q[tri[2]][axis]) / 3;
    const int first_above = std::clamp(static_cast<int>(std::floor((centroid - lo) / step)) + 1, 0, kLines + 1);
    if (first_above <= kLines) below[first_above] += area_of(chart, tri);
    // The lines crossing the triangle: the extent of its section along the other axis.
    double t_lo = kInf;
    double t_hi = -kInf;
    for (std::uint32_t v : tri) {
      t_lo = std::min(t_lo, q[v][axis]);
      t_hi = std::max(t_hi, q[v][axis]);
    }
    for (int k = std::max(1, static_cast<int>(std::ceil((t_lo - lo) / step)));
         k < kLines && lo + k * step <= t_hi; ++k) {
      const double line = lo + k * step;
      double s_lo = kInf;
      double s_hi = -kInf;
      for (int e = 0; e < 3; ++e) {
        const Vec2& a = q[tri[e]];
        const Vec2& b = q[tri[(e + 1) % 3]];
        if ((a[axis] - line) * (b[axis] - line) > 0 || a[axis] == b[axis]) continue;
        const double other = a[1 - axis] + (b[1 - axis] - a[1 - axis]) * (line - a[axis]) / (b[axis] - a[axis]);
        s_lo = std::min(s_lo, other);
        s_hi = std::max(s_hi, other);
      }
      if (s_lo <= s_hi) length[k] += s_hi - s_lo;
    }
  }
  std::partial_sum(below.begin(), below.end(), below.begin());
  for (int k = kLines / 8; k <= kLines - kLines / 8; ++k) {
    const double smaller = std::min(below[k], piece.area - below[k]);
    if (!(smaller > 0)) continue;
    cuts.push_back({length[k] / std::sqrt(smaller), angle, axis, lo + k * step});
  }
}

// Connected parts (through shared vertices) of the triangles on each side of the cut.
std::vector<Piece> split_piece(const PackChart& chart, const Piece& piece, const Cut& cut) {
  const double c = std::cos(cut.angle);
  const double s = std::sin(cut.angle);
  // Vertices are shared by the two sides along the cut: a key of (side, vertex) keeps them apart.
  std::vector<int> side(piece.triangles.size());
  std::vector<std::uint32_t> node(2 * chart.uv.size(), UINT32_MAX);
  for (std::size_t i = 0; i < piece.triangles.size(); ++i) {
    const Triangle& tri = chart.triangles[piece.triangles[i]];
    Vec2 centroid = (chart.uv[tri[0]] + chart.uv[tri[1]] + chart.uv[tri[2]]) / 3;
    const double coord = cut.axis == 0 ? c * centroid.x() - s * centroid.y() : s * centroid.x() + c * centroid.y();
    side[i] = coord < cut.at ? 0 : 1;
  }
  std::vector<std::uint32_t> sets;  // union-find over (side, vertex) nodes
  auto node_of = [&](int sd, std::uint32_t v) {
    std::uint32_t& n = node[sd * chart.uv.size() + v];
    if (n == UINT32_MAX) {
      n = static_cast<std::uint32_t>(sets.size());
      sets.push_back(n);
    }
    return n;
  };
  auto root = [&](std::uint32_t x) {
    while (sets[x] != x) x = sets[x] = sets[sets[x]];
    return x;
  };
  for (std::size_t i = 0; i < piece.triangles.size(); ++i) {
    const Triangle& tri = chart.triangles[piece.triangles[i]];
    const std::uint32_t a = root(node_of(side[i], tri[0]));
    for (int k = 1; k < 3; ++k) sets[root(node_of(side[i], tri[k]))] = a;
  }
  std::map<std::uint32_t, std::size_t> part;
  std::vector<Piece> out;
  for (std::size_t i = 0; i < piece.triangles.size(); ++i) {
    const std::uint32_t t = piece.triangles[i];
    const auto [it, added] = part.try_emplace(root(node_of(side[i], chart.triangles[t][0])), out.size());
    if (added) out.emplace_back();
    out[it->second].triangles.push_back(t);
    out[it->second].area += area_of(chart, chart.triangles[t]);
  }
  return out;
}

// The best-scored cuts of a piece across either side of its minimal rectangle.
std::vector<Cut> best_cuts(const PackChart& chart, const Piece& piece) {
  const double angle = min_area_rect(convex_hull(points_of(chart, piece))).angle;
  const double c = std::cos(angle);
  const double s = std::sin(angle);
  std::vector<Vec2> q(chart.uv.size());
  for (std::size_t v = 0; v < q.size(); ++v) {
    q[v] = Vec2(c * chart.uv[v].x() - s * chart.uv[v].y(), s * chart.uv[v].x() + c * chart.uv[v].y());
  }
  // The best kCandidates over both axes, and the best kCandidates / 4 of each axis (so one
  // axis whose narrow cuts make poor parts cannot crowd out the other).
  std::vector<Cut> cuts[2];
  for (int axis : {0, 1}) {
    cuts_along(chart, piece, q, angle, axis, cuts[axis]);
    std::sort(cuts[axis].begin(), cuts[axis].end(), [](const Cut& a, const Cut& b) { return std::tie(a.score, a.at) < std::tie(b.score, b.at); });
  }
  std::vector<Cut> best;
  std::size_t taken[2] = {0, 0};
  while (best.size() < kCandidates && (taken[0] < cuts[0].size() || taken[1] < cuts[1].size())) {
    const int axis = taken[1] >= cuts[1].size() || (taken[0] < cuts[0].size() && cuts[0][taken[0]].score <= cuts[1][taken[1]].score) ? 0 : 1;
    best.push_back(cuts[axis][taken[axis]++]);
  }
  for (int axis : {0, 1}) {
    for (; taken[axis] < std::min(cuts[axis].size(), kCandidates / 4); ++taken[axis]) best.push_back(cuts[axis][taken[axis]]);
  }
  return best;
}

// The pieces of one chart: the piece of largest area whose fill is low is split first.
std::vector<Piece> pieces_of(const PackChart& chart, const SplitOptions& options) {
  Piece whole;
  whole.triangles.resize(chart.triangles.size());
  std::iota(whole.triangles.begin(), whole.triangles.end(), 0u);
  for (const Triangle& t : chart.triangles) whole.area += area_of(chart, t);
  std::vector<Piece> done;
  std::vector<Piece> open{whole};
  while (!open.empty()) {
    auto largest = std::max_element(open.begin(), open.end(), [](const Piece& a, const Piece& b) { return a.area < b.area; });
    Piece piece = std::move(*largest);
    open.erase(largest);
    const double fill = fill_of(chart, piece);
    // Of the candidate cuts, the one whose parts fill their squares best (their area over the
    // sum of their squares' areas).
    std::vector<Piece> parts;
    double parts_fill = fill;
    if (fill < options.min_fill && piece.triangles.size() >= options.min_triangles) {
      for (const Cut& cut : best_cuts(chart, piece)) {
        std::vector<Piece> trial = split_piece(chart, piece, cut);
        double squares = 0;
        for (const Piece& p : trial) squares += p.area / fill_of(chart, p);
        if (trial.size() >= 2 && piece.area / squares > parts_fill) {
          parts_fill = piece.area / squares;
          parts = std::move(trial);
        }
      }
    }
    const bool room = done.size() + open.size() + parts.size() <= options.max_pieces;
    if (parts.empty() || !room) {
      done.push_back(std::move(piece));
      continue;
    }
    for (Piece& p : parts) open.push_back(std::move(p));
  }
  std::sort(done.begin(), done.end(), [](const Piece& a, const Piece& b) { return a.triangles.front() < b.triangles.front(); });
  return done;
}

}  // namespace

ChartPieces chart_pieces(const PackChart& chart, std::size_t index, std::span<const std::vector<std::uint32_t>> parts,
                         std::span<const std::uint32_t> point) {
  SEAM_ASSERT(point.empty() || point.size() == chart.uv.size());
  std::vector<double> areas;
  double uv_area = 0;
  for (const auto& part : parts) {
    double area = 0;
    for (std::uint32_t t : part) area += area_of(chart, chart.triangles[t]);
    areas.push_back(area);
    uv_area += area;
  }
  SEAM_ASSERT(uv_area > 0);
  const double scale = std::sqrt(chart.surface_area / uv_area);
  ChartPieces result;
  // Edges (between points) by their uses: an edge that two pieces use is a cut, an edge used
  // once a border; one piece's triangles using it three times make neither.
  struct Uses {
    std::size_t count = 0;
    std::size_t first_piece = 0;
    bool cut = false;
  };
  std::map<std::pair<std::uint32_t, std::uint32_t>, Uses> edges;
  const auto key = [&](std::uint32_t v) { return point.empty() ? v : point[v]; };
  for (std::size_t p = 0; p < parts.size(); ++p) {
    ChartPiece out{index, {}, {}, parts[p], chart.surface_area * areas[p] / uv_area};
    std::map<std::uint32_t, std::uint32_t> local;
    for (std::uint32_t t : parts[p]) {
      Triangle tri;
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = chart.triangles[t][k];
        const auto [it, added] = local.try_emplace(v, static_cast<std::uint32_t>(out.vertices.size()));
        if (added) out.vertices.push_back(v);
        tri[k] = it->second;
        auto [e, fresh] =
            edges.try_emplace(std::minmax(key(v), key(chart.triangles[t][(k + 1) % 3])), Uses{0, p, false});
        e->second.count += 1;
        e->second.cut = e->second.cut || e->second.first_piece != p;
      }
      out.triangles.push_back(tri);
    }
    result.pieces.push_back(std::move(out));
  }
  for (const auto& [e, use] : edges) {
    const double length = scale * (chart.uv[e.first] - chart.uv[e.second]).norm();
    if (use.count == 1) result.boundary_length += length;
    if (use.cut) result.cut_length += length;
  }
  return result;
}

Result<SplitResult> split_sprawling_charts(std::span<const PackChart> charts, const SplitOptions& options) {
  if (!(options.min_fill >= 0 && options.min_fill <= 1) || options.max_pieces < 1 || options.min_triangles < 2) {
    return make_error(ErrorCode::kInvalidArgument, "split: min_fill must be in [0, 1], max_pieces >= 1, min_triangles >= 2");
  }
  if (Status valid = validate_pack_charts(charts); !valid.ok()) return valid.take_error();
  SplitResult result;
  for (std::size_t c = 0; c < charts.size(); ++c) {
    const PackChart& chart = charts[c];
    const std::vector<Piece> pieces = pieces_of(chart, options);
    double uv_area = 0;
    for (const Piece& p : pieces) uv_area += p.area;
    if (!(uv_area > 0)) return make_error(ErrorCode::kInvalidArgument, "split: chart " + std::to_string(c) + " has zero UV area");
    std::vector<std::vector<std::uint32_t>> parts;
    for (const Piece& p : pieces) parts.push_back(p.triangles);
    ChartPieces out = chart_pieces(chart, c, parts);
    for (ChartPiece& p : out.pieces) result.pieces.push_back(std::move(p));
    result.cut_length += out.cut_length;
    result.boundary_length += out.boundary_length;
    if (pieces.size() > 1) ++result.charts_split;
  }
  return result;
}

}  // namespace seam::core
