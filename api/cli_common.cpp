// The CLI's argument parser, input sniffing and output checks (api/cli_common.h).
#include "api/cli_common.h"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string_view>

#include "api/gltf_reader.h"
#include "api/gltf_writer.h"
#include "api/json_limits.h"
#include "api/mesh_io.h"

namespace seam::api::cli {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

enum class ValueKind { kString, kBool, kInteger, kNumber, kExtrema, kJson };

struct ParamFlag {
  std::string_view flag;  // without the dashes
  std::string_view key;   // the API parameter
  ValueKind kind;
};

// The API parameters with a value syntax of their own. Any other `--name` still reaches
// params_from_json (as JSON or a string), which accepts or refuses it.
constexpr ParamFlag kParamFlags[] = {
    {"extrema", "extrema", ValueKind::kExtrema},
    {"method", "method", ValueKind::kString},
    {"uv", "uv", ValueKind::kString},
    {"refine", "refine", ValueKind::kBool},
    {"draco", "draco", ValueKind::kBool},
    {"repair", "repair", ValueKind::kBool},
    {"weld-epsilon", "weld_epsilon", ValueKind::kNumber},
    // HTTP's `mesh` is the mesh index; the CLI's --mesh is the input file (an alias of IN).
    {"mesh-index", "mesh", ValueKind::kInteger},
    {"primitive", "primitive", ValueKind::kInteger},
    {"primitives", "primitives", ValueKind::kJson},
    {"output", "output", ValueKind::kString},
};

const ParamFlag* find_param_flag(std::string_view name) {
  for (const auto& f : kParamFlags) {
    if (f.flag == name) return &f;
  }
  return nullptr;
}

std::optional<bool> parse_bool(std::string_view v) {
  if (v == "true" || v == "1") return true;
  if (v == "false" || v == "0") return false;
  return std::nullopt;
}

bool all_digits(std::string_view s) {
  return !s.empty() && s.size() <= 10 && s.find_first_not_of("0123456789") == std::string_view::npos;
}

// A value given as JSON where it parses (numbers, booleans, arrays, objects, quoted
// strings), else the text itself as a string ("all", "features").
json json_or_string(const std::string& value) {
  auto parsed = parse_json_limited(value);
  if (parsed.ok()) return std::move(parsed).value();
  return value;
}

ApiResult<json> convert(const ParamFlag& flag, const std::string& value) {
  const std::string name = "--" + std::string(flag.flag);
  const std::string key(flag.key);
  switch (flag.kind) {
    case ValueKind::kString:
      return json(value);
    case ValueKind::kBool: {
      const auto b = parse_bool(value);
      if (!b) return usage_error(key, name + " must be true or false (or no value for true)");
      return json(*b);
    }
    case ValueKind::kInteger:
      if (!all_digits(value)) return usage_error(key, name + " must be a non-negative integer");
      return json(std::stoull(value));
    case ValueKind::kNumber: {
      char* end = nullptr;
      errno = 0;
      const double d = std::strtod(value.c_str(), &end);
      if (value.empty() || end != value.c_str() + value.size() || errno == ERANGE) {
        return usage_error(key, name + " must be a number");
      }
      return json(d);
    }
    case ValueKind::kExtrema: {
      if (value == "auto") return json("auto");
      if (!value.empty() && (value.front() == '[' || value.front() == '{')) {
        auto parsed = parse_json_limited(value);
        if (!parsed.ok()) return usage_error(key, name + ": " + parsed.error().message);
        return std::move(parsed).value();
      }
      json list = json::array();
      std::size_t start = 0;
      while (true) {
        const auto comma = value.find(',', start);
        const std::string item = value.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        if (!all_digits(item)) {
          return usage_error(key, name + " must be auto, comma-separated vertex indices (12,345,678) or JSON");
        }
        list.push_back(std::stoull(item));
        if (comma == std::string::npos) break;
        start = comma + 1;
      }
      return list;
    }
    case ValueKind::kJson:
      return json_or_string(value);
  }
  return usage_error(key, name + ": unknown flag kind");
}

std::string errno_text() { return std::strerror(errno); }

// Read from /proc: umask() can only be read by setting it, which would race with the
// batch workers creating files.
mode_t current_umask() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("Umask:", 0) == 0) return static_cast<mode_t>(std::strtoul(line.c_str() + 6, nullptr, 8));
  }
  return 022;
}

bool is_stdout_path(const std::string& path) {
  return path == "-" || path == "/dev/stdout" || path == "/dev/fd/1" || path == "/proc/self/fd/1";
}

}  // namespace

