#!/usr/bin/env bash
# Builds the libFuzzer target for the asset loader with clang (-fsanitize=fuzzer,address,
# undefined) and runs it for N seconds (default 60) over a scratch copy of the committed seed
# corpus tests/fuzz/corpus. A crash, leak or sanitizer report fails the run and leaves the
# reproducer in build/fuzz/artifacts.
#   scripts/fuzz.sh [seconds]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
seconds="${1:-60}"
build="$root/build/fuzz"
cmake -S "$root/tests/fuzz" -B "$build" -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS="-DTINYGLTF_NO_STB_IMAGE -DTINYGLTF_NO_STB_IMAGE_WRITE -DTINYGLTF_NO_EXTERNAL_IMAGE -DTINYGLTF_ENABLE_DRACO" >/dev/null
cmake --build "$build" -j "${SEAM_JOBS:-2}"
work="$build/corpus"
rm -rf "$work" && mkdir -p "$work" "$build/artifacts"
cp "$root"/tests/fuzz/corpus/* "$work/"
"$build/gltf_fuzz" -max_total_time="$seconds" -max_len=65536 -rss_limit_mb=2048 -timeout=10 \
  -artifact_prefix="$build/artifacts/" "$work" 2>&1 | tail -n 5
echo "fuzz: ${seconds}s without a finding"
