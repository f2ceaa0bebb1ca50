#include "core/uv/multilevel.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <span>
#include <string>

#include "core/uv/collision.h"

namespace seam::core {

namespace {

constexpr double kThinArea2x = 1e-11;

// 4 sqrt(3) area / sum of squared edges: 1 for an equilateral triangle, negative when the
// triangle is clockwise, 0 when degenerate.
double quality(const Vec2& a, const Vec2& b, const Vec2& c) {
  const double edges = (b - a).squaredNorm() + (c - b).squaredNorm() + (a - c).squaredNorm();
  return edges > 0 ? 2.0 * std::sqrt(3.0) * cross2(a, b, c) / edges : 0.0;
}

double quality(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double edges = (b - a).squaredNorm() + (c - b).squaredNorm() + (a - c).squaredNorm();
  return edges > 0 ? 2.0 * std::sqrt(3.0) * (b - a).cross(c - a).norm() / edges : 0.0;
}

// Barycentric coordinates of p in triangle t of `uv` (positively oriented).
Vec3 barycentric(const Vec2& p, const Triangle& t, const std::vector<Vec2>& uv) {
  const double whole = cross2(uv[t[0]], uv[t[1]], uv[t[2]]);
  return Vec3(cross2(p, uv[t[1]], uv[t[2]]) / whole, cross2(uv[t[0]], p, uv[t[2]]) / whole,
              cross2(uv[t[0]], uv[t[1]], p) / whole);
}

// Barycentric coordinates moved onto the triangle (no negative weight, sum 1).
Vec3 clamped(Vec3 b) {
  b = b.cwiseMax(0.0);
  const double sum = b.sum();
  return sum > 0 ? Vec3(b / sum) : Vec3(1.0, 0.0, 0.0);
}

// Per vertex, the log of the start map's linear scale around it: half the log of UV over 3D
// area, averaged over the vertex's triangles weighted by 3D area (0 where all are degenerate).
std::vector<double> vertex_log_scales(const DiscPatch& patch, const std::vector<Vec2>& uv) {
  std::vector<double> sum(patch.num_vertices(), 0.0);
  std::vector<double> weight(patch.num_vertices(), 0.0);
  for (const Triangle& t : patch.triangles) {
    const Vec3& p0 = patch.positions[t[0]];
    const double area_3d = 0.5 * (patch.positions[t[1]] - p0).cross(patch.positions[t[2]] - p0).norm();
    const double area_uv = 0.5 * cross2(uv[t[0]], uv[t[1]], uv[t[2]]);
    if (!(area_3d > 0) || !(area_uv > 0)) continue;
    const double log_scale = 0.5 * std::log(area_uv / area_3d);
    for (std::uint32_t v : t) {
      sum[v] += area_3d * log_scale;
      weight[v] += area_3d;
    }
  }
  for (std::size_t v = 0; v < sum.size(); ++v) sum[v] = weight[v] > 0 ? sum[v] / weight[v] : 0.0;
  return sum;
}

// Vertex -> incident live triangles, in one array: each vertex has room for its starting
// count or `room` triangles, whichever is more (a collapse never gives a vertex more than
// max_valence). Removal keeps the order.
class StarLists {
 public:
  StarLists(const std::vector<Triangle>& tris, std::size_t n, std::size_t room) : offset_(n + 1, 0), size_(n, 0) {
    for (const Triangle& t : tris) {
      for (std::uint32_t v : t) ++size_[v];
    }
    std::size_t total = 0;
    for (std::size_t v = 0; v < n; ++v) {
      total += std::max<std::size_t>(size_[v], room);
      SEAM_ASSERT(total < kNone);
      offset_[v + 1] = static_cast<std::uint32_t>(total);
    }
    slots_.resize(total);
    std::fill(size_.begin(), size_.end(), 0);
    for (std::uint32_t f = 0; f < tris.size(); ++f) {
      for (std::uint32_t v : tris[f]) push(v, f);
    }
  }
  std::span<const std::uint32_t> operator[](std::uint32_t v) const { return {slots_.data() + offset_[v], size_[v]}; }
  void push(std::uint32_t v, std::uint32_t f) {
    SEAM_ASSERT(offset_[v] + size_[v] < offset_[v + 1]);
    slots_[offset_[v] + size_[v]++] = f;
  }
  void erase(std::uint32_t v, std::uint32_t f) {
    std::uint32_t* first = slots_.data() + offset_[v];
    std::uint32_t* last = std::remove(first, first + size_[v], f);
    size_[v] = static_cast<std::uint32_t>(last - first);
  }
  void clear(std::uint32_t v) { size_[v] = 0; }

