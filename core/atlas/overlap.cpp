#include "core/atlas/overlap.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/atlas/predicates.h"
#include "core/mesh/topology.h"
#include "core/timing.h"

namespace seam::core {

namespace {

using Tri = std::array<Vec2, 3>;

// Counter-clockwise copy, or false when the triangle has no interior (exactly collinear).
bool counter_clockwise(const Tri& in, Tri& out) {
  const int o = orient2d(in[0], in[1], in[2]);
  if (o == 0) return false;
  out = in;
  if (o < 0) std::swap(out[1], out[2]);
  return true;
}

// True when some edge line of `a` has all of `b` on its closed outer side.
bool separated_by_edge_of(const Tri& a, const Tri& b) {
  for (int k = 0; k < 3; ++k) {
    const Vec2& p = a[k];
    const Vec2& q = a[(k + 1) % 3];
    if (orient2d(p, q, b[0]) <= 0 && orient2d(p, q, b[1]) <= 0 && orient2d(p, q, b[2]) <= 0) return true;
  }
  return false;
}

bool interiors_intersect_ccw(const Tri& a, const Tri& b) {
  return !separated_by_edge_of(a, b) && !separated_by_edge_of(b, a);
}

double polygon_area(const std::vector<Vec2>& poly) {
  double twice = 0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec2& p = poly[i];
    const Vec2& q = poly[(i + 1) % poly.size()];
    twice += p.x() * q.y() - p.y() * q.x();
  }
  return 0.5 * std::abs(twice);
}

double clipped_area_ccw(const Tri& a, const Tri& b) {
  std::vector<Vec2> poly(b.begin(), b.end());
  std::vector<Vec2> next;
  for (int k = 0; k < 3 && !poly.empty(); ++k) {
    const Vec2 p = a[k];
    const Vec2 e = a[(k + 1) % 3] - p;
    auto side = [&](const Vec2& x) { return e.x() * (x.y() - p.y()) - e.y() * (x.x() - p.x()); };
    next.clear();
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const Vec2& s = poly[i];
      const Vec2& t = poly[(i + 1) % poly.size()];
      const double ds = side(s);
      const double dt = side(t);
      if (ds >= 0) next.push_back(s);
      if ((ds >= 0) != (dt >= 0)) next.push_back(s + (ds / (ds - dt)) * (t - s));
    }
    poly.swap(next);
  }
  return poly.size() >= 3 ? polygon_area(poly) : 0.0;
}

struct Grid {
  Vec2 origin = Vec2::Zero();
  double inv_cell = 1;
  std::int64_t nx = 1;
  std::int64_t ny = 1;
  std::vector<std::uint32_t> offset;  // CSR: cell -> triangles
  std::vector<std::uint32_t> items;

  // Clamped before the conversion: a query may lie far outside the grid's items (a loop's box
  // around its head points), where the cell number does not fit an integer.
  static std::int64_t cell(double offset, double inv_cell, std::int64_t n) {
    const double c = offset * inv_cell;
    if (!(c > 0)) return 0;
    return c >= static_cast<double>(n - 1) ? n - 1 : static_cast<std::int64_t>(c);
  }
  std::int64_t cx(double x) const { return cell(x - origin.x(), inv_cell, nx); }
  std::int64_t cy(double y) const { return cell(y - origin.y(), inv_cell, ny); }
};

struct Box {
  Vec2 lo;
  Vec2 hi;
};

