#!/usr/bin/env bash
# Atlas coverage beside xatlas (issue 12's anchor: xatlas through `gltf-transform unwrap
# --group-by scene` reached 0.57-0.72 coverage with 300-8,500 charts). Same inputs, one atlas
# per input, default options on both sides:
#   1. the test assets (.cache/assets, plain variants: the Draco and quantized ones carry the
#      same geometry): ours is `seamd seam` (default job, pack group_by asset): uv.coverage and
#      the chart count (the cut primitives' Euler characteristics: every chart is a disc), then
#      the same job with `pack.split: true` (uv.charts per primitive);
#      xatlas gets every TRIANGLES primitive of every glTF mesh once, in mesh space (node
#      transforms and instancing ignored), which is what the service cuts and packs.
#   2. bench/atlas_bench.cpp's packing groups of CGAL meshes (with ATLAS_BENCH, whose `pack`
#      section prints ours, default and with the sprawling charts split): xatlas gets the same
#      meshes as one atlas.
# coverage = chart UV area / atlas area on both sides (xatlas: its width x height, which
# gltf-transform scales to [0,1]^2 per axis; area ratios are unchanged). util = xatlas's own
# texel utilization (rasterized charts plus bilinear-sampled texels). xatlas pads 0 texels by
# default, ours keeps 4 px margins at 1024.
#
#   XATLAS_BIN=/path/to/xatlas_run scripts/xatlas-coverage.sh [SEAMD]
#   env: ATLAS_BENCH=build/<dir>/bench/atlas_bench (optional, section 2 ours)
#
# xatlas_run is a small driver around jpcy/xatlas (docs/peers.md builds it in a scratch
# folder); it is never built or fetched here. Without XATLAS_BIN the script says so and
# exits 0. SEAMD defaults to build/release/server/seamd.
set -euo pipefail

here="$(cd "$(dirname "$0")/.." && pwd)"
seamd="${1:-$here/build/release/server/seamd}"
if [[ -z "${XATLAS_BIN:-}" || ! -x "${XATLAS_BIN:-}" ]]; then
  echo "xatlas-coverage: skipped: set XATLAS_BIN to an xatlas_run binary (docs/peers.md builds one)"
  exit 0
fi
[[ -x "$seamd" ]] || { echo "xatlas-coverage: no seamd at $seamd"; exit 2; }
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
echo "xatlas-coverage: $(uptime)"
atlas_bench="${ATLAS_BENCH:-}"
[[ -n "$atlas_bench" ]] && atlas_bench="$(realpath "$atlas_bench")"  # it runs from the repo root
SEAMD="$seamd" XATLAS="$XATLAS_BIN" WORK="$work" ROOT="$here" ATLAS_BENCH="$atlas_bench" python3 - <<'PY'
import json, os, re, subprocess, sys

env = os.environ
root, work = env["ROOT"], env["WORK"]
assets_dir = os.path.join(root, ".cache", "assets")
meshes_dir = os.path.join(root, ".cache", "data", "meshes")


def xatlas(files):
    p = subprocess.run([env["XATLAS"], *files], capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"xatlas-coverage: xatlas_run failed on {files}: {p.stderr.strip()[:300]}")
    return dict(kv.split("=", 1) for kv in p.stdout.split())


def ours_asset(path, split=False):
    cmd = [env["SEAMD"], "seam", path, os.path.join(work, "out.glb")]
    if split:
        cmd[2:2] = ["--params", '{"pack": {"split": true}}']
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        return None, None
    prims = json.loads(p.stdout)["primitives"]
    coverage = prims[0]["uv"]["coverage"] if prims else 0.0
    charts = sum(q["uv"].get("charts", q["cut"]["euler_characteristic"]) for q in prims)
    return coverage, charts


def cell(value, fmt):
    return format(value, fmt) if value is not None else "-"


def row(label, faces, ours, split, xa):
    print(f"{label:<46} {faces:>7} {cell(ours[0], '.3f'):>8} {cell(ours[1], 'd'):>7} {cell(split[0], '.3f'):>8} "
          f"{cell(split[1], 'd'):>7} {float(xa['coverage']):>8.3f} {float(xa['utilization']):>6.3f} "
          f"{xa['charts']:>7} {float(xa['ms']):>8.0f}", flush=True)


header = (f"{'asset':<46} {'faces':>7} {'ours':>8} {'charts':>7} {'split':>8} {'charts':>7} {'xatlas':>8} {'util':>6} "
          f"{'charts':>7} {'xa_ms':>8}")
manifest = json.load(open(os.path.join(assets_dir, "manifest.json")))
print("\n== 1. test assets (mesh space, one atlas per asset): coverage and charts")
print(header)
for a in manifest["assets"]:
    if a.get("variant") != "plain":
        continue
    path = os.path.join(assets_dir, a["file"])
    row(a["file"], a["faces"], ours_asset(path), ours_asset(path, split=True), xatlas([path]))

# The groups of bench/atlas_bench.cpp pack_section (label -> CGAL meshes), in its order.
groups = [
    ("animals: hand camel dino elephant", ["hand", "camel", "dino", "elephant"]),
    ("figures: homer man bear armadillo", ["homer", "man", "bear", "armadillo"]),
    ("mixed: bunny mushroom elk knot1 pig", ["bunny00", "mushroom", "elk", "knot1", "pig"]),
    ("hard: fandisk rotor pinion joint cube", ["fandisk", "rotor", "pinion", "joint", "cube"]),
    ("hard: cheese-box couplingdown turbine", ["cheese-box", "couplingdown", "turbine"]),
]
ours, split = {}, {}
if env.get("ATLAS_BENCH") and os.access(env["ATLAS_BENCH"], os.X_OK):
    bench = subprocess.run([env["ATLAS_BENCH"], "pack"], capture_output=True, text=True, cwd=root)
    out = bench.stdout
    for line in (bench.stdout + bench.stderr).splitlines():
        if line.startswith("cannot load"):
            print("   atlas_bench: " + line)
    last = None  # atlas_bench prints a group's split row right after the group's own row
    for line in out.splitlines():
        for label, _ in groups:
            if line.startswith(label + " "):
                cols = line[len(label):].split()
                if cols and cols[0] in ("seam", "features"):
                    ours[label] = (float(cols[5]), int(cols[1]), cols[0])
                    last = label
        if line.startswith("  + split sprawling charts") and last is not None:
            cols = line[len("  + split sprawling charts"):].split()
            split[last] = (float(cols[5]), int(cols[1]))
            last = None
print("\n== 2. atlas_bench packing groups (CGAL meshes, one atlas per group): coverage and charts")
if not ours:
    print("   (ours: set ATLAS_BENCH to build/<dir>/bench/atlas_bench to fill these columns)")
print(header)
for label, names in groups:
    files = [os.path.join(meshes_dir, n + ".off") for n in names]
    xa = xatlas(files)
    cov, charts, kind = ours.get(label, (None, None, ""))
    row(f"{label} ({kind})" if kind else label, int(xa["faces"]), (cov, charts), split.get(label, (None, None)), xa)
PY
