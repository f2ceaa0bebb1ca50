#!/usr/bin/env python3
"""Soak benchmark of seamd under mixed honest and hostile traffic (issue 10, item 11).

Starts seamd on a loopback port, then runs CLIENTS threads for DURATION seconds. Each client
loops over a weighted mix of cases: honest seam requests (raw GLB, multipart with params,
JSON with glb_base64) and the hostile cases of docs/http.md (deep JSON, bodies over the limit
in each framing, missing length, gzip, header floods, slow heads, disconnects mid-job, Range,
pipelining, garbage). Samples seamd's RSS every second. Prints, per case, the answers by
status, then: requests answered, crashes (the process must stay up: 0), peak RSS and RSS after
warm-up vs at the end, p50/p99 latency of the honest requests.

Not part of the test command (it runs for minutes); figures go to docs/http.md.

  scripts/soak.py [--seamd build/release/server/seamd] [--clients 64] [--duration 600]
"""
import argparse
import base64
import json
import os
import random
import socket
import statistics
import subprocess
import sys
import threading
import time
from collections import Counter, defaultdict

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LIMIT = 4 << 20  # --max-body-bytes for the soak


def free_port():
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


def exchange(port, data, timeout=30.0, trickle=None, close_after=None, half_close=False):
    """Sends data (a bytes or a list of chunks), returns (status, seconds). status 0 = no answer."""
    t0 = time.monotonic()
    try:
        s = socket.create_connection(("127.0.0.1", port), timeout=5)
    except OSError:
        return -1, 0.0  # connect refused or timed out
    s.settimeout(timeout)
    try:
        chunks = data if isinstance(data, list) else [data]
        for c in chunks:
            s.sendall(c)
            if trickle:
                time.sleep(trickle)
        if close_after is not None:
            time.sleep(close_after)
            s.close()
            return 0, time.monotonic() - t0
        if half_close:
            s.shutdown(socket.SHUT_WR)
        out = b""
        while b"\r\n\r\n" not in out:
            d = s.recv(65536)
            if not d:
                break
            out += d
        status = int(out[9:12]) if out.startswith(b"HTTP/1.1 ") else 0
        # Read the rest so the server's write completes (bounded by the socket timeout).
        while True:
            d = s.recv(1 << 20)
            if not d:
                break
        return status, time.monotonic() - t0
    except (OSError, ValueError):
        return 0, time.monotonic() - t0
    finally:
        s.close()


def post(body, ctype="model/gltf-binary", extra=b"", path=b"/seam"):
    return (b"POST " + path + b" HTTP/1.1\r\nHost: soak\r\nContent-Type: " + ctype.encode() +
            b"\r\nContent-Length: " + str(len(body)).encode() + b"\r\n" + extra + b"Connection: close\r\n\r\n" + body)


def multipart(glb, params):
    b = b"soakboundary"
    body = (b"--" + b + b"\r\nContent-Disposition: form-data; name=\"mesh\"; filename=\"m.glb\"\r\n"
            b"Content-Type: model/gltf-binary\r\n\r\n" + glb + b"\r\n--" + b +
            b"\r\nContent-Disposition: form-data; name=\"params\"\r\n\r\n" + params + b"\r\n--" + b + b"--\r\n")
    return post(body, "multipart/form-data; boundary=soakboundary")


def make_cases(glb, big_glb):
    deep = b"[" * 100000 + b"]" * 100000
    b64 = base64.b64encode(glb)
    flood = b"GET /healthz HTTP/1.1\r\n" + b"".join(b"X-%d: v\r\n" % i for i in range(5000)) + b"\r\n"
    chunk = b"10000\r\n" + b"x" * 0x10000 + b"\r\n"
    return {
        # name: (weight, honest, callable(port) -> (status, seconds))
        "honest_raw_glb": (30, True, lambda p: exchange(p, post(glb))),
        "honest_multipart_mst": (15, True, lambda p: exchange(p, multipart(glb, b'{"method":"mst","uv":"none"}'))),
        "honest_json_b64": (10, True, lambda p: exchange(p, post(b'{"mesh":{"glb_base64":"' + b64 + b'"}}', "application/json"))),
        "deep_json_params": (4, False, lambda p: exchange(p, multipart(glb, b'{"extrema":' + deep + b"}"))),
        "deep_json_body": (4, False, lambda p: exchange(p, post(b'{"mesh":{"gltf":' + deep + b"}}", "application/json"))),
        "over_limit_length": (3, False, lambda p: exchange(p, post(b"").replace(b"Content-Length: 0", b"Content-Length: 1000000000000"))),
        "over_limit_chunked": (3, False, lambda p: exchange(p, [b"POST /seam HTTP/1.1\r\nHost: s\r\nContent-Type: model/gltf-binary\r\nTransfer-Encoding: chunked\r\n\r\n"] + [chunk] * 96)),
        "no_length": (3, False, lambda p: exchange(p, b"POST /seam HTTP/1.1\r\nHost: s\r\nContent-Type: model/gltf-binary\r\n\r\n")),
        "gzip_body": (3, False, lambda p: exchange(p, post(glb, extra=b"Content-Encoding: gzip\r\n"))),
        "expect_over_limit": (3, False, lambda p: exchange(p, post(b"", extra=b"Expect: 100-continue\r\n").replace(b"Content-Length: 0", b"Content-Length: 99999999"))),
        "header_flood": (3, False, lambda p: exchange(p, flood)),
        "range_amplify": (3, False, lambda p: exchange(p, b"GET /version HTTP/1.1\r\nHost: s\r\nRange: bytes=0-" + b",0-" * 2000 + b"\r\nConnection: close\r\n\r\n")),
        "slow_head": (3, False, lambda p: exchange(p, [b"GET /healthz HTTP/1.1\r\n"] + [b"X: y\r\n"] * 6, trickle=1.0, timeout=40)),
        "disconnect_mid_job": (3, False, lambda p: exchange(p, post(big_glb), close_after=0.3)),
        "half_close_mid_job": (2, False, lambda p: exchange(p, post(big_glb), half_close=True)),
        "pipelined": (3, False, lambda p: exchange(p, b"GET /healthz HTTP/1.1\r\nHost: s\r\n\r\n" * 5 + b"GET /version HTTP/1.1\r\nHost: s\r\nConnection: close\r\n\r\n")),
        "smuggling_syntax": (3, False, lambda p: exchange(p, b"POST /seam HTTP/1.1\r\nContent-Length : 5\r\nTransfer-Encoding: chunked\r\n\r\n0\r\n\r\n")),
        "garbage": (3, False, lambda p: exchange(p, os.urandom(random.randint(1, 4000)) + b"\r\n\r\n")),
        "form_body": (2, False, lambda p: exchange(p, post(b"a=b", "application/x-www-form-urlencoded"))),
        "healthz": (5, True, lambda p: exchange(p, b"GET /healthz HTTP/1.1\r\nHost: s\r\nConnection: close\r\n\r\n")),
    }


