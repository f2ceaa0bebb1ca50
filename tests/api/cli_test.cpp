// The command line: the sample starfish, `seamd seam` (positional and aliased in/out, stdin
// and stdout, every parameter flag against a direct pipeline call, duplicates, outputs
// refused before any work, --help, --version) and `seamd batch` over a folder.
#include <doctest/doctest.h>

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "api/base64.h"
#include "api/cli.h"
#include "api/gltf_reader.h"
#include "api/gltf_writer.h"
#include "api/pipeline.h"
#include "api/sample_mesh.h"
#include "core/mesh/halfedge_mesh.h"
#include "core/mesh/topology.h"
#include "gltf_test_util.h"
#include "test_data.h"

namespace seam_cli_test {

namespace {

using nlohmann::json;
namespace fs = std::filesystem;

struct CliRun {
  int code = -1;
  std::string out, err;
  double seconds = 0;
};

CliRun run(std::vector<std::string> args, const std::string& stdin_bytes = "",
           const seam::api::CliContext& context = {}) {
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  std::istringstream in(stdin_bytes);
  std::ostringstream o, e;
  const auto start = std::chrono::steady_clock::now();
  CliRun r;
  r.code = seam::api::run_cli(static_cast<int>(argv.size()), argv.data(), in, o, e, context);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.out = o.str();
  r.err = e.str();
  return r;
}

int cli(std::vector<std::string> args, std::string& out, std::string& err) {
  const auto r = run(std::move(args));
  out = r.out;
  err = r.err;
  return r.code;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A fresh directory per test case, removed at the end.
struct TempDir {
  fs::path path;
  explicit TempDir(const std::string& name) : path(seam::test_gltf::temp_path(name)) {
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  std::string operator/(const std::string& name) const { return (path / name).string(); }
};

// CGAL's hand (2390 faces) as the plain GLB the CLI makes from the OFF file.
const std::string& hand_glb() {
  static const std::string glb = [] {
    auto mesh = seam::test_data::load_cgal("hand");
    auto bytes = seam::api::write_plain_glb(mesh);
    REQUIRE(bytes.ok());
    return *bytes;
  }();
  return glb;
}

// The pipeline called directly with the HTTP parameter JSON.
seam::api::PipelineOutput direct(const json& params, const std::string& asset = hand_glb()) {
  auto p = seam::api::params_from_json(params);
  REQUIRE_MESSAGE(p.ok(), (p.ok() ? "" : p.error().message));
  auto result = seam::api::run_seam_pipeline(asset, seam::api::AssetKind::kAuto, *p, {}, seam::core::CancelToken::none());
  REQUIRE_MESSAGE(result.ok(), (result.ok() ? "" : result.error().message));
  return std::move(result).value();
}

// The parts of a 200 body that do not depend on the clock.
json stable(json body) {
  body.erase("timings_ms");
  body.erase("asset");
  if (body.contains("primitives")) {
    for (auto& entry : body["primitives"]) entry.erase("timings_ms");
  }
  for (const char* k : {"input", "format", "written", "bytes"}) body.erase(k);
  return body;
}

// Reads a GLB back with the service's own reader; returns the triangles of mesh 0 / primitive 0.
std::size_t glb_triangles(const std::string& glb, bool* has_texcoord = nullptr) {
  auto doc = seam::api::parse_asset(glb, seam::api::AssetKind::kGlb);
  REQUIRE_MESSAGE(doc.ok(), (doc.ok() ? "" : doc.error().message));
  auto prim = seam::api::read_primitive(*doc, 0, 0);
  REQUIRE_MESSAGE(prim.ok(), (prim.ok() ? "" : prim.error().message));
  if (has_texcoord != nullptr) {
    *has_texcoord = false;
    for (const auto& a : prim->attributes) *has_texcoord |= a.name.rfind("TEXCOORD_", 0) == 0;
  }
  return prim->mesh.triangles.size();
}

json error_of(const CliRun& r) {
  const auto body = json::parse(r.err);
  return body.at("error");
}

const std::vector<std::string> kFast = {"--uv", "none", "--refine", "false"};

std::vector<std::string> cat(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

}  // namespace

TEST_CASE("the sample is a closed genus-0 starfish whose five tips are the seam's leaves") {
  using namespace seam;
  const auto m = api::sample_mesh();
  auto mesh = core::build_halfedge_mesh(m.positions, m.triangles);
  REQUIRE(mesh.ok());
  const auto topo = core::compute_topology(*mesh);
  CHECK(topo.components.size() == 1);
  CHECK(topo.total_genus() == 0);
  CHECK(topo.boundary_loops.empty());
  CHECK(m.triangles.size() >= 2000);
  const auto tips = api::sample_tips();
  CHECK(std::set<std::uint32_t>(tips.begin(), tips.end()).size() == 5);

  std::string out, err;
  TempDir dir("sample");
  const std::string sample = dir / "sample.glb";
  const std::string cut = dir / "cut.glb";
  REQUIRE_MESSAGE(cli({"sample", "--out", sample}, out, err) == 0, err);
  std::string report;
  CHECK_MESSAGE(test_gltf::validator_errors(slurp(sample), report) == 0, report);

  std::string extrema;
  for (auto t : tips) extrema += (extrema.empty() ? "" : ",") + std::to_string(t);
  REQUIRE_MESSAGE(cli({"seam", "--mesh", sample, "--extrema", extrema, "--out", cut}, out, err) == 0, err);
  const auto body = nlohmann::json::parse(out);
  CHECK(!body.contains("asset"));
  CHECK(body["written"] == cut);
  CHECK(body["seam"]["extrema"].size() == 5);
  std::map<std::uint32_t, int> degree;
  for (const auto& e : body["seam"]["edges"]) {
    ++degree[e[0].get<std::uint32_t>()];
    ++degree[e[1].get<std::uint32_t>()];
  }
  for (auto t : tips) CHECK(degree[t] == 1);  // every extremum is a leaf (method skeleton)
  CHECK(body["cut"]["euler_characteristic"] == 1);
  CHECK_MESSAGE(test_gltf::validator_errors(slurp(cut), report) == 0, report);

  // The positional form, and `-`: the sample's bytes on stdout, the summary on stderr.
  const auto piped = run({"sample", "-"});
  REQUIRE_MESSAGE(piped.code == 0, piped.err);
  CHECK(piped.out == slurp(sample));
  CHECK(json::parse(piped.err)["tips"].size() == 5);
}

TEST_CASE("seamd seam reads OFF, refuses bad usage with 2 and bad input with 1") {
  std::string out, err;
  const std::string off = seam::test_data::cgal_mesh_path("hand");
  TempDir dir("hand");
  const std::string cut = dir / "hand_cut.glb";
  REQUIRE_MESSAGE(cli({"seam", "--mesh", off, "--uv", "none", "--method", "mst", "--extrema", "0,100", "--out", cut},
                      out, err) == 0,
                  err);
  const auto body = nlohmann::json::parse(out);
  CHECK(body["seam"]["method"] == "mst");
  CHECK(body["uv"].is_null());
  CHECK(body["format"] == "off");
  CHECK(glb_triangles(slurp(cut)) == 2390);

  CHECK(cli({"seam"}, out, err) == 2);
  CHECK(nlohmann::json::parse(err)["error"]["code"] == "invalid_parameter");
  CHECK(cli({"seam", "--mesh", off, "--method", "best"}, out, err) == 2);
  CHECK(nlohmann::json::parse(err)["error"]["message"].get<std::string>().find("--method") != std::string::npos);
  CHECK(cli({"seam", "--mesh", "/nonexistent/x.glb"}, out, err) == 1);
  CHECK(nlohmann::json::parse(err)["error"]["code"] == "malformed_asset");
  CHECK(cli({"frobnicate"}, out, err) == 2);
  CHECK(cli({"seam", off, "a.glb", "b.glb"}, out, err) == 2);
  CHECK(cli({"seam", off, "-x"}, out, err) == 2);
}

TEST_CASE("seamd seam IN OUT writes what a direct pipeline call writes, --mesh and --out are aliases") {
  TempDir dir("positional");
  const std::string off = seam::test_data::cgal_mesh_path("hand");
  const json params = {{"uv", "bff"}, {"refine", false}, {"method", "skeleton"}, {"extrema", {0, 100, 700}}};
  const auto expected = direct(params);

  const std::string a = dir / "a.glb";
  const auto positional = run({"seam", off, a, "--uv", "bff", "--refine", "false", "--extrema", "0,100,700"});
  REQUIRE_MESSAGE(positional.code == 0, positional.err);
  CHECK(positional.err.empty());
  CHECK(slurp(a) == expected.glb);  // byte for byte
  bool texcoord = false;
  CHECK(glb_triangles(slurp(a), &texcoord) == 2390);
  CHECK(texcoord);
  const auto summary = json::parse(positional.out);
  CHECK(stable(summary) == stable(expected.body));
  CHECK(summary["bytes"] == expected.glb.size());
  std::string report;
  CHECK_MESSAGE(seam::test_gltf::validator_errors(slurp(a), report) == 0, report);

  const std::string b = dir / "b.glb";
  const auto aliased = run({"seam", "--mesh", off, "--out", b, "--uv", "bff", "--no-refine", "--extrema", "0,100,700"});
  REQUIRE_MESSAGE(aliased.code == 0, aliased.err);
  CHECK(slurp(b) == expected.glb);

  // An existing output is replaced whole (through a renamed temporary, none left behind).
  seam::test_gltf::write_file(b, std::string(1 << 20, 'x'));
  REQUIRE(run({"seam", off, b, "--uv", "bff", "--refine=false", "--extrema=0,100,700"}).code == 0);
  CHECK(slurp(b) == expected.glb);
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir.path)) ++files;
  CHECK(files == 2);

  // No OUT: only the summary.
  const auto no_out = run({"seam", off, "--uv", "bff", "--refine", "false", "--extrema", "0,100,700"});
  REQUIRE(no_out.code == 0);
  CHECK(stable(json::parse(no_out.out)) == stable(expected.body));
  CHECK(!json::parse(no_out.out).contains("written"));
}

TEST_CASE("seamd seam - - reads stdin and writes only the GLB to stdout, the summary to stderr or --report") {
  TempDir dir("stdio");
  const auto expected = direct({{"uv", "none"}, {"refine", false}});
  const auto piped = run(cat({"seam", "-", "-"}, kFast), hand_glb());
  REQUIRE_MESSAGE(piped.code == 0, piped.err);
  CHECK(piped.out == expected.glb);  // nothing else in the stream
  const auto summary = json::parse(piped.err);
  CHECK(summary["written"] == "-");
  CHECK(summary["format"] == "glb");
  CHECK(stable(summary) == stable(expected.body));

  // /dev/stdout is stdout too (it is not opened, which would truncate a redirected file).
  const auto dev = run(cat({"seam", "-", "/dev/stdout"}, kFast), hand_glb());
  REQUIRE_MESSAGE(dev.code == 0, dev.err);
  CHECK(dev.out == expected.glb);

  // The format comes from the content: OFF text on stdin.
  const auto off_in = run(cat({"seam", "-", "-", "--report", dir / "r.json"}, kFast),
                          slurp(seam::test_data::cgal_mesh_path("hand")));
  REQUIRE_MESSAGE(off_in.code == 0, off_in.err);
  CHECK(off_in.out == expected.glb);
  CHECK(off_in.err.empty());
  const auto report = json::parse(slurp(dir / "r.json"));
  CHECK(report["format"] == "off");
  CHECK(stable(report) == stable(expected.body));

  // A binary GLB is not written to a terminal.
  seam::api::CliContext tty;
  tty.stdout_is_terminal = true;
  const auto refused = run(cat({"seam", "-", "-"}, kFast), hand_glb(), tty);
  CHECK(refused.code == 2);
  CHECK(refused.out.empty());
  CHECK(error_of(refused)["details"]["parameter"] == "out");
}

TEST_CASE("every parameter flag maps onto the HTTP parameter JSON") {
  TempDir dir("flags");
  const std::string off = seam::test_data::cgal_mesh_path("hand");
  struct Case {
    std::vector<std::string> flags;
    json params;
  };
  const std::vector<Case> cases = {
      {{"--uv", "none", "--refine", "false"}, {{"uv", "none"}, {"refine", false}}},
      {{"--uv", "lscm", "--no-refine"}, {{"uv", "lscm"}, {"refine", false}}},
      {{"--uv", "none", "--refine", "true"}, {{"uv", "none"}, {"refine", true}}},
      {{"--uv", "none", "--refine"}, {{"uv", "none"}, {"refine", true}}},
      {{"--uv=none", "--method=greedy"}, {{"uv", "none"}, {"method", "greedy"}}},
      {{"--uv", "none", "--method", "mst", "--extrema", "5,50,500"},
       {{"uv", "none"}, {"method", "mst"}, {"extrema", {5, 50, 500}}}},
      {{"--uv", "none", "--no-refine", "--extrema", R"({"auto": true, "max_count": 2})"},
       {{"uv", "none"}, {"refine", false}, {"extrema", {{"auto", true}, {"max_count", 2}}}}},
      {{"--uv", "none", "--no-refine", "--extrema", "auto"}, {{"uv", "none"}, {"refine", false}, {"extrema", "auto"}}},
      {{"--uv", "none", "--no-refine", "--weld-epsilon", "1e-9"},
       {{"uv", "none"}, {"refine", false}, {"weld_epsilon", 1e-9}}},
      {{"--uv", "none", "--no-refine", "--draco"}, {{"uv", "none"}, {"refine", false}, {"draco", true}}},
      {{"--uv", "none", "--no-refine", "--draco", "false"}, {{"uv", "none"}, {"refine", false}, {"draco", false}}},
      {{"--uv", "none", "--no-refine", "--mesh-index", "0", "--primitive", "0"},
       {{"uv", "none"}, {"refine", false}, {"mesh", 0}, {"primitive", 0}}},
      // Unlisted flags reach params_from_json as JSON: --weld_epsilon spelled as the key.
      {{"--uv", "none", "--no-refine", "--weld_epsilon", "0"}, {{"uv", "none"}, {"refine", false}, {"weld_epsilon", 0}}},
  };
  for (const auto& c : cases) {
    CAPTURE(c.params.dump());
    const std::string path = dir / "out.glb";
    const auto r = run(cat({"seam", off, path}, c.flags));
    REQUIRE_MESSAGE(r.code == 0, r.err);
    const auto expected = direct(c.params);
    CHECK(stable(json::parse(r.out)) == stable(expected.body));
    CHECK(slurp(path) == expected.glb);
  }

  SUBCASE("--draco writes a Draco-compressed primitive") {
    const auto r = run(cat({"seam", off, dir / "d.glb", "--draco"}, kFast));
    REQUIRE_MESSAGE(r.code == 0, r.err);
    CHECK(json::parse(r.out)["draco"] == true);
    CHECK(slurp(dir / "d.glb").find("KHR_draco_mesh_compression") != std::string::npos);
    CHECK(glb_triangles(slurp(dir / "d.glb")) == 2390);
  }
  SUBCASE("--mesh-index and --primitive select (HTTP's mesh and primitive)") {
    const auto r = run(cat({"seam", off, "--mesh-index", "1"}, kFast));
    CHECK(r.code == 1);
    CHECK(error_of(r)["code"] == "no_triangle_primitive");
    CHECK(run(cat({"seam", off, "--primitive", "2"}, kFast)).code == 1);
    const auto bad = run({"seam", off, "--mesh-index", "first"});
    CHECK(bad.code == 2);
    CHECK(error_of(bad)["message"].get<std::string>().find("--mesh-index") != std::string::npos);
  }
  SUBCASE("--output json writes the HTTP JSON body, the asset in base64") {
    const auto r = run(cat({"seam", off, dir / "o.json", "--output", "json"}, kFast));
    REQUIRE_MESSAGE(r.code == 0, r.err);
    const auto body = json::parse(slurp(dir / "o.json"));
    const auto glb = seam::api::decode_base64(body["asset"]["glb_base64"].get<std::string>());
    REQUIRE(glb.ok());
    CHECK(*glb == direct({{"uv", "none"}, {"refine", false}}).glb);
    CHECK(!json::parse(r.out).contains("asset"));
    const auto bad = run({"seam", off, "--output", "svgz"});
    CHECK(bad.code == 2);
    CHECK(error_of(bad)["details"]["parameter"] == "output");
  }
  SUBCASE("bad values are usage errors naming the flag") {
    for (const auto& flags : std::vector<std::vector<std::string>>{{"--weld-epsilon", "abc"},
                                                                    {"--extrema", "1,x"},
                                                                    {"--uv", "fancy"},
                                                                    {"--draco=maybe"},
                                                                    {"--no-draco=1"},
                                                                    {"--frobnicate", "1"},
                                                                    {"--uv"}}) {
      CAPTURE(flags[0]);
      const auto r = run(cat({"seam", off}, flags));
      CHECK(r.code == 2);
      CHECK(r.out.empty());
      CHECK(error_of(r)["code"] == "invalid_parameter");
      const std::string flag = flags[0].substr(0, flags[0].find('='));
      CHECK(error_of(r)["message"].get<std::string>().find(flag) != std::string::npos);
    }
  }
}

TEST_CASE("--params JSON|@file|@- is the HTTP parameter object, flags override it key by key") {
  TempDir dir("params");
  const std::string off = seam::test_data::cgal_mesh_path("hand");
  const json params = {{"uv", "none"}, {"method", "mst"}, {"extrema", {3, 30, 300}}, {"refine", false}};
  const auto expected = direct(params);

  const auto inline_json = run({"seam", off, "--params", params.dump()});
  REQUIRE_MESSAGE(inline_json.code == 0, inline_json.err);
  CHECK(stable(json::parse(inline_json.out)) == stable(expected.body));

  seam::test_gltf::write_file(dir / "p.json", params.dump());
  const auto from_file = run({"seam", off, "--params", "@" + dir / "p.json"});
  REQUIRE_MESSAGE(from_file.code == 0, from_file.err);
  CHECK(stable(json::parse(from_file.out)) == stable(expected.body));

  // @- reads the parameters from stdin; stdin cannot also be IN.
  const auto from_stdin = run({"seam", off, "--params", "@-"}, params.dump());
  REQUIRE_MESSAGE(from_stdin.code == 0, from_stdin.err);
  CHECK(stable(json::parse(from_stdin.out)) == stable(expected.body));
  const auto both = run({"seam", "-", "--params", "@-"}, params.dump());
  CHECK(both.code == 2);
  CHECK(error_of(both)["message"].get<std::string>().find("stdin cannot be both") != std::string::npos);

  // --method and --extrema win over the file's.
  const auto overridden = run({"seam", off, "--params=@" + dir / "p.json", "--method", "greedy", "--extrema", "4,40"});
  REQUIRE_MESSAGE(overridden.code == 0, overridden.err);
  json merged = params;
  merged["method"] = "greedy";
  merged["extrema"] = {4, 40};
  CHECK(stable(json::parse(overridden.out)) == stable(direct(merged).body));
  CHECK(json::parse(overridden.out)["seam"]["method"] == "greedy");

  CHECK(run({"seam", off, "--params", "[1]"}).code == 2);
  CHECK(run({"seam", off, "--params", "{\"uv\": 3}"}).code == 2);
  const auto missing = run({"seam", off, "--params", "@" + dir / "none.json"});
  CHECK(missing.code == 2);
  CHECK(error_of(missing)["message"].get<std::string>().find("none.json") != std::string::npos);
  const auto unknown = run({"seam", off, "--params", R"({"colour": "red"})"});
  CHECK(unknown.code == 2);
  CHECK(error_of(unknown)["details"]["parameter"] == "colour");
}

TEST_CASE("a flag given twice, or a flag and its alias, is a usage error") {
  const std::string off = seam::test_data::cgal_mesh_path("hand");
  for (const auto& args : std::vector<std::vector<std::string>>{
           {"seam", off, "--uv", "none", "--uv", "bff"},
           {"seam", off, "--draco", "--no-draco"},
           {"seam", off, "--refine", "false", "--refine=true"},
           {"seam", off, "--mesh", off},
           {"seam", "--mesh", off, "--mesh", off},
           {"seam", off, "x.glb", "--out", "y.glb"},
           {"seam", off, "--out", "x.glb", "--out", "x.glb"},
           {"seam", off, "--params", "{}", "--params", "{}"},
           {"seam", off, "--weld-epsilon", "0", "--weld_epsilon", "0"},
       }) {
    CAPTURE(args[2]);
    const auto r = run(args);
    CHECK(r.code == 2);
    CHECK(r.out.empty());
    const std::string message = error_of(r)["message"];
    CHECK_MESSAGE((message.find("twice") != std::string::npos || message.find("both") != std::string::npos ||
                   message.find("same flag") != std::string::npos),
                  message);
  }
}

TEST_CASE("--help prints the usage on stdout with exit 0, --version prints the version") {
  for (const char* command : {"seam", "batch", "sample"}) {
    const auto help = run({command, "--help"});
    CHECK(help.code == 0);
    CHECK(help.err.empty());
    CHECK(help.out == seam::api::cli_usage());
    CHECK(help.out.find("seamd seam IN [OUT]") != std::string::npos);
    CHECK(help.out.find("--mesh-index N") != std::string::npos);
    CHECK(help.out.find("--out-dir DIR") != std::string::npos);
  }
  CHECK(run({"seam", "-h"}).code == 0);
  // Help wins over anything else on the line, even a bad flag value.
  CHECK(run({"seam", "in.glb", "--help"}).code == 0);

  seam::api::CliContext context;
  context.version = "9.8.7";
  for (const auto& args : std::vector<std::vector<std::string>>{{"--version"}, {"seam", "--version"}, {"batch", "--version"}}) {
    const auto v = run(args, "", context);
    CHECK(v.code == 0);
    CHECK(v.out == "seamd 9.8.7\n");
    CHECK(v.err.empty());
  }
}

TEST_CASE("an unwritable output is refused with exit 2 before any work, naming the path") {
  TempDir dir("unwritable");
  // camel: about 2 s of work with the defaults; the refusal comes before it is read.
  const std::string camel = seam::test_data::cgal_mesh_path("camel");
  seam::test_gltf::write_file(dir / "file", "x");
  std::vector<std::string> refused = {
      dir.path.string(),           // a directory
      dir / "missing/out.glb",     // a missing directory
      dir / "file/out.glb",        // a parent that is a file
      "",                          // no path at all
  };
  if (::geteuid() != 0) {  // root writes anywhere: a read-only directory only stops others
    fs::create_directories(dir / "ro");
    fs::permissions(dir / "ro", fs::perms::owner_read | fs::perms::owner_exec);
    refused.push_back(dir / "ro/out.glb");
  }
  for (const auto& path : refused) {
    CAPTURE(path);
    for (const auto& args : std::vector<std::vector<std::string>>{{"seam", camel, path},
                                                                   {"seam", camel, "--out", path},
                                                                   {"seam", camel, "--report", path}}) {
      const auto r = run(args);
      CHECK(r.code == 2);
      CHECK(r.seconds < 0.5);
      CHECK(r.out.empty());
      const auto error = error_of(r);
      CHECK(error["code"] == "invalid_parameter");
      CHECK(error["details"]["path"] == path);
      CHECK(error["message"].get<std::string>().find(path) != std::string::npos);
    }
  }
  // Checked before the input is even read: a missing input with a bad output is a usage error.
  CHECK(run({"seam", dir / "nope.off", dir / "missing/out.glb"}).code == 2);
  CHECK(!fs::exists(dir / "missing"));
  if (fs::exists(dir / "ro")) fs::permissions(dir / "ro", fs::perms::owner_all, fs::perm_options::add);
}

TEST_CASE("seamd batch cuts a folder over two workers, keeps going past a failure and reports both") {
  TempDir dir("batch");
  const std::string in = dir / "in";
  fs::create_directories(fs::path(in) / "sub");
  fs::copy_file(seam::test_data::cgal_mesh_path("hand"), fs::path(in) / "hand.off");
  const auto sample = seam::api::sample_glb();
  REQUIRE(sample.ok());
  seam::test_gltf::write_file(in + "/sub/star.glb", *sample);
  seam::test_gltf::write_file(in + "/broken.obj", "v 0 0 0\nv 1 0 0\nf 1 2 9\n");
  seam::test_gltf::write_file(in + "/notes.txt", "not an asset");
  const std::string out_dir = dir / "out";

  const auto r = run(cat({"batch", in, "--out-dir", out_dir, "--workers", "2"}, kFast));
  CHECK(r.code == 1);
  CHECK(r.out.empty());

  // One progress line per asset (name, faces, seconds, status), then the summary.
  std::istringstream lines(r.err);
  std::vector<std::string> progress;
  for (std::string line; std::getline(lines, line);) progress.push_back(line);
  REQUIRE(progress.size() == 4);
  auto line_of = [&](const std::string& name) {
    for (const auto& l : progress) {
      if (l.find("] " + name + " ") != std::string::npos) return l;
    }
    FAIL("no progress line for " << name << " in\n" << r.err);
    return std::string();
  };
  CHECK(line_of("hand.off").find("2,390 faces") != std::string::npos);
  CHECK(line_of("hand.off").find(" s  ok") != std::string::npos);
  CHECK(line_of("sub/star.glb").find("5,120 faces") != std::string::npos);
  CHECK(progress[3].find("batch: 3 assets, 2 ok, 1 failed") != std::string::npos);

  const auto report = json::parse(slurp(out_dir + "/report.json"));
  CHECK(report["summary"]["assets"] == 3);
  CHECK(report["summary"]["ok"] == 2);
  CHECK(report["summary"]["failed"] == 1);
  CHECK(report["workers"] == 2);
  REQUIRE(report["assets"].size() == 3);
  std::map<std::string, json> by_name;
  for (const auto& a : report["assets"]) by_name[fs::path(a["input"].get<std::string>()).filename().string()] = a;
  CHECK(by_name["broken.obj"]["status"] == "failed");
  const std::string broken_code = by_name["broken.obj"]["error"]["code"];
  CHECK(broken_code == "malformed_asset");  // face 1 2 9 of a two-vertex OBJ
  CHECK(line_of("broken.obj").find("? faces") != std::string::npos);
  CHECK(line_of("broken.obj").find("failed: " + broken_code) != std::string::npos);
  CHECK(by_name["broken.obj"]["output"].is_null());
  CHECK(!fs::exists(out_dir + "/broken.glb"));

  // The outputs are the GLBs a direct call writes, read back by the service's reader.
  const auto hand = direct({{"uv", "none"}, {"refine", false}});
  CHECK(by_name["hand.off"]["status"] == "ok");
  CHECK(by_name["hand.off"]["faces"] == 2390);
  CHECK(by_name["hand.off"]["output"] == out_dir + "/hand.glb");
  CHECK(slurp(out_dir + "/hand.glb") == hand.glb);
  CHECK(stable(by_name["hand.off"]["result"]) == stable(hand.body));
  const auto star = direct({{"uv", "none"}, {"refine", false}}, *sample);
  CHECK(by_name["star.glb"]["status"] == "ok");
  CHECK(slurp(out_dir + "/sub/star.glb") == star.glb);  // the folder's layout is mirrored
  CHECK(glb_triangles(slurp(out_dir + "/sub/star.glb")) == 5120);
  CHECK(by_name["star.glb"]["result"]["seam"]["edges"] == star.body["seam"]["edges"]);

  // A rerun into the same folder does not take its own outputs for inputs; --report moves
  // the report; all good files: exit 0.
  const auto again = run(cat({"batch", in + "/hand.off", in + "/sub", in, "--out-dir", in + "/out", "--report",
                              dir / "r.json"},
                             kFast));
  CHECK(again.code == 1);  // broken.obj again
  CHECK(json::parse(slurp(dir / "r.json"))["summary"]["assets"] == 3);  // hand.off once
  const auto good = run(cat({"batch", in + "/hand.off", "--out-dir", out_dir, "--workers", "1"}, kFast));
  CHECK(good.code == 0);

  // Usage errors, before any work.
  CHECK(run({"batch", in}).code == 2);                                  // no --out-dir
  CHECK(run({"batch", "--out-dir", out_dir}).code == 2);                // no input
  CHECK(run({"batch", dir / "nothing", "--out-dir", out_dir}).code == 2);
  CHECK(run({"batch", in, "--out-dir", dir / "in/hand.off"}).code == 2);  // a file
  CHECK(run({"batch", in, "--out-dir", out_dir, "--workers", "0"}).code == 2);
  seam::test_gltf::write_file(in + "/hand.obj", "v 0 0 0\n");
  const auto clash = run({"batch", in, "--out-dir", dir / "clash"});
  CHECK(clash.code == 2);  // hand.obj and hand.off would both be hand.glb
  CHECK(error_of(clash)["message"].get<std::string>().find("hand.glb") != std::string::npos);
}

}  // namespace seam_cli_test
