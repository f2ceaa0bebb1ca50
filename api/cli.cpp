// `seamd seam`, `seamd sample`, `--version` and the usage text; `seamd batch` is in
// api/cli_batch.cpp, the shared parsing and IO in api/cli_common.cpp.
#include "api/cli.h"

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "api/cli_common.h"
#include "api/pipeline.h"
#include "api/process_env.h"
#include "api/sample_mesh.h"
#include "core/uv/sparse_cholesky.h"

namespace seam::api {

// Defined in api/cli_batch.cpp.
int run_batch(int argc, char** argv, std::istream& in, std::ostream& out, std::ostream& err, const CliContext& context);

namespace {

using cli::with_usage_hint;
using nlohmann::json;

constexpr const char* kUsage = R"(usage:
  seamd seam IN [OUT] [flags]            cut one asset
  seamd batch IN... --out-dir DIR [flags] cut many assets in parallel
  seamd sample [OUT]                     write the bundled starfish sample (5120 faces, 5 arms)
  seamd --version                        print the version
  seamd [serve flags]                    the HTTP service (seamd --help lists its flags)

IN   .glb, .gltf (buffers as data URIs), .drc, .obj or .off; - reads stdin. The format comes
     from the content (an OBJ that starts with no statement falls back to the .obj name).
OUT  the cut asset: a GLB (or the HTTP JSON body with --output json); - or /dev/stdout
     writes it to stdout and nothing else goes there. Checked before any work: a directory,
     a missing or read-only directory is refused with exit 2. Without OUT only the summary
     is printed. Written through a temporary file renamed over OUT.

seam flags
  --mesh FILE            the same as IN (kept for existing scripts; HTTP's `mesh` is
                         the mesh index: --mesh-index)
  --out FILE             the same as OUT (kept for existing scripts)
  --report FILE          write the JSON summary to FILE instead of stdout
  --params JSON|@FILE    API parameters as the HTTP JSON body's object (or read from FILE, @- stdin);
                         flags override it key by key
  --threads N            threads for the job (default: every core)
  -h, --help             this text on stdout, exit 0
  --version              seamd's version on stdout, exit 0

API parameters (the HTTP parameters, same names and rules; api/README.md "Parameters")
  --extrema auto|I,J,K|JSON   vertex indices, or the JSON array/object forms
  --method skeleton|mst|greedy|optimal
  --uv slim|arap|bff|lscm|none
  --refine [true|false]       --no-refine is --refine false
  --draco [true|false]        --no-draco; default: as the input
  --repair [true|false]       --no-repair
  --weld-epsilon X
  --mesh-index N              HTTP's `mesh`: which mesh of the asset
  --primitive N
  --primitives all|JSON
  --output glb|json           what OUT receives (default glb)
  --NAME VALUE                any other parameter: key NAME with - as _, VALUE as JSON if
                              it parses, else as a string
  Each flag once; --flag VALUE or --flag=VALUE.

batch flags (the API parameters above apply to every asset)
  IN...                  files, and folders searched recursively for .glb .gltf .drc .obj .off
  --out-dir DIR          outputs as DIR/<path below the folder, or file name>.glb (created)
  --workers N            assets processed at once (default: every core)
  --threads N            threads per asset (default: cores / workers, at least 1)
  --report FILE          the JSON report (default DIR/report.json)
  Progress on stderr: one line per asset (name, faces, seconds, status), then a summary.

The summary is the HTTP 200 body without the asset, plus input, format, written, bytes; it
goes to stdout, or to stderr when OUT is stdout, or to --report FILE.
Exit codes: 0 ok; 1 processing error (the asset failed, a write failed; batch: any asset
failed); 2 usage error (unknown or repeated flag, invalid parameter, unwritable output),
found before any mesh work. Errors are the HTTP API's {"error": {"code", "message",
"details"}} on stderr.
)";

int usage(std::ostream& err, const ApiError& error) {
  return cli::fail(err, with_usage_hint(error, "seam"), 2);
}

int print_version(std::ostream& out, const CliContext& context) {
  out << "seamd " << context.version << "\n";
  return 0;
}

