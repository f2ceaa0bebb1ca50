#include "api/gltf_reader.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <optional>
#include <string_view>

#include "api/base64.h"
#include "api/draco_io.h"
#include "api/json_limits.h"

namespace seam::api {
namespace {

using nlohmann::json;

constexpr std::uint32_t kGlbMagic = 0x46546C67;  // "glTF"
constexpr std::uint32_t kChunkJson = 0x4E4F534A;
constexpr std::uint32_t kChunkBin = 0x004E4942;
// Values above 2^53 cannot be exact JSON numbers anyway; keeping every declared size below
// it (and counts below 2^32) makes all later sums and products overflow-free in 64 bits.
constexpr std::uint64_t kMaxDeclared = std::uint64_t{1} << 53;
constexpr std::uint64_t kMaxCount = std::uint64_t{1} << 32;

std::uint32_t read_u32(const char* p) {
  std::uint32_t v;
  std::memcpy(&v, p, 4);
  return v;  // GLB is little-endian; so are all the targets we build for.
}

// An optional non-negative integer member. Absent -> nullopt; present but not an integer
// in [0, 2^53) -> error naming `where`.
ApiResult<std::optional<std::uint64_t>> get_uint(const json& obj, const char* key, const std::string& where) {
  const auto it = obj.find(key);
  if (it == obj.end()) return std::optional<std::uint64_t>();
  if (!it->is_number_unsigned() && !(it->is_number_integer() && it->get<std::int64_t>() >= 0)) {
    return malformed_asset(where + "." + key + " must be a non-negative integer");
  }
  const std::uint64_t v = it->get<std::uint64_t>();
  if (v >= kMaxDeclared) return malformed_asset(where + "." + key + " is too large");
  return std::optional<std::uint64_t>(v);
}

ApiResult<std::uint64_t> require_uint(const json& obj, const char* key, const std::string& where) {
  SEAM_TRY(auto v, get_uint(obj, key, where));
  if (!v) return malformed_asset(where + "." + key + " is required");
  return *v;
}

bool is_index(const json& v) { return v.is_number_unsigned() || (v.is_number_integer() && v.get<std::int64_t>() >= 0); }

const json* array_member(const json& root, const char* key) {
  const auto it = root.find(key);
  return it == root.end() ? nullptr : &*it;
}

std::size_t array_size(const json& root, const char* key) {
  const json* a = array_member(root, key);
  return (a != nullptr && a->is_array()) ? a->size() : 0;
}

std::size_t component_size_of(int component_type) {
  switch (component_type) {
    case 5120:
    case 5121: return 1;
    case 5122:
    case 5123: return 2;
    case 5125:
    case 5126: return 4;
    default: return 0;
  }
}

int components_of(const std::string& type) {
  if (type == "SCALAR") return 1;
  if (type == "VEC2") return 2;
  if (type == "VEC3") return 3;
  if (type == "VEC4") return 4;
  if (type == "MAT2") return 4;
  if (type == "MAT3") return 9;
  if (type == "MAT4") return 16;
  return 0;
}

std::string short_uri(const std::string& uri) { return uri.size() > 120 ? uri.substr(0, 120) + "..." : uri; }

// data:[<mediatype>][;base64],<data>. Only base64 payloads: that is what glTF exporters write.
ApiResult<std::vector<std::uint8_t>> decode_data_uri(const std::string& uri, const std::string& where) {
  const auto comma = uri.find(',');
  if (comma == std::string::npos) return malformed_asset(where + ": data URI without ','");
  const std::string_view header(uri.data(), comma);
  if (header.size() < 7 || header.substr(header.size() - 7) != ";base64") {
    return malformed_asset(where + ": only base64 data URIs are supported");
  }
  std::vector<std::uint8_t> out;
  auto decoded = decode_base64(std::string_view(uri).substr(comma + 1));
  if (!decoded.ok()) return malformed_asset(where + ": bad base64 in data URI: " + decoded.error().describe());
  out.assign(decoded->begin(), decoded->end());
  return out;
}

bool is_data_uri(const std::string& uri) { return uri.rfind("data:", 0) == 0; }

struct ViewRange {
  std::size_t buffer = 0;
  std::size_t offset = 0;  // absolute, within the buffer
  std::size_t length = 0;
  std::size_t stride = 0;  // 0 = tightly packed
};

ApiResult<ViewRange> view_range(const GltfDocument& doc, std::uint64_t view_index, const std::string& where) {
  const json* views = array_member(doc.json, "bufferViews");
  if (views == nullptr || !views->is_array() || view_index >= views->size()) {
    return malformed_asset(where + " names bufferView " + std::to_string(view_index) + ", which does not exist");
  }
  const json& v = (*views)[view_index];
  const std::string vw = "bufferViews[" + std::to_string(view_index) + "]";
  if (!v.is_object()) return malformed_asset(vw + " is not an object");
  SEAM_TRY(const std::uint64_t buffer, require_uint(v, "buffer", vw));
  SEAM_TRY(const std::uint64_t length, require_uint(v, "byteLength", vw));
  SEAM_TRY(const auto offset, get_uint(v, "byteOffset", vw));
  SEAM_TRY(const auto stride, get_uint(v, "byteStride", vw));
  if (buffer >= doc.buffers.size())
    return malformed_asset(vw + ".buffer " + std::to_string(buffer) + " does not exist");
  const std::uint64_t off = offset.value_or(0);
  if (off + length > doc.buffers[buffer].size()) {
    return malformed_asset(vw + " (bytes " + std::to_string(off) + ".." + std::to_string(off + length) +
                           ") runs past the end of buffer " + std::to_string(buffer) + " (" +
                           std::to_string(doc.buffers[buffer].size()) + " bytes)");
  }
  if (stride && (*stride < 4 || *stride > 252 || *stride % 4 != 0)) {
    return malformed_asset(vw + ".byteStride must be a multiple of 4 in [4, 252]");
  }
  return ViewRange{buffer, off, length, stride.value_or(0)};
}

struct AccessorInfo {
  int component_type = 0;
  int components = 0;
  std::string type;
  bool normalized = false;
  std::size_t count = 0;
  std::optional<ViewRange> view;
  std::size_t byte_offset = 0;
  std::size_t stride = 0;
  struct Sparse {
    std::size_t count = 0;
    ViewRange indices;
    int index_type = 0;
    ViewRange values;
  };
  std::optional<Sparse> sparse;
};

// An accessor's componentType, type and normalized.
ApiResult<AccessorInfo> accessor_format(const json& a, const std::string& where) {
  AccessorInfo info;
  SEAM_TRY(const std::uint64_t ct, require_uint(a, "componentType", where));
  info.component_type = static_cast<int>(std::min<std::uint64_t>(ct, 1u << 20));
  if (component_size_of(info.component_type) == 0) {
    return malformed_asset(where + ".componentType " + std::to_string(ct) + " is not a glTF component type");
  }
  const auto type_it = a.find("type");
  if (type_it == a.end() || !type_it->is_string()) return malformed_asset(where + ".type is required");
  info.type = type_it->get<std::string>();
  info.components = components_of(info.type);
  if (info.components == 0) return malformed_asset(where + ".type '" + short_uri(info.type) + "' is not a glTF type");
  const auto norm_it = a.find("normalized");
  if (norm_it != a.end()) {
    if (!norm_it->is_boolean()) return malformed_asset(where + ".normalized must be a boolean");
    info.normalized = norm_it->get<bool>();
  }
  return info;
}

// The bytes of a sparse accessor's indices or values (`where`): its bufferView from
// `offset` on, which must hold `count` entries of `entry_size` bytes.
ApiResult<ViewRange> sparse_part(const GltfDocument& doc, std::uint64_t view_index, std::uint64_t offset,
                                 std::uint64_t count, std::uint64_t entry_size, const std::string& where) {
  SEAM_TRY(ViewRange range, view_range(doc, view_index, where));
  const std::uint64_t needed = offset + count * entry_size;
  if (needed > range.length) return malformed_asset(where + " run past their bufferView");
  range.offset += offset;
  range.length -= offset;
  return range;
}

// An accessor's `sparse` object; `count` and `elem` are the accessor's count and element size.
ApiResult<AccessorInfo::Sparse> check_sparse(const GltfDocument& doc, const json& s, const std::string& where,
                                             std::uint64_t count, std::size_t elem) {
  const std::string sw = where + ".sparse";
  if (!s.is_object()) return malformed_asset(sw + " is not an object");
  SEAM_TRY(const std::uint64_t scount, require_uint(s, "count", sw));
  if (scount == 0 || scount > count) return malformed_asset(sw + ".count must be in [1, accessor count]");
  const auto ii = s.find("indices");
  const auto vi = s.find("values");
  if (ii == s.end() || !ii->is_object() || vi == s.end() || !vi->is_object()) {
    return malformed_asset(sw + " needs indices and values objects");
  }
  AccessorInfo::Sparse sp;
  sp.count = scount;
  SEAM_TRY(const std::uint64_t iview, require_uint(*ii, "bufferView", sw + ".indices"));
  SEAM_TRY(const auto ioff, get_uint(*ii, "byteOffset", sw + ".indices"));
  SEAM_TRY(const std::uint64_t ict, require_uint(*ii, "componentType", sw + ".indices"));
  if (ict != 5121 && ict != 5123 && ict != 5125) return malformed_asset(sw + ".indices.componentType must be unsigned");
  sp.index_type = static_cast<int>(ict);
  SEAM_TRY(sp.indices,
           sparse_part(doc, iview, ioff.value_or(0), scount, component_size_of(sp.index_type), sw + ".indices"));
  SEAM_TRY(const std::uint64_t vview, require_uint(*vi, "bufferView", sw + ".values"));
  SEAM_TRY(const auto voff, get_uint(*vi, "byteOffset", sw + ".values"));
  SEAM_TRY(sp.values, sparse_part(doc, vview, voff.value_or(0), scount, elem, sw + ".values"));
  return sp;
}

// Checks an accessor completely against the buffers, without allocating anything sized by it.
ApiResult<AccessorInfo> check_accessor(const GltfDocument& doc, std::uint64_t index) {
  const json* accessors = array_member(doc.json, "accessors");
  if (accessors == nullptr || !accessors->is_array() || index >= accessors->size()) {
    return malformed_asset("accessor " + std::to_string(index) + " does not exist");
  }
  const json& a = (*accessors)[index];
  const std::string where = "accessors[" + std::to_string(index) + "]";
  if (!a.is_object()) return malformed_asset(where + " is not an object");
  SEAM_TRY(AccessorInfo info, accessor_format(a, where));
  SEAM_TRY(const std::uint64_t count, require_uint(a, "count", where));
  if (count == 0 || count >= kMaxCount)
    return malformed_asset(where + ".count " + std::to_string(count) + " is out of range");
  info.count = count;
  const std::size_t csize = component_size_of(info.component_type);
  const std::size_t elem = csize * static_cast<std::size_t>(info.components);
  SEAM_TRY(const auto view_index, get_uint(a, "bufferView", where));
  SEAM_TRY(const auto byte_offset, get_uint(a, "byteOffset", where));
  info.byte_offset = byte_offset.value_or(0);
  if (view_index) {
    SEAM_TRY(const ViewRange view, view_range(doc, *view_index, where));
    info.view = view;
    info.stride = view.stride ? view.stride : elem;
    if (info.byte_offset % csize != 0)
      return malformed_asset(where + ".byteOffset is not a multiple of the component size");
    // The declared count must fit in the view: this is what refuses huge counts before any
    // allocation.
    const std::uint64_t needed = info.byte_offset + (count - 1) * info.stride + elem;
    if (needed > view.length) {
      return malformed_asset(where + " needs " + std::to_string(needed) + " bytes (count " + std::to_string(count) +
                             ") but its bufferView has " + std::to_string(view.length));
    }
  } else if (byte_offset && *byte_offset != 0) {
    return malformed_asset(where + ".byteOffset without a bufferView");
  }
  const auto sparse_it = a.find("sparse");
  if (sparse_it != a.end()) {
    SEAM_TRY(info.sparse, check_sparse(doc, *sparse_it, where, count, elem));
  }
  return info;
}

std::uint32_t read_index(const std::uint8_t* p, int component_type) {
  switch (component_type) {
    case 5121: return *p;
    case 5123: {
      std::uint16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    default: {
      std::uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
  }
}

// Reads an accessor into a tight array in its own component type (sparse applied).
// `max_count` caps accessors without a bufferView, whose count no data bounds.
ApiResult<AttributeArray> read_accessor(const GltfDocument& doc, std::uint64_t index, const std::string& name,
                                        const ReadLimits& limits) {
  SEAM_TRY(const AccessorInfo info, check_accessor(doc, index));
  if (info.components > 4)
    return malformed_asset("accessor " + std::to_string(index) + " for " + name + " is a matrix");
  if (info.count > limits.max_vertices) {
    return make_api_error(ApiErrorCode::kMeshTooLarge,
                          "accessor " + std::to_string(index) + " declares " + std::to_string(info.count) +
                              " elements, more than the limit of " + std::to_string(limits.max_vertices),
                          {{"count", info.count}, {"limit", limits.max_vertices}});
  }
  AttributeArray out;
  out.name = name;
  out.component_type = info.component_type;
  out.components = info.components;
  out.type = info.type;
  out.normalized = info.normalized;
  out.count = info.count;
  const std::size_t elem = out.element_size();
  out.data.assign(info.count * elem, 0);  // no bufferView: zeros (then sparse), per the spec
  if (info.view) {
    const std::uint8_t* base = doc.buffers[info.view->buffer].data() + info.view->offset + info.byte_offset;
    for (std::size_t i = 0; i < info.count; ++i) std::memcpy(out.data.data() + i * elem, base + i * info.stride, elem);
  }
  if (info.sparse) {
    const auto& sp = *info.sparse;
    const std::uint8_t* idx = doc.buffers[sp.indices.buffer].data() + sp.indices.offset;
    const std::uint8_t* val = doc.buffers[sp.values.buffer].data() + sp.values.offset;
    const std::size_t isize = component_size_of(sp.index_type);
    std::int64_t previous = -1;
    for (std::size_t j = 0; j < sp.count; ++j) {
      const std::uint32_t target = read_index(idx + j * isize, sp.index_type);
      if (target >= info.count || static_cast<std::int64_t>(target) <= previous) {
        return malformed_asset("accessor " + std::to_string(index) + ": sparse index " + std::to_string(target) +
                               " is out of range or not increasing");
      }
      previous = target;
      std::memcpy(out.data.data() + static_cast<std::size_t>(target) * elem, val + j * elem, elem);
    }
  }
  return out;
}

double component_as_double(const std::uint8_t* p, int component_type, bool normalized) {
  switch (component_type) {
    case 5120: {
      const auto c = static_cast<std::int8_t>(*p);
      return normalized ? std::max(c / 127.0, -1.0) : c;
    }
    case 5121: return normalized ? *p / 255.0 : *p;
    case 5122: {
      std::int16_t c;
      std::memcpy(&c, p, 2);
      return normalized ? std::max(c / 32767.0, -1.0) : c;
    }
    case 5123: {
      std::uint16_t c;
      std::memcpy(&c, p, 2);
      return normalized ? c / 65535.0 : c;
    }
    case 5125: {
      std::uint32_t c;
      std::memcpy(&c, p, 4);
      return c;
    }
    default: {
      float f;
      std::memcpy(&f, p, 4);
      return f;
    }
  }
}

// glTF 2.0 §3.12: "If a glTF contains a required extension that is not supported, the loader
// must fail." EXT_meshopt_compression's bufferViews, say, hold compressed bytes: read as plain
// ones they would give a garbage mesh, and the output would still require the extension.
ApiResult<core::Ok> check_required_extensions(const json& root) {
  const auto it = root.find("extensionsRequired");
  if (it == root.end()) return core::Ok{};
  if (!it->is_array()) return malformed_asset("extensionsRequired must be an array of extension names");
  json unsupported = json::array();
  for (const auto& e : *it) {
    if (!e.is_string()) return malformed_asset("extensionsRequired must be an array of extension names");
    const auto& name = e.get_ref<const std::string&>();
    if (!supported_required_extension(name) && unsupported.size() < 16) unsupported.push_back(name.substr(0, 60));
  }
  if (unsupported.empty()) return core::Ok{};
  std::string message =
      "the asset requires extension " + unsupported[0].get<std::string>() +
      (unsupported.size() > 1 ? " (and " + std::to_string(unsupported.size() - 1) + " more)" : "") +
      ", which this service cannot read; supported when required: KHR_draco_mesh_compression, "
      "KHR_mesh_quantization, and material, texture, light and instancing extensions it passes through "
      "(api/README.md)";
  return make_api_error(ApiErrorCode::kUnsupportedExtension, std::move(message),
                        {{"extensions", std::move(unsupported)}});
}

ApiResult<GltfDocument> parse_json_document(std::string_view text, const ReadLimits& limits) {
  if (text.size() > limits.max_json_bytes) return malformed_asset("the glTF JSON is larger than the limit");
  // The client's JSON: depth is checked while parsing (the writer dumps this document later).
  auto parsed = parse_json_limited(text);
  if (!parsed.ok()) return malformed_asset("the glTF JSON: " + parsed.error().message);
  GltfDocument doc;
  doc.json = std::move(parsed).value();
  if (!doc.json.is_object()) return malformed_asset("the glTF JSON is not an object");
  const auto asset = doc.json.find("asset");
  if (asset == doc.json.end() || !asset->is_object()) return malformed_asset("the glTF has no 'asset' object");
  const auto version = asset->find("version");
  if (version == asset->end() || !version->is_string() || version->get<std::string>().rfind("2.", 0) != 0) {
    return malformed_asset("asset.version must be \"2.0\" (only glTF 2 is supported)");
  }
  for (const char* key : {"buffers", "bufferViews", "accessors", "meshes", "images", "nodes"}) {
    const auto it = doc.json.find(key);
    if (it != doc.json.end() && !it->is_array()) return malformed_asset(std::string("'") + key + "' must be an array");
  }
  SEAM_TRY(const core::Ok required, check_required_extensions(doc.json));
  (void)required;
  return doc;
}

// Resolves buffers (`bin` is the GLB BIN chunk) and checks image URIs and every range.
ApiResult<GltfDocument> resolve_buffers(GltfDocument doc, std::optional<std::string_view> bin) {
  const json* buffers = array_member(doc.json, "buffers");
  const std::size_t n = array_size(doc.json, "buffers");
  for (std::size_t i = 0; i < n; ++i) {
    const json& b = (*buffers)[i];
    const std::string where = "buffers[" + std::to_string(i) + "]";
    if (!b.is_object()) return malformed_asset(where + " is not an object");
    SEAM_TRY(const std::uint64_t length, require_uint(b, "byteLength", where));
    const auto uri = b.find("uri");
    std::vector<std::uint8_t> data;
    if (uri != b.end()) {
      if (!uri->is_string()) return malformed_asset(where + ".uri must be a string");
      const std::string u = uri->get<std::string>();
      if (!is_data_uri(u)) {
        return make_api_error(ApiErrorCode::kExternalUri,
                              where + ".uri '" + short_uri(u) +
                                  "' is not a data URI; the service never reads files or URLs named in an asset: "
                                  "embed the buffer (GLB or data URI)",
                              {{"uri", short_uri(u)}});
      }
      SEAM_TRY(data, decode_data_uri(u, where));
    } else if (i == 0 && bin) {
      data.assign(bin->begin(), bin->end());
    } else {
      return malformed_asset(where + " has no uri and is not the GLB binary chunk");
    }
    if (data.size() < length) {
      return malformed_asset(where + ".byteLength is " + std::to_string(length) + " but only " +
                             std::to_string(data.size()) + " bytes are present");
    }
    data.resize(length);  // a GLB BIN chunk may carry up to 3 bytes of padding
    doc.buffers.push_back(std::move(data));
  }
  const json* images = array_member(doc.json, "images");
  for (std::size_t i = 0; i < array_size(doc.json, "images"); ++i) {
    const json& im = (*images)[i];
    const std::string where = "images[" + std::to_string(i) + "]";
    if (!im.is_object()) return malformed_asset(where + " is not an object");
    const auto uri = im.find("uri");
    if (uri != im.end()) {
      if (!uri->is_string()) return malformed_asset(where + ".uri must be a string");
      const std::string u = uri->get<std::string>();
      if (!is_data_uri(u)) {
        return make_api_error(ApiErrorCode::kExternalUri,
                              where + ".uri '" + short_uri(u) +
                                  "' is not a data URI; the service never reads files or URLs named in an asset",
                              {{"uri", short_uri(u)}});
      }
    }
    SEAM_TRY(const auto view, get_uint(im, "bufferView", where));
    if (view) {
      SEAM_TRY(const ViewRange unused, view_range(doc, *view, where));
      (void)unused;
    }
  }
  // Every bufferView and accessor is checked up front, so the writer can copy any of them.
  for (std::size_t i = 0; i < array_size(doc.json, "bufferViews"); ++i) {
    SEAM_TRY(const ViewRange unused, view_range(doc, i, "asset"));
    (void)unused;
  }
  for (std::size_t i = 0; i < array_size(doc.json, "accessors"); ++i) {
    SEAM_TRY(const AccessorInfo unused, check_accessor(doc, i));
    (void)unused;
  }
  return doc;
}

ApiResult<GltfDocument> parse_glb(std::string_view bytes, const ReadLimits& limits) {
  if (bytes.size() < 20) return malformed_asset("GLB shorter than its 12-byte header and first chunk header");
  if (read_u32(bytes.data()) != kGlbMagic) return malformed_asset("not a GLB: bad magic");
  const std::uint32_t version = read_u32(bytes.data() + 4);
  if (version != 2) return malformed_asset("GLB version " + std::to_string(version) + " is not 2");
  const std::uint32_t length = read_u32(bytes.data() + 8);
  if (length > bytes.size()) {
    return malformed_asset("GLB header declares " + std::to_string(length) + " bytes but " +
                           std::to_string(bytes.size()) + " were received (truncated?)");
  }
  if (length < 20) return malformed_asset("GLB header length is too small");
  bytes = bytes.substr(0, length);
  const std::uint64_t json_length = read_u32(bytes.data() + 12);
  if (read_u32(bytes.data() + 16) != kChunkJson) return malformed_asset("the first GLB chunk is not JSON");
  if (20 + json_length > bytes.size())
    return malformed_asset("the GLB JSON chunk length runs past the end of the file");
  // The spec pads the JSON chunk with spaces; some exporters pad with NULs. Accept both.
  std::string_view json_text = bytes.substr(20, json_length);
  while (!json_text.empty() && (json_text.back() == '\0' || json_text.back() == ' ')) json_text.remove_suffix(1);
  SEAM_TRY(GltfDocument doc, parse_json_document(json_text, limits));
  std::optional<std::string_view> bin;
  std::size_t pos = 20 + json_length;
  if (pos + 8 <= bytes.size()) {
    const std::uint64_t bin_length = read_u32(bytes.data() + pos);
    const std::uint32_t type = read_u32(bytes.data() + pos + 4);
    if (pos + 8 + bin_length > bytes.size())
      return malformed_asset("the GLB BIN chunk length runs past the end of the file");
    if (type == kChunkBin) bin = bytes.substr(pos + 8, bin_length);
  } else if (pos != bytes.size()) {
    return malformed_asset("trailing bytes after the GLB JSON chunk");
  }
  doc.kind = AssetKind::kGlb;
  return resolve_buffers(std::move(doc), bin);
}

// A raw .drc mesh becomes a document with one Draco-compressed primitive, so one code path
// reads and writes both.
ApiResult<GltfDocument> parse_raw_draco(std::string_view bytes, const ReadLimits& limits) {
  SEAM_TRY(const DracoMesh dm,
           decode_draco(std::span(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()), limits));
  json attributes = json::object();
  json accessors = json::array();
  json ext_attributes = json::object();
  int texcoords = 0, colors = 0, generics = 0;
  static constexpr const char* kTypes[] = {"", "SCALAR", "VEC2", "VEC3", "VEC4"};
  bool has_position = false;
  for (const auto& a : dm.attributes) {
    std::string name;
    if (a.semantic == "POSITION" && a.components == 3 && !has_position) {
      name = "POSITION";
      has_position = true;
    } else if (a.semantic == "NORMAL" && a.components == 3 && !attributes.contains("NORMAL")) {
      name = "NORMAL";
    } else if (a.semantic == "TEX_COORD" && a.components == 2) {
      name = "TEXCOORD_" + std::to_string(texcoords++);
    } else if (a.semantic == "COLOR" && (a.components == 3 || a.components == 4)) {
      name = "COLOR_" + std::to_string(colors++);
    } else {
      name = "_GENERIC_" + std::to_string(generics++);
    }
    attributes[name] = accessors.size();
    ext_attributes[name] = a.unique_id;
    // Values are read as float32: every glTF reader accepts it for these semantics, and
    // Draco dequantizes on decode anyway.
    accessors.push_back({{"componentType", 5126}, {"count", dm.num_points}, {"type", kTypes[a.components]}});
  }
  if (!has_position) return malformed_asset("the Draco mesh has no 3-component POSITION attribute");
  const std::size_t indices = accessors.size();
  accessors.push_back({{"componentType", 5125}, {"count", dm.triangles.size() * 3}, {"type", "SCALAR"}});
  GltfDocument doc;
  doc.kind = AssetKind::kDraco;
  doc.json = {
      {"asset", {{"version", "2.0"}, {"generator", "seam service (from raw Draco)"}}},
      {"scene", 0},
      {"scenes", json::array({{{"nodes", {0}}}})},
      {"nodes", json::array({{{"mesh", 0}}})},
      {"meshes",
       json::array({{{"primitives",
                      json::array({{{"attributes", attributes},
                                    {"indices", indices},
                                    {"mode", 4},
                                    {"extensions",
                                     {{"KHR_draco_mesh_compression", {{"bufferView", 0}, {"attributes", ext_attributes}}}}}}})}}})},
      {"accessors", accessors},
      {"bufferViews", json::array({{{"buffer", 0}, {"byteLength", bytes.size()}}})},
      {"buffers", json::array({{{"byteLength", bytes.size()}}})},
      {"extensionsUsed", {"KHR_draco_mesh_compression"}},
      {"extensionsRequired", {"KHR_draco_mesh_compression"}},
  };
  doc.buffers.emplace_back(bytes.begin(), bytes.end());
  return doc;
}

}  // namespace

std::size_t AttributeArray::component_size() const { return component_size_of(component_type); }

bool supported_required_extension(std::string_view name) {
  static constexpr std::array<std::string_view, 10> kSupported = {
      "KHR_draco_mesh_compression", "KHR_mesh_quantization", "KHR_texture_transform", "KHR_texture_basisu",
      "EXT_texture_webp",           "EXT_texture_avif",      "KHR_lights_punctual",   "EXT_mesh_gpu_instancing",
      "KHR_animation_pointer",      "KHR_xmp_json_ld"};
  if (name.starts_with("KHR_materials_")) return true;
  return std::find(kSupported.begin(), kSupported.end(), name) != kSupported.end();
}

AssetKind detect_asset_kind(std::string_view bytes) {
  if (bytes.size() >= 4 && read_u32(bytes.data()) == kGlbMagic) return AssetKind::kGlb;
  if (bytes.size() >= 5 && bytes.substr(0, 5) == "DRACO") return AssetKind::kDraco;
  for (char c : bytes) {
    if (c == ' ' || c == '\t' || c == '\r' || c == '\n') continue;
    if (c == '{') return AssetKind::kGltfJson;
    break;
  }
  // Unknown bytes: let the GLB parser explain what is wrong.
  return AssetKind::kGlb;
}

ApiResult<GltfDocument> parse_asset(std::string_view bytes, AssetKind kind, const ReadLimits& limits) {
  if (kind == AssetKind::kAuto) kind = detect_asset_kind(bytes);
  switch (kind) {
    case AssetKind::kGlb: return parse_glb(bytes, limits);
    case AssetKind::kDraco: return parse_raw_draco(bytes, limits);
    case AssetKind::kGltfJson: {
      SEAM_TRY(GltfDocument doc, parse_json_document(bytes, limits));
      doc.kind = AssetKind::kGltfJson;
      return resolve_buffers(std::move(doc), std::nullopt);
    }
    case AssetKind::kAuto: break;
  }
  return malformed_asset("unknown asset kind");
}

namespace {

using ApiStatus = ApiResult<core::Ok>;

// The primitive's JSON and its path for messages ("meshes[0].primitives[1]").
struct PrimitiveRef {
  const json* prim = nullptr;
  std::string where;
};

ApiResult<PrimitiveRef> locate_primitive(const GltfDocument& doc, std::uint32_t mesh_index, std::uint32_t primitive_index) {
  const json* meshes = array_member(doc.json, "meshes");
  if (meshes == nullptr || mesh_index >= meshes->size()) {
    return make_api_error(ApiErrorCode::kNoTrianglePrimitive,
                          "mesh " + std::to_string(mesh_index) + " does not exist (the asset has " +
                              std::to_string(array_size(doc.json, "meshes")) + " meshes)",
                          {{"mesh", mesh_index}, {"meshes", array_size(doc.json, "meshes")}});
  }
  const json& mesh = (*meshes)[mesh_index];
  const std::string mw = "meshes[" + std::to_string(mesh_index) + "]";
  if (!mesh.is_object()) return malformed_asset(mw + " is not an object");
  const auto prims = mesh.find("primitives");
  if (prims == mesh.end() || !prims->is_array()) return malformed_asset(mw + ".primitives must be an array");
  if (primitive_index >= prims->size()) {
    return make_api_error(ApiErrorCode::kNoTrianglePrimitive,
                          "primitive " + std::to_string(primitive_index) + " of mesh " + std::to_string(mesh_index) +
                              " does not exist (it has " + std::to_string(prims->size()) + ")",
                          {{"mesh", mesh_index}, {"primitive", primitive_index}, {"primitives", prims->size()}});
  }
  const json& prim = (*prims)[primitive_index];
  PrimitiveRef out{&prim, mw + ".primitives[" + std::to_string(primitive_index) + "]"};
  if (!prim.is_object()) return malformed_asset(out.where + " is not an object");
  return out;
}

// The mode (a surface one), and the attributes object with POSITION.
ApiResult<int> surface_mode(const json& prim, const std::string& pw) {
  SEAM_TRY(const auto mode, get_uint(prim, "mode", pw));
  const int m = static_cast<int>(mode.value_or(4));
  if (mode && *mode > 6) return malformed_asset(pw + ".mode " + std::to_string(*mode) + " is not a glTF mode");
  if (m <= 3) {
    static constexpr const char* kNames[] = {"POINTS", "LINES", "LINE_LOOP", "LINE_STRIP"};
    return make_api_error(ApiErrorCode::kUnsupportedPrimitiveMode,
                          pw + " has mode " + kNames[m] +
                              "; a seam needs a triangle surface (TRIANGLES, TRIANGLE_STRIP or TRIANGLE_FAN)",
                          {{"mode", m}});
  }
  const auto attrs = prim.find("attributes");
  if (attrs == prim.end() || !attrs->is_object()) return malformed_asset(pw + ".attributes must be an object");
  if (!attrs->contains("POSITION")) {
    return make_api_error(ApiErrorCode::kNoTrianglePrimitive, pw + " has no POSITION attribute");
  }
  return m;
}

// KHR_draco_mesh_compression: the extension object and its decoded mesh (quantization read),
// or neither. We decode the extension's bufferView ourselves (tinygltf would not check it).
struct DracoPart {
  const json* ext = nullptr;
  std::optional<DracoMesh> mesh;
};

ApiResult<DracoPart> read_draco_part(const GltfDocument& doc, const json& prim, const std::string& pw,
                                     const ReadLimits& limits) {
  DracoPart out;
  const auto exts = prim.find("extensions");
  if (exts == prim.end() || !exts->is_object()) return out;
  const auto d = exts->find("KHR_draco_mesh_compression");
  if (d == exts->end()) return out;
  const std::string dw = pw + ".extensions.KHR_draco_mesh_compression";
  if (!d->is_object()) return malformed_asset(dw + " is not an object");
  out.ext = &*d;
  SEAM_TRY(const std::uint64_t view_index, require_uint(*d, "bufferView", dw));
  SEAM_TRY(const ViewRange view, view_range(doc, view_index, dw));
  const auto ea = d->find("attributes");
  if (ea == d->end() || !ea->is_object()) return malformed_asset(dw + ".attributes must be an object");
  SEAM_TRY(DracoMesh decoded, decode_draco(std::span(doc.buffers[view.buffer].data() + view.offset, view.length), limits, true));
  out.mesh = std::move(decoded);
  return out;
}

// One attribute from the Draco blob (with its quantization) when the extension names it,
// else from its accessor.
ApiStatus read_attribute(const GltfDocument& doc, const DracoPart& draco, const std::string& name, const json& ref,
                      const std::string& pw, const ReadLimits& limits, PrimitiveData& out) {
  if (!is_index(ref)) return malformed_asset(pw + ".attributes." + name + " must be an accessor index");
  const std::uint64_t acc = ref.get<std::uint64_t>();
  std::optional<std::uint64_t> uid;
  if (draco.ext != nullptr) {
    const json& ea = (*draco.ext)["attributes"];
    if (const auto u = ea.find(name); u != ea.end()) {
      if (!is_index(*u) || u->get<std::uint64_t>() > 0xffffffffu) {
        return malformed_asset(pw + ": Draco attribute id for " + name + " must be an unsigned integer");
      }
      uid = u->get<std::uint64_t>();
    }
  }
  if (!uid) {
    SEAM_TRY(AttributeArray a, read_accessor(doc, acc, name, limits));
    out.attributes.push_back(std::move(a));
    return core::Ok{};
  }
  SEAM_TRY(const AccessorInfo info, check_accessor(doc, acc));
  if (info.count != draco.mesh->num_points) {
    return malformed_asset(pw + ".attributes." + name + " declares " + std::to_string(info.count) +
                           " vertices but the Draco data has " + std::to_string(draco.mesh->num_points));
  }
  if (info.components > 4) return malformed_asset(pw + ".attributes." + name + " is a matrix");
  SEAM_TRY(AttributeArray a, read_draco_attribute(*draco.mesh, static_cast<std::uint32_t>(*uid), info.component_type,
                                                  info.components, info.normalized, name));
  a.type = info.type;
  for (const auto& q : draco.mesh->quantization) {
    if (q.unique_id != *uid) continue;
    out.draco_quantization.push_back(q);
    out.draco_quantization.back().name = name;
  }
  out.attributes.push_back(std::move(a));
  return core::Ok{};
}

// POSITION as doubles (float32, or normalized/integer under KHR_mesh_quantization), every
// attribute with POSITION's count, no NaN or infinity.
ApiStatus read_positions(const std::string& pw, PrimitiveData& out) {
  const auto pos_it = std::find_if(out.attributes.begin(), out.attributes.end(),
                                   [](const AttributeArray& a) { return a.name == "POSITION"; });
  const AttributeArray& pos = *pos_it;
  if (pos.components != 3) return malformed_asset(pw + ": POSITION must be VEC3");
  const std::size_t n = pos.count;
  for (const auto& a : out.attributes) {
    if (a.count != n) {
      return malformed_asset(pw + ": attribute " + a.name + " has " + std::to_string(a.count) +
                             " elements but POSITION has " + std::to_string(n));
    }
  }
  out.mesh.positions.resize(n);
  std::vector<std::uint32_t> bad;
  const std::size_t cs = pos.component_size();
  for (std::size_t v = 0; v < n; ++v) {
    for (int c = 0; c < 3; ++c) {
      out.mesh.positions[v][c] = component_as_double(pos.data.data() + (v * 3 + c) * cs, pos.component_type, pos.normalized);
    }
    if (!out.mesh.positions[v].allFinite() && bad.size() < 8) bad.push_back(static_cast<std::uint32_t>(v));
  }
  if (!bad.empty()) {
    return make_api_error(ApiErrorCode::kNonFinitePosition,
                          pw + ": POSITION of vertex " + std::to_string(bad.front()) + " is NaN or infinite",
                          {{"vertices", bad}});
  }
  return core::Ok{};
}

// Morph targets (uncompressed even in Draco primitives, per KHR_draco_mesh_compression).
ApiStatus read_targets(const GltfDocument& doc, const json& prim, const std::string& pw, const ReadLimits& limits,
                    PrimitiveData& out) {
  const auto targets = prim.find("targets");
  if (targets == prim.end()) return core::Ok{};
  if (!targets->is_array()) return malformed_asset(pw + ".targets must be an array");
  const std::size_t n = out.mesh.positions.size();
  for (std::size_t t = 0; t < targets->size(); ++t) {
    const json& target = (*targets)[t];
    if (!target.is_object()) return malformed_asset(pw + ".targets[" + std::to_string(t) + "] is not an object");
    std::vector<AttributeArray> arrays;
    for (auto it = target.begin(); it != target.end(); ++it) {
      if (!is_index(*it)) return malformed_asset(pw + ".targets: " + it.key() + " must be an accessor index");
      SEAM_TRY(AttributeArray a, read_accessor(doc, it->get<std::uint64_t>(), it.key(), limits));
      if (a.count != n)
        return malformed_asset(pw + ".targets[" + std::to_string(t) + "]." + it.key() + " has the wrong count");
      arrays.push_back(std::move(a));
    }
    out.targets.push_back(std::move(arrays));
  }
  return core::Ok{};
}

// The index list: an index accessor (u8/u16/u32), or implicit 0..n-1; every index < n.
ApiResult<std::vector<std::uint32_t>> read_indices(const GltfDocument& doc, const json& prim, const std::string& pw,
                                                   std::size_t n, const ReadLimits& limits) {
  std::vector<std::uint32_t> indices;
  SEAM_TRY(const auto idx, get_uint(prim, "indices", pw));
  if (idx) {
    SEAM_TRY(const AttributeArray ia, read_accessor(doc, *idx, "indices", limits));
    if (ia.components != 1 || ia.normalized ||
        (ia.component_type != 5121 && ia.component_type != 5123 && ia.component_type != 5125)) {
      return malformed_asset(pw + ".indices must be an unsigned SCALAR accessor (u8, u16 or u32)");
    }
    indices.resize(ia.count);
    for (std::size_t i = 0; i < ia.count; ++i) indices[i] = read_index(ia.data.data() + i * ia.component_size(), ia.component_type);
  } else {
    indices.resize(n);
    for (std::size_t i = 0; i < n; ++i) indices[i] = static_cast<std::uint32_t>(i);
  }
  for (std::size_t i = 0; i < indices.size(); ++i) {
    if (indices[i] < n) continue;
    return make_api_error(ApiErrorCode::kIndexOutOfRange,
                          pw + ": index " + std::to_string(i) + " is " + std::to_string(indices[i]) +
                              " but the primitive has " + std::to_string(n) + " vertices",
                          {{"index", i}, {"value", indices[i]}, {"vertices", n}});
  }
  return indices;
}

// Triangles from TRIANGLES, TRIANGLE_STRIP or TRIANGLE_FAN indices, winding kept.
ApiResult<std::vector<core::Triangle>> assemble_triangles(const std::vector<std::uint32_t>& indices, int mode,
                                                          const std::string& pw, const ReadLimits& limits) {
  const std::size_t m = indices.size();
  const std::size_t faces = mode == 4 ? m / 3 : (m >= 3 ? m - 2 : 0);
  if (faces > limits.max_faces) {
    return make_api_error(
        ApiErrorCode::kMeshTooLarge,
        pw + " has " + std::to_string(faces) + " triangles, more than the limit of " + std::to_string(limits.max_faces),
        {{"count", faces}, {"limit", limits.max_faces}});
  }
  std::vector<core::Triangle> out;
  out.reserve(faces);
  if (mode == 4) {
    if (m % 3 != 0)
      return malformed_asset(pw + ": TRIANGLES with " + std::to_string(m) + " indices (not a multiple of 3)");
    for (std::size_t i = 0; i + 2 < m; i += 3) out.push_back({indices[i], indices[i + 1], indices[i + 2]});
    return out;
  }
  for (std::size_t i = 0; i + 2 < m; ++i) {
    core::Triangle t;
    if (mode == 5) {  // strip: odd triangles are flipped to keep the winding
      t = (i % 2 == 0) ? core::Triangle{indices[i], indices[i + 1], indices[i + 2]}
                       : core::Triangle{indices[i + 1], indices[i], indices[i + 2]};
    } else {  // fan
      t = {indices[0], indices[i + 1], indices[i + 2]};
    }
    // Strips use repeated indices as restarts: those triangles are not surface.
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
    out.push_back(t);
  }
  return out;
}

}  // namespace

ApiResult<PrimitiveData> read_primitive(const GltfDocument& doc, std::uint32_t mesh_index, std::uint32_t primitive_index,
                                        const ReadLimits& limits) {
  SEAM_TRY(const PrimitiveRef ref, locate_primitive(doc, mesh_index, primitive_index));
  const json& prim = *ref.prim;
  const std::string& pw = ref.where;
  PrimitiveData out;
  SEAM_TRY(out.mode, surface_mode(prim, pw));
  SEAM_TRY(const DracoPart draco, read_draco_part(doc, prim, pw, limits));
  out.draco = draco.mesh.has_value();
  for (const auto& [name, index] : prim.at("attributes").items()) {
    if (auto r = read_attribute(doc, draco, name, index, pw, limits, out); !r.ok()) return r.take_error();
  }
  if (auto r = read_positions(pw, out); !r.ok()) return r.take_error();
  if (auto r = read_targets(doc, prim, pw, limits, out); !r.ok()) return r.take_error();
  if (draco.mesh) {
    if (out.mode != 4) return malformed_asset(pw + ": a Draco primitive must have mode TRIANGLES");
    // The triangles index the Draco mesh's points, so every attribute has to have that many,
    // also those the extension does not name (read from their accessors).
    if (out.mesh.positions.size() != draco.mesh->num_points) {
      return malformed_asset(pw + ": POSITION has " + std::to_string(out.mesh.positions.size()) +
                             " vertices but the Draco data has " + std::to_string(draco.mesh->num_points) +
                             " (an attribute the extension does not name still needs the Draco mesh's vertex count)");
    }
    out.mesh.triangles = draco.mesh->triangles;
  } else {
    SEAM_TRY(const std::vector<std::uint32_t> indices, read_indices(doc, prim, pw, out.mesh.positions.size(), limits));
    SEAM_TRY(out.mesh.triangles, assemble_triangles(indices, out.mode, pw, limits));
  }
  if (out.mesh.triangles.size() > limits.max_faces) {
    return make_api_error(ApiErrorCode::kMeshTooLarge,
                          pw + " has " + std::to_string(out.mesh.triangles.size()) +
                              " triangles, more than the limit of " + std::to_string(limits.max_faces),
                          {{"count", out.mesh.triangles.size()}, {"limit", limits.max_faces}});
  }
  if (out.mesh.triangles.empty()) return make_api_error(ApiErrorCode::kEmptyMesh, pw + " has no triangles");
  return out;
}

}  // namespace seam::api
