#!/usr/bin/env bash
# Fetches CGAL's sample meshes (Debian's libcgal-demo ships them in data.tar.gz) into the
# git-ignored cache .cache/data/meshes, or into $SEAM_TEST_DATA_DIR/meshes when that is set
# (the CTest fixture `fetch_test_data` sets it to the build's SEAM_TEST_DATA_DIR).
# Idempotent: does nothing when they are present.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cache="${SEAM_DATA_CACHE:-$root/.cache}"
data="${SEAM_TEST_DATA_DIR:-$cache/data}"
meshes="$data/meshes"
if [[ -f "$meshes/hand.off" && -f "$meshes/elephant.off" ]]; then
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