ApiError usage_error(const std::string& parameter, std::string message) {
  return make_api_error(ApiErrorCode::kInvalidParameter, std::move(message), {{"parameter", parameter}});
}

int fail(std::ostream& err, const ApiError& error, int code) {
  err << error_text(error) << "\n";
  err.flush();
  return code;
}

ApiError with_usage_hint(ApiError error, std::string_view command) {
  error.message += " (seamd " + std::string(command) + " --help shows the usage)";
  return error;
}

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

namespace {

// The flag being read: `--name` or `--name=value`, and the arguments after it.
struct FlagCursor {
  int argc;
  char** argv;
  int& i;  // the flag's index; taking a separate value advances it
  std::string name;
  std::optional<std::string> inline_value;

  std::optional<std::string> take_value() {
    if (inline_value) return inline_value;
    if (i + 1 >= argc) return std::nullopt;
    return std::string(argv[++i]);
  }
  // A following boolean word (`--draco false`), taken only when it is one.
  std::optional<bool> take_bool() {
    if (inline_value || i + 1 >= argc) return std::nullopt;
    const auto b = parse_bool(argv[i + 1]);
    if (b) ++i;
    return b;
  }
};

std::optional<ApiError> take_own_flag(ParsedArgs& args, const OwnFlag& own, FlagCursor& flag) {
  const auto value = flag.take_value();
  if (!value) return usage_error(own.canonical, flag.name + " needs a value");
  if (const auto it = args.own_flag.find(own.canonical); it != args.own_flag.end()) {
    return usage_error(own.canonical, it->second == flag.name ? flag.name + " is given twice"
                                                              : it->second + " and " + flag.name + " are the same flag");
  }
  args.own[own.canonical] = *value;
  args.own_flag[own.canonical] = flag.name;
  return std::nullopt;
}

// An API parameter flag: a listed one (`--no-NAME` for booleans) converted by its kind, or an
// unlisted `--a-b V` as key a_b with V as JSON when it parses.
std::optional<ApiError> take_param_flag(ParsedArgs& args, FlagCursor& flag) {
  std::string flag_name = flag.name.substr(2);
  bool negated = false;
  const ParamFlag* spec = find_param_flag(flag_name);
  if (spec == nullptr && flag_name.rfind("no-", 0) == 0) {
    const ParamFlag* positive = find_param_flag(flag_name.substr(3));
    if (positive != nullptr && positive->kind == ValueKind::kBool) {
      spec = positive;
      negated = true;
    }
  }
  json value;
  std::string key;
  if (spec != nullptr) {
    key = std::string(spec->key);
    if (negated) {
      if (flag.inline_value) return usage_error(key, flag.name + " takes no value");
      value = false;
    } else if (spec->kind == ValueKind::kBool && !flag.inline_value) {
      value = flag.take_bool().value_or(true);  // `--draco` alone is true
    } else {
      const auto text = flag.take_value();
      if (!text) return usage_error(key, flag.name + " needs a value");
      auto converted = convert(*spec, *text);
      if (!converted.ok()) return converted.take_error();
      value = std::move(converted).value();
    }
  } else {
    if (flag_name.empty()) return usage_error(flag.name, "unknown flag " + flag.name);
    key = flag_name;
    for (auto& c : key) c = c == '-' ? '_' : c;
    const auto text = flag.take_value();
    if (!text) return usage_error(key, flag.name + " needs a value (or it is not a flag of this command)");
    value = json_or_string(*text);
    args.generic_key[key] = true;
  }
  if (const auto it = args.flag_of_key.find(key); it != args.flag_of_key.end()) {
    return usage_error(key, it->second == flag.name ? flag.name + " is given twice"
                                                    : it->second + " and " + flag.name + " both set " + key);
  }
  args.param_flags[key] = std::move(value);
  args.flag_of_key[key] = flag.name;
  return std::nullopt;
}

}  // namespace

ApiResult<ParsedArgs> parse_args(int argc, char** argv, const std::vector<OwnFlag>& own_flags) {
  ParsedArgs args;
  bool flags_done = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (flags_done || arg == "-" || arg.empty() || arg[0] != '-') {
      args.positional.push_back(arg);
    } else if (arg == "--") {
      flags_done = true;
    } else if (arg == "--help" || arg == "-h") {
      args.help = true;
    } else if (arg == "--version") {
      args.version = true;
    } else if (arg.rfind("--", 0) != 0) {
      return usage_error(arg, "unknown flag " + arg);
    } else {
      const auto eq = arg.find('=');
      FlagCursor flag{argc, argv, i, arg.substr(0, eq), std::nullopt};
      if (eq != std::string::npos) flag.inline_value = arg.substr(eq + 1);
      const auto own = std::find_if(own_flags.begin(), own_flags.end(), [&](const OwnFlag& f) { return f.name == flag.name; });
      auto error = own != own_flags.end() ? take_own_flag(args, *own, flag) : take_param_flag(args, flag);
      if (error) return *error;
    }
  }
  return args;
}