int run_sample(int argc, char** argv, std::ostream& out, std::ostream& err, const CliContext& context) {
  auto args = cli::parse_args(argc, argv, {{"--out", "out"}});
  if (!args.ok()) return usage(err, args.error());
  if (args->help) {
    out << kUsage;
    return 0;
  }
  if (args->version) return print_version(out, context);
  if (!args->param_flags.empty()) {
    return usage(err, cli::usage_error(args->flag_of_key.begin()->first,
                                       "sample takes no flag " + args->flag_of_key.begin()->second));
  }
  if (args->positional.size() > 1) return usage(err, cli::usage_error("out", "sample takes one OUT"));
  if (args->positional.size() == 1) {
    if (auto e = cli::set_positional(*args, "out", args->positional[0], "OUT")) return usage(err, *e);
  }
  if (args->own.count("out") == 0) return usage(err, cli::usage_error("out", "sample needs OUT (a .glb path or -)"));
  auto target = cli::check_output(args->own["out"], "out");
  if (!target.ok()) return cli::fail(err, target.error(), 2);
  auto glb = sample_glb();
  if (!glb.ok()) return cli::fail(err, glb.error(), 1);
  const json summary = {{"written", target->path}, {"bytes", glb->size()}, {"tips", sample_tips()}};
  if (target->to_stdout) {
    out.write(glb->data(), static_cast<std::streamsize>(glb->size()));
    out.flush();
    err << summary.dump() << "\n";
    return 0;
  }
  if (auto e = cli::write_output(*target, *glb)) return cli::fail(err, *e, 1);
  out << summary.dump() << "\n";
  return 0;
}

// Takes IN and OUT from the positionals (refusing one that a flag set too) and returns IN,
// which is required.
ApiResult<std::string> seam_input(cli::ParsedArgs& args) {
  if (args.positional.size() > 2) {
    return with_usage_hint(
        cli::usage_error("out", "seam takes IN and at most one OUT; extra argument " + args.positional[2]), "seam");
  }
  if (!args.positional.empty()) {
    if (auto e = cli::set_positional(args, "in", args.positional[0], "IN")) return with_usage_hint(*e, "seam");
  }
  if (args.positional.size() == 2) {
    if (auto e = cli::set_positional(args, "out", args.positional[1], "OUT")) return with_usage_hint(*e, "seam");
  }
  if (args.own.count("in") == 0) {
    return with_usage_hint(cli::usage_error("in", "seam needs an input: seamd seam IN [OUT]"), "seam");
  }
  return args.own["in"];
}

// The process's settings, before anything is read: a second start must find stdin (IN `-`,
// `--params @/dev/stdin`) and every file as the first one did.
void set_up_process(const std::string& in_path, char** reexec_argv) {
  std::error_code ec;
  const std::uintmax_t size = in_path == "-" ? 0 : std::filesystem::file_size(in_path, ec);
  if (!ec && size >= kReexecInputBytes) {
    reexec_with(ProcessEnv{}, reexec_argv);
  } else {
    keep_freed_memory_for_short_job();  // not worth a second start
  }
  core::use_single_threaded_solvers();  // before the job starts threads of its own
}

// OUT and --report FILE, when given.
struct SeamOutputs {
  std::optional<cli::OutputTarget> target;
  std::optional<cli::OutputTarget> report;
};

// Errors: check_output's, OUT's before the report's.
ApiResult<SeamOutputs> check_seam_outputs(cli::ParsedArgs& args) {
  SeamOutputs outputs;
  if (args.own.count("out") != 0) {
    auto t = cli::check_output(args.own["out"], "out");
    if (!t.ok()) return t.error();
    outputs.target = *t;
  }
  if (args.own.count("report") != 0) {
    auto r = cli::check_output(args.own["report"], "report");
    if (!r.ok()) return r.error();
    outputs.report = *r;
  }
  return outputs;
}

// `seamd seam` as asked, with every check done before the input is read.
struct SeamJob {
  std::string in_path;
  SeamParams params;
  PipelineLimits limits;
  SeamOutputs outputs;
};

// The parameters, the limits and the outputs, checked in that order.
ApiResult<SeamJob> plan_seam(cli::ParsedArgs& args, const std::string& in_path, const CliContext& context,
                             std::istream& in) {
  if (in_path == "-" && args.own.count("params") != 0 && args.own["params"] == "@-") {
    return with_usage_hint(cli::usage_error("params", "stdin cannot be both IN and --params @-"), "seam");
  }
  SeamJob job;
  job.in_path = in_path;
  json merged;
  auto params = cli::build_params(args, merged, in);
  if (!params.ok()) return with_usage_hint(params.error(), "seam");
  job.params = std::move(params).value();
  job.limits.threads = context.cores;
  if (args.own.count("threads") != 0) {
    auto threads = cli::positive_count("threads", args.own["threads"]);
    if (!threads.ok()) return with_usage_hint(threads.error(), "seam");
    job.limits.threads = *threads;
  }

  // Every output is checked before the input is read.
  SEAM_TRY(job.outputs, check_seam_outputs(args));
  const auto& [target, report] = job.outputs;
  // The HTTP default is a JSON body; on the command line OUT is a GLB unless asked.
  if (!merged.contains("output") || !target) job.params.output = OutputFormat::kGlb;
  if (target && target->to_stdout) {
    if (report && report->to_stdout) {
      return with_usage_hint(cli::usage_error("report", "OUT and --report cannot both be stdout"), "seam");
    }
    if (context.stdout_is_terminal && job.params.output == OutputFormat::kGlb) {
      return with_usage_hint(cli::usage_error("out",
                                              "refusing to write a binary GLB to a terminal; redirect stdout "
                                              "or give an OUT file"),
                             "seam");
    }
  }
  return job;
}

