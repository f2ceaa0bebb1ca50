// A small OFF reader for the viewer (OFF/COFF/NOFF headers, '#' comments, per-vertex and
// per-face colours ignored, polygons fanned into triangles). The vertex numbering is kept, so
// extrema picked on it are the file's vertex indices.
import { BufferGeometry, Float32BufferAttribute } from 'three';

export function parseOff(text) {
  const lines = text.split('\n').map((l) => l.replace(/#.*/, '').trim()).filter(Boolean);
  const numbers = (i) => (lines[i] ?? '').split(/\s+/).map(Number);
  let at = 0;
  const first = (lines[at] ?? '').split(/\s+/);
  if (!/^[CN]*OFF$/.test(first[0] ?? '')) throw new Error('not an OFF file (the first word must be OFF)');
  // The counts may follow the header word on its line or stand on the next.
  let counts = first.slice(1).map(Number);
  at += 1;
  if (counts.length < 2) counts = numbers(at++);
  const [nv, nf] = counts;
  if (!Number.isInteger(nv) || !Number.isInteger(nf) || nv < 0 || nf < 0) throw new Error('OFF: bad vertex or face count');
  if (at + nv + nf > lines.length) throw new Error('OFF: fewer lines than the counts announce');
  const positions = new Float32Array(nv * 3);
  for (let v = 0; v < nv; ++v) {
    const xyz = numbers(at++);
    if (xyz.length < 3 || xyz.slice(0, 3).some((x) => !Number.isFinite(x))) throw new Error(`OFF: vertex ${v} is not three numbers`);
    positions.set(xyz.slice(0, 3), v * 3);
  }
  const index = [];
  for (let f = 0; f < nf; ++f) {
    const w = numbers(at++);
    const n = w[0];
    const corners = w.slice(1, 1 + n);
    if (!(n >= 3) || corners.length !== n || corners.some((c) => !Number.isInteger(c) || c < 0 || c >= nv)) {
      throw new Error(`OFF: face ${f} is not a polygon of vertex indices`);
    }
    for (let k = 1; k + 1 < n; ++k) index.push(corners[0], corners[k], corners[k + 1]);
  }
  const g = new BufferGeometry();
  g.setAttribute('position', new Float32BufferAttribute(positions, 3));
  g.setIndex(index);
  return g;
}
