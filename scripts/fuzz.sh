#!/usr/bin/env bash
# The libFuzzer targets of tests/fuzz (docs/fuzzing.md): one clang build (-fsanitize=fuzzer,
# address,undefined) into build/fuzz, then
#   scripts/fuzz.sh [seconds]        every target for `seconds` (default 60) over a scratch copy
#                                    of its committed corpus plus its regression inputs (CI)
#   scripts/fuzz.sh --campaign RUNS  the long campaign: RUNS executions in all, split evenly
#                                    across the targets (-runs per target); then the committed
#                                    corpora are minimized with what the runs found
#   scripts/fuzz.sh --minimize       only that minimization
# Minimizing keeps the hand-written seeds (files not named by a SHA-1) and, of every other
# input, committed or new, a small set that covers the same edges (-merge=1 -use_counters=0:
# edges, not hit counts, so that a corpus stays a few hundred files).
# Targets run ${SEAM_JOBS:-2} at a time. A crash, leak, timeout, out-of-memory or sanitizer
# report fails the run (exit 1) and leaves the reproducer in build/fuzz/artifacts, named after
# its target. Per target: executions, executions per second, seconds, corpus size, findings.
# Environment:
#   SEAM_JOBS            parallel compile jobs and fuzzers (default 2)
#   SEAM_FUZZ_TARGETS    a subset, e.g. "request_fuzz multipart_fuzz"
#   SEAM_FUZZ_TOLERATE   known findings to look past, comma-separated (docs/fuzzing.md
#                        "Findings"); unset in CI, so that every finding fails the run
#   SEAM_FUZZ_SANITIZERS off: build into build/fuzz-fast without ASan/UBSan (-O2, coverage
#                        only) for a campaign: the targets' properties at 3-5x the executions,
#                        no memory or UB checks (CI keeps them on)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$root/build/fuzz"
sanitizers=ON
if [[ "${SEAM_FUZZ_SANITIZERS:-on}" == off ]]; then
  build="$root/build/fuzz-fast"
  sanitizers=OFF
fi
jobs="${SEAM_JOBS:-2}"
read -r -a targets <<<"${SEAM_FUZZ_TARGETS:-gltf_fuzz http_head_fuzz request_fuzz multipart_fuzz atlas_fuzz mesh_fuzz}"

