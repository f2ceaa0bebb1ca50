#include "core/extrema.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <utility>

#include "core/geodesic.h"
#include "core/topology.h"

namespace seam::core {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Single-source Dijkstra with buffers reused across the many runs of one detection. We do not
// call core::dijkstra here: it allocates and clears five arrays of the whole mesh per run,
// which dominates on meshes with many small components, and we need neither parents nor
// targets. Only the vertices a run touched are reset afterwards.
class DistanceScratch {
 public:
  explicit DistanceScratch(std::size_t num_vertices) : distance_(num_vertices, kInf) {}

  // Distances from `source` to every vertex of its component; read them with distance().
  Status run(const EdgeGraph& graph, std::uint32_t source, const CancelToken& cancel) {
    for (std::uint32_t v : touched_) distance_[v] = kInf;
    touched_.clear();
    heap_.clear();
    distance_[source] = 0.0;
    touched_.push_back(source);
    heap_.emplace_back(0.0, source);
    std::uint32_t polls = 0;
    const auto later = std::greater<>();
    while (!heap_.empty()) {
      if (cancel.poll(polls)) return cancelled_error("extrema detection");
      std::pop_heap(heap_.begin(), heap_.end(), later);
      const auto [d, v] = heap_.back();
      heap_.pop_back();
      if (d > distance_[v]) continue;  // a stale entry: v was reached more cheaply since
      for (std::uint32_t slot = graph.offsets[v]; slot < graph.offsets[v + 1]; ++slot) {
        const std::uint32_t w = graph.head[slot].value();
        const double nd = d + graph.weight[slot];
        if (nd < distance_[w]) {
          if (distance_[w] == kInf) touched_.push_back(w);
          distance_[w] = nd;
          heap_.emplace_back(nd, w);
          std::push_heap(heap_.begin(), heap_.end(), later);
        }
      }
    }
    return Ok{};
  }

  double distance(std::uint32_t v) const { return distance_[v]; }

