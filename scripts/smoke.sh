#!/usr/bin/env bash
# Smoke test of a deployed seam service, as a texturing farm would run it:
#   scripts/smoke.sh [BASE_URL]            (default http://127.0.0.1:8080)
# Needs curl and python3. The sample asset comes from $SAMPLE (a GLB), or is written by
# `seamd sample` ($SEAMD, or seamd on PATH, or build*/server/seamd in this checkout).
# Checks: /healthz and /readyz, /version, one seam on the sample (JSON, then GLB),
# one bad request (a JSON 4xx error body), X-Request-Id echo. Exit 0 only if all pass.
set -euo pipefail

BASE="${1:-${BASE_URL:-http://127.0.0.1:8080}}"
BASE="${BASE%/}"
here="$(cd "$(dirname "$0")/.." && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
failures=0

pass() { printf 'ok    %s\n' "$1"; }
fail() { printf 'FAIL  %s\n' "$1"; failures=$((failures + 1)); }

# --- the sample asset -------------------------------------------------------------------
sample="${SAMPLE:-}"
if [[ -z "$sample" ]]; then
  seamd="${SEAMD:-$(command -v seamd || true)}"
  if [[ -z "$seamd" ]]; then
    for candidate in "$here"/build*/server/seamd; do
      [[ -x "$candidate" ]] && seamd="$candidate" && break
    done
  fi
  [[ -n "$seamd" ]] || { echo "smoke: set SAMPLE=asset.glb or SEAMD=/path/to/seamd" >&2; exit 2; }
  "$seamd" sample --out "$work/sample.glb" > /dev/null
  sample="$work/sample.glb"
fi
[[ -s "$sample" ]] || { echo "smoke: sample $sample is missing or empty" >&2; exit 2; }

# --- health -------------------------------------------------------------------------------
code=$(curl -sS -o "$work/h" -w '%{http_code}' "$BASE/healthz") || code=000
[[ "$code" == 200 ]] && grep -q '"ok"' "$work/h" && pass "GET /healthz -> 200" || fail "GET /healthz -> $code"

code=$(curl -sS -o "$work/r" -w '%{http_code}' "$BASE/readyz") || code=000
[[ "$code" == 200 ]] && pass "GET /readyz -> 200" || fail "GET /readyz -> $code $(cat "$work/r" 2>/dev/null)"

code=$(curl -sS -o "$work/v" -w '%{http_code}' "$BASE/version") || code=000
[[ "$code" == 200 ]] && pass "GET /version -> 200 $(tr -d '\n' < "$work/v" | cut -c1-80)" || fail "GET /version -> $code"

# --- the viewer: its page and its bundle (a build without Node.js serves a page saying so) ---
code=$(curl -sS -o "$work/index" -w '%{http_code}' "$BASE/") || code=000
if [[ "$code" == 200 ]] && grep -q 'src="/viewer.js"' "$work/index"; then
  code=$(curl -sS -o "$work/viewer.js" -w '%{http_code}' "$BASE/viewer.js") || code=000
  [[ "$code" == 200 && -s "$work/viewer.js" ]] && pass "GET / and /viewer.js -> 200 ($(wc -c < "$work/viewer.js") bytes of viewer)" \
    || fail "GET /viewer.js -> $code"
else
  fail "GET / -> $code without the viewer's page"
fi

# --- one seam on the sample (multipart, the curl form) ------------------------------------
start=$(date +%s.%N)
code=$(curl -sS -o "$work/seam.json" -D "$work/seam.h" -w '%{http_code}' \
        -H 'X-Request-Id: smoke-test-1' -F "mesh=@$sample" "$BASE/seam") || code=000
elapsed=$(python3 -c "import sys; print(f'{float(sys.argv[2]) - float(sys.argv[1]):.3f}')" "$start" "$(date +%s.%N)")
if [[ "$code" == 200 ]] && python3 - "$work/seam.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
s, cut = r["seam"], r["cut"]
assert s["edges"], "no seam edges"
assert cut["euler_characteristic"] == 1 and cut["boundary_loops"] == 1, cut
assert len(r["asset"]["glb_base64"]) > 100
print(f'      seam: {len(s["edges"])} edges, length {s["length"]:.4g}, {len(s["extrema"])} extrema, '
      f'mesh {r["mesh"]["faces"]} faces, total {r["timings_ms"]["total"]:.1f} ms')
PY
then
  pass "POST /seam (multipart sample) -> 200 in ${elapsed}s, cut is a disc"
else
  fail "POST /seam (multipart sample) -> $code $(head -c 300 "$work/seam.json" 2>/dev/null)"
fi
grep -qi '^x-request-id: smoke-test-1' "$work/seam.h" && pass "X-Request-Id echoed" || fail "X-Request-Id not echoed"

code=$(curl -sS -o "$work/cut.glb" -w '%{http_code}' -H 'Accept: model/gltf-binary' \
        -H 'Content-Type: model/gltf-binary' --data-binary "@$sample" "$BASE/seam") || code=000
if [[ "$code" == 200 && "$(head -c 4 "$work/cut.glb")" == "glTF" ]]; then
  pass "POST /seam (raw GLB, Accept: model/gltf-binary) -> 200, $(stat -c %s "$work/cut.glb") bytes of GLB"
else
  fail "POST /seam (raw GLB -> GLB) -> $code"
fi

# --- one bad request ------------------------------------------------------------------------
code=$(curl -sS -o "$work/bad.json" -w '%{http_code}' -H 'Content-Type: model/gltf-binary' \
        --data-binary 'this is not a GLB' "$BASE/seam") || code=000
if [[ "$code" == 400 ]] && python3 -c "import json,sys; e=json.load(open(sys.argv[1]))['error']; assert e['code'] and e['message']; print('      error:', e['code'], '-', e['message'][:90])" "$work/bad.json"; then
  pass "POST /seam (garbage) -> 400 with a JSON error body"
else
  fail "POST /seam (garbage) -> $code $(head -c 200 "$work/bad.json" 2>/dev/null)"
fi

if (( failures > 0 )); then
  echo "smoke: $failures check(s) failed against $BASE"
  exit 1
fi
echo "smoke: all checks passed against $BASE"
