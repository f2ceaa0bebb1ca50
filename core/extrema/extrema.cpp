#include "core/extrema/extrema.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <span>
#include <string>
#include <thread>
#include <utility>

#include "core/mesh/topology.h"
#include "core/paths/dijkstra_kernel.h"
#include "core/paths/geodesic.h"
#include "core/timing.h"

namespace seam::core {
namespace {

struct Component {
  std::vector<std::uint32_t> vertices;  // ascending vertex ids; local index = position here
  double area = 0;
};

// relax_from's visitor: vertices in a component's local numbering, one distance array.
template <class OnImprove>
struct LocalVisitor {
  const Component& comp;
  const std::vector<std::uint32_t>& local_of;
  std::vector<double>& dist;
  IndexedHeap& heap;
  OnImprove& on_improve;
  std::size_t max_settled;
  double* last_settled;
  double stop_at;

  SettleAction settle(std::uint32_t v, double) {
    if (dist[v] >= stop_at) return SettleAction::kStop;
    if (last_settled) *last_settled = dist[v];
    return max_settled-- == 0 ? SettleAction::kStop : SettleAction::kExpand;
  }
  double distance(std::uint32_t v) const { return dist[v]; }
  std::uint32_t graph_vertex(std::uint32_t v) const { return comp.vertices[v]; }
  void relax(std::uint32_t v, std::uint32_t head, double nd, std::uint32_t) {
    const std::uint32_t w = local_of[head];
    if (nd < dist[w]) {
      dist[w] = nd;
      on_improve(w, v);
      heap.push_or_decrease(w);
    }
  }
};

// Dijkstra on one component in local indices from one or more sources. `distance` holds
// upper bounds on entry (kInf, or the distances to earlier sources); a vertex is relaxed only
// when the new sources are strictly closer, so with earlier distances in place only the new
// source's geodesic Voronoi cell is explored: farthest-point sampling then costs a few full
// runs in total, not one per sample. `on_improve(w, from)` is called for every vertex whose
// distance drops, with the vertex it was reached from (kNone for a source).
// With `max_settled`, stops after settling that many vertices and reports the last settled
// distance in `*last_settled`: every distance below it is final (the heap is then left
// non-empty and must be emptied or discarded). With `stop_at`, stops at the first vertex at
// that distance or beyond: every distance below it is final.
template <class OnImprove>
Status relax_from(const EdgeGraph& graph, const Component& comp, const std::vector<std::uint32_t>& local_of,
                  std::span<const std::uint32_t> sources, std::vector<double>& distance, IndexedHeap& heap,
                  const CancelToken& cancel, OnImprove&& on_improve,
                  std::size_t max_settled = std::numeric_limits<std::size_t>::max(), double* last_settled = nullptr,
                  double stop_at = kInf) {
  for (std::uint32_t source : sources) {
    distance[source] = 0.0;
    on_improve(source, kNone);
    heap.push_or_decrease(source);
  }
  LocalVisitor<OnImprove> visitor{comp, local_of, distance, heap, on_improve, max_settled, last_settled, stop_at};
  return run_dijkstra(graph, heap, visitor, cancel, "extrema detection");
}

template <class OnImprove>
Status relax_from(const EdgeGraph& graph, const Component& comp, const std::vector<std::uint32_t>& local_of,
                  std::uint32_t source, std::vector<double>& distance, IndexedHeap& heap, const CancelToken& cancel,
                  OnImprove&& on_improve, std::size_t max_settled = std::numeric_limits<std::size_t>::max(),
                  double* last_settled = nullptr) {
  const std::uint32_t sources[] = {source};
  return relax_from(graph, comp, local_of, std::span<const std::uint32_t>(sources), distance, heap, cancel,
                    std::forward<OnImprove>(on_improve), max_settled, last_settled);
}

// One third of the area of every incident face: the vertex's share of the surface.
std::vector<double> vertex_areas(const HalfedgeMesh& mesh) {
  std::vector<double> area(mesh.num_vertices(), 0.0);
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    const auto v = mesh.face_vertices(FaceId(f));
    const Vec3& a = mesh.position(v[0]);
    const double third = (mesh.position(v[1]) - a).cross(mesh.position(v[2]) - a).norm() / 6.0;
    for (VertexId u : v) area[u.index()] += third;
  }
  return area;
}

// Vertex lists of the components that have faces, numbered as compute_topology() does.
std::vector<Component> collect_components(const HalfedgeMesh& mesh, const Topology& topo,
                                          const std::vector<double>& area) {
  std::vector<Component> components(topo.components.size());
  for (std::size_t c = 0; c < components.size(); ++c) components[c].vertices.reserve(topo.components[c].vertices);
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
    const std::uint32_t c = topo.vertex_component[VertexId(v)];
    if (c == VertexId::kInvalidValue) continue;
    components[c].vertices.push_back(static_cast<std::uint32_t>(v));
    components[c].area += area[v];
  }
  return components;
}

