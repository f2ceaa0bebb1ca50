#!/usr/bin/env bash
# Fetches CGAL's sample meshes (Debian's libcgal-demo ships them in data.tar.gz) into the
# git-ignored cache .cache/data/meshes, or into $SEAM_TEST_DATA_DIR/meshes when that is set
# (the CTest fixture `fetch_test_data` sets it to the build's SEAM_TEST_DATA_DIR).
# Then builds the real-looking glTF asset set from them (tests/assets/build_assets.mjs, with
# glTF-Transform from tests/node_modules) into .cache/assets beside the data directory, when
# Node and tests/node_modules are there (`npm install --prefix tests`); without them the asset
# tests fail naming this script, and every other test runs.
# Idempotent: does nothing when the meshes are present and the assets are built by the
# current builder (its manifest's stamp).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cache="${SEAM_DATA_CACHE:-$root/.cache}"
data="${SEAM_TEST_DATA_DIR:-$cache/data}"
meshes="$data/meshes"
assets="${SEAM_ASSETS_DIR:-$(dirname "$data")/assets}"

# The asset set: needs the meshes, node and the npm packages in tests/package.json.
build_assets() {
  local tests="$root/tests"
  if ! command -v node >/dev/null 2>&1 || [[ ! -d "$tests/node_modules" ]]; then
    echo "fetch-test-data: no node or no $tests/node_modules: the asset set is not built" \
         "(npm install --prefix tests)" >&2
    return 0
  fi
  local module
  for module in @gltf-transform/core @gltf-transform/extensions @gltf-transform/functions draco3dgltf gltf-validator; do
    if [[ ! -d "$tests/node_modules/$module" ]]; then
      echo "fetch-test-data: installing the npm packages of tests/package.json (missing $module)"
      (cd "$tests" && npm install --no-audit --no-fund --loglevel=error) ||
        { echo "fetch-test-data: npm install failed: the asset set is not built" >&2; return 0; }
      break
    fi
  done
  # The builder returns at once when its manifest's stamp matches; it fails on an asset the
  # validator finds invalid, which the asset tests then report.
  node "$tests/assets/build_assets.mjs" "$meshes" "$assets" ||
    echo "fetch-test-data: building the asset set into $assets failed" >&2
}

if [[ -f "$meshes/hand.off" && -f "$meshes/elephant.off" ]]; then
  build_assets
  exit 0
fi
mkdir -p "$cache/download"
cd "$cache/download"
if ! ls libcgal-demo_*.deb >/dev/null 2>&1; then
  # apt-get download runs as the _apt user when it can; a root-owned cache is fine too.
  apt-get download libcgal-demo 2>&1 | grep -v "^W: Download is performed unsandboxed" || true
fi
if ! ls libcgal-demo_*.deb >/dev/null 2>&1; then
  echo "fetch-test-data: could not download libcgal-demo (apt-get download libcgal-demo); the tests that" >&2
  echo "need CGAL's meshes cannot run without $meshes" >&2
  exit 1
fi
deb="$(ls libcgal-demo_*.deb | head -n 1)"
rm -rf extract && mkdir extract
dpkg-deb --fsys-tarfile "$deb" | tar -x -C extract ./usr/share/doc/libcgal-dev/data.tar.gz
tar -xzf extract/usr/share/doc/libcgal-dev/data.tar.gz -C extract data/meshes
mkdir -p "$data"
rm -rf "$meshes"
mv extract/data/meshes "$meshes"
rm -rf extract
echo "CGAL meshes in $meshes ($(ls "$meshes" | wc -l) files)"
build_assets
