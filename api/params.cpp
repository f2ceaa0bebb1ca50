// Parsing the POST /seam parameters (API.md "Parameters") from JSON or the query string.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "api/json_limits.h"
#include "api/params.h"

namespace seam::api {
namespace {

using nlohmann::json;

// Parameter names come from the client: details carry at most 60 bytes of one (a 3 KB key
// given twice was echoed whole; request_fuzz).
ApiError invalid(const std::string& name, std::string message) {
  return make_api_error(ApiErrorCode::kInvalidParameter, std::move(message), {{"parameter", name.substr(0, 60)}});
}

ApiResult<std::uint32_t> vertex_index(const json& v, const std::string& name) {
  if (v.is_number_unsigned() || (v.is_number_integer() && v.get<std::int64_t>() >= 0)) {
    const auto u = v.get<std::uint64_t>();
    if (u < std::numeric_limits<std::uint32_t>::max()) return static_cast<std::uint32_t>(u);
  }
  // Described, never dumped: a value nested 60,000 deep would overflow the stack in dump().
  return invalid(name, name + ": vertex indices must be non-negative integers below 2^32-1, got " + describe_json(v));
}

ApiResult<std::vector<std::uint32_t>> index_list(const json& v, const std::string& name) {
  if (!v.is_array()) return invalid(name, name + " must be an array of vertex indices");
  std::vector<std::uint32_t> out;
  for (const auto& e : v) {
    SEAM_TRY(const std::uint32_t i, vertex_index(e, name));
    out.push_back(i);
  }
  return out;
}

ApiResult<std::array<double, 3>> position(const json& v) {
  const auto it = v.find("position");
  if (v.size() != 1 || it == v.end() || !it->is_array() || it->size() != 3) {
    return invalid("extrema", "extrema: a position must be {\"position\": [x, y, z]}");
  }
  std::array<double, 3> p{};
  for (int c = 0; c < 3; ++c) {
    const auto& x = (*it)[static_cast<std::size_t>(c)];
    if (!x.is_number() || !std::isfinite(x.get<double>())) {
      return invalid("extrema", "extrema: position coordinates must be finite numbers");
    }
    p[static_cast<std::size_t>(c)] = x.get<double>();
  }
  return p;
}

ApiResult<ExtremaSpec> extrema_from_json(const json& v) {
  ExtremaSpec spec;
  if (v.is_string()) {
    if (v.get<std::string>() != "auto") return invalid("extrema", "extrema must be \"auto\", an array or an object");
    spec.automatic = true;
    return spec;
  }
  if (v.is_array()) {
    spec.automatic = false;
    for (const auto& e : v) {
      if (e.is_object()) {
        SEAM_TRY(const auto p, position(e));
        spec.positions.push_back(p);
      } else {
        SEAM_TRY(const std::uint32_t i, vertex_index(e, "extrema"));
        spec.indices.push_back(i);
      }
    }
    if (spec.indices.empty() && spec.positions.empty()) {
      return invalid("extrema", "extrema: the array is empty; give vertex indices, positions or \"auto\"");
    }
    return spec;
  }
  if (v.is_object()) {
    // Our addition: {"auto": true, "include": [...], "exclude": [...], "min_protrusion": 0.15, "max_count": 16}
    for (auto it = v.begin(); it != v.end(); ++it) {
      const std::string& key = it.key();
      if (key == "auto") {
        if (!it->is_boolean()) return invalid("extrema.auto", "extrema.auto must be a boolean");
        spec.automatic = it->get<bool>();
      } else if (key == "include") {
        if (!it->is_array()) return invalid("extrema.include", "extrema.include must be an array");
        for (const auto& e : *it) {
          if (e.is_object()) {
            SEAM_TRY(const auto p, position(e));
            spec.positions.push_back(p);
          } else {
            SEAM_TRY(const std::uint32_t i, vertex_index(e, "extrema.include"));
            spec.indices.push_back(i);
          }
        }
      } else if (key == "exclude") {
        SEAM_TRY(spec.exclude, index_list(*it, "extrema.exclude"));
      } else if (key == "min_protrusion") {
        if (!it->is_number() || !std::isfinite(it->get<double>()) || it->get<double>() < 0) {
          return invalid("extrema.min_protrusion", "extrema.min_protrusion must be a number >= 0");
        }
        spec.auto_options.min_protrusion = it->get<double>();
      } else if (key == "max_count") {
        SEAM_TRY(const std::uint32_t n, vertex_index(*it, "extrema.max_count"));
        // 0 used to be taken and ignored (detection kept its default); "no automatic
        // extrema" is said with auto false.
        if (n == 0) {
          return invalid("extrema.max_count",
                         "extrema.max_count must be at least 1; for no automatic extrema give "
                         "{\"auto\": false, \"include\": [...]}");
        }
        spec.auto_options.max_count = n;
      } else {
        return invalid("extrema." + key.substr(0, 60), "extrema: unknown key \"" + key.substr(0, 60) +
                                             "\" (known: auto, include, exclude, min_protrusion, max_count)");
      }
    }
    if (!spec.automatic && spec.indices.empty() && spec.positions.empty()) {
      return invalid("extrema", "extrema: with auto false, give include");
    }
    return spec;
  }
  return invalid("extrema", "extrema must be \"auto\", an array of vertex indices or positions, or an object");
}

ApiResult<std::uint32_t> small_index(const json& v, const std::string& name) {
  if (v.is_number_integer() && v.get<std::int64_t>() >= 0 && v.get<std::int64_t>() < (std::int64_t{1} << 31)) {
    return static_cast<std::uint32_t>(v.get<std::int64_t>());
  }
  return invalid(name, name + " must be a non-negative integer");
}

ApiResult<PrimitiveSelector> selector_from_json(const json& v) {
  if (!v.is_object()) {
    return invalid("primitives", "primitives: each entry must be an object such as {\"mesh\": 0, \"primitive\": 1} "
                                 "or {\"mesh\": \"Body\"}");
  }
  PrimitiveSelector out;
  for (auto it = v.begin(); it != v.end(); ++it) {
    const std::string& key = it.key();
    if (key == "mesh") {
      if (it->is_string()) {
        out.mesh_name = it->get<std::string>();
      } else {
        SEAM_TRY(out.mesh, small_index(*it, "primitives.mesh"));
      }
    } else if (key == "primitive") {
      SEAM_TRY(out.primitive, small_index(*it, "primitives.primitive"));
    } else if (key == "extrema") {
      SEAM_TRY(out.extrema, extrema_from_json(*it));
    } else {
      return invalid("primitives." + key.substr(0, 60), "primitives: unknown key \"" + key.substr(0, 60) +
                                                            "\" in an entry (known: mesh, primitive, extrema)");
    }
  }
  if (!out.mesh && out.mesh_name.empty()) {
    return invalid("primitives.mesh", "primitives: every entry needs \"mesh\" (an index or a mesh name)");
  }
  return out;
}

ApiResult<std::optional<std::vector<PrimitiveSelector>>> primitives_from_json(const json& v) {
  if (v.is_string() && v.get<std::string>() == "all") return std::optional<std::vector<PrimitiveSelector>>{};
  if (!v.is_array() || v.empty()) {
    return invalid("primitives", "primitives must be \"all\" or a non-empty array of {\"mesh\": i or \"name\", "
                                 "\"primitive\": j, \"extrema\": ...} entries");
  }
  std::vector<PrimitiveSelector> out;
  for (const auto& e : v) {
    SEAM_TRY(PrimitiveSelector s, selector_from_json(e));
    out.push_back(std::move(s));
  }
  return std::optional<std::vector<PrimitiveSelector>>(std::move(out));
}

ApiResult<PackParams> pack_from_json(const json& v) {
  PackParams out;
  if (v.is_boolean()) {
    out.enabled = v.get<bool>();
    return out;
  }
  if (!v.is_object()) return invalid("pack", "pack must be an object ({\"group_by\": ..., \"texture_size\": ...}) or false");
  for (auto it = v.begin(); it != v.end(); ++it) {
    const std::string& key = it.key();
    const json& x = *it;
    if (key == "group_by") {
      const std::string g = x.is_string() ? x.get<std::string>() : "";
      if (g == "asset") out.group_by = PackGroup::kAsset;
      else if (g == "mesh") out.group_by = PackGroup::kMesh;
      else if (g == "material") out.group_by = PackGroup::kMaterial;
      else if (g == "primitive") out.group_by = PackGroup::kPrimitive;
      else return invalid("pack.group_by", "pack.group_by must be one of asset, mesh, material, primitive");
    } else if (key == "texture_size") {
      if (!x.is_number_integer() || x.get<std::int64_t>() < 16 || x.get<std::int64_t>() > 65536) {
        return invalid("pack.texture_size", "pack.texture_size must be an integer from 16 to 65536");
      }
      out.texture_size = static_cast<int>(x.get<std::int64_t>());
      out.sized_by_caller = true;
    } else if (key == "margin_px") {
      if (!x.is_number() || !std::isfinite(x.get<double>()) || x.get<double>() < 0) {
        return invalid("pack.margin_px", "pack.margin_px must be a number >= 0");
      }
      out.margin_px = x.get<double>();
      out.sized_by_caller = true;
    } else if (key == "rotate") {
      if (!x.is_boolean()) return invalid("pack.rotate", "pack.rotate must be true or false");
      out.rotate = x.get<bool>();
    } else if (key == "split") {
      if (!x.is_boolean()) return invalid("pack.split", "pack.split must be true or false");
      out.split = x.get<bool>();
    } else {
      return invalid("pack." + key.substr(0, 60), "pack: unknown key \"" + key.substr(0, 60) +
                                                      "\" (known: group_by, texture_size, margin_px, rotate, split)");
    }
  }
  if (out.margin_px > out.texture_size / 8.0) {
    return invalid("pack.margin_px", "pack.margin_px must be at most texture_size / 8 (" +
                                         std::to_string(out.texture_size / 8) + ")");
  }
  return out;
}

ApiResult<std::vector<std::array<double, 3>>> views_from_json(const json& v) {
  if (!v.is_array() || v.empty() || v.size() > 64) {
    return invalid("hide_from", "hide_from must be an array of 1 to 64 view directions [x, y, z]");
  }
  std::vector<std::array<double, 3>> out;
  for (const auto& d : v) {
    if (!d.is_array() || d.size() != 3) return invalid("hide_from", "hide_from: each view direction is [x, y, z]");
    std::array<double, 3> p{};
    for (std::size_t c = 0; c < 3; ++c) {
      if (!d[c].is_number() || !std::isfinite(d[c].get<double>())) {
        return invalid("hide_from", "hide_from: coordinates must be finite numbers");
      }
      p[c] = d[c].get<double>();
    }
    if (p[0] == 0 && p[1] == 0 && p[2] == 0) return invalid("hide_from", "hide_from: a view direction cannot be [0, 0, 0]");
    out.push_back(p);
  }
  return out;
}

// A string parameter that names one of a few choices.
template <class T>
ApiResult<T> choice(const json& v, const char* key, std::initializer_list<std::pair<const char*, T>> choices,
                    const char* message) {
  const std::string m = v.is_string() ? v.get<std::string>() : "";
  for (const auto& [name, value] : choices) {
    if (m == name) return value;
  }
  return invalid(key, message);
}

ApiResult<bool> boolean(const json& v, const std::string& key) {
  if (!v.is_boolean()) return invalid(key, key + " must be true or false");
  return v.get<bool>();
}

ApiResult<double> number_in(const json& v, const char* key, double lo, double hi, const char* message) {
  if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < lo || v.get<double>() > hi) {
    return invalid(key, message);
  }
  return v.get<double>();
}

using ApiStatus = ApiResult<core::Ok>;
using Setter = ApiStatus (*)(SeamParams&, const json&);

// Every parameter the API takes, in the order the unknown-parameter error lists them.
// `mesh` as an object is the JSON request form's asset, which the server removes first.
const std::vector<std::pair<std::string, Setter>>& parameter_setters() {
  static const std::vector<std::pair<std::string, Setter>> setters = {
      {"extrema", [](SeamParams& p, const json& v) -> ApiStatus { SEAM_TRY(p.extrema, extrema_from_json(v)); return core::Ok{}; }},
      {"mesh", [](SeamParams& p, const json& v) -> ApiStatus {
         if (!v.is_object()) {
           SEAM_TRY(p.mesh, small_index(v, "mesh"));
         }
         return core::Ok{};
       }},
      {"primitive", [](SeamParams& p, const json& v) -> ApiStatus { SEAM_TRY(p.primitive, small_index(v, "primitive")); return core::Ok{}; }},
      {"primitives", [](SeamParams& p, const json& v) -> ApiStatus { SEAM_TRY(p.primitives, primitives_from_json(v)); return core::Ok{}; }},
      {"method", [](SeamParams& p, const json& v) -> ApiStatus {
         SEAM_TRY(p.method, choice<core::SeamMethod>(v, "method",
                                                     {{"skeleton", core::SeamMethod::kSkeleton}, {"mst", core::SeamMethod::kMst},
                                                      {"greedy", core::SeamMethod::kGreedy}, {"optimal", core::SeamMethod::kOptimal}},
                                                     "method must be one of skeleton, mst, greedy, optimal"));
         return core::Ok{};
       }},
      {"uv", [](SeamParams& p, const json& v) -> ApiStatus {
         using Uv = std::optional<core::UvMethod>;
         SEAM_TRY(p.uv, choice<Uv>(v, "uv",
                                   {{"slim", core::UvMethod::kSlim}, {"arap", core::UvMethod::kArap}, {"bff", core::UvMethod::kBff},
                                    {"lscm", core::UvMethod::kLscm}, {"none", std::nullopt}},
                                   "uv must be one of slim, arap, bff, lscm, none"));
         return core::Ok{};
       }},
      {"output", [](SeamParams& p, const json& v) -> ApiStatus {
         SEAM_TRY(p.output, choice<OutputFormat>(v, "output",
                                                 {{"json", OutputFormat::kJson}, {"glb", OutputFormat::kGlb}, {"svg", OutputFormat::kSvg}},
                                                 "output must be \"json\", \"glb\" or \"svg\""));
         p.output_given = true;
         return core::Ok{};
       }},
      {"draco", [](SeamParams& p, const json& v) -> ApiStatus { SEAM_TRY(p.draco, boolean(v, "draco")); return core::Ok{}; }},
      {"refine", [](SeamParams& p, const json& v) -> ApiStatus { SEAM_TRY(p.refine, boolean(v, "refine")); return core::Ok{}; }},
      {"repair", [](SeamParams& p, const json& v) -> ApiStatus { SEAM_TRY(p.repair, boolean(v, "repair")); return core::Ok{}; }},
      {"weld_epsilon", [](SeamParams& p, const json& v) -> ApiStatus {
         SEAM_TRY(p.weld_epsilon, number_in(v, "weld_epsilon", 0, std::numeric_limits<double>::infinity(),
                                            "weld_epsilon must be a finite number >= 0"));
         return core::Ok{};
       }},
      {"pack", [](SeamParams& p, const json& v) -> ApiStatus { SEAM_TRY(p.pack, pack_from_json(v)); return core::Ok{}; }},
      {"charts", [](SeamParams& p, const json& v) -> ApiStatus {
         SEAM_TRY(p.charts, choice<ChartMode>(v, "charts", {{"seam", ChartMode::kSeam}, {"features", ChartMode::kFeatures}},
                                              "charts must be \"seam\" or \"features\""));
         return core::Ok{};
       }},
      {"feature_angle_deg", [](SeamParams& p, const json& v) -> ApiStatus {
         SEAM_TRY(p.feature_angle_deg, number_in(v, "feature_angle_deg", 0, 180, "feature_angle_deg must be a number from 0 to 180"));
         return core::Ok{};
       }},
      {"hide_from", [](SeamParams& p, const json& v) -> ApiStatus { SEAM_TRY(p.hide_from, views_from_json(v)); return core::Ok{}; }},
      {"hide_occluded", [](SeamParams& p, const json& v) -> ApiStatus { SEAM_TRY(p.hide_occluded, boolean(v, "hide_occluded")); return core::Ok{}; }},
      {"hide_strength", [](SeamParams& p, const json& v) -> ApiStatus {
         SEAM_TRY(p.hide_strength, number_in(v, "hide_strength", 0, 1000, "hide_strength must be a number from 0 to 1000"));
         return core::Ok{};
       }},
  };
  return setters;
}

ApiError unknown_parameter(const std::string& key) {
  std::string known;
  for (const auto& [name, _] : parameter_setters()) known += (known.empty() ? "" : ", ") + name;
  return invalid(key, "unknown parameter \"" + key.substr(0, 60) + "\" (known: " + known + ")");
}

}  // namespace