// A thread takes at least this many vertex settles of the full passes (sources x vertices;
// about 1.5 ms at 80 ns each), or the calling thread does them all: starting a thread costs
// about 0.1 ms. (Counted in vertices alone, as before, a 10k-face mesh stayed on one thread
// with 16 x 4,930 settles to do.)
constexpr std::size_t kMinSettlesPerThread = 20000;

// Farthest-point samples of a component (local indices), each vertex's nearest sample, and a
// bound on every distance in the component (twice the eccentricity of vertex 0).
struct FarthestSamples {
  std::vector<std::uint32_t> sources;
  std::vector<std::uint32_t> nearest_sample;  // per local vertex: its index in `sources`
  double bound = 0;
};

// Farthest-point sampling with incremental (Voronoi-pruned) Dijkstra runs, starting from the
// vertex farthest from local vertex 0; at most `k_max` samples.
Result<FarthestSamples> farthest_point_samples(const EdgeGraph& graph, const Component& comp,
                                               const std::vector<std::uint32_t>& local_of, std::size_t k_max,
                                               const CancelToken& cancel) {
  const std::size_t n = comp.vertices.size();
  auto farthest = [&](const std::vector<double>& value) {
    std::size_t best = 0;
    for (std::size_t j = 1; j < n; ++j) {
      if (value[j] > value[best]) best = j;
    }
    return static_cast<std::uint32_t>(best);
  };
  auto nothing = [](std::uint32_t, std::uint32_t) {};
  FarthestSamples out;
  std::vector<double> nearest_distance(n, kInf);
  out.nearest_sample.assign(n, 0);
  IndexedHeap heap(nearest_distance, n);
  if (auto st = relax_from(graph, comp, local_of, 0, nearest_distance, heap, cancel, nothing); !st.ok()) {
    return st.take_error();
  }
  std::uint32_t source = farthest(nearest_distance);
  out.bound = 2.0 * nearest_distance[source];
  std::fill(nearest_distance.begin(), nearest_distance.end(), kInf);
  while (out.sources.size() < k_max) {
    const auto k = static_cast<std::uint32_t>(out.sources.size());
    out.sources.push_back(source);
    auto claim = [&](std::uint32_t w, std::uint32_t) { out.nearest_sample[w] = k; };
    if (auto st = relax_from(graph, comp, local_of, source, nearest_distance, heap, cancel, claim); !st.ok()) {
      return st.take_error();
    }
    source = farthest(nearest_distance);
    if (nearest_distance[source] == 0.0) break;  // every vertex is a source already
  }
  return out;
}

