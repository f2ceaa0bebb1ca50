// One seam request: parse -> select primitives -> read them -> run each primitive's job in
// parallel within the request's thread budget -> write the asset once -> the response.
#include "api/pipeline.h"

#include <algorithm>
#include <atomic>
#include <limits>
#include <new>
#include <optional>
#include <thread>

#include "api/base64.h"
#include "api/gltf_writer.h"
#include "api/pack_step.h"
#include "api/primitive_job.h"
#include "api/svg.h"
#include "core/timing.h"

namespace seam::api {
namespace {

using core::ms_since;
using nlohmann::json;

// One primitive to process and the extrema it uses.
struct Selected {
  std::uint32_t mesh = 0;
  std::uint32_t primitive = 0;
  const ExtremaSpec* extrema = nullptr;
};

ApiError invalid_selection(std::string message, json details = json::object()) {
  details["parameter"] = "primitives";
  return make_api_error(ApiErrorCode::kInvalidParameter, std::move(message), std::move(details));
}

const json& meshes_of(const GltfDocument& doc) {
  static const json kNone = json::array();
  const auto it = doc.json.find("meshes");
  return it != doc.json.end() && it->is_array() ? *it : kNone;
}

// A primitive the default selection takes: not points or lines (malformed modes and objects
// are taken, so read_primitive names the defect instead of the primitive vanishing).
bool is_surface(const json& prim) {
  if (!prim.is_object()) return true;
  const auto mode = prim.find("mode");
  return mode == prim.end() || !mode->is_number_unsigned() || mode->get<std::uint64_t>() > 3;
}

// Every surface primitive of mesh m (in asset order).
void add_mesh(const GltfDocument& doc, std::uint32_t m, const ExtremaSpec* extrema, std::vector<Selected>& out) {
  const json& mesh = meshes_of(doc)[m];
  if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) {
    out.push_back({m, 0, extrema});  // read_primitive reports the malformed mesh
    return;
  }
  const json& prims = mesh["primitives"];
  for (std::uint32_t p = 0; p < prims.size(); ++p) {
    if (is_surface(prims[p])) out.push_back({m, p, extrema});
  }
}

// Meshes named `name` (several meshes may share a name; all of them are meant).
std::vector<std::uint32_t> meshes_named(const GltfDocument& doc, const std::string& name) {
  std::vector<std::uint32_t> out;
  const json& meshes = meshes_of(doc);
  for (std::uint32_t m = 0; m < meshes.size(); ++m) {
    const json& mesh = meshes[m];
    if (mesh.is_object() && mesh.contains("name") && mesh["name"].is_string() && mesh["name"].get<std::string>() == name) {
      out.push_back(m);
    }
  }
  return out;
}

ApiResult<std::vector<Selected>> select_listed(const GltfDocument& doc, const SeamParams& params) {
  std::vector<Selected> out;
  for (const PrimitiveSelector& s : *params.primitives) {
    const ExtremaSpec* extrema = s.extrema ? &*s.extrema : &params.extrema;
    std::vector<std::uint32_t> meshes;
    if (s.mesh) {
      meshes.push_back(*s.mesh);
    } else {
      meshes = meshes_named(doc, s.mesh_name);
      if (meshes.empty()) {
        return invalid_selection("primitives: no mesh is named \"" + s.mesh_name.substr(0, 60) + "\"",
                                 {{"mesh", s.mesh_name.substr(0, 60)}});
      }
    }
    for (const std::uint32_t m : meshes) {
      if (s.primitive || m >= meshes_of(doc).size()) out.push_back({m, s.primitive.value_or(0), extrema});
      else add_mesh(doc, m, extrema, out);
    }
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> keys;
  for (const auto& s : out) keys.emplace_back(s.mesh, s.primitive);
  std::sort(keys.begin(), keys.end());
  const auto dup = std::adjacent_find(keys.begin(), keys.end());
  if (dup != keys.end()) {
    return invalid_selection("primitives: primitive " + std::to_string(dup->second) + " of mesh " +
                                 std::to_string(dup->first) + " is selected twice",
                             {{"mesh", dup->first}, {"primitive", dup->second}});
  }
  return out;
}

// API.md v2 "Whole assets": v1's mesh/primitive select one primitive; a list selects its
// entries; the default is every surface primitive of every mesh (a mesh used by several
// nodes is one mesh, so it is cut once).
ApiResult<std::vector<Selected>> select_primitives(const GltfDocument& doc, const SeamParams& params) {
  std::vector<Selected> out;
  if (params.mesh || params.primitive) {
    out.push_back({params.mesh.value_or(0), params.primitive.value_or(0), &params.extrema});
  } else if (params.primitives) {
    SEAM_TRY(out, select_listed(doc, params));
  } else {
    for (std::uint32_t m = 0; m < meshes_of(doc).size(); ++m) add_mesh(doc, m, &params.extrema, out);
    if (out.empty()) {
      return make_api_error(ApiErrorCode::kNoTrianglePrimitive,
                            "the asset has no triangle primitive (TRIANGLES, TRIANGLE_STRIP or TRIANGLE_FAN) to cut",
                            {{"meshes", meshes_of(doc).size()}});
    }
  }
  std::sort(out.begin(), out.end(), [](const Selected& a, const Selected& b) {
    return std::pair(a.mesh, a.primitive) < std::pair(b.mesh, b.primitive);
  });
  // Vertex indices and positions name vertices of one primitive: the request's top-level list
  // cannot serve several.
  const auto shared = std::count_if(out.begin(), out.end(), [&](const Selected& s) { return s.extrema == &params.extrema; });
  if (shared > 1 && params.extrema.names_vertices()) {
    return make_api_error(ApiErrorCode::kInvalidParameter,
                          "extrema names vertices, which belong to one primitive, but " + std::to_string(out.size()) +
                              " primitives are selected: give each its own list in primitives "
                              "([{\"mesh\": i, \"primitive\": j, \"extrema\": [...]}]) or select one with mesh/primitive",
                          {{"parameter", "extrema"}, {"primitives", out.size()}});
  }
  return out;
}

// The explicit extrema of the whole request (top level and every entry) against the limit,
// before the asset is parsed.
ApiResult<std::size_t> request_explicit_extrema(const SeamParams& params, std::size_t limit) {
  ExtremaSpec all = params.extrema;
  if (params.primitives) {
    for (const auto& s : *params.primitives) {
      if (!s.extrema) continue;
      all.indices.insert(all.indices.end(), s.extrema->indices.begin(), s.extrema->indices.end());
      all.positions.insert(all.positions.end(), s.extrema->positions.begin(), s.extrema->positions.end());
      if (all.indices.size() + all.positions.size() > limit) break;  // enough to refuse
    }
  }
  return explicit_extrema_count(all, limit);
}

// A primitive's error says which primitive when the request processes several.
ApiError at_primitive(ApiError error, const Selected& s, bool several) {
  if (!error.details.is_object()) error.details = json::object();
  error.details["mesh"] = s.mesh;
  error.details["primitive"] = s.primitive;
  if (several) {
    error.message = "mesh " + std::to_string(s.mesh) + " primitive " + std::to_string(s.primitive) + ": " + error.message;
  }
  return error;
}

// Reads the selected primitives. The face limit holds for the request as a whole: each read
// is bounded by it, and so is their sum.
ApiResult<std::vector<PrimitiveData>> read_selected(const GltfDocument& doc, const std::vector<Selected>& selected,
                                                    const ReadLimits& limits) {
  std::vector<PrimitiveData> out;
  out.reserve(selected.size());
  std::size_t faces = 0;
  for (const Selected& s : selected) {
    auto data = read_primitive(doc, s.mesh, s.primitive, limits);
    if (!data.ok()) return at_primitive(data.take_error(), s, selected.size() > 1);
    faces += data->mesh.triangles.size();
    if (faces > limits.max_faces) {
      return make_api_error(ApiErrorCode::kMeshTooLarge,
                            "the selected primitives have more than " + std::to_string(limits.max_faces) +
                                " triangles in all, the limit (select fewer with primitives)",
                            {{"limit", limits.max_faces}, {"primitives", selected.size()}});
    }
    out.push_back(std::move(data).value());
  }
  return out;
}

struct JobOutcomes {
  std::vector<std::optional<PrimitiveResult>> results;
  std::optional<ApiError> error;  ///< of the first failing primitive in asset order
};

// Runs every primitive's job: min(budget, jobs) workers take the largest remaining first,
// each with an equal share of the thread budget. After a failure, primitives after it in
// asset order are skipped (the error reported is the first in asset order either way).
JobOutcomes run_jobs(const std::vector<Selected>& selected, const std::vector<PrimitiveData>& data,
                     const SeamParams& params, const PipelineLimits& limits, const core::CancelToken& cancel) {
  const std::size_t n = selected.size();
  const unsigned budget = limits.threads != 0 ? limits.threads : std::max(1u, std::thread::hardware_concurrency());
  const unsigned workers = static_cast<unsigned>(std::min<std::size_t>(budget, n));
  std::vector<std::size_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return data[a].mesh.triangles.size() > data[b].mesh.triangles.size();
  });
  JobOutcomes out;
  out.results.resize(n);
  std::vector<std::optional<ApiError>> errors(n);
  std::atomic<std::size_t> next{0}, first_failed{n};
  PrimitiveJobOptions options{limits.max_extrema, std::max(1u, budget / std::max(1u, workers))};
  auto work = [&] {
    for (std::size_t k = next++; k < n; k = next++) {
      const std::size_t i = order[k];
      if (i > first_failed.load()) continue;
      auto r = process_primitive(data[i], *selected[i].extrema, params, options, cancel);
      if (r.ok()) {
        out.results[i] = std::move(r).value();
        continue;
      }
      errors[i] = at_primitive(r.take_error(), selected[i], n > 1);
      std::size_t seen = first_failed.load();
      while (i < seen && !first_failed.compare_exchange_weak(seen, i)) {
      }
    }
  };
  std::vector<std::thread> threads;
  for (unsigned w = 1; w < workers; ++w) threads.emplace_back(work);
  work();
  for (auto& t : threads) t.join();
  if (first_failed.load() < n) out.error = std::move(errors[first_failed.load()]);
  return out;
}

