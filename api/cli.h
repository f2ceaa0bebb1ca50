// The command line: `seamd seam`, `seamd batch`, `seamd sample`, `seamd --version` (no HTTP
// server). The usage text is cli_usage(); api/README.md "Command line" documents it.
#pragma once

#include <istream>
#include <ostream>
#include <string>

namespace seam::api {

/// What the process around run_cli knows and the library does not.
struct CliContext {
  std::string version = "unknown";  ///< printed by --version (main passes SEAM_VERSION)
  /// Set when stdout is a terminal: the CLI then refuses to write a binary GLB to it.
  bool stdout_is_terminal = false;
  /// Default `batch --workers` and the thread budget split among workers; 0 = the hardware
  /// concurrency.
  unsigned cores = 0;
  /// main's argv, set when the CLI has the process to itself. Then `seamd seam` with an input
  /// file of at least kReexecInputBytes (api/process_env.h) and `seamd batch` execute the
  /// program again under ProcessEnv (no OpenBLAS thread pool), once the arguments are checked
  /// and before any input is read; a smaller `seamd seam` job keeps freed memory for reuse
  /// instead (keep_freed_memory_for_short_job). Null (the tests): neither.
  char** reexec_argv = nullptr;
};

/// Runs a CLI command. argv[0] is the command: "seam", "batch", "sample" or "--version".
/// `in` is read only for the input `-`; `out` receives the asset when the output is `-` or
/// /dev/stdout (then nothing else is written to it) and the JSON summary otherwise; `err`
/// receives errors as the contract's JSON error body, and batch progress.
/// Returns the process exit code: 0 ok, 1 processing error (an asset failed, a write
/// failed), 2 usage error (unknown or repeated flag, invalid parameter, unwritable output:
/// all found before any mesh work).
int run_cli(int argc, char** argv, std::istream& in, std::ostream& out, std::ostream& err,
            const CliContext& context = {});

/// run_cli with no standard input (an input of `-` reads nothing).
int run_cli(int argc, char** argv, std::ostream& out, std::ostream& err);

/// The usage text `seamd seam --help` prints (every command, every flag).
std::string cli_usage();

}  // namespace seam::api