// One full Dijkstra per source, in parallel, summing weight[i] * d_i(v) per local vertex in
// fixed point (`to_fixed` per unit). Each term is rounded before summing, so integer addition
// makes the sum independent of the order and thus of the thread count: the result is
// bit-identical on every machine.
Result<std::vector<std::int64_t>> fixed_point_weighted_sums(const EdgeGraph& graph, const Component& comp,
                                                            const std::vector<std::uint32_t>& local_of,
                                                            const std::vector<std::uint32_t>& sources,
                                                            const std::vector<double>& weight, double to_fixed,
                                                            unsigned threads, const CancelToken& cancel) {
  const std::size_t n = comp.vertices.size();
  auto nothing = [](std::uint32_t, std::uint32_t) {};
  // hardware_concurrency reads /sys on every call: only when asked for, not once per part.
  const std::size_t wanted = threads != 0 ? threads : std::max(1u, std::thread::hardware_concurrency());
  const std::size_t num_threads = std::clamp<std::size_t>(std::min(wanted, n * sources.size() / kMinSettlesPerThread), 1,
                                                          sources.size());
  std::vector<std::vector<std::int64_t>> partial(num_threads);
  std::vector<Status> status(num_threads, Ok{});
  auto work = [&](std::size_t t) {
    std::vector<std::int64_t>& acc = partial[t];
    acc.assign(n, 0);
    std::vector<double> distance(n, kInf);
    IndexedHeap heap(distance, n);
    for (std::size_t i = t; i < sources.size(); i += num_threads) {
      std::fill(distance.begin(), distance.end(), kInf);
      auto st = relax_from(graph, comp, local_of, sources[i], distance, heap, cancel, nothing);
      if (!st.ok()) {
        status[t] = std::move(st);
        return;
      }
      const double scale = weight[i] * to_fixed;
      // Terms are >= 0, so adding 0.5 and truncating rounds like llround without a libm call.
      for (std::size_t j = 0; j < n; ++j) acc[j] += static_cast<std::int64_t>(distance[j] * scale + 0.5);
    }
  };
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < num_threads; ++t) pool.emplace_back(work, t);
  work(0);
  for (auto& thread : pool) thread.join();
  for (auto& st : status) {
    if (!st.ok()) return st.take_error();
  }
  for (std::size_t t = 1; t < num_threads; ++t) {
    for (std::size_t j = 0; j < n; ++j) partial[0][j] += partial[t][j];
  }
  return std::move(partial[0]);
}

// The AGD estimate on one component, divided by sqrt(area), indexed like comp.vertices.
// Farthest-point sampling starts from the vertex farthest from the component's lowest id (an
// end of an approximate diameter), so the start depends on the numbering only through the
// ties of a symmetric shape.
Result<std::vector<double>> component_field(const EdgeGraph& graph, const Component& comp,
                                            const std::vector<std::uint32_t>& local_of, const std::vector<double>& area,
                                            std::size_t samples, unsigned threads, std::size_t& samples_used,
                                            const CancelToken& cancel) {
  const std::size_t n = comp.vertices.size();
  const std::size_t k_max = std::min(samples, n);

  // 1. Farthest-point sampling.
  SEAM_TRY(const FarthestSamples sampled, farthest_point_samples(graph, comp, local_of, k_max, cancel));
  const std::vector<std::uint32_t>& sources = sampled.sources;
  samples_used = sources.size();

  // 2. Geodesic Voronoi cell areas make the sum a quadrature of the area integral, not an
  // average over sources that farthest-point sampling places preferentially at tips.
  std::vector<double> weight(sources.size(), 0.0);
  for (std::size_t j = 0; j < n; ++j) weight[sampled.nearest_sample[j]] += area[comp.vertices[j]] / comp.area;

  // 3. One full Dijkstra per source, in parallel, summed in fixed point.
  const double to_fixed = sampled.bound > 0 ? std::ldexp(1.0, 52) / sampled.bound : 0.0;
  SEAM_TRY(const std::vector<std::int64_t> sums,
           fixed_point_weighted_sums(graph, comp, local_of, sources, weight, to_fixed, threads, cancel));
  const double from_fixed = to_fixed > 0 ? 1.0 / (to_fixed * std::sqrt(comp.area)) : 0.0;
  std::vector<double> f(n);
  for (std::size_t j = 0; j < n; ++j) f[j] = static_cast<double>(sums[j]) * from_fixed;
  return f;
}

struct Peak {
  std::uint32_t local = 0;
  std::uint32_t saddle = VertexId::kInvalidValue;  // local index, or invalid
  double prominence = 0;
};

