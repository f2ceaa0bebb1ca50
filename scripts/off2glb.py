#!/usr/bin/env python3
"""Converts an OFF triangle mesh into a minimal GLB (float32 POSITION, uint32 indices),
optionally refined by 1-to-4 midpoint subdivision, to make load-test inputs of a chosen size.

    scripts/off2glb.py IN.off OUT.glb [--subdivide N]

Prints the vertex and face counts written. Pure standard library (no numpy needed).
"""
import argparse
import json
import struct
import sys


def read_off(path):
    # Line-based: COFF/NOFF vertex lines and colored face lines carry extra numbers.
    with open(path) as f:
        lines = [l.split('#', 1)[0].split() for l in f]
    lines = [l for l in lines if l]
    head = lines[0]
    if head[0].endswith('OFF'):
        head = head[1:]
        lines = lines[1:]
    else:
        lines = lines[1:]
    if not head:
        head, lines = lines[0], lines[1:]
    nv, nf = int(head[0]), int(head[1])
    verts = [tuple(float(t) for t in l[:3]) for l in lines[:nv]]
    tris = []
    for l in lines[nv:nv + nf]:
        k = int(l[0])
        ids = [int(t) for t in l[1:1 + k]]
        for i in range(1, k - 1):  # fan-triangulate polygons
            tris.append((ids[0], ids[i], ids[i + 1]))
    return verts, tris


def subdivide(verts, tris):
    verts = list(verts)
    mid = {}

    def midpoint(a, b):
        key = (a, b) if a < b else (b, a)
        m = mid.get(key)
        if m is None:
            pa, pb = verts[a], verts[b]
            verts.append(tuple((x + y) / 2 for x, y in zip(pa, pb)))
            m = mid[key] = len(verts) - 1
        return m

    out = []
    for a, b, c in tris:
        ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
        out += [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
    return verts, out


def write_glb(path, verts, tris):
    pos = struct.pack('<%df' % (3 * len(verts)), *[x for v in verts for x in v])
    idx = struct.pack('<%dI' % (3 * len(tris)), *[i for t in tris for i in t])
    lo = [min(v[k] for v in verts) for k in range(3)]
    hi = [max(v[k] for v in verts) for k in range(3)]
    gltf = {
        'asset': {'version': '2.0', 'generator': 'seam off2glb.py'},
        'scene': 0, 'scenes': [{'nodes': [0]}], 'nodes': [{'mesh': 0}],
        'meshes': [{'primitives': [{'attributes': {'POSITION': 0}, 'indices': 1, 'mode': 4}]}],
        'buffers': [{'byteLength': len(pos) + len(idx)}],
        'bufferViews': [{'buffer': 0, 'byteOffset': 0, 'byteLength': len(pos), 'target': 34962},
                        {'buffer': 0, 'byteOffset': len(pos), 'byteLength': len(idx), 'target': 34963}],
        'accessors': [{'bufferView': 0, 'componentType': 5126, 'count': len(verts), 'type': 'VEC3',
                       'min': lo, 'max': hi},
                      {'bufferView': 1, 'componentType': 5125, 'count': 3 * len(tris), 'type': 'SCALAR'}],
    }
    js = json.dumps(gltf, separators=(',', ':')).encode()
    js += b' ' * (-len(js) % 4)
    binary = pos + idx
    binary += b'\0' * (-len(binary) % 4)
    total = 12 + 8 + len(js) + 8 + len(binary)
    with open(path, 'wb') as f:
        f.write(struct.pack('<4sII', b'glTF', 2, total))
        f.write(struct.pack('<I4s', len(js), b'JSON') + js)
        f.write(struct.pack('<I4s', len(binary), b'BIN\0') + binary)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument('input')
    p.add_argument('output')
    p.add_argument('--subdivide', type=int, default=0)
    a = p.parse_args()
    verts, tris = read_off(a.input)
    for _ in range(a.subdivide):
        verts, tris = subdivide(verts, tris)
    write_glb(a.output, verts, tris)
    print(f'{a.output}: {len(verts)} vertices, {len(tris)} faces')


if __name__ == '__main__':
    sys.exit(main())