 private:
  std::vector<std::uint32_t> offset_;
  std::vector<std::uint32_t> size_;
  std::vector<std::uint32_t> slots_;
};

// The disc's triangles under half-edge collapses: vertex -> incident triangles, kept in step.
class Collapser {
 public:
  struct Worst {       // shape qualities (see quality())
    double uv = 0;     // in the start map
    double space = 0;  // in 3D
  };

  Collapser(const DiscPatch& patch, const std::vector<Vec2>& uv, const CoarsenOptions& options)
      : patch_(patch),
        uv_(uv),
        options_(options),
        tris_(patch.triangles),
        tri_alive_(tris_.size(), 1),
        faces_of_(tris_, patch.num_vertices(), options.max_valence),
        boundary_(patch.num_vertices(), 0),
        alive_(patch.num_vertices(), 1),
        parent_(patch.num_vertices(), kNone),
        seen_(patch.num_vertices(), 0),
        locked_(patch.num_vertices(), 0),
        alive_count_(patch.num_vertices()) {
    for (std::uint32_t v : patch.boundary) boundary_[v] = 1;
    log_scale_ = vertex_log_scales(patch, uv);
  }

  // One round, a matching: every interior vertex not yet paired this round collapses onto its
  // nearest unpaired neighbour that passes the checks, and that neighbour is paired. So one
  // round at most halves the vertices and every vertex left stands for at most two of the
  // round's start, which keeps the coarse vertices evenly spread. Returns the collapses made.
  Result<std::size_t> round(std::size_t target, const CancelToken& cancel) {
    ++round_;
    std::size_t collapses = 0;
    std::uint32_t poll = 0;
    std::vector<std::uint32_t> ring;
    std::vector<std::pair<double, std::uint32_t>> candidates;
    for (std::uint32_t v = 0; v < alive_.size() && alive_count_ > target; ++v) {
      if (cancel.poll(poll)) return cancelled_error("coarsening a chart");
      if (!alive_[v] || boundary_[v] || locked_[v] == round_) continue;
      neighbours(v, ring);
      // The neighbours not yet paired this round, nearest first (ties by index).
      const Vec3& p = patch_.positions[v];
      candidates.clear();
      for (std::uint32_t w : ring) {
        if (locked_[w] != round_) candidates.emplace_back((patch_.positions[w] - p).squaredNorm(), w);
      }
      if (candidates.empty()) continue;
      std::sort(candidates.begin(), candidates.end());
      const Worst worst = worst_of_star(v);
      for (const auto& [distance, w] : candidates) {
        if (!collapse(v, w, worst)) continue;
        locked_[w] = round_;  // w has its partner for this round
        ++collapses;
        --alive_count_;
        break;
      }
    }
    return collapses;
  }

  std::size_t alive_count() const { return alive_count_; }
  bool alive(std::uint32_t v) const { return alive_[v] != 0; }
  bool tri_alive(std::uint32_t f) const { return tri_alive_[f] != 0; }
  const Triangle& tri(std::uint32_t f) const { return tris_[f]; }
  std::uint32_t some_face(std::uint32_t v) const { return faces_of_[v].empty() ? kNone : faces_of_[v].front(); }

  // The kept vertex that v was collapsed onto, directly or through others (v itself if kept).
  std::uint32_t kept_for(std::uint32_t v) const {
    while (!alive_[v]) v = parent_[v];
    return v;
  }