// Merge tree of the superlevel sets of f on the component's edge graph (0-dimensional
// persistence): every local maximum with its prominence and saddle.
std::vector<Peak> persistent_maxima(const EdgeGraph& graph, const Component& comp, const std::vector<double>& f,
                                    const std::vector<std::uint32_t>& local_of) {
  const std::size_t n = comp.vertices.size();
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  // Descending f; equal values by ascending id, which makes a plateau a strict order and the
  // result deterministic.
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return f[a] != f[b] ? f[a] > f[b] : a < b;
  });
  std::vector<std::uint32_t> rank(n);
  for (std::size_t r = 0; r < n; ++r) rank[order[r]] = static_cast<std::uint32_t>(r);

  constexpr std::uint32_t kUnset = VertexId::kInvalidValue;
  std::vector<std::uint32_t> parent(n, kUnset);
  std::vector<std::uint32_t> peak(n, kUnset);  // per root: its highest vertex
  auto find = [&](std::uint32_t x) {
    std::uint32_t root = x;
    while (parent[root] != root) root = parent[root];
    while (parent[x] != root) x = std::exchange(parent[x], root);
    return root;
  };

  std::vector<Peak> peaks;
  std::vector<std::uint32_t> roots;
  for (std::uint32_t v : order) {
    roots.clear();
    const std::uint32_t gv = comp.vertices[v];
    for (std::uint32_t slot = graph.offsets[gv]; slot < graph.offsets[gv + 1]; ++slot) {
      const std::uint32_t u = local_of[graph.head[slot].index()];
      if (rank[u] > rank[v]) continue;  // not yet in the superlevel set
      const std::uint32_t r = find(u);
      if (std::find(roots.begin(), roots.end(), r) == roots.end()) roots.push_back(r);
    }
    if (roots.empty()) {  // a local maximum is born
      parent[v] = v;
      peak[v] = v;
      continue;
    }
    std::uint32_t best = roots[0];
    for (std::uint32_t r : roots) {
      if (rank[peak[r]] < rank[peak[best]]) best = r;
    }
    parent[v] = best;
    for (std::uint32_t r : roots) {
      if (r == best) continue;
      // The lower maximum dies here: v is its saddle.
      peaks.push_back({peak[r], v, f[peak[r]] - f[v]});
      parent[r] = best;
    }
  }
  const std::uint32_t top = order.front();
  peaks.push_back({top, kUnset, f[top] - f[order.back()]});
  return peaks;
}

// Multi-resolution (the paper's §6: find the big protrusions at low resolution). Components
// of at least 2 * kCoarseCellsMin vertices run the sampling, the AGD and the merge tree on a
// graph of Voronoi cells of ~n / kVerticesPerCell seeds (at least kCoarseCellsMin),
// which costs a breadth-first pass and a quarter Dijkstra pass on the mesh plus samples + 4
// passes on a graph 32 times smaller, instead of samples + 4 passes on the mesh. A cell is at
// most a few edges across, ~0.006 sqrt(area) at the minimum count, an order of magnitude
// below the default threshold; tips and saddles are reported at the cells' seed vertices.
constexpr std::size_t kCoarseCellsMin = 8000;
constexpr std::size_t kVerticesPerCell = 32;

struct CoarseLevel {
  EdgeGraph graph;                      // over cells; head holds cell indices
  Component cells;                      // vertices 0..M-1 (identity), area of the component
  std::vector<double> cell_area;        // per cell
  std::vector<std::uint32_t> identity;  // the local_of of the cell graph
  std::vector<std::uint32_t> seed;      // per cell: its seed, a local vertex of the component
  std::vector<std::uint32_t> cell_of;   // per local vertex: its cell
};

// SplitMix64 finaliser: a fixed hash of the vertex id, so seeds do not depend on position
// (rigid motion and scale leave them unchanged) and are spread like a random sample.
std::uint64_t mix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

// Each vertex is a seed with probability proportional to its area, so cells have about
// equal area on any tessellation; local vertex 0 when no vertex is drawn.
std::vector<std::uint32_t> area_weighted_seeds(const Component& comp, const std::vector<double>& area) {
  const std::size_t n = comp.vertices.size();
  const double target = static_cast<double>(std::max(n / kVerticesPerCell, kCoarseCellsMin));
  std::vector<std::uint32_t> seed;
  for (std::size_t j = 0; j < n; ++j) {
    const double u = static_cast<double>(mix(comp.vertices[j]) >> 11) * 0x1.0p-53;
    if (u < area[comp.vertices[j]] * target / comp.area) seed.push_back(static_cast<std::uint32_t>(j));
  }
  if (seed.empty()) seed.push_back(0);
  return seed;
}

struct GrownCells {
  std::vector<std::uint32_t> cell_of;  // per local vertex: its cell
  std::vector<double> distance;        // per local vertex: length of its path from its seed
};

