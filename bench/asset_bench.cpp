// Whole assets (issue 11): the 6-primitive, ~100k-face asset of the test set cut in one
// request (default parameters: every primitive, run in parallel within the thread budget)
// against the sum of its primitives cut one request each, as a client had to before v2.
// Paired runs (whole, then each primitive alone with v1's {"mesh": i, "primitive": j}), medians; the target is whole/sum <= 0.7 on
// 2 threads. Then one whole-asset run per asset of the set, for the per-asset table.
//
//   asset_bench [PAIRS=5] [THREADS=2]
//
// The assets are built by scripts/fetch-test-data.sh (tests/assets/build_assets.mjs) into
// .cache/assets; the benchmark exits with that hint when they are missing.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/gltf_reader.h"
#include "api/pipeline.h"
#include "bench_util.h"

namespace {

using namespace seam;
using nlohmann::json;

std::filesystem::path assets_dir() { return std::filesystem::path(SEAM_TEST_DATA_DIR).parent_path() / "assets"; }

std::string read_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    std::fprintf(stderr, "cannot read %s: run scripts/fetch-test-data.sh (after npm install --prefix tests)\n",
                 path.string().c_str());
    std::exit(1);
  }
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// Milliseconds of one run_seam_pipeline call with `params`; exits on failure (a benchmark
/// of a failing request measures nothing).
double run_ms(const std::string& asset, const json& params, unsigned threads, json* body = nullptr) {
  auto p = api::params_from_json(params);
  if (!p.ok()) {
    std::fprintf(stderr, "bad parameters %s: %s\n", params.dump().c_str(), p.error().message.c_str());
    std::exit(1);
  }
  api::PipelineLimits limits;
  limits.threads = threads;
  const auto t0 = std::chrono::steady_clock::now();
  auto out = api::run_seam_pipeline(asset, api::AssetKind::kAuto, *p, limits, core::CancelToken::none());
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (!out.ok()) {
    std::fprintf(stderr, "request %s failed: %s\n", params.dump().c_str(), out.error().message.c_str());
    std::exit(1);
  }
  if (body) *body = std::move(out->body);
  return ms;
}

