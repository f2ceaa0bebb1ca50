// Known findings a fuzz campaign may look past (docs/fuzzing.md "Findings"): the environment
// variable SEAM_FUZZ_TOLERATE lists their names, comma-separated, e.g.
// SEAM_FUZZ_TOLERATE=long-field-line. Unset (CI), every finding is a crash. Remove a name here
// and from the docs once its fix has landed.
#pragma once

#include <cstdlib>
#include <string>
#include <string_view>

namespace seam::fuzz {

inline bool tolerated(std::string_view finding) {
  static const std::string list = [] {
    const char* env = std::getenv("SEAM_FUZZ_TOLERATE");
    return "," + std::string(env ? env : "") + ",";
  }();
  return list.find("," + std::string(finding) + ",") != std::string::npos;
}

}  // namespace seam::fuzz