// OUT's bytes: on stdout, or through a temporary file renamed over OUT.
std::optional<ApiError> write_target(const cli::OutputTarget& target, const std::string& bytes, std::ostream& out) {
  if (!target.to_stdout) return cli::write_output(target, bytes);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.flush();
  if (!out) return make_api_error(ApiErrorCode::kInternal, "cannot write to stdout");
  return std::nullopt;
}

// Writes OUT (when given), then the summary: to --report FILE, else to stderr when OUT is
// stdout, else to stdout.
int write_seam_outputs(const SeamJob& job, PipelineOutput result, const std::string& format, std::ostream& out,
                       std::ostream& err) {
  const auto& [target, report] = job.outputs;
  json summary = result.body;
  summary.erase("asset");
  summary["input"] = job.in_path;
  summary["format"] = format;
  if (target) {
    const std::string written =
        job.params.output == OutputFormat::kJson ? result.body.dump() + "\n" : std::move(result.glb);
    if (auto e = write_target(*target, written, out)) return cli::fail(err, *e, 1);
    summary["written"] = target->path;
    summary["bytes"] = written.size();
  }
  const std::string text = summary.dump(2) + "\n";
  if (report && !report->to_stdout) {
    if (auto e = cli::write_output(*report, text)) return cli::fail(err, *e, 1);
  } else if (target && target->to_stdout) {
    err << text;
  } else {
    out << text;
  }
  return 0;
}

int run_seam(int argc, char** argv, std::istream& in, std::ostream& out, std::ostream& err, const CliContext& context) {
  auto parsed = cli::parse_args(
      argc, argv,
      {{"--mesh", "in"}, {"--out", "out"}, {"--report", "report"}, {"--params", "params"}, {"--threads", "threads"}});
  if (!parsed.ok()) return usage(err, parsed.error());
  cli::ParsedArgs& args = *parsed;
  if (args.help) {
    out << kUsage;
    return 0;
  }
  if (args.version) return print_version(out, context);
  auto in_path = seam_input(args);
  if (!in_path.ok()) return cli::fail(err, in_path.error(), 2);
  if (context.reexec_argv != nullptr) set_up_process(*in_path, context.reexec_argv);
  auto job = plan_seam(args, *in_path, context, in);
  if (!job.ok()) return cli::fail(err, job.error(), 2);

  auto bytes = cli::read_input(job->in_path, in);
  if (!bytes.ok()) return cli::fail(err, bytes.error(), 1);
  auto asset = cli::load_asset(std::move(bytes).value(), job->in_path);
  if (!asset.ok()) return cli::fail(err, asset.error(), 1);
  auto result = run_seam_pipeline(asset->bytes, asset->kind, job->params, job->limits, core::CancelToken::none());
  if (!result.ok()) return cli::fail(err, result.error(), 1);
  return write_seam_outputs(*job, std::move(result).value(), asset->format, out, err);
}

}  // namespace

std::string cli_usage() { return kUsage; }

int run_cli(int argc, char** argv, std::istream& in, std::ostream& out, std::ostream& err,
            const CliContext& context) {
  if (argc < 1) return usage(err, cli::usage_error("command", "missing command (seam, batch, sample)"));
  const std::string command = argv[0];
  if (command == "--version") return print_version(out, context);
  if (command == "seam") return run_seam(argc, argv, in, out, err, context);
  if (command == "batch") return run_batch(argc, argv, in, out, err, context);
  if (command == "sample") return run_sample(argc, argv, out, err, context);
  return usage(err, cli::usage_error("command", "unknown command " + command + " (seam, batch, sample)"));
}

int run_cli(int argc, char** argv, std::ostream& out, std::ostream& err) {
  std::istringstream empty;
  return run_cli(argc, argv, empty, out, err);
}

}  // namespace seam::api