// Cells grow breadth-first from all seeds at once, each vertex joining the cell that
// reaches it in the fewest edges; `distance` is the length of that path. A cell is a few
// edges across, so hops are as good as geodesics here, and a FIFO queue is several times
// faster than a Dijkstra heap holding every seed's front at once.
Result<GrownCells> grow_cells(const EdgeGraph& graph, const Component& comp, const std::vector<std::uint32_t>& local_of,
                              const std::vector<std::uint32_t>& seed, const CancelToken& cancel) {
  const std::size_t n = comp.vertices.size();
  const std::size_t m = seed.size();
  GrownCells cells;
  std::vector<double>& distance = cells.distance;
  distance.assign(n, kInf);
  cells.cell_of.assign(n, kNone);
  std::vector<std::uint32_t> queue(seed.begin(), seed.end());
  queue.reserve(n);
  for (std::size_t c = 0; c < m; ++c) {
    cells.cell_of[seed[c]] = static_cast<std::uint32_t>(c);
    distance[seed[c]] = 0.0;
  }
  std::uint32_t polls = 0;
  for (std::size_t head = 0; head < queue.size(); ++head) {
    if (cancel.poll(polls)) return cancelled_error("extrema detection");
    const std::uint32_t v = queue[head];
    const std::uint32_t gv = comp.vertices[v];
    for (std::uint32_t slot = graph.offsets[gv]; slot < graph.offsets[gv + 1]; ++slot) {
      const std::uint32_t w = local_of[graph.head[slot].index()];
      if (cells.cell_of[w] != kNone) continue;
      cells.cell_of[w] = cells.cell_of[v];
      distance[w] = distance[v] + graph.weight[slot];
      queue.push_back(w);
    }
  }
  return cells;
}

// The graph of `m` cells: two cells are adjacent where a mesh edge crosses between them; the
// edge's weight is the shortest seed-to-seed path through such an edge.
EdgeGraph cell_graph(const EdgeGraph& graph, const Component& comp, const std::vector<std::uint32_t>& local_of,
                     const GrownCells& cells, std::size_t m) {
  const std::size_t n = comp.vertices.size();
  struct Link {
    std::uint32_t a, b;
    double weight;
  };
  std::vector<Link> links;
  for (std::size_t j = 0; j < n; ++j) {
    const std::uint32_t gv = comp.vertices[j];
    const std::uint32_t cj = cells.cell_of[j];
    for (std::uint32_t slot = graph.offsets[gv]; slot < graph.offsets[gv + 1]; ++slot) {
      const std::uint32_t w = local_of[graph.head[slot].index()];
      const std::uint32_t cw = cells.cell_of[w];
      if (cj < cw) links.push_back({cj, cw, cells.distance[j] + graph.weight[slot] + cells.distance[w]});
    }
  }
  std::sort(links.begin(), links.end(), [](const Link& x, const Link& y) {
    return x.a != y.a ? x.a < y.a : x.b != y.b ? x.b < y.b : x.weight < y.weight;
  });
  links.erase(std::unique(links.begin(), links.end(), [](const Link& x, const Link& y) { return x.a == y.a && x.b == y.b; }),
              links.end());
  EdgeGraph cg;
  cg.offsets.assign(m + 1, 0);
  for (const Link& l : links) ++cg.offsets[l.a + 1], ++cg.offsets[l.b + 1];
  for (std::size_t c = 0; c < m; ++c) cg.offsets[c + 1] += cg.offsets[c];
  cg.head.resize(2 * links.size());
  cg.weight.resize(2 * links.size());
  std::vector<std::uint32_t> slot(cg.offsets.begin(), cg.offsets.end() - 1);
  for (const Link& l : links) {
    cg.head[slot[l.a]] = VertexId(l.b), cg.weight[slot[l.a]++] = l.weight;
    cg.head[slot[l.b]] = VertexId(l.a), cg.weight[slot[l.b]++] = l.weight;
  }
  return cg;
}

// Distances from the first seed to the seeds, summed over the seeds whose exact distance is
// final, exact (on the mesh, stopped after a quarter of the vertices) and on the cell graph.
struct SeedDistanceSums {
  double exact = 0;
  double coarse = 0;
};