campaign=0
minimize_only=0
if [[ "${1:-}" == "--campaign" ]]; then
  campaign=1
  total_runs="${2:?usage: scripts/fuzz.sh --campaign RUNS}"
  per_target=$(( (total_runs + ${#targets[@]} - 1) / ${#targets[@]} ))
elif [[ "${1:-}" == "--minimize" ]]; then
  minimize_only=1
else
  seconds="${1:-60}"
fi

short() { echo "${1%_fuzz}"; }
corpus_of() { if [[ "$1" == gltf_fuzz ]]; then echo "$root/tests/fuzz/corpus"; else echo "$root/tests/fuzz/corpus_$(short "$1")"; fi; }
max_len_of() {
  case "$1" in
    gltf_fuzz) echo 65536 ;;
    mesh_fuzz) echo 1024 ;;  # 66 vertices and 160 triangles take 690 bytes
    *) echo 16384 ;;
  esac
}

start=$(date +%s)
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S "$root/tests/fuzz" -B "$build" -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DSEAM_FUZZ_SANITIZERS="$sanitizers" "${launcher[@]}" >/dev/null
cmake --build "$build" -j "$jobs" --target "${targets[@]}"
built=$(date +%s)
echo "fuzz: built ${targets[*]} in $(( built - start )) s"

mkdir -p "$build/artifacts" "$build/logs"
# One target: fuzz a scratch copy of its corpus (campaign: keep it for the merge), write the
# exit status and the timing next to the log.
run_target() {
  local t="$1" work="$build/work/$1" log="$build/logs/$1.log"
  local args=(-max_len="$(max_len_of "$t")" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1
              -artifact_prefix="$build/artifacts/$t-")
  [[ -f "$root/tests/fuzz/$(short "$t").dict" ]] && args+=(-dict="$root/tests/fuzz/$(short "$t").dict")
  if (( campaign )); then args+=(-runs="$per_target"); else args+=(-max_total_time="$seconds"); fi
  local dirs=("$work")
  [[ -d "$root/tests/fuzz/regressions/$(short "$t")" ]] && dirs+=("$root/tests/fuzz/regressions/$(short "$t")")
  rm -rf "$work" && mkdir -p "$work"
  cp "$(corpus_of "$t")"/* "$work/"
  local t0 rc=0
  t0=$(date +%s)
  "$build/$t" "${args[@]}" "${dirs[@]}" >"$log" 2>&1 || rc=$?
  echo "$rc $(( $(date +%s) - t0 ))" >"$build/logs/$t.status"
}

# The committed corpus of target $1, minimized together with its campaign work directory.
minimize() {
  local t="$1" committed out="$build/minimized/$1" sha='.*/[0-9a-f]{40}'
  committed="$(corpus_of "$t")"
  rm -rf "$out" && mkdir -p "$out"
  find "$committed" -maxdepth 1 -type f -regextype posix-extended ! -regex "$sha" -exec cp {} "$out/" \;
  local inputs=("$committed")
  (( campaign )) && inputs+=("$build/work/$t")
  "$build/$t" -merge=1 -use_counters=0 -max_len="$(max_len_of "$t")" -timeout=10 -rss_limit_mb=2048 \
    -artifact_prefix="$build/artifacts/$t-merge-" "$out" "${inputs[@]}" >"$build/logs/$t.merge.log" 2>&1
  local before
  before=$(ls "$committed" | wc -l)
  find "$committed" -maxdepth 1 -type f -regextype posix-extended -regex "$sha" -delete
  find "$out" -maxdepth 1 -type f -regextype posix-extended -regex "$sha" -exec cp {} "$committed/" \;
  echo "fuzz: $t: $(echo "$committed" | sed "s|$root/||") minimized from $before to $(ls "$committed" | wc -l) files"
}

if (( minimize_only )); then
  for t in "${targets[@]}"; do minimize "$t"; done
  exit 0
fi

for t in "${targets[@]}"; do
  while (( $(jobs -rp | wc -l) >= jobs )); do wait -n || true; done
  echo "fuzz: $t ..."
  run_target "$t" &
done
wait

if (( campaign )); then
  for t in "${targets[@]}"; do minimize "$t"; done
fi

failed=0
total=0
printf '\n%-16s %12s %9s %7s %8s %10s  %s\n' target executions exec/s seconds corpus "corpus KB" result
for t in "${targets[@]}"; do
  log="$build/logs/$t.log"
  read -r rc secs <"$build/logs/$t.status"
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log")
  dir="$build/work/$t"
  (( campaign )) && dir="$(corpus_of "$t")"
  files=$(ls "$dir" | wc -l)
  kb=$(( $(du -sb "$dir" | cut -f1) / 1024 ))
  result=ok
  if [[ "$rc" != 0 ]]; then
    failed=1
    result="FAILED (exit $rc): $(grep -m1 -E 'SUMMARY|ERROR: libFuzzer' "$log" || echo 'see log')"
  fi
  total=$(( total + ${runs:-0} ))
  printf '%-16s %12s %9s %7s %8s %10s  %s\n' "$t" "${runs:-?}" "${rate:-?}" "$secs" "$files" "$kb" "$result"
  grep -h 'Test unit written to' "$log" | sed 's/^.*Test unit written to /    reproducer: /' || true
done
echo "fuzz: $total executions; logs in ${build#"$root"/}/logs; total $(( $(date +%s) - start )) s (build $(( built - start )) s)"
if (( failed )); then
  echo "fuzz: FAILED: see the reproducers above (docs/fuzzing.md: reproducing a finding)" >&2
  exit 1
fi
echo "fuzz: no finding"
