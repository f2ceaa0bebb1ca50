#!/usr/bin/env bash
# Load benchmark of seamd on loopback with wrk (Debian): ~10k- and ~100k-face GLBs made from
# CGAL meshes at run time (scripts/off2glb.py), at 1, 8 and 64 concurrent connections.
# Prints a table: throughput, p50/p99 latency, share of 503s, peak RSS of seamd; and at
# concurrency 1 the CLI's time for the same job (`seamd seam`) against the HTTP latency.
# Last, connect-time percentiles under a burst of 256 connections (scripts/burst-bench.py).
#
#   scripts/load-bench.sh [SEAMD] [--workers N] [--duration S]
#
# SEAMD defaults to build-server/server/seamd. Meshes come from .cache/data/meshes
# (scripts/fetch-test-data.sh). seamd is restarted per row so peak RSS is per row.
set -euo pipefail

here="$(cd "$(dirname "$0")/.." && pwd)"
seamd="$here/build-server/server/seamd"
workers="$(nproc)"
duration=15
while (( $# )); do
  case "$1" in
    --workers) workers="$2"; shift 2 ;;
    --duration) duration="$2"; shift 2 ;;
    *) seamd="$1"; shift ;;
  esac
done
command -v wrk > /dev/null || { echo "load-bench: wrk missing (apt-get install wrk)"; exit 2; }
[[ -x "$seamd" ]] || { echo "load-bench: no seamd at $seamd"; exit 2; }
meshes="$here/.cache/data/meshes"
work="$(mktemp -d)"
port=18181
pid=""
cleanup() { [[ -n "$pid" ]] && kill "$pid" 2> /dev/null; wait 2> /dev/null; rm -rf "$work"; }
trap cleanup EXIT

# name  source  subdivisions  wrk-seconds. The job: automatic extrema, the MST method, no UV
# (override with SEAM_BENCH_QUERY / SEAM_BENCH_CLI_ARGS, keeping the two the same job).
inputs=("fandisk-13k fandisk 0 $duration" "dino-125k dino 2 $((duration * 4))")
query="${SEAM_BENCH_QUERY:-?method=mst&uv=none}"
cli_args="${SEAM_BENCH_CLI_ARGS:---method mst --uv none}"
for spec in "${inputs[@]}"; do
  read -r name src sub _ <<< "$spec"
  python3 "$here/scripts/off2glb.py" "$meshes/$src.off" "$work/$name.glb" --subdivide "$sub" > /dev/null
done

cat > "$work/post.lua" <<'LUA'
local f = assert(io.open(os.getenv("BODY_FILE"), "rb"))
wrk.method = "POST"
wrk.body = f:read("*a")
f:close()
wrk.headers["Content-Type"] = "model/gltf-binary"
done = function(summary, latency, requests)
  io.write(string.format("RESULT %d %.3f %d %d %.1f %.1f %.1f\n", summary.requests, summary.duration / 1e6,
    summary.errors.status, summary.errors.timeout + summary.errors.connect + summary.errors.read,
    latency:percentile(50) / 1000, latency:percentile(99) / 1000, latency.mean / 1000))
end
LUA

start_server() {
  "$seamd" --bind 127.0.0.1 --port "$port" --workers "$workers" --queue 256 --log-level warn \
    --time-budget-ms 600000 > "$work/seamd.log" 2>&1 &
  pid=$!
  for _ in $(seq 1 100); do curl -fsS "http://127.0.0.1:$port/healthz" > /dev/null 2>&1 && return; sleep 0.05; done
  echo "seamd did not start"; cat "$work/seamd.log"; exit 1
}
stop_server() {
  local hwm
  hwm=$(awk '/VmHWM/ {printf "%.0f", $2/1024}' "/proc/$pid/status")
  kill -TERM "$pid"; wait "$pid" || true; pid=""
  echo "$hwm"
}