// A uniform grid with about one cell per triangle (at most 2^22 cells); each triangle is
// listed in every cell its bounding box meets.
Grid build_grid(const std::vector<Box>& boxes, const std::vector<char>& live) {
  Grid g;
  Vec2 lo = Vec2::Constant(std::numeric_limits<double>::infinity());
  Vec2 hi = -lo;
  std::size_t count = 0;
  for (std::size_t t = 0; t < boxes.size(); ++t) {
    if (!live[t]) continue;
    lo = lo.cwiseMin(boxes[t].lo);
    hi = hi.cwiseMax(boxes[t].hi);
    ++count;
  }
  g.offset.assign(2, 0);
  if (count == 0) return g;
  const Vec2 extent = (hi - lo).cwiseMax(1e-300);
  const double cells = std::min<double>(static_cast<double>(count), 1 << 22);
  // About `cells` cells: square ones, or for a layout thinner than that (one row), as many
  // along its length.
  const double cell = std::max(std::sqrt(extent.x() * extent.y() / cells), std::max(extent.x(), extent.y()) / cells);
  g.origin = lo;
  g.inv_cell = 1.0 / cell;
  // Clamped as doubles: a layout thin in one direction makes the cell tiny, and its cell count
  // along the other would not fit an integer.
  auto along = [&](double length) {
    return static_cast<std::int64_t>(std::clamp(std::floor(length / cell) + 1, 1.0, double{1 << 22}));
  };
  g.nx = along(extent.x());
  g.ny = along(extent.y());
  while (g.nx * g.ny > (std::int64_t{1} << 23)) {  // a very thin layout: coarsen
    g.inv_cell *= 0.5;
    g.nx = (g.nx + 1) / 2;
    g.ny = (g.ny + 1) / 2;
  }
  const auto ncell = static_cast<std::size_t>(g.nx * g.ny);
  g.offset.assign(ncell + 1, 0);
  auto for_cells = [&](std::size_t t, auto&& f) {
    for (std::int64_t y = g.cy(boxes[t].lo.y()); y <= g.cy(boxes[t].hi.y()); ++y) {
      for (std::int64_t x = g.cx(boxes[t].lo.x()); x <= g.cx(boxes[t].hi.x()); ++x) {
        f(static_cast<std::size_t>(y * g.nx + x));
      }
    }
  };
  for (std::size_t t = 0; t < boxes.size(); ++t) {
    if (live[t]) for_cells(t, [&](std::size_t c) { ++g.offset[c + 1]; });
  }
  for (std::size_t c = 0; c < ncell; ++c) g.offset[c + 1] += g.offset[c];
  g.items.resize(g.offset[ncell]);
  std::vector<std::uint32_t> fill(g.offset.begin(), g.offset.end() - 1);
  for (std::size_t t = 0; t < boxes.size(); ++t) {
    if (live[t]) for_cells(t, [&](std::size_t c) { g.items[fill[c]++] = static_cast<std::uint32_t>(t); });
  }
  return g;
}

// Calls f(a, b) once for every pair of boxes listed together in a cell of g that meet, in the
// cell holding the lower-left corner of their intersection. `closed`: boxes touching along a
// line or at a point meet too; otherwise only boxes sharing area do. Stops and returns false as
// soon as f returns false.
template <class F>
bool for_candidate_pairs(const Grid& g, const std::vector<Box>& boxes, bool closed, F&& f) {
  for (std::size_t c = 0; c + 1 < g.offset.size(); ++c) {
    const std::int64_t cx = static_cast<std::int64_t>(c) % g.nx;
    const std::int64_t cy = static_cast<std::int64_t>(c) / g.nx;
    for (std::uint32_t i = g.offset[c]; i < g.offset[c + 1]; ++i) {
      const std::uint32_t a = g.items[i];
      for (std::uint32_t j = i + 1; j < g.offset[c + 1]; ++j) {
        const std::uint32_t b = g.items[j];
        const Vec2 lo = boxes[a].lo.cwiseMax(boxes[b].lo);
        const Vec2 hi = boxes[a].hi.cwiseMin(boxes[b].hi);
        const bool meet = closed ? lo.x() <= hi.x() && lo.y() <= hi.y() : lo.x() < hi.x() && lo.y() < hi.y();
        if (!meet) continue;
        if (g.cx(lo.x()) != cx || g.cy(lo.y()) != cy) continue;  // met in another cell
        if (!f(a, b)) return false;
      }
    }
  }
  return true;
}

