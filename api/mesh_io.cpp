#include "api/mesh_io.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

namespace seam::api {
namespace {

ApiError malformed(std::string_view format, std::size_t line, const std::string& what) {
  return make_api_error(ApiErrorCode::kMalformedAsset,
                        std::string(format) + " line " + std::to_string(line) + ": " + what,
                        {{"line", line}});
}

// Splits text into lines with comments removed and tokens split on white space.
class LineTokens {
 public:
  explicit LineTokens(std::string_view text) : text_(text) {}

  // Advances to the next line with at least one token; false at the end.
  bool next() {
    while (pos_ < text_.size()) {
      std::size_t end = text_.find('\n', pos_);
      if (end == std::string_view::npos) end = text_.size();
      std::string_view line = text_.substr(pos_, end - pos_);
      pos_ = end + 1;
      ++line_number_;
      if (auto hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
      tokens_.clear();
      std::size_t i = 0;
      while (i < line.size()) {
        while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
        std::size_t j = i;
        while (j < line.size() && !std::isspace(static_cast<unsigned char>(line[j]))) ++j;
        if (j > i) tokens_.push_back(line.substr(i, j - i));
        i = j;
      }
      if (!tokens_.empty()) return true;
    }
    return false;
  }
  const std::vector<std::string_view>& tokens() const { return tokens_; }
  std::size_t line_number() const { return line_number_; }
  std::size_t remaining_bytes() const { return pos_ < text_.size() ? text_.size() - pos_ : 0; }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t line_number_ = 0;
  std::vector<std::string_view> tokens_;
};

bool parse_double(std::string_view s, double& out) {
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && ptr == s.data() + s.size();
}

bool parse_int(std::string_view s, long long& out) {
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && ptr == s.data() + s.size();
}

void fan(const std::vector<std::uint32_t>& corners, std::vector<core::Triangle>& out) {
  for (std::size_t k = 1; k + 1 < corners.size(); ++k) out.push_back({corners[0], corners[k], corners[k + 1]});
}

}  // namespace

ApiResult<core::IndexedMesh> read_off(std::string_view text) {
  LineTokens lines(text);
  if (!lines.next()) return malformed("OFF", 0, "the file is empty");
  auto tokens = lines.tokens();
  std::size_t first = 0;
  const std::string_view header = tokens[0];
  if (header.size() >= 3 && header.substr(header.size() - 3) == "OFF") {
    first = 1;
    if (header.find("4") != std::string_view::npos || header.find("n") != std::string_view::npos) {
      return malformed("OFF", lines.line_number(), "only 3D OFF is supported, not '" + std::string(header) + "'");
    }
  }
  if (tokens.size() == first) {
    if (!lines.next()) return malformed("OFF", lines.line_number(), "missing the vertex and face counts");
    tokens = lines.tokens();
    first = 0;
  }
  long long nv = 0;
  long long nf = 0;
  if (tokens.size() < first + 2 || !parse_int(tokens[first], nv) || !parse_int(tokens[first + 1], nf) || nv < 0 ||
      nf < 0) {
    return malformed("OFF", lines.line_number(), "expected 'vertex_count face_count [edge_count]'");
  }
  // Each vertex needs at least 6 bytes and each face 8: larger counts are lies, refused
  // before any allocation sized by them.
  if (static_cast<unsigned long long>(nv) * 6 + static_cast<unsigned long long>(nf) * 8 > lines.remaining_bytes() + 16) {
    return malformed("OFF", lines.line_number(), "the declared counts do not fit in the file");
  }
  core::IndexedMesh mesh;
  mesh.positions.reserve(static_cast<std::size_t>(nv));
  for (long long v = 0; v < nv; ++v) {
    if (!lines.next()) return malformed("OFF", lines.line_number(), "the file ends inside the vertex list");
    const auto& t = lines.tokens();
    core::Vec3 p;
    if (t.size() < 3 || !parse_double(t[0], p.x()) || !parse_double(t[1], p.y()) || !parse_double(t[2], p.z())) {
      return malformed("OFF", lines.line_number(), "a vertex needs three numbers");
    }
    mesh.positions.push_back(p);
  }
  std::vector<std::uint32_t> corners;
  for (long long f = 0; f < nf; ++f) {
    if (!lines.next()) return malformed("OFF", lines.line_number(), "the file ends inside the face list");
    const auto& t = lines.tokens();
    long long n = 0;
    if (!parse_int(t[0], n) || n < 3 || static_cast<std::size_t>(n) + 1 > t.size()) {
      return malformed("OFF", lines.line_number(), "a face needs a corner count >= 3 and that many indices");
    }
    corners.clear();
    for (long long k = 0; k < n; ++k) {
      long long index = 0;
      if (!parse_int(t[1 + k], index) || index < 0 || index >= nv) {
        return malformed("OFF", lines.line_number(), "face index '" + std::string(t[1 + k]) + "' is out of range");
      }
      corners.push_back(static_cast<std::uint32_t>(index));
    }
    fan(corners, mesh.triangles);
  }
  return mesh;
}

ApiResult<core::IndexedMesh> read_obj(std::string_view text) {
  LineTokens lines(text);
  core::IndexedMesh mesh;
  std::vector<std::uint32_t> corners;
  while (lines.next()) {
    const auto& t = lines.tokens();
    if (t[0] == "v") {
      core::Vec3 p;
      if (t.size() < 4 || !parse_double(t[1], p.x()) || !parse_double(t[2], p.y()) || !parse_double(t[3], p.z())) {
        return malformed("OBJ", lines.line_number(), "a 'v' line needs three numbers");
      }
      mesh.positions.push_back(p);
    } else if (t[0] == "f") {
      if (t.size() < 4) return malformed("OBJ", lines.line_number(), "a face needs at least three corners");
      corners.clear();
      for (std::size_t k = 1; k < t.size(); ++k) {
        const std::string_view corner = t[k].substr(0, t[k].find('/'));
        long long index = 0;
        if (!parse_int(corner, index) || index == 0) {
          return malformed("OBJ", lines.line_number(), "bad face corner '" + std::string(t[k]) + "'");
        }
        const long long n = static_cast<long long>(mesh.positions.size());
        const long long zero_based = index > 0 ? index - 1 : n + index;
        if (zero_based < 0 || zero_based >= n) {
          return malformed("OBJ", lines.line_number(), "face corner '" + std::string(t[k]) + "' names no vertex");
        }
        corners.push_back(static_cast<std::uint32_t>(zero_based));
      }
      fan(corners, mesh.triangles);
    }
  }
  if (mesh.triangles.empty()) return malformed("OBJ", lines.line_number(), "the file has no faces");
  return mesh;
}

ApiResult<core::IndexedMesh> read_mesh_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return malformed_asset("cannot open '" + path + "'");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::string ext = path.substr(path.find_last_of('.') == std::string::npos ? path.size() : path.find_last_of('.'));
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".off") return read_off(text);
  if (ext == ".obj") return read_obj(text);
  return malformed_asset("'" + path + "' is neither .off nor .obj");
}

std::string write_off(const core::IndexedMesh& mesh) {
  std::ostringstream out;
  out.precision(17);
  out << "OFF\n" << mesh.positions.size() << ' ' << mesh.triangles.size() << " 0\n";
  for (const auto& p : mesh.positions) out << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  for (const auto& t : mesh.triangles) out << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
  return out.str();
}

}  // namespace seam::api
