// libFuzzer target for the asset loader: parse_asset (GLB, glTF JSON, raw Draco) and
// read_primitive on every primitive, then the cut-asset writer with an identity "cut" on every
// readable primitive at once. Any crash, sanitizer report, leak or uncaught exception is a bug: bad
// input must come back as an ApiError.
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <utility>
#include <vector>

#include "api/gltf_reader.h"
#include "api/gltf_writer.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace seam::api;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  ReadLimits limits;
  limits.max_faces = 1u << 20;
  limits.max_vertices = 1u << 22;
  auto doc = parse_asset(bytes, AssetKind::kAuto, limits);
  if (!doc.ok()) return 0;
  const auto meshes = doc->json.find("meshes");
  if (meshes == doc->json.end() || !meshes->is_array()) return 0;
  // Every readable primitive (of the first four meshes, four each) replaced at once by an
  // identity "cut", so the writer's compaction of what they leave unused is fuzzed too.
  std::vector<PrimitiveData> prims;
  std::vector<CutPrimitive> cuts;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> where;
  for (std::uint32_t m = 0; m < meshes->size() && m < 4; ++m) {
    const auto& mesh = (*meshes)[m];
    if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
    for (std::uint32_t p = 0; p < mesh["primitives"].size() && p < 4; ++p) {
      auto prim = read_primitive(*doc, m, p, limits);
      if (!prim.ok()) continue;
      CutPrimitive cut;
      cut.source_vertex.resize(prim->mesh.positions.size());
      for (std::uint32_t v = 0; v < cut.source_vertex.size(); ++v) cut.source_vertex[v] = v;
      cut.triangles = prim->mesh.triangles;
      cut.uv.assign(cut.source_vertex.size(), {0.5f, 0.5f});
      prims.push_back(std::move(prim).value());
      cuts.push_back(std::move(cut));
      where.emplace_back(m, p);
    }
  }
  if (prims.empty()) return 0;
  std::vector<ReplacedPrimitive> replaced;
  for (std::size_t i = 0; i < prims.size(); ++i) replaced.push_back({where[i].first, where[i].second, &prims[i], &cuts[i]});
  auto out = write_cut_asset(*doc, replaced);
  if (out.ok()) {
    // What we write must read back, every replaced primitive included.
    auto again = parse_asset(out->glb, AssetKind::kGlb, limits);
    if (!again.ok()) __builtin_trap();
    for (const auto& [m, p] : where) {
      if (!read_primitive(*again, m, p, limits).ok()) __builtin_trap();
    }
  }
  return 0;
}
