#!/usr/bin/env python3
"""Connection-burst benchmark of seamd (issue 17): N clients connect at the same instant and
post the bundled sample; prints connect-time percentiles, answers (200, 503 with Retry-After),
resets and the kernel's listen-overflow counter, for each --backlog given, in one run.

  scripts/burst-bench.py [--seamd build/release/server/seamd] [--clients 256] [--rounds 6]
                         [--backlogs 5,1024]

The service's workers 2, queue 16 (the issue's set-up). Loopback only; bounded.
"""
import argparse
import os
import socket
import statistics
import subprocess
import threading
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def listen_overflows():
    try:
        with open("/proc/net/netstat") as f:
            lines = f.read().splitlines()
    except OSError:
        return None
    for names, values in zip(lines[::2], lines[1::2]):
        if names.startswith("TcpExt:"):
            d = dict(zip(names.split()[1:], values.split()[1:]))
            return int(d.get("ListenOverflows", 0)) + int(d.get("ListenDrops", 0))
    return None


def free_port():
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    p = s.getsockname()[1]
    s.close()
    return p


def one_client(port, request, barrier, out, i):
    barrier.wait()
    t0 = time.monotonic()
    status, reset, retry = 0, False, False
    try:
        s = socket.create_connection(("127.0.0.1", port), timeout=30)
        connect = time.monotonic() - t0
        s.settimeout(120)
        s.sendall(request)
        data = b""
        while True:
            d = s.recv(65536)
            if not d:
                break
            data += d
        s.close()
        if data.startswith(b"HTTP/1.1 "):
            status = int(data[9:12])
            retry = b"\r\nRetry-After: " in data.split(b"\r\n\r\n", 1)[0]
    except ConnectionResetError:
        connect, reset = time.monotonic() - t0, True
    except OSError:
        connect = time.monotonic() - t0
    out[i] = (connect, status, retry, reset)


def burst(seamd, backlog, clients, rounds, request):
    port = free_port()
    args = [seamd, "--bind", "127.0.0.1", "--port", str(port), "--workers", "2", "--queue", "16",
            "--log-level", "warn", "--backlog", str(backlog)]
    proc = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    time.sleep(0.5)
    connects, counts = [], {"200": 0, "503+Retry-After": 0, "reset": 0, "other": 0}
    before = listen_overflows()
    for _ in range(rounds):
        out = [None] * clients
        barrier = threading.Barrier(clients)
        threads = [threading.Thread(target=one_client, args=(port, request, barrier, out, i)) for i in range(clients)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        for connect, status, retry, reset in out:
            connects.append(connect * 1000)
            if reset:
                counts["reset"] += 1
            elif status == 200:
                counts["200"] += 1
            elif status == 503 and retry:
                counts["503+Retry-After"] += 1
            else:
                counts["other"] += 1
    after = listen_overflows()
    proc.terminate()
    proc.wait(timeout=60)
    connects.sort()
    q = lambda f: connects[min(len(connects) - 1, int(f * len(connects)))]
    overflow = "n/a" if before is None or after is None else str(after - before)
    print(f"{backlog:8} {clients:4}x{rounds:<3} {q(0.5):8.2f} {q(0.99):8.2f} {connects[-1]:9.1f} "
          f"{counts['200']:6} {counts['503+Retry-After']:8} {counts['reset']:6} {counts['other']:6} {overflow:>9}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seamd", default=os.path.join(ROOT, "build/release/server/seamd"))
    ap.add_argument("--clients", type=int, default=256)
    ap.add_argument("--rounds", type=int, default=6)
    ap.add_argument("--backlogs", default="5,1024")
    a = ap.parse_args()
    sample = f"/tmp/seam-burst-{os.getpid()}.glb"
    subprocess.run([a.seamd, "sample", "--out", sample], check=True, capture_output=True)
    body = open(sample, "rb").read()
    os.remove(sample)
    request = (b"POST /seam HTTP/1.1\r\nHost: b\r\nContent-Type: model/gltf-binary\r\nContent-Length: " +
               str(len(body)).encode() + b"\r\nConnection: close\r\n\r\n" + body)
    print(f"burst benchmark: {os.cpu_count()} cores, sample GLB {len(body)} B, somaxconn "
          f"{open('/proc/sys/net/core/somaxconn').read().strip()}, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
    print(f"{'backlog':>8} {'clients':>8} {'p50 ms':>8} {'p99 ms':>8} {'max ms':>9} {'200':>6} {'503+RA':>8} "
          f"{'reset':>6} {'other':>6} {'overflows':>9}")
    for b in a.backlogs.split(","):
        burst(a.seamd, int(b), a.clients, a.rounds, request)


if __name__ == "__main__":
    main()