std::optional<ApiError> set_positional(ParsedArgs& args, const std::string& canonical, const std::string& value,
                                       const std::string& what) {
  if (const auto it = args.own_flag.find(canonical); it != args.own_flag.end()) {
    return usage_error(canonical, what + " is given twice: " + it->second + " " + args.own[canonical] + " and " +
                                      value + " (use one)");
  }
  args.own[canonical] = value;
  args.own_flag[canonical] = what;
  return std::nullopt;
}

ApiResult<SeamParams> build_params(const ParsedArgs& args, json& merged, std::istream& in) {
  merged = json::object();
  if (const auto it = args.own.find("params"); it != args.own.end()) {
    std::string text = it->second;
    if (text == "@-") {
      std::ostringstream ss;
      ss << in.rdbuf();
      if (in.bad()) return usage_error("params", "--params: cannot read stdin");
      text = ss.str();
    } else if (!text.empty() && text[0] == '@') {
      const std::string path = text.substr(1);
      std::ifstream file(path, std::ios::binary);
      if (!file) return usage_error("params", "--params: cannot read " + path + ": " + errno_text());
      std::ostringstream ss;
      ss << file.rdbuf();
      text = ss.str();
    }
    auto parsed = parse_json_limited(text);
    if (!parsed.ok()) return usage_error("params", "--params: " + parsed.error().message);
    if (!parsed->is_object()) return usage_error("params", "--params must be a JSON object, e.g. {\"uv\": \"bff\"}");
    merged = std::move(parsed).value();
  }
  // Flags override --params, key by key.
  for (auto it = args.param_flags.begin(); it != args.param_flags.end(); ++it) merged[it.key()] = it.value();
  auto params = params_from_json(merged);
  if (params.ok()) return params;
  ApiError error = params.take_error();
  const auto parameter = error.details.value("parameter", std::string());
  if (const auto flag = args.flag_of_key.find(parameter); flag != args.flag_of_key.end()) {
    if (args.generic_key.count(parameter) != 0 && error.message.rfind("unknown parameter", 0) == 0) {
      error.message = "unknown flag " + flag->second + ": neither a flag of this command nor an API parameter (" +
                      error.message + ")";
    } else {
      error.message += " (from " + flag->second + ")";
    }
  }
  return error;
}

ApiResult<unsigned> positive_count(const std::string& flag, const std::string& value) {
  if (!all_digits(value) || std::stoull(value) == 0 || std::stoull(value) > 4096) {
    return usage_error(flag, "--" + flag + " must be an integer from 1 to 4096");
  }
  return static_cast<unsigned>(std::stoull(value));
}

ApiResult<std::string> read_input(const std::string& path, std::istream& in) {
  std::ostringstream ss;
  if (path == "-") {
    ss << in.rdbuf();
    return ss.str();
  }
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    return make_api_error(ApiErrorCode::kMalformedAsset, "cannot read " + path + ": it is a directory",
                          {{"path", path}});
  }
  std::ifstream file(path, std::ios::binary);
  if (!file) {
    return make_api_error(ApiErrorCode::kMalformedAsset, "cannot read " + path + ": " + errno_text(),
                          {{"path", path}});
  }
  ss << file.rdbuf();
  if (file.bad()) {
    return make_api_error(ApiErrorCode::kMalformedAsset, "cannot read " + path + ": read error", {{"path", path}});
  }
  return ss.str();
}

