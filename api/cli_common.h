// What `seamd seam` and `seamd batch` share: the argument parser that maps flags onto the
// HTTP API's parameter JSON, input sniffing, and output paths checked before any work.
// Internal to the CLI (api/cli*.cpp); the public entry point is api/cli.h.
#pragma once

#include <istream>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/error.h"
#include "api/pipeline.h"

namespace seam::api::cli {

/// A flag of the command itself (not an API parameter). `canonical` is the name duplicates
/// are counted by, so an alias and its flag (`--mesh` and IN) cannot both be given.
struct OwnFlag {
  std::string name;       ///< "--out"
  std::string canonical;  ///< "out"
};

/// The command line split into the command's own flags, API parameter flags and positionals.
struct ParsedArgs {
  std::map<std::string, std::string> own;           ///< canonical -> value
  std::map<std::string, std::string> own_flag;      ///< canonical -> the flag that set it
  std::vector<std::string> positional;
  nlohmann::json param_flags = nlohmann::json::object();  ///< API key -> JSON value
  std::map<std::string, std::string> flag_of_key;   ///< API key -> the flag that set it
  std::map<std::string, bool> generic_key;          ///< API key -> came from an unlisted flag
  bool help = false;
  bool version = false;
};

/// Parses argv[1..argc). Every own flag takes a value (`--flag V` or `--flag=V`). Any other
/// `--name` is an API parameter: listed ones get their value converted (booleans may omit
/// `true`; `--no-NAME` is false; `--extrema 1,2,3` is a list), unlisted ones map `--a-b V`
/// to key `a_b` with V as JSON when it parses, else as a string, so parameters added to
/// params_from_json work without a CLI change. `--` ends the flags.
/// Errors (kInvalidParameter): a flag given twice (or a flag and its alias), a missing
/// value, a single-dash flag other than `-h`, a malformed `--extrema` list.
ApiResult<ParsedArgs> parse_args(int argc, char** argv, const std::vector<OwnFlag>& own_flags);

/// Sets `canonical` from a positional, refusing it when a flag already set it.
/// Errors: kInvalidParameter (details.parameter = `canonical`) naming both, when it is given twice.
std::optional<ApiError> set_positional(ParsedArgs& args, const std::string& canonical, const std::string& value,
                                       const std::string& what);

/// The parameters: `--params JSON|@FILE|@-` (own["params"]; `@-` reads `in`, the process's
/// stdin) with the parameter flags laid over it, then params_from_json, the one parameter
/// parser. `merged` receives the JSON it parsed.
/// Errors: kInvalidParameter (unreadable @FILE, not a JSON object, anything
/// params_from_json refuses; the message names the flag that set the key).
ApiResult<SeamParams> build_params(const ParsedArgs& args, nlohmann::json& merged, std::istream& in);

/// Parses a positive integer flag value (`--workers`, `--threads`).
/// Errors: kInvalidParameter (not an integer from 1 to 4096), details.parameter = `flag`.
ApiResult<unsigned> positive_count(const std::string& flag, const std::string& value);

/// The input file, or `in` for "-". Errors: kMalformedAsset naming the path and the reason.
ApiResult<std::string> read_input(const std::string& path, std::istream& in);

/// Asset bytes ready for run_seam_pipeline: glTF, GLB and Draco pass through (sniffed by
/// content); OFF and OBJ (sniffed by content, else by the name's extension) become a plain
/// GLB. `format` is "glb", "gltf", "draco", "off" or "obj".
/// Errors: read_off's and read_obj's (kMalformedAsset with the line), write_plain_glb's
/// (kInternal); glTF, GLB and Draco bytes are checked later by the pipeline, not here.
struct LoadedAsset {
  std::string bytes;
  AssetKind kind = AssetKind::kAuto;
  std::string format;
};
ApiResult<LoadedAsset> load_asset(std::string bytes, const std::string& name);

/// Where an output goes, checked before any work.
struct OutputTarget {
  std::string path;
  bool to_stdout = false;  ///< "-", /dev/stdout, /dev/fd/1
  bool special = false;    ///< an existing non-regular file (a device, a FIFO): written in place
};

/// Checks that `path` can be written: "-" and /dev/stdout are stdout; an existing directory,
/// a missing or non-directory parent, a read-only file or directory are refused
/// (kInvalidParameter, details {parameter: `what`, path}). Does not create anything.
ApiResult<OutputTarget> check_output(const std::string& path, const std::string& what);

/// Writes `bytes` to a file target: a temporary file beside it renamed over it, so a reader
/// never sees half a file and a failed write leaves the old file. Not for stdout targets.
/// Errors: kInternal naming the path and errno's reason.
std::optional<ApiError> write_output(const OutputTarget& target, const std::string& bytes);

/// Prints the JSON error body on `err` and returns `code`.
int fail(std::ostream& err, const ApiError& error, int code);
/// A usage mistake of `seamd <command>`: the message gains where the usage is.
ApiError with_usage_hint(ApiError error, std::string_view command);

/// kInvalidParameter with details.parameter.
ApiError usage_error(const std::string& parameter, std::string message);

/// Faces of the processed primitives in a 200 body (v1 `mesh.faces`, or the sum over v2's
/// `primitives[].topology.faces`); nullopt when the body has neither.
std::optional<std::size_t> body_faces(const nlohmann::json& body);

/// The extension in lower case, with its dot ("" when none).
std::string lower_extension(const std::string& path);

}  // namespace seam::api::cli
