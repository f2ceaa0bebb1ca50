#include "core/uv/collision.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/atlas/predicates.h"

namespace seam::core {

namespace {

struct Box {
  Vec2 lo;
  Vec2 hi;
};

// Items (boxes) bucketed in a uniform grid of about one cell per item; calls f(i, j) once for
// every pair of items whose boxes meet, i < j, in a deterministic order. With 0 < split <
// boxes.size(), only the pairs of an item below `split` with one from `split` on (two kinds of
// item, e.g. points and edges): the others are never tested. A pair is reported in the cell of
// its boxes' common lower corner, the first cell both cover in x and y.
template <class F>
void for_each_box_pair(const std::vector<Box>& boxes, std::size_t split, F&& f) {
  if (boxes.size() < 2) return;
  if (split >= boxes.size()) split = 0;
  Vec2 lo = boxes[0].lo;
  Vec2 hi = boxes[0].hi;
  for (const Box& b : boxes) {
    lo = lo.cwiseMin(b.lo);
    hi = hi.cwiseMax(b.hi);
  }
  const Vec2 extent = (hi - lo).cwiseMax(1e-300);
  const double n = static_cast<double>(boxes.size());
  double cell = std::max(std::sqrt(extent.x() * extent.y() / n), std::max(extent.x(), extent.y()) / n);
  const auto nx = std::clamp<std::int64_t>(static_cast<std::int64_t>(extent.x() / cell) + 1, 1, 4096);
  const auto ny = std::clamp<std::int64_t>(static_cast<std::int64_t>(extent.y() / cell) + 1, 1, 4096);
  auto cx = [&](double x) { return std::clamp<std::int64_t>(static_cast<std::int64_t>((x - lo.x()) / cell), 0, nx - 1); };
  auto cy = [&](double y) { return std::clamp<std::int64_t>(static_cast<std::int64_t>((y - lo.y()) / cell), 0, ny - 1); };
  // Each box's cells, computed once: the grid pass compares the first cells as integers.
  struct Cells {
    std::int32_t x0, y0, x1, y1;
  };
  std::vector<Cells> cells(boxes.size());
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const Box& b = boxes[i];
    cells[i] = {static_cast<std::int32_t>(cx(b.lo.x())), static_cast<std::int32_t>(cy(b.lo.y())),
                static_cast<std::int32_t>(cx(b.hi.x())), static_cast<std::int32_t>(cy(b.hi.y()))};
  }
  std::vector<std::uint32_t> offset(static_cast<std::size_t>(nx * ny) + 1, 0);
  auto cells_of = [&](const Cells& c, auto&& g) {
    for (std::int64_t y = c.y0; y <= c.y1; ++y) {
      for (std::int64_t x = c.x0; x <= c.x1; ++x) g(static_cast<std::size_t>(y * nx + x));
    }
  };
  for (const Cells& c : cells) cells_of(c, [&](std::size_t k) { ++offset[k + 1]; });
  for (std::size_t c = 0; c + 1 < offset.size(); ++c) offset[c + 1] += offset[c];
  // Within a cell the items stay in increasing order, so those below `split` come first.
  std::vector<std::uint32_t> items(offset.back());
  std::vector<std::uint32_t> fill(offset.begin(), offset.end() - 1);
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    cells_of(cells[i], [&](std::size_t k) { items[fill[k]++] = static_cast<std::uint32_t>(i); });
  }
  for (std::size_t c = 0; c + 1 < offset.size(); ++c) {
    const auto x = static_cast<std::int32_t>(static_cast<std::int64_t>(c) % nx);
    const auto y = static_cast<std::int32_t>(static_cast<std::int64_t>(c) / nx);
    const std::uint32_t* first = items.data() + offset[c];
    const std::uint32_t* last = items.data() + offset[c + 1];
    const std::uint32_t* second_kind =
        split > 0 ? std::lower_bound(first, last, static_cast<std::uint32_t>(split)) : first;
    const std::uint32_t* a_end = split > 0 ? second_kind : last;
    for (const std::uint32_t* a = first; a < a_end; ++a) {
      const Cells& ca = cells[*a];
      const Box& p = boxes[*a];
      for (const std::uint32_t* b = split > 0 ? second_kind : a + 1; b < last; ++b) {
        const Cells& cb = cells[*b];
        if (std::max(ca.x0, cb.x0) != x || std::max(ca.y0, cb.y0) != y) continue;  // reported elsewhere
        const Box& q = boxes[*b];
        if (std::max(p.lo.x(), q.lo.x()) > std::min(p.hi.x(), q.hi.x()) ||
            std::max(p.lo.y(), q.lo.y()) > std::min(p.hi.y(), q.hi.y())) {
          continue;
        }
        f(*a, *b);
      }
    }
  }
}