ApiResult<LoadedAsset> load_asset(std::string bytes, const std::string& name) {
  LoadedAsset asset;
  const std::string_view view(bytes);
  // The first token after blank lines and '#' comments tells OFF ("OFF", "COFF", "NOFF")
  // and OBJ statements apart from glTF JSON ('{'); binary formats have magics.
  std::string token;
  for (std::size_t i = 0; i < view.size() && i < 4096;) {
    const char c = view[i];
    if (std::isspace(static_cast<unsigned char>(c))) {
      ++i;
    } else if (c == '#') {
      while (i < view.size() && view[i] != '\n') ++i;
    } else {
      while (i < view.size() && !std::isspace(static_cast<unsigned char>(view[i])) && token.size() < 16) {
        token += view[i++];
      }
      break;
    }
  }
  const std::string ext = lower_extension(name);
  const bool glb = view.size() >= 4 && view.substr(0, 4) == "glTF";
  const bool draco = view.substr(0, 5) == "DRACO";
  const bool off = !glb && !draco && (token == "OFF" || token == "COFF" || token == "NOFF" || token == "CNOFF");
  const bool obj = !glb && !draco && !off &&
                   (token == "v" || token == "vt" || token == "vn" || token == "f" || token == "o" || token == "g" ||
                    token == "s" || token == "mtllib" || token == "usemtl" ||
                    (ext == ".obj" && (token.empty() || token[0] != '{')));
  if (off || obj) {
    auto mesh = off ? read_off(view) : read_obj(view);
    if (!mesh.ok()) return mesh.take_error();
    SEAM_TRY(asset.bytes, write_plain_glb(*mesh));
    asset.kind = AssetKind::kGlb;
    asset.format = off ? "off" : "obj";
    return asset;
  }
  asset.kind = detect_asset_kind(view);
  asset.format = draco ? "draco" : asset.kind == AssetKind::kGltfJson ? "gltf" : "glb";
  asset.bytes = std::move(bytes);
  return asset;
}

ApiResult<OutputTarget> check_output(const std::string& path, const std::string& what) {
  OutputTarget target;
  target.path = path;
  auto refuse = [&](const std::string& why) {
    return make_api_error(ApiErrorCode::kInvalidParameter, "cannot write " + what + " " + path + ": " + why,
                          {{"parameter", what}, {"path", path}});
  };
  if (path.empty()) return refuse("the path is empty");
  if (is_stdout_path(path)) {
    target.to_stdout = true;
    return target;
  }
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) return refuse("it is a directory (give a file name)");
    if (::access(path.c_str(), W_OK) != 0) return refuse("the file is not writable (" + errno_text() + ")");
    if (!S_ISREG(st.st_mode)) {
      target.special = true;  // /dev/null, a FIFO: written in place
      return target;
    }
  } else if (errno != ENOENT) {
    return refuse(errno_text());
  }
  // The file is replaced by a rename, so its directory must take a new file.
  fs::path parent = fs::path(path).parent_path();
  if (parent.empty()) parent = ".";
  struct stat dir {};
  if (::stat(parent.c_str(), &dir) != 0) {
    return refuse(errno == ENOENT ? "the directory " + parent.string() + " does not exist"
                                  : parent.string() + ": " + errno_text());
  }
  if (!S_ISDIR(dir.st_mode)) return refuse(parent.string() + " is not a directory");
  if (::access(parent.c_str(), W_OK | X_OK) != 0) {
    return refuse("the directory " + parent.string() + " is not writable (" + errno_text() + ")");
  }
  return target;
}

std::optional<ApiError> write_output(const OutputTarget& target, const std::string& bytes) {
  auto failed = [&](const std::string& why) {
    return make_api_error(ApiErrorCode::kInternal, "cannot write " + target.path + ": " + why,
                          {{"path", target.path}});
  };
  if (target.special) {
    std::ofstream file(target.path, std::ios::binary);
    file.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    file.flush();
    if (!file) return failed(errno_text());
    return std::nullopt;
  }
  fs::path parent = fs::path(target.path).parent_path();
  if (parent.empty()) parent = ".";
  std::string temp = (parent / ("." + fs::path(target.path).filename().string() + ".XXXXXX")).string();
  const int fd = ::mkstemp(temp.data());
  if (fd < 0) return failed(errno_text());
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const std::string why = errno_text();
      ::close(fd);
      ::unlink(temp.c_str());
      return failed(why);
    }
    done += static_cast<std::size_t>(n);
  }
  // mkstemp makes the file 0600; an output file gets the usual mode (0666 minus umask).
  ::fchmod(fd, 0666 & ~current_umask());
  if (::close(fd) != 0 || ::rename(temp.c_str(), target.path.c_str()) != 0) {
    const std::string why = errno_text();
    ::unlink(temp.c_str());
    return failed(why);
  }
  return std::nullopt;
}

std::optional<std::size_t> body_faces(const json& body) {
  if (const auto p = body.find("primitives"); p != body.end() && p->is_array() && !p->empty()) {
    std::size_t faces = 0;
    for (const auto& prim : *p) {
      const auto topology = prim.find("topology");
      if (topology == prim.end() || !topology->contains("faces")) return std::nullopt;
      faces += (*topology)["faces"].get<std::size_t>();
    }
    return faces;
  }
  if (const auto m = body.find("mesh"); m != body.end() && m->is_object() && m->contains("faces")) {
    return (*m)["faces"].get<std::size_t>();
  }
  return std::nullopt;
}

}  // namespace seam::api::cli