// Whether closed segments pq and rs share a point (exact).
bool segments_meet(const Vec2& p, const Vec2& q, const Vec2& r, const Vec2& s) {
  const int o1 = orient2d(p, q, r);
  const int o2 = orient2d(p, q, s);
  const int o3 = orient2d(r, s, p);
  const int o4 = orient2d(r, s, q);
  if (o1 * o2 > 0 || o3 * o4 > 0) return false;
  if (o1 != 0 || o2 != 0) return true;
  // Collinear: they meet iff their bounding boxes do (exact comparisons).
  return std::max(std::min(p.x(), q.x()), std::min(r.x(), s.x())) <= std::min(std::max(p.x(), q.x()), std::max(r.x(), s.x())) &&
         std::max(std::min(p.y(), q.y()), std::min(r.y(), s.y())) <= std::min(std::max(p.y(), q.y()), std::max(r.y(), s.y()));
}

// Every triangle's directed edges, listed per tail vertex (CSR).
struct OutEdges {
  std::vector<std::uint32_t> offset;  // tail v's heads are head[offset[v] .. offset[v + 1])
  std::vector<std::uint32_t> head;

  OutEdges(std::size_t nv, std::span<const Triangle> triangles) : offset(nv + 1, 0) {
    for (const Triangle& t : triangles) {
      for (int k = 0; k < 3; ++k) ++offset[t[k] + 1];
    }
    for (std::size_t v = 0; v < nv; ++v) offset[v + 1] += offset[v];
    head.resize(offset[nv]);
    std::vector<std::uint32_t> fill(offset.begin(), offset.end() - 1);
    for (const Triangle& t : triangles) {
      for (int k = 0; k < 3; ++k) head[fill[t[k]]++] = t[(k + 1) % 3];
    }
  }
  std::size_t vertices() const { return offset.size() - 1; }
  std::span<const std::uint32_t> out(std::uint32_t v) const {
    return std::span<const std::uint32_t>(head).subspan(offset[v], offset[v + 1] - offset[v]);
  }
  bool has(std::uint32_t a, std::uint32_t b) const { return std::ranges::find(out(a), b) != out(a).end(); }
};

// The boundary of a consistently oriented triangle set: per vertex, the target of its one
// boundary edge (a directed edge whose reverse is no triangle's), or kNone. Empty when the set
// is not such a surface: a directed edge used twice, or a vertex on two boundary edges out or
// in (a pinch).
std::vector<std::uint32_t> boundary_successors(const OutEdges& edges) {
  const std::size_t nv = edges.vertices();
  std::vector<std::uint32_t> next(nv, kNone);
  std::vector<char> has_in(nv, 0);
  for (std::uint32_t a = 0; a < nv; ++a) {
    const std::span<const std::uint32_t> out = edges.out(a);
    for (std::size_t i = 0; i < out.size(); ++i) {
      const std::uint32_t b = out[i];
      if (std::find(out.begin() + i + 1, out.end(), b) != out.end()) return {};
      if (edges.has(b, a)) continue;
      if (next[a] != kNone || has_in[b]) return {};
      next[a] = b;
      has_in[b] = 1;
    }
  }
  return next;
}

// The vertices on a directed edge whose reverse no triangle uses, ascending.
std::vector<std::uint32_t> unpaired_edge_ends(const OutEdges& edges) {
  std::vector<char> on(edges.vertices(), 0);
  for (std::uint32_t a = 0; a < edges.vertices(); ++a) {
    for (const std::uint32_t b : edges.out(a)) {
      if (!edges.has(b, a)) on[a] = on[b] = 1;
    }
  }
  std::vector<std::uint32_t> ends;
  for (std::uint32_t v = 0; v < on.size(); ++v) {
    if (on[v]) ends.push_back(v);
  }
  return ends;
}