json mesh_name(const GltfDocument& doc, std::uint32_t m) {
  const json& mesh = meshes_of(doc)[m];
  return mesh.contains("name") && mesh["name"].is_string() ? mesh["name"] : json("");
}

// The atlas step (api/pack_step.h) over every processed primitive with new UVs.
ApiResult<std::vector<PackOutcome>> pack_step(const GltfDocument& doc, const std::vector<Selected>& selected,
                                              JobOutcomes& jobs, const SeamParams& params,
                                              const core::CancelToken& cancel) {
  std::vector<PackMember> members;
  for (std::size_t i = 0; i < selected.size(); ++i) {
    members.push_back({selected[i].mesh, selected[i].primitive, &*jobs.results[i]});
  }
  if (!params.uv) return std::vector<PackOutcome>(selected.size());
  return pack_uv_sets(doc, members, params.pack, cancel);
}

// output "svg": the new UV sets as a DCC's UV-layout export (api/svg.h).
ApiResult<std::string> uv_layout_svg(const GltfDocument& doc, const std::vector<Selected>& selected,
                                     const JobOutcomes& jobs) {
  std::vector<UvLayout> layouts;
  for (std::size_t i = 0; i < selected.size(); ++i) {
    const CutPrimitive& cut = jobs.results[i]->cut;
    if (cut.uv.empty()) continue;
    UvLayout layout;
    const json name = mesh_name(doc, selected[i].mesh);
    layout.name = "mesh " + std::to_string(selected[i].mesh) + " primitive " + std::to_string(selected[i].primitive) +
                  (name.get<std::string>().empty() ? "" : " (" + name.get<std::string>() + ")");
    for (const auto& p : cut.uv) layout.uv.push_back({p[0], 1.0 - p[1]});  // v up, as a UV editor shows it
    for (const auto& t : cut.triangles) layout.triangles.push_back({t[0], t[1], t[2]});
    layout.seam_edges = boundary_edges(layout.triangles);
    layouts.push_back(std::move(layout));
  }
  if (layouts.empty()) {
    return make_api_error(ApiErrorCode::kInvalidParameter, "output \"svg\" draws the new UV sets, but uv is \"none\"",
                          {{"parameter", "output"}});
  }
  return render_uv_svg(layouts);
}


