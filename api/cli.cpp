// `seamd seam` and `seamd sample`: the batch mode an asset pipeline uses without HTTP.
#include "api/cli.h"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "api/gltf_writer.h"
#include "api/mesh_io.h"
#include "api/pipeline.h"
#include "api/sample_mesh.h"

namespace seam::api {
namespace {

constexpr const char* kUsage =
    "usage:\n"
    "  seamd seam --mesh FILE(.off|.obj|.glb|.gltf|.drc) [--extrema i,j,k|auto] [--method skeleton|mst|greedy|optimal]\n"
    "             [--uv slim|arap|bff|lscm|none] [--weld-epsilon X] [--mesh-index N] [--primitive N]\n"
    "             [--out cut.glb] [--draco]\n"
    "  seamd sample --out sample.glb";

int fail(std::ostream& err, const ApiError& error, int code) {
  err << error_body(error).dump(2) << "\n";
  return code;
}

int usage(std::ostream& err, const std::string& message) {
  return fail(err, make_api_error(ApiErrorCode::kInvalidParameter, message + "\n" + kUsage), 2);
}

bool read_file(const std::string& path, std::string& out) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream ss;
  ss << in.rdbuf();
  out = ss.str();
  return static_cast<bool>(in) || in.eof();
}

bool write_file(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return static_cast<bool>(out);
}

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

int run_sample(int argc, char** argv, std::ostream& out, std::ostream& err) {
  std::string path;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--out" && i + 1 < argc) path = argv[++i];
    else return usage(err, "unknown argument " + arg);
  }
  if (path.empty()) return usage(err, "sample needs --out FILE.glb");
  auto glb = sample_glb();
  if (!glb.ok()) return fail(err, glb.error(), 1);
  if (!write_file(path, *glb)) return fail(err, make_api_error(ApiErrorCode::kInternal, "cannot write " + path), 1);
  nlohmann::json tips = sample_tips();
  out << nlohmann::json{{"written", path}, {"bytes", glb->size()}, {"tips", tips}}.dump() << "\n";
  return 0;
}

int run_seam(int argc, char** argv, std::ostream& out, std::ostream& err) {
  std::string mesh_path, out_path;
  std::vector<std::pair<std::string, std::string>> query;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&](const char* name) -> const char* {
      if (i + 1 >= argc) return nullptr;
      (void)name;
      return argv[++i];
    };
    const char* v = nullptr;
    if (arg == "--draco") {
      query.emplace_back("draco", "true");
    } else if (arg == "--no-draco") {
      query.emplace_back("draco", "false");
    } else if (arg == "--mesh" || arg == "--out" || arg == "--extrema" || arg == "--method" || arg == "--uv" ||
               arg == "--weld-epsilon" || arg == "--mesh-index" || arg == "--primitive") {
      if ((v = value(arg.c_str())) == nullptr) return usage(err, arg + " needs a value");
      if (arg == "--mesh") mesh_path = v;
      else if (arg == "--out") out_path = v;
      else if (arg == "--weld-epsilon") query.emplace_back("weld_epsilon", v);
      else if (arg == "--mesh-index") query.emplace_back("mesh", v);
      else query.emplace_back(arg.substr(2), v);
    } else {
      return usage(err, "unknown argument " + arg);
    }
  }
  if (mesh_path.empty()) return usage(err, "seam needs --mesh FILE");
  auto params = params_from_query(query);
  if (!params.ok()) return fail(err, params.error(), 2);
  params->output = OutputFormat::kGlb;  // the asset goes to --out, never into stdout

  std::string bytes;
  AssetKind kind = AssetKind::kAuto;
  const std::string ext = lower_extension(mesh_path);
  if (ext == ".off" || ext == ".obj") {
    auto mesh = read_mesh_file(mesh_path);
    if (!mesh.ok()) return fail(err, mesh.error(), 1);
    auto glb = write_plain_glb(*mesh);
    if (!glb.ok()) return fail(err, glb.error(), 1);
    bytes = std::move(glb).value();
    kind = AssetKind::kGlb;
  } else {
    if (!read_file(mesh_path, bytes)) {
      return fail(err, make_api_error(ApiErrorCode::kMalformedAsset, "cannot read " + mesh_path), 1);
    }
    if (ext == ".glb") kind = AssetKind::kGlb;
    else if (ext == ".gltf") kind = AssetKind::kGltfJson;
    else if (ext == ".drc") kind = AssetKind::kDraco;
  }
  auto result = run_seam_pipeline(bytes, kind, *params, PipelineLimits{}, core::CancelToken::none());
  if (!result.ok()) return fail(err, result.error(), 1);
  if (!out_path.empty() && !write_file(out_path, result->glb)) {
    return fail(err, make_api_error(ApiErrorCode::kInternal, "cannot write " + out_path), 1);
  }
  nlohmann::json body = result->body;
  body.erase("asset");
  if (!out_path.empty()) body["written"] = out_path;
  out << body.dump(2) << "\n";
  return 0;
}

}  // namespace

int run_cli(int argc, char** argv, std::ostream& out, std::ostream& err) {
  if (argc < 1) return usage(err, "missing subcommand");
  const std::string command = argv[0];
  if (command == "seam") return run_seam(argc, argv, out, err);
  if (command == "sample") return run_sample(argc, argv, out, err);
  return usage(err, "unknown subcommand " + command);
}

}  // namespace seam::api
