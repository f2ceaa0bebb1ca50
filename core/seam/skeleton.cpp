#include "core/seam/skeleton.h"

#include <exception>
#include <functional>
#include <optional>
#include <string>
#include <thread>

#include "core/seam/improve.h"
#include "core/seam/refine.h"
#include "core/seam/skeleton_trace.h"
#include "core/seam/straighten.h"
#include "core/timing.h"

namespace seam::core {

namespace {

Status validate_inputs(const HalfedgeMesh& mesh, const TerminalPaths& paths) {
  const std::size_t k = paths.size();
  if (k < 2) return make_error(ErrorCode::kInvalidArgument, "the skeleton seam needs at least two terminals");
  for (VertexId t : paths.terminals) {
    if (!t.valid() || t.index() >= mesh.num_vertices()) {
      return make_error(ErrorCode::kInvalidArgument, "terminal out of range", {t.value()});
    }
  }
  if (paths.mst.size() + 1 != k) {
    return make_error(ErrorCode::kInvalidArgument, "the terminals are not all connected (or paths are missing)");
  }
  return Ok{};
}

// Above this many vertices the moves run only after the refinement: on camel x64 (625k
// vertices, k = 6..32, seam_bench --size camel-large) the start on the straightened tree never
// won by more than 0.005% of the length (k = 6: 4.0423 against 4.0425) and cost 150-330 ms of a
// 1.5 s seam stage, since the moves' work budget (ImproveOptions::max_settled) binds there.
constexpr std::size_t kOneStartVertices = 300000;
// The nearest-terminal start reaches regions the tour of Algorithm 2 never encloses (bunny00
// farthest-point rows). Its search is capped at 2e6 expanded vertices, and it is skipped where
// k searches of half the mesh would exceed that, as they did before the tree's searches became
// one growing search (at 1.25M faces with 16 extrema they cost 2x the paper's whole seam
// stage). The rule stays: at that size the start's moves alone would spend their 1e6-vertex
// budget (~0.18 s of a ~1 s seam stage at 1.25M faces).
constexpr std::size_t kStartBudget = 2000000;

// A start's tree and its length.
struct StartTree {
  std::vector<EdgeId> edges;
  double length = 0.0;
};

using Improve = std::function<Result<ImproveResult>(std::span<const EdgeId>, double& ms)>;

// The main start: the refinement (refine.h), then the global moves (improve.h).
Result<StartTree> refine_then_improve(const SearchSurface& surface, std::span<const VertexId> terminals,
                                      std::vector<EdgeId> edges, const SkeletonOptions& options, SkeletonTrace& tr,
                                      SkeletonResult& result, const Improve& improve, const CancelToken& cancel) {
  StartTree out{std::move(edges), 0.0};
  if (options.refine) {
    const auto start = StageClock::now();
    SEAM_TRY(RefineResult refined, refine_tree(surface, terminals, out.edges, {}, cancel));
    out.edges = std::move(refined.edges);
    out.length = refined.stats.length_after;
    tr.refine_stats = refined.stats;
    result.stats.refine_ms = ms_since(start);
    tr.refined_length = tr.refine_stats.length_after;
  }
  if (options.improve) {
    SEAM_TRY(ImproveResult improved, improve(out.edges, result.stats.improve_ms));
    out.edges = std::move(improved.edges);
    out.length = improved.stats.length_after;
  }
  return out;
}

// The other starts, with both steps on: the moves on the straightened tree (up to
// kOneStartVertices) and on the nearest-terminal tree (within kStartBudget). Each reads only
// shared inputs and writes only its own outcome, so they may run beside the main start.
struct OtherStarts {
  std::optional<Result<ImproveResult>> straightened;
  std::optional<Result<ImproveResult>> nearest;
  double improve_ms = 0;  // their moves' time