 private:
  std::vector<double> distance_;
  std::vector<std::uint32_t> touched_;
  std::vector<std::pair<double, std::uint32_t>> heap_;
};

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

struct Component {
  std::vector<std::uint32_t> vertices;  // ascending vertex ids; local index = position here
  double area = 0;
};

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

// The AGD estimate on one component, divided by sqrt(area), indexed like comp.vertices.
// Farthest-point sampling starts from the vertex farthest from the component's lowest id, an
// end of an approximate diameter, so the first source does not depend on the numbering more
// than the ties of a symmetric shape do.
Result<std::vector<double>> component_field(const EdgeGraph& graph, const Component& comp,
                                            const std::vector<double>& area, std::size_t samples,
                                            DistanceScratch& scratch, std::size_t& samples_used,
                                            const CancelToken& cancel) {
  const std::size_t n = comp.vertices.size();
  const std::size_t k_max = std::min(samples, n);
  auto farthest = [&](const std::vector<double>& value) {
    std::size_t best = 0;
    for (std::size_t j = 1; j < n; ++j) {
      if (value[j] > value[best]) best = j;
    }
    return best;
  };

  std::vector<double> nearest_distance(n, kInf);
  std::vector<std::uint32_t> nearest_sample(n, 0);
  // Distances from every source, kept as floats (half the memory; 7 digits are plenty for a
  // sum that is thresholded at a few percent of sqrt(area)).
  std::vector<float> distances;
  distances.reserve(k_max * n);

  if (auto st = scratch.run(graph, comp.vertices[0], cancel); !st.ok()) return st.take_error();
  {
    std::vector<double> from_first(n);
    for (std::size_t j = 0; j < n; ++j) from_first[j] = scratch.distance(comp.vertices[j]);
    std::size_t source = farthest(from_first);
    std::size_t k = 0;
    while (k < k_max) {
      if (cancel.is_cancelled()) return cancelled_error("extrema detection");
      if (auto st = scratch.run(graph, comp.vertices[source], cancel); !st.ok()) return st.take_error();
      for (std::size_t j = 0; j < n; ++j) {
        const double d = scratch.distance(comp.vertices[j]);
        SEAM_ASSERT(d != kInf);  // a component is connected through its edges
        distances.push_back(static_cast<float>(d));
        if (d < nearest_distance[j]) {
          nearest_distance[j] = d;
          nearest_sample[j] = static_cast<std::uint32_t>(k);
        }
      }
      ++k;
      source = farthest(nearest_distance);
      if (nearest_distance[source] == 0.0) break;  // every vertex is a source already
    }
    samples_used = k;
  }

  // Geodesic Voronoi cell areas make the sum a quadrature of the area integral instead of
  // an average over sources that farthest-point sampling places preferentially at tips.
  std::vector<double> weight(samples_used, 0.0);
  for (std::size_t j = 0; j < n; ++j) weight[nearest_sample[j]] += area[comp.vertices[j]];
  const double scale = 1.0 / (comp.area * std::sqrt(comp.area));
  std::vector<double> f(n, 0.0);
  for (std::size_t i = 0; i < samples_used; ++i) {
    const double w = weight[i] * scale;
    const float* row = distances.data() + i * n;
    for (std::size_t j = 0; j < n; ++j) f[j] += w * static_cast<double>(row[j]);
  }
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

Status validate(const ExtremaOptions& options) {
  if (!std::isfinite(options.min_protrusion) || options.min_protrusion < 0) {
    return make_error(ErrorCode::kInvalidArgument,
                      "extrema min_protrusion must be a finite number >= 0, got " +
                          std::to_string(options.min_protrusion));
  }
  if (options.samples < 2) {
    return make_error(ErrorCode::kInvalidArgument,
                      "extrema samples must be >= 2, got " + std::to_string(options.samples));
  }
  return Ok{};
}

}  // namespace

Result<ExtremaResult> detect_extrema(const HalfedgeMesh& mesh, const ExtremaOptions& options,
                                     const CancelToken& cancel) {
  const auto start = std::chrono::steady_clock::now();
  if (auto st = validate(options); !st.ok()) return st.take_error();

  ExtremaResult result;
  const Topology topo = compute_topology(mesh);
  const std::vector<double> area = vertex_areas(mesh);
  const std::vector<Component> components = collect_components(mesh, topo, area);
  const EdgeGraph graph = build_edge_graph(mesh);
  std::vector<std::uint32_t> local_of(mesh.num_vertices(), VertexId::kInvalidValue);
  DistanceScratch scratch(mesh.num_vertices());

  for (std::size_t c = 0; c < components.size(); ++c) {
    const Component& comp = components[c];
    if (comp.vertices.empty() || !(comp.area > 0)) continue;
    ++result.stats.components;
    for (std::size_t j = 0; j < comp.vertices.size(); ++j) local_of[comp.vertices[j]] = static_cast<std::uint32_t>(j);

    std::size_t used = 0;
    SEAM_TRY(const std::vector<double> f,
             component_field(graph, comp, area, options.samples, scratch, used, cancel));
    result.stats.samples += used;
    if (cancel.is_cancelled()) return cancelled_error("extrema detection");

    std::vector<Peak> peaks = persistent_maxima(graph, comp, f, local_of);
    result.stats.local_maxima += peaks.size();
    std::erase_if(peaks, [&](const Peak& p) { return p.prominence < options.min_protrusion; });
    std::sort(peaks.begin(), peaks.end(), [](const Peak& a, const Peak& b) {
      return a.prominence != b.prominence ? a.prominence > b.prominence : a.local < b.local;
    });
    if (options.max_count > 0 && peaks.size() > options.max_count) peaks.resize(options.max_count);
    for (const Peak& p : peaks) {
      Extremum e;
      e.vertex = VertexId(comp.vertices[p.local]);
      e.saddle = p.saddle == VertexId::kInvalidValue ? VertexId() : VertexId(comp.vertices[p.saddle]);
      e.prominence = p.prominence;
      e.component = static_cast<std::uint32_t>(c);
      result.extrema.push_back(e);
    }
  }
  result.stats.milliseconds =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
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
  DistanceScratch scratch(mesh.num_vertices());
  VertexData<double> field(mesh.num_vertices(), 0.0);
  for (const Component& comp : components) {
    if (comp.vertices.empty() || !(comp.area > 0)) continue;
    std::size_t used = 0;
    SEAM_TRY(const std::vector<double> f, component_field(graph, comp, area, samples, scratch, used, cancel));
    for (std::size_t j = 0; j < comp.vertices.size(); ++j) field[VertexId(comp.vertices[j])] = f[j];
  }
  return field;
}

}  // namespace seam::core
