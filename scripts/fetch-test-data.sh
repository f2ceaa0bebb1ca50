#!/usr/bin/env bash
# Fetches CGAL's sample meshes (Debian's libcgal-demo ships them in data.tar.gz) into the
# git-ignored cache .cache/data/meshes. Idempotent: does nothing when they are present.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cache="${SEAM_DATA_CACHE:-$root/.cache}"
meshes="$cache/data/meshes"
if [[ -f "$meshes/hand.off" && -f "$meshes/elephant.off" ]]; then
  exit 0
fi
mkdir -p "$cache/download"
cd "$cache/download"
if ! ls libcgal-demo_*.deb >/dev/null 2>&1; then
  # apt-get download runs as the _apt user when it can; a root-owned cache is fine too.
  apt-get download libcgal-demo 2>&1 | grep -v "^W: Download is performed unsandboxed" || true
fi
deb="$(ls libcgal-demo_*.deb | head -n 1)"
rm -rf extract && mkdir extract
dpkg-deb --fsys-tarfile "$deb" | tar -x -C extract ./usr/share/doc/libcgal-dev/data.tar.gz
mkdir -p "$cache/data"
tar -xzf extract/usr/share/doc/libcgal-dev/data.tar.gz -C "$cache" data/meshes
rm -rf extract
echo "CGAL meshes in $meshes ($(ls "$meshes" | wc -l) files)"
