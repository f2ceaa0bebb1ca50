#!/usr/bin/env bash
# Set-up command 1: install what is missing, build, write the bundled sample mesh and start
# seamd on 127.0.0.1:8080 (override with SEAMD_PORT / SEAMD_BIND). Ctrl-C stops it.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh" release -DSEAM_BUILD_TESTS=OFF
seamd="$root/build/release/server/seamd"
sample="$root/build/sample.glb"
"$seamd" sample --out "$sample" >/dev/null
port="${SEAMD_PORT:-8080}"
bind="${SEAMD_BIND:-127.0.0.1}"
cat <<MSG

seamd is starting on http://$bind:$port  (Ctrl-C to stop)
Try it with the bundled sample (a procedural shape with five protrusions):

  curl -s -F mesh=@$sample -F 'params={"method":"skeleton"}' http://$bind:$port/seam | python3 -m json.tool | grep -v glb_base64 | head -n 60

(the full answer also carries the cut asset as asset.glb_base64; for the GLB itself use
 -F 'params={"method":"skeleton","output":"glb"}' -o cut.glb)

MSG
exec "$seamd" --bind "$bind" --port "$port"