// The 200 body: one entry per primitive; with exactly one, v1's top-level objects too.
json response_body(const GltfDocument& doc, const std::vector<Selected>& selected, std::vector<json> summaries,
                   const std::vector<bool>& draco, json timings) {
  json body = {{"primitives", json::array()}};
  for (std::size_t i = 0; i < selected.size(); ++i) {
    json entry = {{"mesh", selected[i].mesh}, {"primitive", selected[i].primitive}, {"name", mesh_name(doc, selected[i].mesh)}};
    for (auto& [key, value] : summaries[i].items()) entry[key] = std::move(value);  // moved: 10k reports are 90 MB
    entry["draco"] = static_cast<bool>(draco[i]);
    body["primitives"].push_back(std::move(entry));
  }
  body["draco"] = std::any_of(draco.begin(), draco.end(), [](bool d) { return d; });
  if (selected.size() == 1) {
    const json& only = body["primitives"][0];
    for (const char* key : {"seam", "repairs", "cut", "uv"}) body[key] = only[key];
    body["mesh"] = only["topology"];
    json merged = only["timings_ms"];
    merged.update(timings);
    timings = std::move(merged);
  }
  body["timings_ms"] = std::move(timings);
  return body;
}

ApiResult<PipelineOutput> run(const std::string& asset_bytes, AssetKind kind, const SeamParams& params,
                              const PipelineLimits& limits, const core::CancelToken& cancel) {
  const auto t_start = core::StageClock::now();
  json timings = json::object();
  auto t = core::StageClock::now();
  // Cost caps before any work on the mesh.
  if (auto count = request_explicit_extrema(params, limits.max_extrema); !count.ok()) return count.take_error();
  ReadLimits read_limits;
  read_limits.max_faces = limits.max_faces;
  SEAM_TRY(const GltfDocument doc, parse_asset(asset_bytes, kind, read_limits));
  SEAM_TRY(const std::vector<Selected> selected, select_primitives(doc, params));
  if (selected.size() > limits.max_primitives) {
    return make_api_error(ApiErrorCode::kMeshTooLarge,
                          "the request selects " + std::to_string(selected.size()) +
                              " triangle primitives, more than the limit of " + std::to_string(limits.max_primitives) +
                              " (--max-primitives; select fewer with primitives)",
                          {{"limit", limits.max_primitives}, {"primitives", selected.size()}});
  }
  SEAM_TRY(const std::vector<PrimitiveData> data, read_selected(doc, selected, read_limits));
  timings["parse"] = ms_since(t);
  if (cancel.is_cancelled()) {
    return make_api_error(ApiErrorCode::kTimeout, "the computation exceeded the time budget during parsing");
  }

  t = core::StageClock::now();
  JobOutcomes jobs = run_jobs(selected, data, params, limits, cancel);
  if (jobs.error) return std::move(*jobs.error);
  timings["primitives"] = ms_since(t);

  t = core::StageClock::now();
  SEAM_TRY(const std::vector<PackOutcome> packed, pack_step(doc, selected, jobs, params, cancel));
  timings["pack"] = ms_since(t);

  t = core::StageClock::now();
  std::vector<ReplacedPrimitive> replaced;
  std::vector<bool> draco;
  for (std::size_t i = 0; i < selected.size(); ++i) {
    ReplacedPrimitive r{selected[i].mesh, selected[i].primitive, &data[i], &jobs.results[i]->cut};
    r.draco = params.draco.value_or(data[i].draco);
    r.draco_options.keep = data[i].draco_quantization;  // a Draco input's grid, kept
    draco.push_back(r.draco);
    replaced.push_back(r);
  }
  SEAM_TRY(WrittenAsset written, write_cut_asset(doc, replaced));
  std::vector<json> summaries;
  for (std::size_t i = 0; i < selected.size(); ++i) {
    json& summary = jobs.results[i]->summary;
    if (summary["uv"].is_object()) {
      json& uv = summary["uv"];
      uv["channel"] = written.primitives[i].uv_channel;
      // Mirroring an untangled piece turns its flipped triangles right way round; the packing's
      // rounding may turn some over.
      const PackOutcome& p = packed[i];
      const std::size_t flipped = uv["flipped"].get<std::size_t>();
      uv["flipped"] = flipped - std::min(flipped, p.untangle.unflipped) + p.flipped;
      uv["overlap_area"] = packed[i].overlap_area;
      uv["coverage"] = packed[i].coverage;
      uv["pack_group"] = packed[i].group;
      uv["charts"] = packed[i].charts;
      if (params.pack.enabled) {
        uv["texel_density"] = p.texel_density;
        uv["texture_size"] = p.texture_size;
        uv["untangle"] = {{"charts", p.untangle.charts},
                          {"pieces_added", p.untangle.pieces_added},
                          {"pieces_mirrored", p.untangle.pieces_mirrored},
                          {"cut_length", p.untangle.cut_length}};
      }
      if (params.pack.enabled && params.pack.split) {
        uv["split"] = {{"charts_split", packed[i].charts_split}, {"cut_length", packed[i].split_cut_length}};
      }
      if (params.pack.enabled && (params.pack.split || p.untangle.charts > 0)) {
        summary["cut"]["asset_vertices"] = jobs.results[i]->cut.source_vertex.size();
      }
    }
    summaries.push_back(std::move(summary));
  }
  timings["encode"] = ms_since(t);
  timings["total"] = ms_since(t_start);

  PipelineOutput output;
  output.body = response_body(doc, selected, std::move(summaries), draco, std::move(timings));
  if (params.output == OutputFormat::kJson) output.body["asset"] = {{"glb_base64", encode_base64(written.glb)}};
  if (params.output == OutputFormat::kSvg) {
    SEAM_TRY(output.svg, uv_layout_svg(doc, selected, jobs));
  }
  output.glb = std::move(written.glb);
  output.total_ms = ms_since(t_start);
  return output;
}

}  // namespace

ApiResult<PipelineOutput> run_seam_pipeline(const std::string& asset_bytes, AssetKind kind, const SeamParams& params,
                                            const PipelineLimits& limits, const core::CancelToken& cancel) {
  try {
    return run(asset_bytes, kind, params, limits, cancel);
  } catch (const std::bad_alloc&) {
    return make_api_error(ApiErrorCode::kInternal, "out of memory while processing the asset");
  } catch (const std::exception& e) {
    return make_api_error(ApiErrorCode::kInternal, std::string("unexpected failure: ") + e.what());
  }
}

}  // namespace seam::api
