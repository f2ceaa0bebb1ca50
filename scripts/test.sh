#!/usr/bin/env bash
# Set-up command 2: install what is missing, build, and run every test:
#   1. Release build with warnings as errors: all doctest suites (core, api, end-to-end server),
#      real CGAL meshes, glTF-Validator checks.
#   2. The same unit and end-to-end suites under AddressSanitizer + UndefinedBehaviorSanitizer.
#   3. A short libFuzzer run of every fuzz target (asset loader, request head, request layer,
#      multipart, atlas, the per-primitive job) over its corpus and regression inputs
#      (scripts/fuzz.sh).
# Exits non-zero when anything fails.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
jobs="${SEAM_JOBS:-2}"
start=$(date +%s)
# Each phase prints its seconds, so a CI log shows where the budget (30 minutes) goes.
phase_start=$start
phase_done() {
  local now
  now=$(date +%s)
  echo "== $1: $(( now - phase_start )) s =="
  phase_start=$now
}
"$root/scripts/install-deps.sh" --test
"$root/scripts/fetch-test-data.sh"
phase_done "dependencies and test data"

echo "== release build (-Werror) =="
"$root/scripts/build.sh" release -DSEAM_WERROR=ON -DSEAM_BUILD_TESTS=ON
phase_done "release build"
echo "== release tests =="
ctest --test-dir "$root/build/release" -j "$jobs" --output-on-failure --timeout 900
phase_done "release tests"

echo "== sanitizer build (address;undefined, -Werror) =="
"$root/scripts/build.sh" asan -DSEAM_WERROR=ON -DSEAM_BUILD_TESTS=ON
phase_done "sanitizer build"
echo "== sanitizer tests =="
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir "$root/build/asan" -j "$jobs" --output-on-failure --timeout 1800
phase_done "sanitizer tests"

if [[ -x "$root/scripts/fuzz.sh" ]]; then
  echo "== fuzz (short run) =="
  "$root/scripts/fuzz.sh" 60
  phase_done "fuzzing"
fi
echo "== all tests passed in $(( $(date +%s) - start )) s =="