// The roots in (0, t_max] of c0 + c1 t + c2 t^2, in increasing order; returns how many.
int step_roots(double c0, double c1, double c2, double t_max, double roots[2]) {
  int count = 0;
  const double scale = std::abs(c0) + std::abs(c1) * t_max + std::abs(c2) * t_max * t_max;
  if (std::abs(c2) * t_max * t_max <= 1e-14 * scale) {
    if (c1 != 0) roots[count++] = -c0 / c1;
  } else {
    double disc = c1 * c1 - 4 * c2 * c0;
    // A tangential contact: round a marginally negative discriminant to the double root.
    if (disc < 0 && disc > -1e-12 * c1 * c1) disc = 0;
    if (disc >= 0) {
      const double sq = std::sqrt(disc);
      const double u = -0.5 * (c1 + std::copysign(sq, c1));
      roots[count++] = u / c2;
      if (u != 0) roots[count++] = c0 / u;
    }
  }
  if (count == 2 && roots[1] < roots[0]) std::swap(roots[0], roots[1]);
  int kept = 0;
  for (int k = 0; k < count; ++k) {
    if (roots[k] > 0 && roots[k] <= t_max) roots[kept++] = roots[k];
  }
  return kept;
}

// Earliest t in (0, t_max] at which p + t dp lies on the segment [a + t da, b + t db], or
// (gap > 0) comes within `gap` of it. The signed area c(t) = cross(e(t), q(t)) is quadratic in
// t; the vertex meets the band |c| <= gap |e| around the segment on either of its lines. Both
// are solved: a vertex beside the segment's end may pass around it to the far side and come
// back across the segment from there within one step (F18: the near line alone found that
// crossing 2e-4 after the step bound, and SLIM's map overlapped itself).
double contact_time(const Vec2& p, const Vec2& dp, const Vec2& a, const Vec2& da, const Vec2& b, const Vec2& db,
                    double t_max, double gap) {
  const Vec2 e = b - a;
  const Vec2 de = db - da;
  const Vec2 q = p - a;
  const Vec2 dq = dp - da;
  const double len = e.norm();
  const double c0 = cross2(e, q);
  const double c1 = cross2(e, dq) + cross2(de, q);
  const double c2 = cross2(de, dq);
  // The values of c(t) at which the vertex touches the band: the segment itself without a gap.
  std::array<double, 2> lines{0.0, 0.0};
  int line_count = 1;
  if (gap > 0 && len > 0) {
    const double side = c0 >= 0 ? 1.0 : -1.0;
    const double s0 = q.dot(e) / (len * len);
    const double slack = gap / len;
    if (std::abs(c0) <= gap * len && s0 >= -slack && s0 <= 1 + slack) {
      // Already within the gap: moving closer is a contact now. Moving away at first order,
      // the vertex can still come back, since the edge turns and stretches along the step
      // (the quadratic term; a spike's vertex beside its own edge's neighbour crossed it so,
      // F16): it may not come closer than half its present distance within the step.
      if (side * c1 < 0) return 0.0;
      lines = {0.5 * c0, -0.5 * c0};
    } else {
      lines = {side * gap * len, -side * gap * len};
    }
    line_count = 2;
  }
  double earliest = std::numeric_limits<double>::infinity();
  for (int l = 0; l < line_count; ++l) {
    double roots[2];
    const int count = step_roots(c0 - lines[l], c1, c2, t_max, roots);
    for (int k = 0; k < count; ++k) {
      const double t = roots[k];
      const Vec2 et = e + t * de;
      const double len2 = et.squaredNorm();
      const double s = len2 > 0 ? (q + t * dq).dot(et) / len2 : 0.0;
      const double slack = len2 > 0 ? 1e-9 + gap / std::sqrt(len2) : 1e-9;
      if (s >= -slack && s <= 1 + slack) {
        earliest = std::min(earliest, t);
        break;  // the later root of this line comes after
      }
    }
  }
  return earliest;
}

bool on_segment(const Vec2& a, const Vec2& b, const Vec2& p) {
  return std::min(a.x(), b.x()) <= p.x() && p.x() <= std::max(a.x(), b.x()) && std::min(a.y(), b.y()) <= p.y() &&
         p.y() <= std::max(a.y(), b.y());
}

