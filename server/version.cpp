// Eigen before httplib.h: <resolv.h>'s `_res` macro must not reach Eigen's templates.
#include <Eigen/Core>

#include <draco/core/draco_version.h>
#include <httplib.h>
#include <nlohmann/json.hpp>
#include <spdlog/version.h>

#include "server/server.h"

namespace seam::server {

nlohmann::json version_info() {
  const std::string eigen = std::to_string(EIGEN_WORLD_VERSION) + "." + std::to_string(EIGEN_MAJOR_VERSION) + "." +
                            std::to_string(EIGEN_MINOR_VERSION);
  const std::string spdlog = std::to_string(SPDLOG_VER_MAJOR) + "." + std::to_string(SPDLOG_VER_MINOR) + "." +
                             std::to_string(SPDLOG_VER_PATCH);
  const std::string json = std::to_string(NLOHMANN_JSON_VERSION_MAJOR) + "." +
                           std::to_string(NLOHMANN_JSON_VERSION_MINOR) + "." +
                           std::to_string(NLOHMANN_JSON_VERSION_PATCH);
#ifdef NDEBUG
  const bool assertions = false;
#else
  const bool assertions = true;
#endif
  return {{"service", "seamd"},
          {"version", SEAM_VERSION},
          {"api", "v1"},
          {"build", {{"compiler", __VERSION__}, {"cplusplus", __cplusplus}, {"debug_assertions", assertions}}},
          {"libraries",
           {{"cpp-httplib", CPPHTTPLIB_VERSION},
            {"spdlog", spdlog},
            {"nlohmann_json", json},
            {"draco", draco::kDracoVersion},
            {"eigen", eigen}}}};
}

}  // namespace seam::server