Result<SeedDistanceSums> seed_distance_sums(const EdgeGraph& graph, const Component& comp,
                                            const std::vector<std::uint32_t>& local_of, const CoarseLevel& level,
                                            const CancelToken& cancel) {
  const std::size_t n = comp.vertices.size();
  const std::size_t m = level.seed.size();
  std::vector<double> exact(n, kInf), coarse(m, kInf);
  auto nothing = [](std::uint32_t, std::uint32_t) {};
  double settled_below = kInf;
  {
    IndexedHeap heap(exact, n);
    if (auto st = relax_from(graph, comp, local_of, level.seed[0], exact, heap, cancel, nothing, n / 4, &settled_below);
        !st.ok()) {
      return st.take_error();
    }
  }
  {
    IndexedHeap heap(coarse, m);
    if (auto st = relax_from(level.graph, level.cells, level.identity, 0u, coarse, heap, cancel, nothing); !st.ok()) {
      return st.take_error();
    }
  }
  SeedDistanceSums sums;
  for (std::size_t c = 0; c < m; ++c) {
    if (!(exact[level.seed[c]] < settled_below)) continue;  // not final
    sums.exact += exact[level.seed[c]];
    sums.coarse += coarse[c];
  }
  return sums;
}

Result<CoarseLevel> coarsen(const EdgeGraph& graph, const Component& comp, const std::vector<std::uint32_t>& local_of,
                            const std::vector<double>& area, const CancelToken& cancel) {
  const std::size_t n = comp.vertices.size();
  CoarseLevel level;
  level.seed = area_weighted_seeds(comp, area);
  const std::size_t m = level.seed.size();
  SEAM_TRY(GrownCells cells, grow_cells(graph, comp, local_of, level.seed, cancel));
  level.graph = cell_graph(graph, comp, local_of, cells, m);
  level.cell_of = std::move(cells.cell_of);

  level.identity.resize(m);
  std::iota(level.identity.begin(), level.identity.end(), 0u);
  level.cells.vertices = level.identity;

  // Paths through seeds zigzag, so cell-graph distances run a few percent long. An exact
  // pass on the mesh from the first seed, stopped after a quarter of the vertices, against
  // one on the cell graph gives the ratio; scaling every cell edge by it keeps prominences
  // on the scale of the exact path.
  if (m > 1) {
    SEAM_TRY(const SeedDistanceSums sums, seed_distance_sums(graph, comp, local_of, level, cancel));
    if (sums.coarse > 0 && sums.exact > 0) {
      for (double& w : level.graph.weight) w *= sums.exact / sums.coarse;
    }
  }
  level.cells.area = comp.area;
  level.cell_area.assign(m, 0.0);
  for (std::size_t j = 0; j < n; ++j) level.cell_area[level.cell_of[j]] += area[comp.vertices[j]];
  return level;
}

// The maxima of one component with their prominence, in the component's local indices; and,
// when `field` is given, f per local vertex (piecewise constant per cell on the coarse path).
Result<std::vector<Peak>> component_peaks(const EdgeGraph& graph, const Component& comp,
                                          const std::vector<std::uint32_t>& local_of,
                                          const std::vector<double>& area, std::size_t samples, unsigned threads,
                                          std::size_t& samples_used, std::vector<double>* field,
                                          const CancelToken& cancel) {
  if (comp.vertices.size() < 2 * kCoarseCellsMin) {
    SEAM_TRY(std::vector<double> f,
             component_field(graph, comp, local_of, area, samples, threads, samples_used, cancel));
    std::vector<Peak> peaks = persistent_maxima(graph, comp, f, local_of);
    if (field) *field = std::move(f);
    return peaks;
  }
  SEAM_TRY(const CoarseLevel coarse, coarsen(graph, comp, local_of, area, cancel));
  SEAM_TRY(const std::vector<double> f,
           component_field(coarse.graph, coarse.cells, coarse.identity, coarse.cell_area, samples, threads,
                           samples_used, cancel));
  std::vector<Peak> peaks = persistent_maxima(coarse.graph, coarse.cells, f, coarse.identity);
  for (Peak& p : peaks) {
    p.local = coarse.seed[p.local];
    if (p.saddle != kNone) p.saddle = coarse.seed[p.saddle];
  }
  if (field) {
    field->resize(comp.vertices.size());
    for (std::size_t j = 0; j < comp.vertices.size(); ++j) (*field)[j] = f[coarse.cell_of[j]];
  }
  return peaks;
}

