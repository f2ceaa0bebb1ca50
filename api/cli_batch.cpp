// `seamd batch IN... --out-dir DIR`: many assets over N workers, one progress line each on
// stderr, a JSON report, past failures to the end.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>
#include <vector>

#include "api/cli.h"
#include "api/cli_common.h"
#include "api/pipeline.h"

namespace seam::api {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

const std::set<std::string> kAssetExtensions = {".glb", ".gltf", ".drc", ".obj", ".off"};

struct Job {
  std::string input;   // as found
  std::string output;  // DIR/<relative>.glb
  std::string name;    // shown in progress lines: the path below its folder, or the file name
};

struct JobResult {
  bool ok = false;
  std::optional<std::size_t> faces;
  double seconds = 0;
  json body;   // the 200 body without the asset
  json error;  // the error body's "error" object
};

// True when `path` lies inside `dir` (both canonical), so a rerun does not take its own
// outputs for inputs.
bool inside(const fs::path& path, const fs::path& dir) {
  auto p = path.begin();
  for (auto d = dir.begin(); d != dir.end(); ++d, ++p) {
    if (p == path.end() || *p != *d) return false;
  }
  return true;
}

std::string with_thousands(std::size_t n) {
  std::string digits = std::to_string(n), out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i != 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

std::string fixed(double x, int decimals) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, x);
  return buffer;
}

JobResult run_job(const Job& job, const SeamParams& params, const PipelineLimits& limits, const std::string& ext) {
  JobResult r;
  const auto start = std::chrono::steady_clock::now();
  auto finish = [&](const ApiError& e) {
    r.error = error_body(e)["error"];
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return r;
  };
  std::istringstream no_stdin;
  auto bytes = cli::read_input(job.input, no_stdin);
  if (!bytes.ok()) return finish(bytes.error());
  auto asset = cli::load_asset(std::move(bytes).value(), job.input);
  if (!asset.ok()) return finish(asset.error());
  auto result = run_seam_pipeline(asset->bytes, asset->kind, params, limits, core::CancelToken::none());
  if (!result.ok()) return finish(result.error());
  std::error_code ec;
  fs::create_directories(fs::path(job.output).parent_path(), ec);
  if (ec) {
    return finish(make_api_error(ApiErrorCode::kInternal, "cannot create " +
                                                              fs::path(job.output).parent_path().string() + ": " +
                                                              ec.message()));
  }
  const std::string written = ext == ".json" ? result->body.dump() + "\n" : std::move(result->glb);
  auto target = cli::check_output(job.output, "out");
  if (!target.ok()) return finish(target.error());
  if (auto e = cli::write_output(*target, written)) return finish(*e);
  r.ok = true;
  r.body = std::move(result->body);
  r.body.erase("asset");
  r.body["format"] = asset->format;
  r.faces = cli::body_faces(r.body);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

int usage(std::ostream& err, const ApiError& error) {
  ApiError e = error;
  e.message += " (seamd batch --help shows the usage)";
  return cli::fail(err, e, 2);
}

}  // namespace

