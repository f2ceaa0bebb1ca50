#!/usr/bin/env python3
"""Pictures of a seam as a camera sees it: the default seam beside the one hidden from that
view (hide_from), for docs/steering/. Orthographic, flat-shaded, painter's algorithm (each seam
edge drawn right after the nearer of its two faces, so nearer faces cover it), rasterized to
PNG by headless chromium.

    scripts/seam-picture.py SEAMD MESH.off 'VIEW_X,VIEW_Y,VIEW_Z' OUT.png
"""
import json
import subprocess
import sys
import tempfile
from pathlib import Path


def read_off(path):
    lines = [l.split('#')[0].split() for l in open(path)]
    lines = [l for l in lines if l]
    head = lines[0]
    if head[0].upper().endswith('OFF') and len(head) == 1:
        lines = lines[1:]
    else:
        lines[0] = head[1:]
    nv, nf = int(lines[0][0]), int(lines[0][1])
    vs = [tuple(float(x) for x in l[:3]) for l in lines[1:1 + nv]]
    fs = []
    for l in lines[1 + nv:1 + nv + nf]:  # a face line may end with a colour
        n = int(l[0])
        idx = [int(x) for x in l[1:1 + n]]
        fs += [(idx[0], idx[k], idx[k + 1]) for k in range(1, n - 1)]
    return vs, fs


def seam_edges(seamd, mesh, params):
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / 'r.json'
        subprocess.run([seamd, 'seam', mesh, str(Path(tmp) / 'o.glb'), '--report', str(out), '--params',
                        json.dumps(params)], check=True, stdout=subprocess.DEVNULL)
        seam = json.load(open(out))['seam']
    cut_graph = {tuple(e) for e in seam['cut_graph_edges']}
    return [tuple(e) for e in seam['edges'] if tuple(e) not in cut_graph], seam


def sub(a, b): return (a[0] - b[0], a[1] - b[1], a[2] - b[2])
def dot(a, b): return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
def cross(a, b): return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
def norm(a):
    n = dot(a, a) ** 0.5
    return (a[0] / n, a[1] / n, a[2] / n) if n else a


def panel(vs, fs, edges, view, x0, size, title):
    d = norm(view)
    up = (0, 0, 1) if abs(d[2]) < 0.9 else (0, 1, 0)
    right = norm(cross(d, up))
    up = cross(right, d)
    pts = [(dot(p, right), dot(p, up)) for p in vs]
    lo_x, hi_x = min(p[0] for p in pts), max(p[0] for p in pts)
    lo_y, hi_y = min(p[1] for p in pts), max(p[1] for p in pts)
    scale = 0.9 * size / max(hi_x - lo_x, hi_y - lo_y)
    def xy(i):
        return (x0 + size / 2 + (pts[i][0] - (lo_x + hi_x) / 2) * scale,
                size / 2 - (pts[i][1] - (lo_y + hi_y) / 2) * scale + 30)
    depth = [max(dot(vs[i], d) for i in f) for f in fs]
    order = sorted(range(len(fs)), key=lambda f: -depth[f])  # far first
    rank = {f: r for r, f in enumerate(order)}
    faces_of = {}
    for fi, f in enumerate(fs):
        for k in range(3):
            a, b = sorted((f[k], f[(k + 1) % 3]))
            faces_of.setdefault((a, b), []).append(fi)
    after = {}
    for e in edges:
        near = max(faces_of.get(e, [0]), key=lambda f: rank[f])
        after.setdefault(near, []).append(e)
    out = [f'<text x="{x0 + 10}" y="20" font-family="sans-serif" font-size="16">{title}</text>']
    for fi in order:
        f = fs[fi]
        n = norm(cross(sub(vs[f[1]], vs[f[0]]), sub(vs[f[2]], vs[f[0]])))
        if dot(n, d) >= 0:
            continue  # back-facing
        g = int(70 + 160 * -dot(n, d))
        p = ' '.join('%.1f,%.1f' % xy(i) for i in f)
        out.append(f'<polygon points="{p}" fill="rgb({g},{g},{g})" stroke="rgb({g},{g},{g})" stroke-width="0.4"/>')
        for a, b in after.get(fi, []):
            (ax, ay), (bx, by) = xy(a), xy(b)
            out.append(f'<line x1="{ax:.1f}" y1="{ay:.1f}" x2="{bx:.1f}" y2="{by:.1f}" stroke="#e0201a" stroke-width="2.5"/>')
    return out


def main():
    seamd, mesh, view_text, png = sys.argv[1:5]
    view = tuple(float(x) for x in view_text.split(','))
    vs, fs = read_off(mesh)
    plain, s0 = seam_edges(seamd, mesh, {'hide_from': [list(view)], 'hide_strength': 0, 'uv': 'none'})
    hidden, s1 = seam_edges(seamd, mesh, {'hide_from': [list(view)], 'uv': 'none'})
    size = 600
    name = Path(mesh).stem
    body = panel(vs, fs, plain, view, 0, size,
                 f'{name}: default seam, seen {s0["visible_length"]:.3g} of length {s0["length"]:.3g}')
    body += panel(vs, fs, hidden, view, size, size,
                  f'hide_from {list(view)}: seen {s1["visible_length"]:.3g} of length {s1["length"]:.3g}')
    svg = (f'<svg xmlns="http://www.w3.org/2000/svg" width="{2 * size}" height="{size + 40}">'
           f'<rect width="100%" height="100%" fill="white"/>' + ''.join(body) + '</svg>')
    with tempfile.TemporaryDirectory() as tmp:
        page = Path(tmp) / 'p.svg'
        page.write_text(svg)
        subprocess.run(['chromium', '--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking',
                        '--disable-component-update', '--no-first-run', f'--user-data-dir={tmp}/profile',
                        f'--screenshot={Path(png).resolve()}', f'--window-size={2 * size},{size + 40}', str(page)],
                       check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


if __name__ == '__main__':
    main()
