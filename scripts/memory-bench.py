#!/usr/bin/env python3
"""Peak memory of one default seam job per face (issue 15): the figure the deployment sizes
pods by. Runs `seamd seam` (the job POST /seam runs: automatic extrema, skeleton seam with
refinement, SLIM UVs, GLB out) on a CGAL mesh subdivided to several sizes, one process per
run, and reads each process's peak RSS (wait4's ru_maxrss). Fits peak = base + per_face *
faces by least squares and prints the formula docs/http.md derives the pod memory from.

  scripts/memory-bench.py [--seamd build/release/server/seamd] [--mesh camel] [--levels 0,1,2,3]
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run(seamd, glb, out):
    start = time.monotonic()
    proc = subprocess.Popen([seamd, "seam", "--mesh", glb, "--out", out], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    _, status, rusage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode != 0:
        raise SystemExit(f"seamd seam failed on {glb} (exit {proc.returncode})")
    return rusage.ru_maxrss * 1024, time.monotonic() - start


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seamd", default=os.path.join(ROOT, "build/release/server/seamd"))
    ap.add_argument("--mesh", default="camel")
    ap.add_argument("--levels", default="0,1,2,3")
    a = ap.parse_args()
    src = os.path.join(ROOT, ".cache/data/meshes", a.mesh + ".off")
    rows = []
    with tempfile.TemporaryDirectory() as work:
        print(f"memory per face of the default job: {a.mesh} subdivided, {os.cpu_count()} cores, "
              f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
        print(f"{'faces':>10} {'peak MiB':>9} {'B/face':>8} {'seconds':>8}")
        for level in [int(x) for x in a.levels.split(",")]:
            glb = os.path.join(work, f"m{level}.glb")
            info = subprocess.run([sys.executable, os.path.join(ROOT, "scripts/off2glb.py"), src, glb, "--subdivide", str(level)],
                                  check=True, capture_output=True, text=True).stdout
            faces = int(info.split()[-2])  # "OUT: V vertices, F faces"
            peak, secs = run(a.seamd, glb, os.path.join(work, "out.glb"))
            rows.append((faces, peak))
            print(f"{faces:10} {peak / 2**20:9.0f} {peak / faces:8.0f} {secs:8.1f}")
    n = len(rows)
    mx = sum(f for f, _ in rows) / n
    my = sum(p for _, p in rows) / n
    k = sum((f - mx) * (p - my) for f, p in rows) / max(1e-9, sum((f - mx) ** 2 for f, _ in rows))
    base = my - k * mx
    print(f"fit: peak = {base / 2**20:.0f} MiB + {k:.0f} B x faces")
    # Issue 14, item 4: the default job's peak at 1.25M faces <= 1.0 GB (10^9 B).
    faces, peak = max(rows)
    if faces >= 1_000_000:
        ratio = peak / 1e9
        print(f"peak at {faces} faces: {peak / 1e9:.3f} GB = {ratio:.3f} x the 1.0 GB target: "
              f"{'met' if ratio <= 1.0 else 'missed'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