// Whether no loop (given by `next`, one head vertex per loop, with its bounding box) winds
// around another's head, for loops already known to be simple and pairwise disjoint: then no
// loop lies inside another. The heads are binned on a grid, so each loop tests only the heads
// in the cells its box meets (a layout of L charts costs O(L), not L^2 box tests). `tests`
// counts the cells and heads visited and the segments walked; past `budget`, false.
bool no_loop_holds_another(std::span<const Vec2> uv, const std::vector<std::uint32_t>& next,
                           const std::vector<std::uint32_t>& heads, const std::vector<Box>& loop_box,
                           std::size_t& tests, std::size_t budget) {
  std::vector<Box> points(heads.size());
  for (std::size_t i = 0; i < heads.size(); ++i) points[i] = {uv[heads[i]], uv[heads[i]]};
  const Grid g = build_grid(points, std::vector<char>(points.size(), 1));
  for (std::size_t j = 0; j < heads.size(); ++j) {
    const Box& b = loop_box[j];
    for (std::int64_t cy = g.cy(b.lo.y()); cy <= g.cy(b.hi.y()); ++cy) {
      for (std::int64_t cx = g.cx(b.lo.x()); cx <= g.cx(b.hi.x()); ++cx) {
        const auto c = static_cast<std::size_t>(cy * g.nx + cx);
        if ((tests += 1 + g.offset[c + 1] - g.offset[c]) > budget) return false;
        for (std::uint32_t k = g.offset[c]; k < g.offset[c + 1]; ++k) {
          const std::uint32_t i = g.items[k];
          const Vec2& p = uv[heads[i]];
          if (i == j || p.x() < b.lo.x() || p.x() > b.hi.x() || p.y() < b.lo.y() || p.y() > b.hi.y()) continue;
          int winding = 0;
          std::uint32_t w = heads[j];
          do {
            if ((tests += 1) > budget) return false;
            const Vec2& u = uv[w];
            const Vec2& x = uv[next[w]];
            if (u.y() <= p.y() && x.y() > p.y() && orient2d(u, x, p) > 0) ++winding;
            if (x.y() <= p.y() && u.y() > p.y() && orient2d(u, x, p) < 0) --winding;
            w = next[w];
          } while (w != heads[j]);
          if (winding != 0) return false;
        }
      }
    }
  }
  return true;
}

// Exact test: the boundary loops (given by `next`) are simple, pairwise disjoint (no two
// segments share a point except consecutive ones at their common vertex), all turn the way
// `turn` says (+1 counter-clockwise, -1 clockwise), and none lies inside another.
// Conservative: false also when checking would cost more than `budget` segment tests.
bool boundary_loops_disjoint(std::span<const Vec2> uv, const std::vector<std::uint32_t>& next, int turn,
                             std::size_t budget) {
  std::vector<std::uint32_t> starts;  // one segment per boundary vertex, named by its start
  for (std::uint32_t v = 0; v < next.size(); ++v) {
    if (next[v] != kNone) starts.push_back(v);
  }
  std::vector<Box> boxes(starts.size());
  for (std::size_t i = 0; i < starts.size(); ++i) {
    const Vec2& p = uv[starts[i]];
    const Vec2& q = uv[next[starts[i]]];
    boxes[i] = {p.cwiseMin(q), p.cwiseMax(q)};
  }
  const Grid g = build_grid(boxes, std::vector<char>(boxes.size(), 1));
  std::size_t tests = 0;
  const bool apart = for_candidate_pairs(g, boxes, true, [&](std::uint32_t a, std::uint32_t b) {
    if (++tests > budget) return false;
    const std::uint32_t sa = starts[a];
    const std::uint32_t sb = starts[b];
    if (next[sa] == sb || next[sb] == sa) {
      // Consecutive: they share one vertex and must not fold back along each other.
      const std::uint32_t first = next[sa] == sb ? sa : sb;
      const Vec2& p = uv[first];
      const Vec2& m = uv[next[first]];
      const Vec2& r = uv[next[next[first]]];
      if (next[next[first]] == first) return false;  // a two-segment loop cannot bound area
      if (orient2d(p, m, r) != 0) return true;
      return p.x() != m.x() ? (p.x() < m.x()) == (m.x() < r.x()) : (p.y() < m.y()) == (m.y() < r.y());
    }
    return !segments_meet(uv[sa], uv[next[sa]], uv[sb], uv[next[sb]]);
  });
  if (!apart) return false;
  // The loops are simple and disjoint. Each must turn as its triangles do (the orientation at
  // its lowest-leftmost vertex is the loop's) and hold no other loop's vertex.
  std::vector<std::uint32_t> loop_of(next.size(), kNone);
  std::vector<std::uint32_t> heads;
  std::vector<Box> loop_box;
  for (std::uint32_t v : starts) {
    if (loop_of[v] != kNone) continue;
    const auto id = static_cast<std::uint32_t>(heads.size());
    std::uint32_t lowest = v;
    Box box{uv[v], uv[v]};
    for (std::uint32_t w = v; loop_of[w] == kNone; w = next[w]) {
      loop_of[w] = id;
      box = {box.lo.cwiseMin(uv[w]), box.hi.cwiseMax(uv[w])};
      const Vec2& a = uv[w];
      const Vec2& b = uv[lowest];
      if (a.x() < b.x() || (a.x() == b.x() && a.y() < b.y())) lowest = w;
    }
    std::uint32_t prev = lowest;
    while (next[prev] != lowest) prev = next[prev];
    if (orient2d(uv[prev], uv[lowest], uv[next[lowest]]) != turn) return false;
    heads.push_back(v);
    loop_box.push_back(box);
  }
  return no_loop_holds_another(uv, next, heads, loop_box, tests, budget);
}