  // The live triangle that holds p in the start map, found by walking from a triangle at
  // vertex `from` across the edge p lies beyond: (triangle, barycentric coordinates, their
  // minimum). p lies near `from` (it was collapsed onto it), so the walk is a few steps; a
  // walk that has not arrived after 256 steps returns where it got closest.
  struct Location {
    std::uint32_t face = kNone;
    Vec3 barycentric = Vec3::Zero();
    double inside = -std::numeric_limits<double>::infinity();
  };
  Location walk_to(std::uint32_t from, const Vec2& p) const {
    Location best;
    std::uint32_t f = some_face(from);
    for (int step = 0; step < 256 && f != kNone; ++step) {
      const Triangle& t = tris_[f];
      const Vec3 b = barycentric(p, t, uv_);
      Eigen::Index out = 0;
      const double inside = b.minCoeff(&out);
      if (inside > best.inside) best = {f, b, inside};
      if (inside >= 0) break;
      f = across(f, t[static_cast<std::size_t>((out + 1) % 3)], t[static_cast<std::size_t>((out + 2) % 3)]);
    }
    return best;
  }

 private:
  // The live triangle other than f on edge (a, b), or kNone on the boundary.
  std::uint32_t across(std::uint32_t f, std::uint32_t a, std::uint32_t b) const {
    for (std::uint32_t g : faces_of_[a]) {
      const Triangle& t = tris_[g];
      if (g != f && (t[0] == b || t[1] == b || t[2] == b)) return g;
    }
    return kNone;
  }

  // The distinct neighbours of v.
  void neighbours(std::uint32_t v, std::vector<std::uint32_t>& out) {
    out.clear();
    ++epoch_;
    for (std::uint32_t f : faces_of_[v]) {
      for (std::uint32_t u : tris_[f]) {
        if (u != v && seen_[u] != epoch_) {
          seen_[u] = epoch_;
          out.push_back(u);
        }
      }
    }
  }

  static std::uint32_t third(const Triangle& t, std::uint32_t a, std::uint32_t b) {
    for (std::uint32_t u : t) {
      if (u != a && u != b) return u;
    }
    return kNone;
  }

  // Moves interior vertex v onto its neighbour w, when the checks pass.
  bool collapse(std::uint32_t v, std::uint32_t w, const Worst& worst) {
    std::uint32_t shared[2] = {kNone, kNone};
    int count = 0;
    for (std::uint32_t f : faces_of_[v]) {
      const Triangle& t = tris_[f];
      if (t[0] != w && t[1] != w && t[2] != w) continue;
      if (count < 2) shared[count] = f;
      ++count;
    }
    if (count != 2) return false;
    const std::uint32_t x = third(tris_[shared[0]], v, w);
    const std::uint32_t y = third(tris_[shared[1]], v, w);
    if (x == y) return false;
    // The shapes first: they read v's star, which the caller has just read, while the link
    // condition reads w's.
    if (!shapes_hold(v, w, shared, worst)) return false;
    // Link condition: v and w have no common neighbour but x and y.
    ++epoch_;
    std::size_t valence_w = 0;
    for (std::uint32_t f : faces_of_[w]) {
      for (std::uint32_t u : tris_[f]) {
        if (u != w && seen_[u] != epoch_) {
          seen_[u] = epoch_;
          ++valence_w;
        }
      }
    }
    const std::uint32_t mark = epoch_;
    ++epoch_;
    std::size_t valence_v = 0;
    for (std::uint32_t f : faces_of_[v]) {
      for (std::uint32_t u : tris_[f]) {
        if (u == v || seen_[u] == epoch_) continue;
        if (seen_[u] == mark && u != w && u != x && u != y) return false;
        seen_[u] = epoch_;
        ++valence_v;
      }
    }
    if (valence_w + valence_v - 4 > options_.max_valence) return false;
    for (std::uint32_t s : shared) {
      tri_alive_[s] = 0;
      for (std::uint32_t u : {w, x, y}) faces_of_.erase(u, s);
    }
    for (std::uint32_t f : faces_of_[v]) {
      if (f == shared[0] || f == shared[1]) continue;
      for (std::uint32_t& u : tris_[f]) {
        if (u == v) u = w;
      }
      faces_of_.push(w, f);
    }
    faces_of_.clear(v);
    alive_[v] = 0;
    parent_[v] = w;
    return true;
  }