  void run_straightened(const HalfedgeMesh& mesh, std::span<const EdgeId> edges, const Improve& improve) {
    if (mesh.num_vertices() <= kOneStartVertices) straightened = improve(edges, improve_ms);
  }
  void run_nearest(const SearchSurface& surface, std::span<const VertexId> terminals, const Improve& improve,
                   const CancelToken& cancel) {
    if (terminals.size() * surface.mesh().num_vertices() / 2 > kStartBudget) return;
    auto greedy = nearest_terminal_tree(surface, terminals, cancel, kStartBudget);
    if (!greedy.ok() && greedy.error().code == ErrorCode::kCancelled) {
      nearest = greedy.take_error();
    } else if (greedy.ok() && !greedy->empty()) {
      nearest = improve(*greedy, improve_ms);
    }
  }
  bool failed() const { return (straightened && !straightened->ok()) || (nearest && !nearest->ok()); }
};

// The steps after the tree exists. Three starts, the shortest kept: the moves on the
// straightened tree, the refinement followed by the moves, and the moves on the
// nearest-terminal tree. Neither of the first two wins everywhere (improving first led the
// refinement into a worse local optimum on dino, refining first did on bunny00;
// seam_quality_bench), and the second is never longer than the refinement alone. With
// options.threads >= 2 the other two run on a second thread beside the second; the starts do
// not depend on each other, so the result is the same, and so is the first error met.
Result<SkeletonResult> finish(const SearchSurface& surface, std::span<const VertexId> terminals,
                              std::vector<EdgeId> final_edges, const SkeletonOptions& options, SkeletonTrace& tr,
                              SkeletonResult& result, const CancelToken& cancel) {
  const Improve improve = [&](std::span<const EdgeId> edges, double& ms) -> Result<ImproveResult> {
    const auto start = StageClock::now();
    auto improved = improve_tree(surface, terminals, edges, {}, cancel);
    ms += ms_since(start);
    return improved;
  };
  const std::vector<EdgeId> straightened = final_edges;
  auto main_start = [&] {
    return refine_then_improve(surface, terminals, final_edges, options, tr, result, improve, cancel);
  };
  OtherStarts other;
  std::optional<Result<StartTree>> main;
  if (!(options.improve && options.refine)) {
    main = main_start();
  } else if (options.threads < 2) {
    other.run_straightened(surface.mesh(), straightened, improve);
    if (!other.failed()) main = main_start();
    if (!other.failed() && main->ok()) other.run_nearest(surface, terminals, improve, cancel);
  } else {
    std::exception_ptr failure;
    {
      const std::jthread beside([&] {
        try {
          other.run_straightened(surface.mesh(), straightened, improve);
          if (!other.failed()) other.run_nearest(surface, terminals, improve, cancel);
        } catch (...) {
          failure = std::current_exception();
        }
      });
      main = main_start();
    }  // joins `beside`
    if (failure) std::rethrow_exception(failure);
  }
  result.stats.improve_ms += other.improve_ms;
  // The first error in the order the starts run one after another.
  if (other.straightened && !other.straightened->ok()) return other.straightened->take_error();
  if (!main->ok()) return main->take_error();
  if (other.nearest && !other.nearest->ok()) return other.nearest->take_error();
  StartTree best = std::move(main->value());
  for (auto* start : {&other.straightened, &other.nearest}) {
    if (*start && (**start)->stats.length_after < best.length) {
      best = {std::move((**start)->edges), (**start)->stats.length_after};
    }
  }
  result.tree = make_steiner_tree(surface, best.edges, terminals);
  return std::move(result);
}

}  // namespace

Result<SkeletonResult> skeleton_seam_traced(const SearchSurface& surface, const TerminalPaths& paths,
                                            const SkeletonOptions& options, SkeletonTrace* trace,
                                            const CancelToken& cancel) {
  const HalfedgeMesh& mesh = surface.mesh();
  if (auto st = validate_inputs(mesh, paths); !st.ok()) return st.take_error();
  SkeletonTrace local;
  SkeletonTrace& tr = trace ? *trace : local;
  tr = SkeletonTrace{};
  SkeletonResult result;
  const auto& terminals = paths.terminals;

  if (paths.size() == 2) {
    // §4.1: with two terminals the seam is their shortest path.
    std::vector<EdgeId> edges;
    for (HalfedgeId h : paths.path_between(0, 1)) edges.push_back(HalfedgeMesh::edge(h));
    result.tree = make_steiner_tree(surface, edges, terminals);
    result.stats.length_before_refine = result.tree.length;
    tr.straightened_length = result.tree.length;
    return result;
  }

  // The paper's three steps. Any failure other than cancellation (a degenerate mesh where
  // the tour or its skeleton cannot be made a full component) falls back to the star tree.
  auto paper = [&]() -> Result<TreeTopology> {
    auto start = StageClock::now();
    SEAM_TRY(TourResult tour, build_tour(mesh, paths, cancel));
    tr.tour = std::move(tour.tour);
    tr.tour_stats = tour.stats;
    result.stats.tour_ms = ms_since(start);
    result.stats.removals = tr.tour_stats.removals;
    result.stats.rejected_removals = tr.tour_stats.rejected_removals;

    start = StageClock::now();
    SEAM_TRY(auto shrunk, shrink_tour(mesh, tr.tour, cancel));
    tr.raw_skeleton = std::move(shrunk.skeleton);
    result.stats.shrink_ms = ms_since(start);

    start = StageClock::now();
    SEAM_TRY(auto topo, skeleton_topology(surface, tr.raw_skeleton, terminals, cancel));
    SEAM_TRY(StraightenResult straight, straighten_topology(surface, topo, cancel));
    tr.straighten_stats = straight.stats;
    result.stats.straighten_ms = ms_since(start);
    if (auto st = check_full_component_tree(mesh, topology_edges(straight.topology), terminals); !st.ok()) {
      return st.take_error();
    }
    return std::move(straight.topology);
  };
  auto straight = options.paper_steps ? paper()
                                      : Result<TreeTopology>(make_error(ErrorCode::kInvalidArgument,
                                                                        "the paper's steps were switched off"));
  if (!straight.ok()) {
    if (straight.error().code == ErrorCode::kCancelled) return straight.take_error();
    tr.fallback = true;
    tr.fallback_reason = straight.error().message;
    result.stats.fallback = true;
    const auto start = StageClock::now();
    SEAM_TRY(auto edges, star_tree(surface, terminals, cancel));
    result.stats.straighten_ms += ms_since(start);
    tr.straightened_length = make_steiner_tree(surface, edges, terminals).length;
    result.stats.length_before_refine = tr.straightened_length;
    // The star is a full component too: the same refinement and global moves apply (without
    // them the fallback stayed up to 1.57x the optimum, elephant in seam_quality_bench).
    return finish(surface, terminals, std::move(edges), options, tr, result, cancel);
  }
  tr.straightened = *straight;
  tr.straightened_length = topology_length(surface, tr.straightened);
  result.stats.length_before_refine = tr.straightened_length;
  return finish(surface, terminals, topology_edges(*straight), options, tr, result, cancel);
}

Result<SkeletonResult> skeleton_seam(const SearchSurface& surface, const TerminalPaths& paths,
                                     const SkeletonOptions& options, const CancelToken& cancel) {
  return skeleton_seam_traced(surface, paths, options, nullptr, cancel);
}

}  // namespace seam::core