// Exact proof that a layout has no overlap, without testing triangle pairs: every triangle
// turns the same way (`turn`) and the set is a consistently oriented surface whose boundary
// loops are simple, disjoint, turn that way too and are not nested. Then the number of
// triangles covering a point off the edges is |the winding number of the boundary chain around
// it| (one per loop holding it: at most 1), so no two interiors meet. False: not proven.
// Vertices at one point are taken as one (same_point_representatives) where they end an edge
// without its reverse: the chain and its winding numbers are the same (merging equal points
// never changes them), and a mesh split along hard edges or seams, whose repeated vertices
// leave coincident boundary edges (or pinches, by index), gets its true boundary. Vertices
// whose edges all pair up cannot end a boundary edge, so only the others are compared; where
// none of those share a point, the boundary by index stands.
bool injective_by_boundary(std::span<const Vec2> uv, std::span<const Triangle> triangles, int turn) {
  const OutEdges by_index(uv.size(), triangles);
  std::vector<std::uint32_t> next = boundary_successors(by_index);
  std::vector<std::uint32_t> ends;
  if (next.empty()) {
    ends = unpaired_edge_ends(by_index);
  } else {
    for (std::uint32_t v = 0; v < next.size(); ++v) {
      if (next[v] != kNone) ends.push_back(v);  // a boundary by index is loops: every end starts one
    }
  }
  const std::vector<std::uint32_t> point = same_point_representatives(uv, ends);
  if (std::ranges::any_of(ends, [&](std::uint32_t v) { return point[v] != v; })) {
    std::vector<Triangle> welded(triangles.begin(), triangles.end());
    for (Triangle& t : welded) t = {point[t[0]], point[t[1]], point[t[2]]};
    next = boundary_successors(OutEdges(uv.size(), welded));
  }
  if (next.empty()) return false;
  return boundary_loops_disjoint(uv, next, turn, 4 * triangles.size() + 64);
}

}  // namespace

bool triangle_interiors_intersect(const Tri& a, const Tri& b) {
  Tri ca;
  Tri cb;
  if (!counter_clockwise(a, ca) || !counter_clockwise(b, cb)) return false;
  return interiors_intersect_ccw(ca, cb);
}

double triangle_intersection_area(const Tri& a, const Tri& b) {
  Tri ca;
  Tri cb;
  if (!counter_clockwise(a, ca) || !counter_clockwise(b, cb)) return 0;
  return clipped_area_ccw(ca, cb);
}