  // Every triangle of v's star that survives the collapse stays positively oriented in the
  // start map, joins vertices of similar scale, and is no worse shaped (there and in 3D) than
  // `worst`.
  bool shapes_hold(std::uint32_t v, std::uint32_t w, const std::uint32_t (&shared)[2], const Worst& worst) {
    auto moved = [&](std::uint32_t f) {
      Triangle t = tris_[f];
      for (std::uint32_t& u : t) {
        if (u == v) u = w;
      }
      return t;
    };
    // The cheap tests first: orientation and scale range, then the shapes.
    for (std::uint32_t f : faces_of_[v]) {
      if (f == shared[0] || f == shared[1]) continue;
      const Triangle t = moved(f);
      const auto [lo, hi] = std::minmax({log_scale_[t[0]], log_scale_[t[1]], log_scale_[t[2]]});
      if (hi - lo > max_log_scale_range_ || !(cross2(uv_[t[0]], uv_[t[1]], uv_[t[2]]) > 0)) return false;
    }
    for (std::uint32_t f : faces_of_[v]) {
      if (f == shared[0] || f == shared[1]) continue;
      const Worst shape = shape_of(moved(f));
      if (!(shape.space > 0) || shape.uv < worst.uv || shape.space < worst.space) return false;
    }
    return true;
  }

  // Triangle t's shape qualities in the start map and in 3D. Computed where needed: a copy per
  // triangle cost 20 MB of fresh memory at 1.25M faces and was slower to fill than to recompute.
  Worst shape_of(const Triangle& t) const {
    return {quality(uv_[t[0]], uv_[t[1]], uv_[t[2]]),
            quality(patch_.positions[t[0]], patch_.positions[t[1]], patch_.positions[t[2]])};
  }

  // The bound on v's new triangles: min_quality, or the worst of v's star if that is worse.
  Worst worst_of_star(std::uint32_t v) const {
    Worst worst{options_.min_quality, options_.min_quality};
    for (std::uint32_t f : faces_of_[v]) {
      const Worst shape = shape_of(tris_[f]);
      worst.uv = std::min(worst.uv, shape.uv);
      worst.space = std::min(worst.space, shape.space);
    }
    return worst;
  }

