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
#include "api/process_env.h"
#include "core/uv/sparse_cholesky.h"

namespace seam::api {
namespace {

using cli::with_usage_hint;
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

// What every job of the batch shares: the parameters, the output kind and the thread split.
struct BatchPlan {
  json merged;  // the parameters as given, for the report
  SeamParams params;
  std::string out_ext;  // ".glb", or ".json" with --output json
  unsigned workers = 1;
  PipelineLimits limits;
};

ApiResult<BatchPlan> plan_batch(cli::ParsedArgs& args, unsigned cores, std::istream& in) {
  if (args.positional.empty()) return with_usage_hint(cli::usage_error("in", "batch needs files or folders"), "batch");
  if (args.own.count("out_dir") == 0)
    return with_usage_hint(cli::usage_error("out_dir", "batch needs --out-dir DIR"), "batch");
  BatchPlan plan;
  auto params = cli::build_params(args, plan.merged, in);
  if (!params.ok()) return with_usage_hint(params.error(), "batch");
  plan.params = std::move(params).value();
  const bool json_output = plan.merged.contains("output") && plan.params.output == OutputFormat::kJson;
  if (!json_output) plan.params.output = OutputFormat::kGlb;
  plan.out_ext = json_output ? ".json" : ".glb";
  plan.workers = cores;
  if (args.own.count("workers") != 0) {
    auto w = cli::positive_count("workers", args.own["workers"]);
    if (!w.ok()) return with_usage_hint(w.error(), "batch");
    plan.workers = *w;
  }
  plan.limits.threads = std::max(1u, cores / plan.workers);
  if (args.own.count("threads") != 0) {
    auto t = cli::positive_count("threads", args.own["threads"]);
    if (!t.ok()) return with_usage_hint(t.error(), "batch");
    plan.limits.threads = *t;
  }
  return plan;
}

// Where results go: the output folder (created) and the report, every check done before any
// asset is read.
struct BatchOutputs {
  std::string out_dir;
  fs::path out_canonical;  // to skip earlier outputs when a folder input contains it
  cli::OutputTarget report;
};

ApiResult<BatchOutputs> prepare_outputs(cli::ParsedArgs& args) {
  BatchOutputs outputs;
  outputs.out_dir = args.own["out_dir"];
  const std::string& out_dir = outputs.out_dir;
  std::error_code ec;
  if (fs::exists(out_dir, ec) && !fs::is_directory(out_dir, ec)) {
    return cli::usage_error("out_dir", "--out-dir " + out_dir + " is not a directory");
  }
  fs::create_directories(out_dir, ec);
  if (ec) return cli::usage_error("out_dir", "cannot create --out-dir " + out_dir + ": " + ec.message());
  outputs.out_canonical = fs::canonical(out_dir, ec);
  auto probe = cli::check_output((fs::path(out_dir) / "probe.glb").string(), "out_dir");
  if (!probe.ok()) return probe.error();
  const std::string report_path =
      args.own.count("report") != 0 ? args.own["report"] : (fs::path(out_dir) / "report.json").string();
  auto report = cli::check_output(report_path, "report");
  if (!report.ok()) return report.error();
  outputs.report = std::move(report).value();
  return outputs;
}

// The asset files one input names: the file itself, or a folder's asset files found
// recursively (sorted), each with the path shown and mirrored below the output folder.
using FoundFiles = std::vector<std::pair<fs::path, fs::path>>;

ApiResult<FoundFiles> find_assets(const std::string& in, const fs::path& out_canonical) {
  FoundFiles found;
  std::error_code ec;
  if (!fs::is_directory(in, ec)) {
    if (!fs::exists(in, ec)) return cli::usage_error("in", "no such file or folder: " + in);
    found.emplace_back(in, fs::path(in).filename());
    return found;
  }
  for (fs::recursive_directory_iterator it(in, fs::directory_options::skip_permission_denied, ec), end;
       !ec && it != end; it.increment(ec)) {
    if (!it->is_regular_file(ec)) continue;
    if (kAssetExtensions.count(cli::lower_extension(it->path().string())) == 0) continue;
    if (!out_canonical.empty() && inside(fs::canonical(it->path(), ec), out_canonical)) continue;
    found.emplace_back(it->path(), fs::relative(it->path(), in, ec));
  }
  if (ec) return cli::usage_error("in", "cannot list " + in + ": " + ec.message());
  std::sort(found.begin(), found.end());
  if (found.empty()) {
    return with_usage_hint(cli::usage_error("in", in + " holds no .glb, .gltf, .drc, .obj or .off file"), "batch");
  }
  return found;
}

// One job per distinct asset file; two inputs that would write the same output are refused.
ApiResult<std::vector<Job>> collect_jobs(const std::vector<std::string>& inputs, const BatchOutputs& outputs,
                                         const std::string& out_ext) {
  std::vector<Job> jobs;
  std::set<std::string> seen_inputs;
  std::map<std::string, std::string> input_of_output;
  std::error_code ec;
  for (const auto& in : inputs) {
    SEAM_TRY(FoundFiles found, find_assets(in, outputs.out_canonical));
    for (const auto& [file, shown] : found) {
      if (!seen_inputs.insert(fs::weakly_canonical(file, ec).string()).second) continue;
      fs::path output = fs::path(outputs.out_dir) / shown;
      output.replace_extension(out_ext);
      const auto [it, fresh] = input_of_output.emplace(output.string(), file.string());
      if (!fresh) {
        return with_usage_hint(
            cli::usage_error("in", file.string() + " and " + it->second + " would both be written to " +
                                       output.string() + "; rename one or run them separately"),
            "batch");
      }
      jobs.push_back({file.string(), output.string(), shown.string()});
    }
  }
  return jobs;
}

// "[ 3/12] sub/a.glb  12,345 faces  0.84 s  ok"
std::string progress_line(std::size_t done, std::size_t total, const Job& job, const JobResult& r) {
  const std::size_t width = std::to_string(total).size();
  std::string index = std::to_string(done);
  index.insert(0, width - std::min(width, index.size()), ' ');
  std::string line = "[" + index + "/" + std::to_string(total) + "] " + job.name + "  " +
                     (r.faces ? with_thousands(*r.faces) : std::string("?")) + " faces  " + fixed(r.seconds, 2) + " s  ";
  if (r.ok) return line + "ok";
  return line + "failed: " + r.error.value("code", std::string()) + ": " + r.error.value("message", std::string());
}

struct BatchRun {
  std::vector<JobResult> results;  // in job order
  double seconds = 0;
  unsigned threads = 0;
};

// Workers take the next job; lines are printed as jobs finish, under one lock.
BatchRun run_jobs(const std::vector<Job>& jobs, const BatchPlan& plan, std::ostream& err) {
  BatchRun run;
  run.results.resize(jobs.size());
  std::atomic<std::size_t> next{0};
  std::size_t done = 0;
  std::mutex print_mutex;
  const auto start = std::chrono::steady_clock::now();
  auto work = [&] {
    for (std::size_t i = next++; i < jobs.size(); i = next++) {
      try {
        run.results[i] = run_job(jobs[i], plan.params, plan.limits, plan.out_ext);
      } catch (const std::exception& e) {  // bad_alloc reading a huge file: this asset fails, not the batch
        run.results[i] = JobResult{};
        run.results[i].error = error_body(make_api_error(ApiErrorCode::kInternal, e.what()))["error"];
      }
      std::lock_guard<std::mutex> lock(print_mutex);
      err << progress_line(++done, jobs.size(), jobs[i], run.results[i]) << "\n";
      err.flush();
    }
  };
  run.threads = static_cast<unsigned>(std::min<std::size_t>(plan.workers, jobs.size()));
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < run.threads; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return run;
}

json batch_report(const std::vector<Job>& jobs, const BatchRun& run, const BatchPlan& plan,
                  const BatchOutputs& outputs, const CliContext& context) {
  std::size_t ok = 0;
  json assets = json::array();
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    const JobResult& r = run.results[i];
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
  return {{"seamd", context.version},
          {"params", plan.merged},
          {"workers", plan.workers},
          {"threads_per_asset", plan.limits.threads},
          {"out_dir", outputs.out_dir},
          {"summary", {{"assets", jobs.size()}, {"ok", ok}, {"failed", jobs.size() - ok}, {"seconds", run.seconds}}},
          {"assets", std::move(assets)}};
}

}  // namespace

int run_batch(int argc, char** argv, std::istream& in, std::ostream& out, std::ostream& err,
              const CliContext& context) {
  auto parsed = cli::parse_args(argc, argv,
                                {{"--out-dir", "out_dir"}, {"--workers", "workers"}, {"--threads", "threads"},
                                 {"--report", "report"}, {"--params", "params"}});
  if (!parsed.ok()) return cli::fail(err, with_usage_hint(parsed.error(), "batch"), 2);
  cli::ParsedArgs& args = *parsed;
  if (args.help) {
    out << cli_usage();
    return 0;
  }
  if (args.version) {
    out << "seamd " << context.version << "\n";
    return 0;
  }
  // The process's settings before anything is read (`--params @/dev/stdin` must reach the
  // second start unread) and before any output exists.
  if (context.reexec_argv != nullptr) {
    reexec_with(ProcessEnv{}, context.reexec_argv);
    core::use_single_threaded_solvers();  // before the workers start
  }
  const unsigned cores = context.cores != 0 ? context.cores : std::max(1u, std::thread::hardware_concurrency());
  auto plan = plan_batch(args, cores, in);
  if (!plan.ok()) return cli::fail(err, plan.error(), 2);
  auto outputs = prepare_outputs(args);
  if (!outputs.ok()) return cli::fail(err, outputs.error(), 2);
  auto jobs = collect_jobs(args.positional, *outputs, plan->out_ext);
  if (!jobs.ok()) return cli::fail(err, jobs.error(), 2);

  const BatchRun run = run_jobs(*jobs, *plan, err);
  const json report = batch_report(*jobs, run, *plan, *outputs, context);
  const std::size_t failed = report["summary"]["failed"].get<std::size_t>();
  const std::size_t ok = jobs->size() - failed;
  int code = failed == 0 ? 0 : 1;
  if (outputs->report.to_stdout) {
    out << report.dump(2) << "\n";
  } else if (auto e = cli::write_output(outputs->report, report.dump(2) + "\n")) {
    cli::fail(err, *e, 1);
    code = 1;
  }
  err << "batch: " << jobs->size() << (jobs->size() == 1 ? " asset, " : " assets, ") << ok << " ok, " << failed
      << " failed in " << fixed(run.seconds, 1) << " s over " << run.threads
      << (run.threads == 1 ? " worker" : " workers") << "; report "
      << (outputs->report.to_stdout ? std::string("on stdout") : outputs->report.path) << "\n";
  return code;
}

}  // namespace seam::api
