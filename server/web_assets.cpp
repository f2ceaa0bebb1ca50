#include "server/web_assets.h"

namespace seam::server {

const WebAsset* find_web_asset(std::string_view path) {
  for (const WebAsset& asset : web_asset_table()) {
    if (asset.path == path) return &asset;
  }
  return nullptr;
}

}  // namespace seam::server