def rss_kib(pid):
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1])
    except OSError:
        pass
    return 0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seamd", default=os.path.join(ROOT, "build/release/server/seamd"))
    ap.add_argument("--clients", type=int, default=64)
    ap.add_argument("--duration", type=float, default=600)
    ap.add_argument("--warmup", type=float, default=60)
    args = ap.parse_args()

    work = f"/tmp/seam-soak-{os.getpid()}"
    os.makedirs(work, exist_ok=True)
    subprocess.run([args.seamd, "sample", "--out", f"{work}/sample.glb"], check=True, capture_output=True)
    glb = open(f"{work}/sample.glb", "rb").read()
    # A heavier job for the disconnect cases: the CGAL camel (~20k faces) if cached.
    camel = os.path.join(ROOT, ".cache/data/meshes/camel.off")
    big_glb = glb
    if os.path.exists(camel):
        subprocess.run([sys.executable, os.path.join(ROOT, "scripts/off2glb.py"), camel, f"{work}/camel.glb"], check=True, capture_output=True)
        big_glb = open(f"{work}/camel.glb", "rb").read()

    port = free_port()
    proc = subprocess.Popen([args.seamd, "--bind", "127.0.0.1", "--port", str(port), "--log-level", "warn",
                             "--max-body-bytes", str(LIMIT), "--request-timeout-s", "10"],
                            stdout=subprocess.DEVNULL, stderr=open(f"{work}/seamd.err", "w"))
    for _ in range(200):
        if exchange(port, b"GET /healthz HTTP/1.1\r\nHost: s\r\nConnection: close\r\n\r\n", timeout=1)[0] == 200:
            break
        time.sleep(0.05)
    cases = make_cases(glb, big_glb)
    names = list(cases)
    weights = [cases[n][0] for n in names]
    results = defaultdict(Counter)
    latencies = []
    lock = threading.Lock()
    stop = time.monotonic() + args.duration
    rss = []
    started = time.monotonic()

    def client(seed):
        rng = random.Random(seed)
        while time.monotonic() < stop and proc.poll() is None:
            name = rng.choices(names, weights)[0]
            status, secs = cases[name][2](port)
            with lock:
                results[name][status] += 1
                if cases[name][1] and status == 200:
                    latencies.append(secs)

    def sampler():
        while time.monotonic() < stop and proc.poll() is None:
            rss.append((time.monotonic() - started, rss_kib(proc.pid)))
            time.sleep(1)

    threads = [threading.Thread(target=client, args=(i,)) for i in range(args.clients)] + [threading.Thread(target=sampler)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    alive = proc.poll() is None
    final_rss = rss_kib(proc.pid) if alive else 0
    if alive:
        proc.terminate()
        proc.wait(timeout=60)

    total = sum(sum(c.values()) for c in results.values())
    answered = sum(n for c in results.values() for s, n in c.items() if s > 0)
    print(f"seamd soak: {args.clients} clients x {args.duration:.0f} s, {os.cpu_count()} cores, body limit {LIMIT}")
    print(f"{'case':22} {'sent':>6}  statuses")
    for name in names:
        c = results[name]
        print(f"{name:22} {sum(c.values()):6}  " + ", ".join(f"{s}: {n}" for s, n in sorted(c.items())))
    after_warmup = [k for t, k in rss if t >= args.warmup]
    lat = sorted(latencies)
    print(f"requests: {total}, answered with a status: {answered} (0 = closed without one, by design for"
          f" disconnects and over-limit bodies the client kept sending)")
    print(f"crashes: {0 if alive else 1} (exit code {proc.returncode})")
    if rss:
        print(f"RSS MiB: peak {max(k for _, k in rss) / 1024:.0f}, after warm-up min {min(after_warmup or [0]) / 1024:.0f}"
              f" max {max(after_warmup or [0]) / 1024:.0f}, final {final_rss / 1024:.0f}")
    if lat:
        print(f"honest requests: {len(lat)} x 200, p50 {statistics.median(lat) * 1000:.0f} ms,"
              f" p99 {lat[int(0.99 * (len(lat) - 1))] * 1000:.0f} ms")
    return 0 if alive else 1


if __name__ == "__main__":
    sys.exit(main())
