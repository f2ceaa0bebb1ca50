// Base64 (RFC 4648, standard alphabet): the one codec for data URIs in assets, the JSON
// request form's mesh.glb_base64 and the response's asset.glb_base64.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "core/error.h"

namespace seam::api {

/// Why a text is not base64, and where.
struct Base64Error {
  enum class Kind {
    kBadCharacter,  ///< a character outside the alphabet, or data after '=' padding
    kTruncated,     ///< a symbol count that no byte string encodes, or bad padding
  };
  Kind kind = Kind::kBadCharacter;
  std::size_t offset = 0;   ///< kBadCharacter: the offending character's offset
  std::size_t symbols = 0;  ///< kTruncated: the data symbols read
  /// "unexpected character at offset 12" or "truncated (length 5 symbols)".
  std::string describe() const;
};

/// Decodes base64. Padding is optional; ASCII whitespace (space, tab, CR, LF) is skipped, as
/// MIME and wrapped JSON strings carry it. Errors: Base64Error. O(text).
core::Result<std::string, Base64Error> decode_base64(std::string_view text);

/// Encodes with '=' padding, no line breaks. O(bytes).
std::string encode_base64(std::string_view bytes);

}  // namespace seam::api