Status validate(const ExtremaOptions& options) {
  if (!std::isfinite(options.min_protrusion) || options.min_protrusion < 0) {
    return make_error(ErrorCode::kInvalidArgument,
                      "extrema min_protrusion must be a finite number >= 0, got " +
                          std::to_string(options.min_protrusion));
  }
  for (const auto& [name, value] : {std::pair<const char*, double>{"min_separation", options.min_separation},
                                     {"small_part", options.small_part},
                                     {"small_part_protrusion", options.small_part_protrusion}}) {
    if (!std::isfinite(value) || value < 0) {
      return make_error(ErrorCode::kInvalidArgument,
                        std::string("extrema ") + name + " must be a finite number >= 0, got " + std::to_string(value));
    }
  }
  if (options.samples < 2) {
    return make_error(ErrorCode::kInvalidArgument,
                      "extrema samples must be >= 2, got " + std::to_string(options.samples));
  }
  return Ok{};
}

// The diagonal of the bounding box of `vertices`.
double bbox_diagonal(const HalfedgeMesh& mesh, std::span<const std::uint32_t> vertices) {
  if (vertices.empty()) return 0;
  Eigen::AlignedBox3d box;
  for (auto v : vertices) box.extend(mesh.position(VertexId(v)));
  return box.diagonal().norm();
}

// `peaks` (most prominent first) without those within `radius` (geodesic) of a kept one; at
// most `max_count` (0: no limit). One Dijkstra bounded by the radius per candidate, on the
// component's local numbering: arrays of the component's size, so a mesh of many small parts
// costs O(its size) in all, not O(parts x mesh).
Result<std::vector<Peak>> separated(const EdgeGraph& graph, const Component& comp,
                                    const std::vector<std::uint32_t>& local_of, std::vector<Peak> peaks, double radius,
                                    std::size_t max_count, const CancelToken& cancel) {
  std::vector<Peak> kept;
  if (peaks.empty()) return kept;
  const std::size_t n = comp.vertices.size();
  std::vector<std::uint8_t> is_kept(n, 0);
  std::vector<double> distance(n, kInf);
  std::vector<std::uint32_t> reached;
  IndexedHeap heap(distance, n);
  auto track = [&](std::uint32_t w, std::uint32_t) { reached.push_back(w); };  // to reset (repeats are harmless)
  for (const Peak& p : peaks) {
    if (max_count > 0 && kept.size() >= max_count) break;
    if (is_kept[p.local]) continue;  // never one vertex twice (coarse cells share seeds)
    bool near = false;
    if (radius > 0 && !kept.empty()) {
      for (std::uint32_t w : reached) distance[w] = kInf;  // the previous candidate's search
      reached.clear();
      while (!heap.empty()) detail::pop_min(heap);
      const std::uint32_t source[] = {p.local};
      if (auto st = relax_from(graph, comp, local_of, std::span<const std::uint32_t>(source), distance, heap, cancel,
                               track, std::numeric_limits<std::size_t>::max(), nullptr, radius);
          !st.ok()) {
        return st.take_error();
      }
      near = std::any_of(kept.begin(), kept.end(), [&](const Peak& k) { return distance[k.local] < radius; });
    }
    if (near) continue;
    is_kept[p.local] = 1;
    kept.push_back(p);
  }
  return kept;
}

}  // namespace

Result<ExtremaResult> detect_extrema(const HalfedgeMesh& mesh, const ExtremaOptions& options,
                                     const CancelToken& cancel) {
  const auto start = StageClock::now();
  const Topology topology = compute_topology(mesh);
  SEAM_TRY(ExtremaResult result, detect_extrema(mesh, topology, options, cancel));
  result.stats.milliseconds = ms_since(start);
  return result;
}