int run_batch(int argc, char** argv, std::ostream& out, std::ostream& err, const CliContext& context) {
  auto parsed = cli::parse_args(argc, argv,
                                {{"--out-dir", "out_dir"}, {"--workers", "workers"}, {"--threads", "threads"},
                                 {"--report", "report"}, {"--params", "params"}});
  if (!parsed.ok()) return usage(err, parsed.error());
  cli::ParsedArgs& args = *parsed;
  if (args.help) {
    out << cli_usage();
    return 0;
  }
  if (args.version) {
    out << "seamd " << context.version << "\n";
    return 0;
  }
  if (args.positional.empty()) return usage(err, cli::usage_error("in", "batch needs files or folders"));
  if (args.own.count("out_dir") == 0) return usage(err, cli::usage_error("out_dir", "batch needs --out-dir DIR"));
  json merged;
  auto params = cli::build_params(args, merged);
  if (!params.ok()) return usage(err, params.error());
  const bool json_output = merged.contains("output") && params->output == OutputFormat::kJson;
  if (!json_output) params->output = OutputFormat::kGlb;
  const std::string out_ext = json_output ? ".json" : ".glb";

  const unsigned cores = context.cores != 0 ? context.cores : std::max(1u, std::thread::hardware_concurrency());
  unsigned workers = cores;
  if (args.own.count("workers") != 0) {
    auto w = cli::positive_count("workers", args.own["workers"]);
    if (!w.ok()) return usage(err, w.error());
    workers = *w;
  }
  PipelineLimits limits;
  limits.threads = std::max(1u, cores / workers);
  if (args.own.count("threads") != 0) {
    auto t = cli::positive_count("threads", args.own["threads"]);
    if (!t.ok()) return usage(err, t.error());
    limits.threads = *t;
  }

  // The output folder: created, and every check done before any asset is read.
  const std::string out_dir = args.own["out_dir"];
  std::error_code ec;
  if (fs::exists(out_dir, ec) && !fs::is_directory(out_dir, ec)) {
    return cli::fail(err, cli::usage_error("out_dir", "--out-dir " + out_dir + " is not a directory"), 2);
  }
  fs::create_directories(out_dir, ec);
  if (ec) {
    return cli::fail(err, cli::usage_error("out_dir", "cannot create --out-dir " + out_dir + ": " + ec.message()), 2);
  }
  const fs::path out_canonical = fs::canonical(out_dir, ec);
  auto probe = cli::check_output((fs::path(out_dir) / "probe.glb").string(), "out_dir");
  if (!probe.ok()) return cli::fail(err, probe.error(), 2);
  const std::string report_path =
      args.own.count("report") != 0 ? args.own["report"] : (fs::path(out_dir) / "report.json").string();
  auto report_target = cli::check_output(report_path, "report");
  if (!report_target.ok()) return cli::fail(err, report_target.error(), 2);

  // The assets: files as given, folders searched recursively (sorted), each once.
  std::vector<Job> jobs;
  std::set<std::string> seen_inputs;
  std::map<std::string, std::string> input_of_output;
  for (const auto& in : args.positional) {
    std::vector<std::pair<fs::path, fs::path>> found;  // (file, the path shown and mirrored)
    if (fs::is_directory(in, ec)) {
      for (fs::recursive_directory_iterator it(in, fs::directory_options::skip_permission_denied, ec), end;
           !ec && it != end; it.increment(ec)) {
        if (!it->is_regular_file(ec)) continue;
        if (kAssetExtensions.count(cli::lower_extension(it->path().string())) == 0) continue;
        if (!out_canonical.empty() && inside(fs::canonical(it->path(), ec), out_canonical)) continue;
        found.emplace_back(it->path(), fs::relative(it->path(), in, ec));
      }
      if (ec) return cli::fail(err, cli::usage_error("in", "cannot list " + in + ": " + ec.message()), 2);
      std::sort(found.begin(), found.end());
      if (found.empty()) {
        return usage(err, cli::usage_error("in", in + " holds no .glb, .gltf, .drc, .obj or .off file"));
      }
    } else if (fs::exists(in, ec)) {
      found.emplace_back(in, fs::path(in).filename());
    } else {
      return cli::fail(err, cli::usage_error("in", "no such file or folder: " + in), 2);
    }
    for (const auto& [file, shown] : found) {
      const std::string key = fs::weakly_canonical(file, ec).string();
      if (!seen_inputs.insert(key).second) continue;
      fs::path output = fs::path(out_dir) / shown;
      output.replace_extension(out_ext);
      const auto [it, fresh] = input_of_output.emplace(output.string(), file.string());
      if (!fresh) {
        return usage(err, cli::usage_error("in", file.string() + " and " + it->second + " would both be written to " +
                                                     output.string() + "; rename one or run them separately"));
      }
      jobs.push_back({file.string(), output.string(), shown.string()});
    }
  }

  // Workers take the next job; lines are printed as jobs finish, under one lock.
  std::vector<JobResult> results(jobs.size());
  std::atomic<std::size_t> next{0};
  std::size_t done = 0;
  std::mutex print_mutex;
  const std::size_t width = std::to_string(jobs.size()).size();
  const auto start = std::chrono::steady_clock::now();
  auto work = [&] {
    for (std::size_t i = next++; i < jobs.size(); i = next++) {
      try {
        results[i] = run_job(jobs[i], *params, limits, out_ext);
      } catch (const std::exception& e) {  // bad_alloc reading a huge file: this asset fails, not the batch
        results[i] = JobResult{};
        results[i].error = error_body(make_api_error(ApiErrorCode::kInternal, e.what()))["error"];
      }
      const JobResult& r = results[i];
      std::lock_guard<std::mutex> lock(print_mutex);
      std::string index = std::to_string(++done);
      index.insert(0, width - std::min(width, index.size()), ' ');
      std::string line = "[" + index + "/" + std::to_string(jobs.size()) + "] " + jobs[i].name + "  " +
                         (r.faces ? with_thousands(*r.faces) : std::string("?")) + " faces  " + fixed(r.seconds, 2) +
                         " s  ";
      if (r.ok) line += "ok";
      else line += "failed: " + r.error.value("code", std::string()) + ": " + r.error.value("message", std::string());
      err << line << "\n";
      err.flush();
    }
  };
  const unsigned threads = static_cast<unsigned>(std::min<std::size_t>(workers, jobs.size()));
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  std::size_t ok = 0;
  json assets = json::array();
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    const JobResult& r = results[i];
    json entry = {{"input", jobs[i].input},
                  {"output", r.ok ? json(jobs[i].output) : json(nullptr)},
                  {"status", r.ok ? "ok" : "failed"},
                  {"faces", r.faces ? json(*r.faces) : json(nullptr)},
                  {"seconds", r.seconds}};
    if (r.ok) {
      ++ok;
      entry["result"] = r.body;
    } else {
      entry["error"] = r.error;
    }
    assets.push_back(std::move(entry));
  }
  const std::size_t failed = jobs.size() - ok;
  const json report = {{"seamd", context.version},
                       {"params", merged},
                       {"workers", workers},
                       {"threads_per_asset", limits.threads},
                       {"out_dir", out_dir},
                       {"summary", {{"assets", jobs.size()}, {"ok", ok}, {"failed", failed}, {"seconds", seconds}}},
                       {"assets", std::move(assets)}};
  const std::string report_text = report.dump(2) + "\n";
  int code = failed == 0 ? 0 : 1;
  if (report_target->to_stdout) {
    out << report_text;
  } else if (auto e = cli::write_output(*report_target, report_text)) {
    cli::fail(err, *e, 1);
    code = 1;
  }
  err << "batch: " << jobs.size() << (jobs.size() == 1 ? " asset, " : " assets, ") << ok << " ok, " << failed << " failed in " << fixed(seconds, 1)
      << " s over " << threads << (threads == 1 ? " worker" : " workers") << "; report "
      << (report_target->to_stdout ? std::string("on stdout") : report_target->path) << "\n";
  return code;
}

}  // namespace seam::api