/// The triangle primitives (mesh, primitive) of an asset, in asset order.
std::vector<std::pair<int, int>> triangle_primitives(const std::string& asset) {
  auto doc = api::parse_asset(asset, api::AssetKind::kAuto);
  if (!doc.ok()) {
    std::fprintf(stderr, "cannot parse the asset: %s\n", doc.error().message.c_str());
    std::exit(1);
  }
  std::vector<std::pair<int, int>> out;
  for (std::size_t m = 0; m < doc->json["meshes"].size(); ++m) {
    const json& prims = doc->json["meshes"][m]["primitives"];
    for (std::size_t p = 0; p < prims.size(); ++p) {
      const int mode = prims[p].value("mode", 4);
      if (mode == 4 || mode == 5 || mode == 6) out.emplace_back(static_cast<int>(m), static_cast<int>(p));
    }
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  seam::bench::run_as_deployed(argv);
  const int pairs = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
  const unsigned threads = argc > 2 ? static_cast<unsigned>(std::max(1, std::atoi(argv[2]))) : 2;
  const json manifest = json::parse(read_bytes(assets_dir() / "manifest.json"));

  // 1. The 6-primitive asset whole against its primitives one by one.
  const std::string bench6 = read_bytes(assets_dir() / "bench6.glb");
  const auto prims = triangle_primitives(bench6);
  std::printf("bench6.glb: %zu triangle primitives, %zu bytes, threads %u, %d paired runs\n", prims.size(),
              bench6.size(), threads, pairs);
  std::vector<double> whole, sum, ratio;
  std::vector<std::vector<double>> each(prims.size());
  std::vector<json> alone_body(prims.size());
  json whole_body;
  for (int r = 0; r < pairs; ++r) {
    const double w = run_ms(bench6, json::object(), threads, &whole_body);
    if (whole_body.value("primitives", json::array()).size() != prims.size()) {
      std::fprintf(stderr, "the default request did not cut every primitive (%zu of %zu listed): no whole-asset figure\n",
                   whole_body.value("primitives", json::array()).size(), prims.size());
      return 1;
    }
    double s = 0;
    for (std::size_t i = 0; i < prims.size(); ++i) {
      // v1's selection: exactly this primitive, the rest of the asset carried through.
      const json one = {{"mesh", prims[i].first}, {"primitive", prims[i].second}};
      const double ms = run_ms(bench6, one, threads, &alone_body[i]);
      each[i].push_back(ms);
      s += ms;
    }
    whole.push_back(w);
    sum.push_back(s);
    ratio.push_back(w / s);
    std::printf("  pair %d: whole %8.1f ms, one by one %8.1f ms, ratio %.3f\n", r + 1, w, s, w / s);
  }
  // Where the time goes: each primitive's stages alone (the whole budget) and in the whole
  // request (a share of it, beside the others), from the last pair.
  std::printf("\n%-6s %-9s %-16s %8s %10s %14s %14s\n", "mesh", "primitive", "name", "faces", "alone ms",
              "uv alone/whole", "seam alone/whole");
  const json& entries = whole_body["primitives"];
  for (std::size_t i = 0; i < prims.size(); ++i) {
    std::string name;
    long faces = 0;
    for (const auto& e : entries) {
      if (e["mesh"] == prims[i].first && e["primitive"] == prims[i].second) {
        name = e.value("name", "");
        faces = e["topology"]["faces"].get<long>();
      }
    }
    auto stage = [](const json& body, int m, int p, const char* key) {
      for (const auto& e : body.value("primitives", json::array())) {
        if (e["mesh"] == m && e["primitive"] == p) return e["timings_ms"].value(key, 0.0);
      }
      return 0.0;
    };
    const auto [m, p] = prims[i];
    std::printf("%-6d %-9d %-16s %8ld %10.1f %6.0f/%-7.0f %6.0f/%-7.0f\n", m, p, name.c_str(), faces, median(each[i]),
                stage(alone_body[i], m, p, "uv"), stage(whole_body, m, p, "uv"), stage(alone_body[i], m, p, "seam"),
                stage(whole_body, m, p, "seam"));
  }
  const double r = median(ratio);
  std::printf("whole request's stages: %s\n", whole_body["timings_ms"].dump().c_str());
  std::printf("\nwhole asset (median)            %10.1f ms\n", median(whole));
  std::printf("sum of primitives alone (median) %9.1f ms\n", median(sum));
  std::printf("ratio whole / sum (median of pairs) %.3f  target <= 0.70  %s\n\n", r, r <= 0.7 ? "met" : "NOT met");

  // 2. Every asset of the set, whole, default parameters.
  std::printf("%-22s %8s %6s %10s %10s %10s\n", "asset", "faces", "prims", "bytes in", "bytes out", "ms");
  for (const auto& a : manifest["assets"]) {
    const std::string file = a["file"].get<std::string>();
    const std::string asset = read_bytes(assets_dir() / file);
    auto p = api::params_from_json(json::object());
    api::PipelineLimits limits;
    limits.threads = threads;
    std::vector<double> times;
    std::size_t out_bytes = 0, entry_count = 0;
    for (int k = 0; k < 3; ++k) {
      const auto t0 = std::chrono::steady_clock::now();
      auto out = api::run_seam_pipeline(asset, api::AssetKind::kAuto, *p, limits, core::CancelToken::none());
      times.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      if (!out.ok()) {
        std::printf("%-22s failed: %s\n", file.c_str(), out.error().message.c_str());
        break;
      }
      out_bytes = out->glb.size();
      entry_count = out->body.value("primitives", json::array()).size();
    }
    std::printf("%-22s %8ld %6zu %10zu %10zu %10.1f\n", file.c_str(), a["faces"].get<long>(), entry_count, asset.size(),
                out_bytes, median(times));
  }
  return 0;
}