ApiResult<SeamParams> params_from_json(const json& params) {
  if (!params.is_object()) return invalid("params", "the parameters must be a JSON object");
  SeamParams out;
  for (auto it = params.begin(); it != params.end(); ++it) {
    const auto& setters = parameter_setters();
    const auto setter = std::find_if(setters.begin(), setters.end(), [&](const auto& s) { return s.first == it.key(); });
    if (setter == setters.end()) return unknown_parameter(it.key());
    SEAM_TRY(core::Ok ok, setter->second(out, *it));
    (void)ok;
  }
  if (params.contains("feature_angle_deg") && out.charts != ChartMode::kFeatures) {
    // Only the feature cut reads the angle: taking it alone would silently change nothing.
    return invalid("feature_angle_deg",
                   "feature_angle_deg only applies with charts \"features\" (sharp edges are "
                   "cut only then): add \"charts\": \"features\" or leave the angle out");
  }
  if (params.contains("primitives") && (out.mesh || out.primitive)) {
    return invalid("primitives", "primitives cannot be combined with mesh or primitive (v1's single-primitive "
                                 "selection): name the primitive as {\"primitives\": [{\"mesh\": i, \"primitive\": j}]}");
  }
  return out;
}

namespace {

// How a query-string value becomes the JSON value it stands for.
enum class QueryKind {
  kString,      // method=mst
  kIndex,       // mesh=0: decimal digits
  kBoolean,     // true, false, 1, 0
  kNumber,      // JSON number syntax: decimal only (0x10, inf, nan are refused)
  kExtrema,     // auto, 12,345,678, or JSON (an array with positions, the object form)
  kPrimitives,  // all, or JSON
  kPack,        // true, false, 1, 0, or a JSON object
  kJson,        // JSON (hide_from)
};

QueryKind query_kind(const std::string& key) {
  static const std::vector<std::pair<std::string, QueryKind>> kinds = {{"mesh", QueryKind::kIndex},
                                                                       {"primitive", QueryKind::kIndex},
                                                                       {"draco", QueryKind::kBoolean},
                                                                       {"refine", QueryKind::kBoolean},
                                                                       {"repair", QueryKind::kBoolean},
                                                                       {"hide_occluded", QueryKind::kBoolean},
                                                                       {"weld_epsilon", QueryKind::kNumber},
                                                                       {"hide_strength", QueryKind::kNumber},
                                                                       {"feature_angle_deg", QueryKind::kNumber},
                                                                       {"extrema", QueryKind::kExtrema},
                                                                       {"primitives", QueryKind::kPrimitives},
                                                                       {"pack", QueryKind::kPack},
                                                                       {"hide_from", QueryKind::kJson}};
  for (const auto& [name, kind] : kinds) {
    if (name == key) return kind;
  }
  return QueryKind::kString;  // strings; unknown keys are refused by params_from_json
}

// A value in JSON syntax (URL-decoded), with the depth limit every client JSON has.
ApiResult<json> query_json(const std::string& key, const std::string& value, const std::string& expected) {
  auto parsed = parse_json_limited(value);
  if (parsed.ok()) return std::move(parsed).value();
  ApiError error = parsed.take_error();
  json details = error.details;
  details["parameter"] = key.substr(0, 60);
  return make_api_error(
      ApiErrorCode::kInvalidParameter,
      key + " must be " + expected + " in the query string, given as JSON (URL-encoded): " + error.message,
      std::move(details));
}

ApiResult<json> comma_separated_indices(const std::string& value) {
  json list = json::array();
  std::size_t start = 0;
  while (start <= value.size()) {
    const auto comma = value.find(',', start);
    const std::string item = value.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    if (item.empty() || item.find_first_not_of("0123456789") != std::string::npos || item.size() > 10) {
      return invalid("extrema",
                     "extrema must be \"auto\", comma-separated vertex indices (12,345,678) or JSON "
                     "(an array with {\"position\": [x, y, z]} entries, or the object form)");
    }
    list.push_back(std::stoull(item));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return list;
}

bool json_syntax(const std::string& value) {
  return !value.empty() && (value[0] == '[' || value[0] == '{');
}

ApiResult<json> query_value(const std::string& key, const std::string& value) {
  const bool truthy = value == "true" || value == "1";
  const bool falsy = value == "false" || value == "0";
  switch (query_kind(key)) {
    case QueryKind::kString:
      return json(value);
    case QueryKind::kIndex:
      if (value.empty() || value.size() > 10 || value.find_first_not_of("0123456789") != std::string::npos) {
        return invalid(key, key + " must be a non-negative integer");
      }
      return json(std::stoull(value));
    case QueryKind::kBoolean:
      if (truthy || falsy) return json(truthy);
      return invalid(key, key + " must be true or false (or 1 or 0)");
    case QueryKind::kNumber: {
      auto number = parse_json_limited(value);
      if (!number.ok() || !number->is_number()) {
        return invalid(key, key + " must be a decimal number (JSON number syntax, e.g. 0.001 or 1e-3)");
      }
      return std::move(number).value();
    }
    case QueryKind::kExtrema:
      if (value == "auto") return json("auto");
      if (json_syntax(value)) return query_json(key, value, "an array or an object");
      return comma_separated_indices(value);
    case QueryKind::kPrimitives:
      if (value == "all") return json("all");
      return query_json(key, value, "\"all\" or an array");
    case QueryKind::kPack:
      if (truthy || falsy) return json(truthy);
      return query_json(key, value, "true, false or an object");
    case QueryKind::kJson:
      return query_json(key, value, "an array");
  }
  return json(value);
}

}  // namespace

ApiResult<SeamParams> params_from_query(const std::vector<std::pair<std::string, std::string>>& query) {
  // Each value is turned into the JSON it stands for, then the JSON rules apply, so both
  // forms accept and refuse exactly the same things.
  json params = json::object();
  for (const auto& [key, value] : query) {
    if (params.contains(key)) return invalid(key, "parameter \"" + key.substr(0, 60) + "\" is given twice");
    SEAM_TRY(params[key], query_value(key, value));
  }
  return params_from_json(params);
}

}  // namespace seam::api