# run_row NAME CONC SECONDS QUERY: one wrk run against a fresh seamd; sets $row (the printed
# line's fields) and $rps.
run_row() {
  local name=$1 conc=$2 secs=$3 q=$4 threads out rss reqs secs_run non2xx errs p50 p99 mean
  start_server
  threads=$(( conc < 2 ? 1 : 2 ))
  out=$(BODY_FILE="$work/$name.glb" wrk -t"$threads" -c"$conc" -d"${secs}s" --timeout 300s \
          -s "$work/post.lua" "http://127.0.0.1:$port/seam$q" 2>&1 | grep '^RESULT' || true)
  rss=$(stop_server)
  read -r _ reqs secs_run non2xx errs p50 p99 mean <<< "$out"
  rps=$(python3 -c "print(f'{$reqs/$secs_run:.2f}')")
  row=$(printf '%-12s %5d %9s %9s %9s %9s %7s %8s' "$name" "$conc" "$rps" "$p50" "$p99" "$mean" "$non2xx" "$rss")
  [[ "${errs:-0}" == 0 ]] || row+=$'\n'"             ($errs socket errors/timeouts)"
}

echo "seamd load benchmark: $(nproc) cores, --workers $workers, query '$query', $(date -u +%FT%TZ)"
printf '%-12s %5s %9s %9s %9s %9s %7s %8s\n' mesh conc req/s p50_ms p99_ms mean_ms 503s rss_MB
for spec in "${inputs[@]}"; do
  read -r name _ _ secs_row <<< "$spec"
  for conc in 1 8 64; do
    run_row "$name" "$conc" "$secs_row" "$query"
    echo "$row"
  done
done

# Issue 14, item 5: with the per-request thread budget (CPUs / workers), 8 clients must get at
# least 1.8x the single client's throughput. Measured on the default job (skeleton seam, SLIM,
# GLB out), which is what most callers send.
echo
echo "Concurrency scaling, default job (no query): throughput at 8 clients / at 1 (target >= 1.8):"
printf '%-12s %9s %9s %7s %7s\n' mesh rps_1 rps_8 ratio target
for spec in "${inputs[@]}"; do
  read -r name _ _ secs_row <<< "$spec"
  run_row "$name" 1 "$secs_row" ""; rps1=$rps
  run_row "$name" 8 "$secs_row" ""; rps8=$rps
  python3 - "$name" "$rps1" "$rps8" <<'PY'
import sys
name, r1, r8 = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
ratio = r8 / r1 if r1 > 0 else 0.0
print(f'{name:<12} {r1:9.2f} {r8:9.2f} {ratio:7.2f} {">= 1.8":>7} {"met" if ratio >= 1.8 else "MISSED"}')
PY
done

echo
echo "HTTP vs CLI at concurrency 1 (same GLB, same parameters; mean of 5 runs):"
printf '%-12s %10s %10s %10s %8s\n' mesh cli_ms http_ms pipeline_ms overhead
for spec in "${inputs[@]}"; do
  read -r name _ _ _ <<< "$spec"
  cli_total=0
  for _ in 1 2 3 4 5; do
    t0=$(date +%s%N)
    # shellcheck disable=SC2086
    "$seamd" seam --mesh "$work/$name.glb" $cli_args > "$work/cli.json"
    cli_total=$(( cli_total + $(date +%s%N) - t0 ))
  done
  start_server
  http_total=0
  for _ in 1 2 3 4 5; do
    t0=$(date +%s%N)
    curl -fsS -o "$work/http.json" -H 'Content-Type: model/gltf-binary' --data-binary "@$work/$name.glb" \
      "http://127.0.0.1:$port/seam$query"
    http_total=$(( http_total + $(date +%s%N) - t0 ))
  done
  stop_server > /dev/null
  pipeline=$(python3 -c "import json; print(json.load(open('$work/http.json'))['timings_ms']['total'])")
  python3 - "$name" "$cli_total" "$http_total" "$pipeline" <<'PY'
import sys
name, cli, http, pipe = sys.argv[1], int(sys.argv[2]) / 5e6, int(sys.argv[3]) / 5e6, float(sys.argv[4])
print(f'{name:<12} {cli:10.1f} {http:10.1f} {pipe:10.1f} {100 * (http - cli) / cli:+7.1f}%')
PY
done

echo
echo "Connection bursts (scripts/burst-bench.py): 256 clients connecting at once, 6 rounds,"
echo "with the library's old backlog of 5 and the default of 1024:"
python3 "$here/scripts/burst-bench.py" --seamd "$seamd" --clients 256 --rounds 6 --backlogs 5,1024