Result<OverlapResult> find_overlaps(std::span<const Vec2> uv, std::span<const Triangle> triangles,
                                    std::span<const std::uint32_t> triangle_chart, const CancelToken& cancel) {
  const auto start = StageClock::now();
  if (!triangle_chart.empty() && triangle_chart.size() != triangles.size()) {
    return make_error(ErrorCode::kInvalidArgument, "find_overlaps: triangle_chart has " +
                                                       std::to_string(triangle_chart.size()) + " entries for " +
                                                       std::to_string(triangles.size()) + " triangles");
  }
  for (std::size_t v = 0; v < uv.size(); ++v) {
    if (!uv[v].allFinite()) {
      return make_error(ErrorCode::kNonFinitePosition, "find_overlaps: UV " + std::to_string(v) + " is not finite",
                        {static_cast<std::uint32_t>(v)});
    }
  }
  const std::size_t nf = triangles.size();
  std::vector<Tri> tri(nf);
  std::vector<Box> boxes(nf);
  std::vector<char> live(nf, 0);
  OverlapResult result;
  int turn = 0;  // +1 / -1 while every triangle so far turns that way; 2 once they differ
  for (std::size_t t = 0; t < nf; ++t) {
    Tri raw;
    for (int k = 0; k < 3; ++k) {
      if (triangles[t][k] >= uv.size()) {
        return make_error(ErrorCode::kIndexOutOfRange,
                          "find_overlaps: triangle " + std::to_string(t) + " names UV " +
                              std::to_string(triangles[t][k]) + " of " + std::to_string(uv.size()),
                          {static_cast<std::uint32_t>(t)});
      }
      raw[k] = uv[triangles[t][k]];
    }
    if (!counter_clockwise(raw, tri[t])) {
      ++result.degenerate_triangles;
      turn = 2;
      continue;
    }
    const int own = tri[t][1] == raw[1] ? 1 : -1;
    if (turn != own) turn = turn == 0 ? own : 2;
    live[t] = 1;
    boxes[t] = {raw[0].cwiseMin(raw[1]).cwiseMin(raw[2]), raw[0].cwiseMax(raw[1]).cwiseMax(raw[2])};
    const Vec2 e1 = tri[t][1] - tri[t][0];
    const Vec2 e2 = tri[t][2] - tri[t][0];
    result.uv_area += 0.5 * std::abs(cross2(e1, e2));
  }

  if (cancel.is_cancelled()) return cancelled_error("find_overlaps");
  if ((turn == 1 || turn == -1) && injective_by_boundary(uv, triangles, turn)) {
    result.proven_by_boundary = true;
    result.ms = ms_since(start);
    return result;
  }
  const Grid g = build_grid(boxes, live);
  std::uint32_t poll = 0;
  // Boxes meeting only along a line cannot share interior points: open boxes.
  const bool finished = for_candidate_pairs(g, boxes, false, [&](std::uint32_t a, std::uint32_t b) {
    if (cancel.poll(poll)) return false;
    ++result.candidate_pairs;
    if (!interiors_intersect_ccw(tri[a], tri[b])) return true;
    const double area = clipped_area_ccw(tri[a], tri[b]);
    const std::uint32_t lo_t = std::min(a, b);
    const std::uint32_t hi_t = std::max(a, b);
    if (!result.overlaps || lo_t < result.first_pair[0] ||
        (lo_t == result.first_pair[0] && hi_t < result.first_pair[1])) {
      result.first_pair[0] = lo_t;
      result.first_pair[1] = hi_t;
    }
    result.overlaps = true;
    ++result.overlapping_pairs;
    result.overlap_area += area;
    const bool same = triangle_chart.empty() || triangle_chart[a] == triangle_chart[b];
    (same ? result.within_chart_area : result.between_charts_area) += area;
    return true;
  });
  if (!finished) return cancelled_error("find_overlaps");
  result.overlap_fraction = result.uv_area > 0 ? result.overlap_area / result.uv_area : 0.0;
  result.ms = ms_since(start);
  return result;
}

Result<OverlapResult> find_overlaps(const HalfedgeMesh& mesh, const VertexData<Vec2>& uv, const CancelToken& cancel) {
  if (uv.size() != mesh.num_vertices()) {
    return make_error(ErrorCode::kInvalidArgument, "find_overlaps: " + std::to_string(uv.size()) + " UVs for " +
                                                       std::to_string(mesh.num_vertices()) + " vertices");
  }
  const std::vector<Triangle> triangles = mesh.triangles();
  const Topology topology = compute_topology(mesh);
  return find_overlaps(uv.raw(), triangles, topology.face_component.raw(), cancel);
}

}  // namespace seam::core
