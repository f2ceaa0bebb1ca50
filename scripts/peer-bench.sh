#!/usr/bin/env bash
# Peer benchmark of issue 14, item 1: the default CLI job of seamd (seam + cut + default UVs +
# packed GLB out) against Boundary First Flattening's command line on the same closed CGAL
# meshes, whole processes, paired runs (seamd and BFF alternate, the order flipping every
# pair), N runs each after one unmeasured warm-up run of each. seamd gets at most K automatic
# extrema ({"auto": true, "max_count": K}); BFF gets as many cones as seamd kept extrema
# (--nCones=E --normalizeUVs; BFF itself turns fewer than 3 into 8 on a closed mesh).
# Prints per mesh: faces, extrema seamd kept = BFF cones,
# the medians of seamd ms, BFF ms and of the paired ratio seamd/BFF against the 0.5 target,
# then the median of seamd's own timings_ms stages over the same runs.
#
#   BFF_CLI=/path/to/bff-command-line scripts/peer-bench.sh [SEAMD]
#   env: MESHES="homer camel armadillo" (CGAL names), K=8, N=5
#
# BFF is not built or fetched here (docs/peers.md says how to build it from its public
# source); without BFF_CLI the script says so and exits 0. SEAMD defaults to
# build/release/server/seamd. Meshes come from .cache/data/meshes (scripts/fetch-test-data.sh).
set -euo pipefail

here="$(cd "$(dirname "$0")/.." && pwd)"
seamd="${1:-$here/build/release/server/seamd}"
if [[ -z "${BFF_CLI:-}" || ! -x "${BFF_CLI:-}" ]]; then
  echo "peer-bench: skipped: set BFF_CLI to a bff-command-line binary (docs/peers.md builds one)"
  exit 0
fi
[[ -x "$seamd" ]] || { echo "peer-bench: no seamd at $seamd"; exit 2; }
meshes_dir="$here/.cache/data/meshes"
[[ -d "$meshes_dir" ]] || { echo "peer-bench: no $meshes_dir (scripts/fetch-test-data.sh)"; exit 2; }
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

echo "peer-bench: $(uptime)"
echo "peer-bench: $("$seamd" --version 2>/dev/null | head -1) ($seamd), BFF $BFF_CLI"
SEAMD="$seamd" BFF="$BFF_CLI" WORK="$work" MESH_DIR="$meshes_dir" OFF2GLB="$here/scripts/off2glb.py" \
  MESHES="${MESHES:-homer camel armadillo}" K="${K:-8}" N="${N:-5}" python3 - <<'PY'
import json, os, statistics, subprocess, sys, time

env = os.environ
work, k, n = env["WORK"], int(env["K"]), int(env["N"])
sys.path.insert(0, os.path.dirname(env["OFF2GLB"]))
from off2glb import read_off  # noqa: E402  (the repo's OFF reader, fan-triangulating)


def prepare(name):
    off = os.path.join(env["MESH_DIR"], name + ".off")
    verts, tris = read_off(off)
    obj = os.path.join(work, name + ".obj")
    with open(obj, "w") as f:
        f.write("".join(f"v {x} {y} {z}\n" for x, y, z in verts))
        f.write("".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in tris))
    glb = os.path.join(work, name + ".glb")
    subprocess.run([sys.executable, env["OFF2GLB"], off, glb], check=True, capture_output=True)
    return obj, glb, len(tris)


def timed(cmd):
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True)
    ms = (time.perf_counter() - t0) * 1000
    if p.returncode != 0:
        sys.exit(f"peer-bench: {cmd[0]} failed ({p.returncode}): {p.stderr.strip()[:400]}")
    return ms, p.stdout


def seamd_run(glb, out):
    ms, stdout = timed([env["SEAMD"], "seam", glb, out, "--extrema", json.dumps({"auto": True, "max_count": k})])
    return ms, json.loads(stdout)


def bff_run(obj, out, cones):
    return timed([env["BFF"], obj, out, f"--nCones={cones}", "--normalizeUVs"])[0]


def kept_extrema(summary):
    return sum(len((p.get("seam") or {}).get("extrema", [])) for p in summary.get("primitives") or [summary])


def stage_rows(summary):
    """Top-level timings_ms: parse, primitives (wall) and, for one primitive, its stages merged."""
    return {key: v for key, v in summary.get("timings_ms", {}).items() if isinstance(v, (int, float))}


results = []
for name in env["MESHES"].split():
    obj, glb, faces = prepare(name)
    seam_ms, bff_ms, ratios, stages = [], [], [], []
    kept = kept_extrema(seamd_run(glb, os.path.join(work, "out.glb"))[1])  # warm-up, unmeasured
    bff_run(obj, os.path.join(work, "out.obj"), kept)
    for i in range(n):
        # Paired: the two processes run back to back, the first of the pair alternating.
        if i % 2 == 0:
            s, summary = seamd_run(glb, os.path.join(work, "out.glb"))
            b = bff_run(obj, os.path.join(work, "out.obj"), kept)
        else:
            b = bff_run(obj, os.path.join(work, "out.obj"), kept)
            s, summary = seamd_run(glb, os.path.join(work, "out.glb"))
        seam_ms.append(s)
        bff_ms.append(b)
        ratios.append(s / b)
        stages.append(stage_rows(summary))
    results.append((name, faces, kept, seam_ms, bff_ms, ratios, stages))
    print(f"  {name}: seamd {[round(x) for x in seam_ms]} ms, BFF {[round(x) for x in bff_ms]} ms", flush=True)

print(f"\n== seamd default job vs BFF CLI (at most K={k} extrema, as many BFF cones; N={n} paired runs, medians)")
print(f"{'mesh':<12} {'faces':>7} {'cones':>7} {'seamd_ms':>9} {'bff_ms':>9} {'ratio':>6} {'target':>6} {'met':>4}")
for name, faces, kept, s, b, r, _ in results:
    ratio = statistics.median(r)
    print(f"{name:<12} {faces:>7} {kept:>7} {statistics.median(s):>9.0f} "
          f"{statistics.median(b):>9.0f} {ratio:>6.2f} {0.5:>6.2f} {'yes' if ratio <= 0.5 else 'no':>4}")

print("\n== seamd timings_ms (median over the same runs)")
for name, faces, _, _, _, _, stages in results:
    keys = sorted({key for row in stages for key in row})
    cells = [f"{key}={statistics.median([row.get(key, 0) for row in stages]):.0f}" for key in keys]
    print(f"{name} ({faces} faces): " + ", ".join(cells))
PY