  const DiscPatch& patch_;
  const std::vector<Vec2>& uv_;
  const CoarsenOptions& options_;
  std::vector<Triangle> tris_;
  std::vector<std::uint8_t> tri_alive_;
  StarLists faces_of_;
  std::vector<std::uint8_t> boundary_;
  std::vector<std::uint8_t> alive_;
  std::vector<std::uint32_t> parent_;  // a collapsed vertex -> the vertex it moved onto
  std::vector<double> log_scale_;      // per vertex: log of the start map's scale around it
  std::vector<std::uint32_t> seen_;    // epoch stamps for neighbour sets
  std::vector<std::uint32_t> locked_;  // round stamps: paired (collapsed or absorbed) this round
  double max_log_scale_range_ = std::log(options_.max_scale_ratio);
  std::uint32_t epoch_ = 0;
  std::uint32_t round_ = 0;
  std::size_t alive_count_;
};

// The triangle of `tris` that holds p best (largest smallest barycentric coordinate), by a
// scan of them all, and those coordinates clamped to it: for a walk that did not arrive (none
// did in the benchmarks), so its O(T) cost stays rare.
std::pair<std::uint32_t, Vec3> locate_anywhere(const std::vector<Triangle>& tris, const std::vector<Vec2>& uv,
                                               const Vec2& p) {
  std::uint32_t best = kNone;
  Vec3 best_bary = Vec3::Zero();
  double best_score = -std::numeric_limits<double>::infinity();
  for (std::uint32_t t = 0; t < tris.size(); ++t) {
    const Vec3 bary = barycentric(p, tris[t], uv);
    if (bary.minCoeff() > best_score) {
      best_score = bary.minCoeff();
      best = t;
      best_bary = bary;
    }
  }
  return {best, clamped(best_bary)};
}

Status check_start(const DiscPatch& patch, const std::vector<Vec2>& uv) {
  if (uv.size() != patch.num_vertices()) {
    return make_error(ErrorCode::kInvalidArgument, "coarsen_chart: the map has " + std::to_string(uv.size()) +
                                                       " points for " + std::to_string(patch.num_vertices()) +
                                                       " vertices");
  }
  for (std::size_t t = 0; t < patch.triangles.size(); ++t) {
    const Triangle& tri = patch.triangles[t];
    if (!(cross2(uv[tri[0]], uv[tri[1]], uv[tri[2]]) > 0)) {
      return make_error(ErrorCode::kInvalidArgument, "coarsen_chart: the map folds triangle " + std::to_string(t));
    }
  }
  return Ok{};
}

// The kept vertices and live triangles of `c` as a compact disc, with the start map there.
CoarseChart compact(const DiscPatch& patch, const std::vector<Vec2>& uv, const Collapser& c,
                    std::vector<std::uint32_t>& coarse_of, std::vector<std::uint32_t>& coarse_tri) {
  CoarseChart coarse;
  coarse_of.assign(patch.num_vertices(), kNone);
  for (std::uint32_t v = 0; v < patch.num_vertices(); ++v) {
    if (!c.alive(v)) continue;
    coarse_of[v] = static_cast<std::uint32_t>(coarse.fine_vertex.size());
    coarse.fine_vertex.push_back(v);
    coarse.patch.to_mesh.push_back(patch.to_mesh[v]);
    coarse.patch.positions.push_back(patch.positions[v]);
    coarse.start.push_back(uv[v]);
  }
  coarse_tri.assign(patch.triangles.size(), kNone);
  for (std::uint32_t f = 0; f < patch.triangles.size(); ++f) {
    if (!c.tri_alive(f)) continue;
    const Triangle& t = c.tri(f);
    coarse_tri[f] = static_cast<std::uint32_t>(coarse.patch.triangles.size());
    coarse.patch.triangles.push_back({coarse_of[t[0]], coarse_of[t[1]], coarse_of[t[2]]});
    coarse.patch.to_mesh_face.push_back(patch.to_mesh_face[f]);
  }
  for (std::uint32_t v : patch.boundary) coarse.patch.boundary.push_back(coarse_of[v]);
  return coarse;
}

}  // namespace

Result<CoarseChart> coarsen_chart(const DiscPatch& patch, const std::vector<Vec2>& uv, const CoarsenOptions& options,
                                  const CancelToken& cancel) {
  if (Status st = check_start(patch, uv); !st.ok()) return st.take_error();
  Collapser collapser(patch, uv, options);
  for (int round = 0; round < 64 && collapser.alive_count() > options.target_vertices; ++round) {
    SEAM_TRY(std::size_t collapses, collapser.round(options.target_vertices, cancel));
    if (collapses * 100 < collapser.alive_count()) break;
  }
  std::vector<std::uint32_t> coarse_of, coarse_tri;
  CoarseChart coarse = compact(patch, uv, collapser, coarse_of, coarse_tri);
  coarse.host.resize(patch.num_vertices());
  coarse.barycentric.resize(patch.num_vertices());
  std::uint32_t poll = 0;
  for (std::uint32_t v = 0; v < patch.num_vertices(); ++v) {
    if (cancel.poll(poll)) return cancelled_error("coarsening a chart");
    if (coarse_of[v] != kNone) {
      // A kept vertex: weight 1 at its own corner of any triangle around it.
      const std::uint32_t face = collapser.some_face(v);
      if (face == kNone) return make_error(ErrorCode::kInvalidArgument, "coarsen_chart: an isolated vertex");
      const std::uint32_t t = coarse_tri[face];
      const Triangle& tri = coarse.patch.triangles[t];
      coarse.host[v] = t;
      coarse.barycentric[v] = Vec3(tri[0] == coarse_of[v], tri[1] == coarse_of[v], tri[2] == coarse_of[v]);
      continue;
    }
    const Collapser::Location at = collapser.walk_to(collapser.kept_for(v), uv[v]);
    if (at.inside >= -1e-12) {
      coarse.host[v] = coarse_tri[at.face];
      coarse.barycentric[v] = clamped(at.barycentric);
      continue;
    }
    const auto [t, bary] = locate_anywhere(coarse.patch.triangles, coarse.start, uv[v]);
    if (t == kNone) return make_error(ErrorCode::kSolverFailed, "coarsen_chart: a vertex lies in no coarse triangle");
    coarse.host[v] = t;
    coarse.barycentric[v] = bary;
  }
  return coarse;
}

std::vector<Vec2> prolongate(const CoarseChart& coarse, const std::vector<Vec2>& coarse_uv) {
  SEAM_ASSERT(coarse_uv.size() == coarse.patch.num_vertices());
  std::vector<Vec2> uv(coarse.host.size());
  for (std::size_t v = 0; v < uv.size(); ++v) {
    const Triangle& t = coarse.patch.triangles[coarse.host[v]];
    const Vec3& b = coarse.barycentric[v];
    uv[v] = b[0] * coarse_uv[t[0]] + b[1] * coarse_uv[t[1]] + b[2] * coarse_uv[t[2]];
  }
  return uv;
}

std::size_t default_coarse_vertices(std::size_t fine_vertices) {
  constexpr std::size_t kCoarsening = 12;
  constexpr std::size_t kMinVertices = 30000;
  return std::max(fine_vertices / kCoarsening, kMinVertices);
}

SlimOptions coarse_slim_options(SlimOptions slim) {
  constexpr int kContactSolves = 96;
  constexpr double kToleranceFactor = 2;
  slim.contact_solves = kContactSolves;
  slim.tolerance = std::min(1.0, kToleranceFactor * slim.tolerance);
  return slim;
}

Result<TwoLevelResult> slim_two_level(const DiscPatch& patch, const std::vector<Vec2>& start,
                                      std::size_t coarse_vertices, const SlimOptions& slim, const CancelToken& cancel) {
  using Clock = std::chrono::steady_clock;
  auto lap = [clock = Clock::now()]() mutable {
    const Clock::time_point now = Clock::now();
    const double ms = std::chrono::duration<double, std::milli>(now - clock).count();
    clock = now;
    return ms;
  };
  SEAM_TRY(CoarseChart coarse, coarsen_chart(patch, start, {.target_vertices = coarse_vertices}, cancel));
  TwoLevelResult result;
  result.coarsen_ms = lap();
  result.coarse_vertices = coarse.patch.num_vertices();
  SEAM_TRY(result.coarse, flatten_slim(coarse.patch, coarse.start, slim, cancel));
  result.slim_ms = lap();
  result.uv = prolongate(coarse, result.coarse.uv);
  // A fine triangle across a coarse edge where the coarse map bends can fold (up to a few dozen
  // at 200k-1M faces); moving interior vertices within their stars unfolds them.
  result.folds_untangled = count_flipped(patch, result.uv);
  const bool folded = untangle(patch, result.uv) > 0;
  // Triangles that a squeezed start leaves thinner than float32 can keep once the chart is
  // fitted into the unit square (doubled area 1e-11 of the chart's extent squared, about
  // 1e-5 of a triangle's share at 1M faces; rounding flipped two such at 1.25M faces) are
  // fattened the same way, as far as their stars allow.
  if (!folded) {
    Vec2 lo = result.uv.front();
    Vec2 hi = lo;
    for (const Vec2& p : result.uv) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    const double extent = (hi - lo).maxCoeff();
    result.thin_left = untangle(patch, result.uv, 20, kThinArea2x * extent * extent);
  }
  if (folded || (slim.injective && !boundary_is_simple(patch, result.uv))) result.uv.clear();
  result.finish_ms = lap();
  return result;
}

}  // namespace seam::core
