// Parsing the POST /seam parameters (API.md "Parameters") from JSON or the query string.
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
    } else if (key == "margin_px") {
      if (!x.is_number() || !std::isfinite(x.get<double>()) || x.get<double>() < 0) {
        return invalid("pack.margin_px", "pack.margin_px must be a number >= 0");
      }
      out.margin_px = x.get<double>();
    } else if (key == "rotate") {
      if (!x.is_boolean()) return invalid("pack.rotate", "pack.rotate must be true or false");
      out.rotate = x.get<bool>();
    } else {
      return invalid("pack." + key.substr(0, 60), "pack: unknown key \"" + key.substr(0, 60) +
                                                      "\" (known: group_by, texture_size, margin_px, rotate)");
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

}  // namespace

ApiResult<SeamParams> params_from_json(const json& params) {
  if (!params.is_object()) return invalid("params", "the parameters must be a JSON object");
  SeamParams out;
  bool primitives_given = false;
  for (auto it = params.begin(); it != params.end(); ++it) {
    const std::string& key = it.key();
    const json& v = *it;
    if (key == "extrema") {
      SEAM_TRY(out.extrema, extrema_from_json(v));
    } else if (key == "mesh") {
      // In the JSON request form "mesh" is the asset object, which the server removes; an
      // integer is the mesh index.
      if (v.is_object()) continue;
      SEAM_TRY(out.mesh, small_index(v, "mesh"));
    } else if (key == "primitive") {
      SEAM_TRY(out.primitive, small_index(v, "primitive"));
    } else if (key == "primitives") {
      SEAM_TRY(out.primitives, primitives_from_json(v));
      primitives_given = true;
    } else if (key == "method") {
      const std::string m = v.is_string() ? v.get<std::string>() : "";
      if (m == "skeleton") out.method = core::SeamMethod::kSkeleton;
      else if (m == "mst") out.method = core::SeamMethod::kMst;
      else if (m == "greedy") out.method = core::SeamMethod::kGreedy;
      else if (m == "optimal") out.method = core::SeamMethod::kOptimal;
      else return invalid("method", "method must be one of skeleton, mst, greedy, optimal");
    } else if (key == "uv") {
      const std::string m = v.is_string() ? v.get<std::string>() : "";
      if (m == "bff") out.uv = core::UvMethod::kBff;
      else if (m == "lscm") out.uv = core::UvMethod::kLscm;
      else if (m == "arap") out.uv = core::UvMethod::kArap;
      else if (m == "slim") out.uv = core::UvMethod::kSlim;
      else if (m == "none") out.uv = std::nullopt;
      else return invalid("uv", "uv must be one of slim, arap, bff, lscm, none");
    } else if (key == "output") {
      const std::string m = v.is_string() ? v.get<std::string>() : "";
      if (m == "json") out.output = OutputFormat::kJson;
      else if (m == "glb") out.output = OutputFormat::kGlb;
      else if (m == "svg") out.output = OutputFormat::kSvg;
      else return invalid("output", "output must be \"json\", \"glb\" or \"svg\"");
    } else if (key == "pack") {
      SEAM_TRY(out.pack, pack_from_json(v));
    } else if (key == "hide_from") {
      SEAM_TRY(out.hide_from, views_from_json(v));
    } else if (key == "hide_occluded") {
      if (!v.is_boolean()) return invalid("hide_occluded", "hide_occluded must be true or false");
      out.hide_occluded = v.get<bool>();
    } else if (key == "hide_strength") {
      if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < 0 || v.get<double>() > 1000) {
        return invalid("hide_strength", "hide_strength must be a number from 0 to 1000");
      }
      out.hide_strength = v.get<double>();
    } else if (key == "charts") {
      const std::string m = v.is_string() ? v.get<std::string>() : "";
      if (m == "seam") out.charts = ChartMode::kSeam;
      else if (m == "features") out.charts = ChartMode::kFeatures;
      else return invalid("charts", "charts must be \"seam\" or \"features\"");
    } else if (key == "feature_angle_deg") {
      if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < 0 || v.get<double>() > 180) {
        return invalid("feature_angle_deg", "feature_angle_deg must be a number from 0 to 180");
      }
      out.feature_angle_deg = v.get<double>();
    } else if (key == "draco") {
      if (!v.is_boolean()) return invalid("draco", "draco must be true or false");
      out.draco = v.get<bool>();
    } else if (key == "refine") {
      if (!v.is_boolean()) return invalid("refine", "refine must be true or false");
      out.refine = v.get<bool>();
    } else if (key == "repair") {
      if (!v.is_boolean()) return invalid("repair", "repair must be true or false");
      out.repair = v.get<bool>();
    } else if (key == "weld_epsilon") {
      if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < 0) {
        return invalid("weld_epsilon", "weld_epsilon must be a finite number >= 0");
      }
      out.weld_epsilon = v.get<double>();
    } else {
      return invalid(key.substr(0, 60), "unknown parameter \"" + key.substr(0, 60) +
                              "\" (known: extrema, mesh, primitive, primitives, method, uv, output, draco, refine, repair, "
                                         "weld_epsilon, pack, charts, feature_angle_deg, hide_from, hide_occluded, hide_strength)");
    }
  }
  if (primitives_given && (out.mesh || out.primitive)) {
    return invalid("primitives", "primitives cannot be combined with mesh or primitive (v1's single-primitive "
                                 "selection): name the primitive as {\"primitives\": [{\"mesh\": i, \"primitive\": j}]}");
  }
  return out;
}

ApiResult<SeamParams> params_from_query(const std::vector<std::pair<std::string, std::string>>& query) {
  // Each value is turned into the JSON it stands for, then the JSON rules apply, so both
  // forms accept and refuse exactly the same things.
  json params = json::object();
  for (const auto& [key, value] : query) {
    if (params.contains(key)) return invalid(key, "parameter \"" + key.substr(0, 60) + "\" is given twice");
    if (key == "extrema") {
      if (value == "auto") {
        params[key] = "auto";
        continue;
      }
      json list = json::array();
      std::size_t start = 0;
      while (start <= value.size()) {
        const auto comma = value.find(',', start);
        const std::string item = value.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        if (item.empty() || item.find_first_not_of("0123456789") != std::string::npos || item.size() > 10) {
          return invalid("extrema", "extrema must be \"auto\" or comma-separated vertex indices, e.g. 12,345,678");
        }
        list.push_back(std::stoull(item));
        if (comma == std::string::npos) break;
        start = comma + 1;
      }
      params[key] = std::move(list);
    } else if (key == "mesh" || key == "primitive") {
      if (value.empty() || value.size() > 10 || value.find_first_not_of("0123456789") != std::string::npos) {
        return invalid(key, key + " must be a non-negative integer");
      }
      params[key] = std::stoull(value);
    } else if (key == "draco" || key == "refine" || key == "repair" || key == "hide_occluded") {
      if (value == "true" || value == "1") params[key] = true;
      else if (value == "false" || value == "0") params[key] = false;
      else return invalid(key, key + " must be true or false");
    } else if (key == "weld_epsilon" || key == "hide_strength" || key == "feature_angle_deg") {
      std::size_t used = 0;
      double d = 0;
      try {
        d = std::stod(value, &used);
      } catch (...) {
        used = 0;
      }
      if (used == 0 || used != value.size()) return invalid(key, key + " must be a number");
      params[key] = d;
    } else {
      params[key] = value;  // strings; unknown keys are refused by params_from_json
    }
  }
  return params_from_json(params);
}

}  // namespace seam::api