// Closed segments [a, b] and [c, d] share a point (exact).
bool segments_meet(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const int o1 = orient2d(a, b, c);
  const int o2 = orient2d(a, b, d);
  const int o3 = orient2d(c, d, a);
  const int o4 = orient2d(c, d, b);
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;
  return (o1 == 0 && on_segment(a, b, c)) || (o2 == 0 && on_segment(a, b, d)) || (o3 == 0 && on_segment(c, d, a)) ||
         (o4 == 0 && on_segment(c, d, b));
}

}  // namespace

CollisionStep max_collision_free_step(const DiscPatch& patch, const std::vector<Vec2>& uv,
                                      const std::vector<Vec2>& direction, double t_max, double gap) {
  CollisionStep out;
  out.step = t_max;
  const std::vector<std::uint32_t>& loop = patch.boundary;
  const std::size_t nb = loop.size();
  if (nb < 4) return out;  // a triangle's boundary cannot cross itself without folding it
  // Items 0..nb-1: boundary vertices (swept points); nb..2nb-1: edges (loop[i], loop[i+1]).
  std::vector<Box> boxes(2 * nb);
  for (std::size_t i = 0; i < nb; ++i) {
    const Vec2& p = uv[loop[i]];
    const Vec2 p1 = p + t_max * direction[loop[i]];
    boxes[i] = {p.cwiseMin(p1) - Vec2::Constant(gap), p.cwiseMax(p1) + Vec2::Constant(gap)};
  }
  for (std::size_t i = 0; i < nb; ++i) {
    const Box& a = boxes[i];
    const Box& b = boxes[(i + 1) % nb];
    boxes[nb + i] = {a.lo.cwiseMin(b.lo), a.hi.cwiseMax(b.hi)};
  }
  double best = std::numeric_limits<double>::infinity();
  for_each_box_pair(boxes, nb, [&](std::uint32_t i, std::uint32_t j) {
    const std::size_t e = j - nb;
    const std::size_t e1 = (e + 1) % nb;
    if (i == e || i == e1) return;  // the edge's own endpoints
    ++out.candidate_pairs;
    const std::uint32_t v = loop[i];
    const std::uint32_t a = loop[e];
    const std::uint32_t b = loop[e1];
    const double t = contact_time(uv[v], direction[v], uv[a], direction[a], uv[b], direction[b], t_max, gap);
    if (t <= t_max) {
      best = std::min(best, t);
      out.colliding.insert(out.colliding.end(), {v, a, b});
      out.contacts.push_back({v, a, b, t});
    }
  });
  if (best <= t_max) {
    out.step = best;
    out.limited = true;
  }
  std::sort(out.colliding.begin(), out.colliding.end());
  out.colliding.erase(std::unique(out.colliding.begin(), out.colliding.end()), out.colliding.end());
  return out;
}

bool boundary_is_simple(const DiscPatch& patch, const std::vector<Vec2>& uv) {
  const std::vector<std::uint32_t>& loop = patch.boundary;
  const std::size_t nb = loop.size();
  std::vector<Box> boxes(nb);
  for (std::size_t i = 0; i < nb; ++i) {
    const Vec2& a = uv[loop[i]];
    const Vec2& b = uv[loop[(i + 1) % nb]];
    boxes[i] = {a.cwiseMin(b), a.cwiseMax(b)};
  }
  bool simple = true;
  for_each_box_pair(boxes, 0, [&](std::uint32_t i, std::uint32_t j) {
    if (!simple) return;
    const Vec2& a = uv[loop[i]];
    const Vec2& b = uv[loop[(i + 1) % nb]];
    const Vec2& c = uv[loop[j]];
    const Vec2& d = uv[loop[(j + 1) % nb]];
    const bool next = (i + 1) % nb == j;
    const bool prev = (j + 1) % nb == i;
    if (next || prev) {
      // Adjacent edges share one vertex; they may not fold back over each other.
      const Vec2& shared = next ? b : a;
      const Vec2& p = next ? a : b;
      const Vec2& q = next ? d : c;
      if (nb > 2 && orient2d(p, shared, q) == 0 && (p - shared).dot(q - shared) > 0) simple = false;
      return;
    }
    if (segments_meet(a, b, c, d)) simple = false;
  });
  return simple;
}

}  // namespace seam::core