Result<ExtremaResult> detect_extrema(const HalfedgeMesh& mesh, const Topology& topo, const ExtremaOptions& options,
                                     const CancelToken& cancel) {
  const auto start = StageClock::now();
  if (auto st = validate(options); !st.ok()) return st.take_error();
  if (auto own = check_topology_of(mesh, topo); !own.ok()) return own.take_error();

  ExtremaResult result;
  const std::vector<double> area = vertex_areas(mesh);
  const std::vector<Component> components = collect_components(mesh, topo, area);
  const EdgeGraph graph = build_edge_graph(mesh);
  std::vector<std::uint32_t> local_of(mesh.num_vertices(), VertexId::kInvalidValue);
  std::vector<double> diagonals(components.size());
  for (std::size_t c = 0; c < components.size(); ++c) diagonals[c] = bbox_diagonal(mesh, components[c].vertices);
  const double largest_diagonal = diagonals.empty() ? 0 : *std::max_element(diagonals.begin(), diagonals.end());

  for (std::size_t c = 0; c < components.size(); ++c) {
    const Component& comp = components[c];
    if (comp.vertices.empty() || !(comp.area > 0)) continue;
    ++result.stats.components;
    for (std::size_t j = 0; j < comp.vertices.size(); ++j) local_of[comp.vertices[j]] = static_cast<std::uint32_t>(j);

    std::size_t used = 0;
    SEAM_TRY(std::vector<Peak> peaks, component_peaks(graph, comp, local_of, area, options.samples, options.threads,
                                                      used, nullptr, cancel));
    result.stats.samples += used;
    if (cancel.is_cancelled()) return cancelled_error("extrema detection");
    result.stats.local_maxima += peaks.size();
    const double diagonal = diagonals[c];
    // A small closed part whose most prominent tip is below small_part_protrusion has no real
    // protrusion: its "tips" are corners, and it is only cut to a disc.
    const bool small_part = topo.components[c].boundary_loops == 0 && diagonal < options.small_part * largest_diagonal;
    const bool protrudes = std::any_of(peaks.begin(), peaks.end(),
                                       [&](const Peak& p) { return p.prominence >= options.small_part_protrusion; });
    if (small_part && !protrudes) peaks.clear();
    std::erase_if(peaks, [&](const Peak& p) { return p.prominence < options.min_protrusion; });
    std::sort(peaks.begin(), peaks.end(), [](const Peak& a, const Peak& b) {
      return a.prominence != b.prominence ? a.prominence > b.prominence : a.local < b.local;
    });
    SEAM_TRY(peaks, separated(graph, comp, local_of, std::move(peaks), options.min_separation * diagonal,
                              options.max_count, cancel));
    for (const Peak& p : peaks) {
      Extremum e;
      e.vertex = VertexId(comp.vertices[p.local]);
      e.saddle = p.saddle == VertexId::kInvalidValue ? VertexId() : VertexId(comp.vertices[p.saddle]);
      e.prominence = p.prominence;
      e.component = static_cast<std::uint32_t>(c);
      result.extrema.push_back(e);
    }
  }
  result.stats.milliseconds = ms_since(start);
  return result;
}

Result<std::vector<VertexId>> find_extrema(const HalfedgeMesh& mesh, const ExtremaOptions& options,
                                           const CancelToken& cancel) {
  SEAM_TRY(ExtremaResult detected, detect_extrema(mesh, options, cancel));
  std::vector<VertexId> tips;
  tips.reserve(detected.extrema.size());
  for (const Extremum& e : detected.extrema) tips.push_back(e.vertex);
  return tips;
}

Result<VertexData<double>> average_geodesic_distance(const HalfedgeMesh& mesh, std::size_t samples,
                                                     const CancelToken& cancel) {
  ExtremaOptions options;
  options.samples = samples;
  if (auto st = validate(options); !st.ok()) return st.take_error();
  const Topology topo = compute_topology(mesh);
  const std::vector<double> area = vertex_areas(mesh);
  const std::vector<Component> components = collect_components(mesh, topo, area);
  const EdgeGraph graph = build_edge_graph(mesh);
  std::vector<std::uint32_t> local_of(mesh.num_vertices(), kNone);
  VertexData<double> field(mesh.num_vertices(), 0.0);
  for (const Component& comp : components) {
    if (comp.vertices.empty() || !(comp.area > 0)) continue;
    for (std::size_t j = 0; j < comp.vertices.size(); ++j) local_of[comp.vertices[j]] = static_cast<std::uint32_t>(j);
    std::size_t used = 0;
    std::vector<double> f;
    SEAM_TRY(const std::vector<Peak> peaks,
             component_peaks(graph, comp, local_of, area, samples, 0, used, &f, cancel));
    for (std::size_t j = 0; j < comp.vertices.size(); ++j) field[VertexId(comp.vertices[j])] = f[j];
  }
  return field;
}

}  // namespace seam::core
