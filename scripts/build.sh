#!/usr/bin/env bash
# Configures and builds one flavour of the project into build/<flavour>.
#   scripts/build.sh release|asan [extra cmake args...]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
flavour="${1:-release}"
shift || true
jobs="${SEAM_JOBS:-2}"
case "$flavour" in
  release) args=(-DCMAKE_BUILD_TYPE=Release) ;;
  # -Og -g1 rather than RelWithDebInfo's -O2 -g: GCC's -O2 over UBSan's checks made this build
  # 2-3x slower to compile (tests/api/pipeline_test.cpp 119 against 35 s, core/uv/slim.cpp 62
  # against 18 s, compiled side by side), while the sanitizer tests run 10-25% longer. -g1 keeps the line tables the reports print.
  asan) args=(-DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-Og -g1 -DNDEBUG"
              "-DSEAM_SANITIZE=address;undefined") ;;
  *) echo "usage: scripts/build.sh release|asan [cmake args]" >&2; exit 2 ;;
esac
# Explicit defaults, so options cached by an earlier configure never leak into this one;
# the caller's arguments come last and win.
defaults=(-DSEAM_BUILD_SERVER=ON -DSEAM_BUILD_TESTS=ON -DSEAM_BUILD_BENCH=OFF -DSEAM_WERROR=OFF -DSEAM_UNITY_BATCH=8)
cmake -S "$root" -B "$root/build/$flavour" -G Ninja "${args[@]}" "${defaults[@]}" "$@" >/dev/null
cmake --build "$root/build/$flavour" -j "$jobs"
