// Meshes the browser test writes as files to open in the page.

// An ellipsoid three times as long along x as across (a lat-long grid with one vertex at each
// pole, faces outward): two clear protrusion tips for automatic extrema. Returns {v, f}.
export function ellipsoid(nu = 32, nv = 16) {
  const v = [[3, 0, 0]];
  for (let i = 1; i < nv; ++i) {
    const t = (Math.PI * i) / nv;
    for (let j = 0; j < nu; ++j) {
      const p = (2 * Math.PI * j) / nu;
      v.push([3 * Math.cos(t), Math.sin(t) * Math.cos(p), Math.sin(t) * Math.sin(p)]);
    }
  }
  v.push([-3, 0, 0]);
  const f = [];
  const ring = (i, j) => 1 + (i - 1) * nu + (j % nu);
  for (let j = 0; j < nu; ++j) f.push([0, ring(1, j), ring(1, j + 1)]);
  for (let i = 1; i + 1 < nv; ++i) {
    for (let j = 0; j < nu; ++j) {
      f.push([ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)], [ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)]);
    }
  }
  const last = v.length - 1;
  for (let j = 0; j < nu; ++j) f.push([last, ring(nv - 1, j + 1), ring(nv - 1, j)]);
  return { v, f };
}

export const toOff = ({ v, f }) =>
  `OFF\n# an ellipsoid\n${v.length} ${f.length} 0\n${v.map((p) => p.join(' ')).join('\n')}\n${f.map((t) => `3 ${t.join(' ')}`).join('\n')}\n`;

export const toObj = ({ v, f }) =>
  `# an ellipsoid\n${v.map((p) => `v ${p.join(' ')}`).join('\n')}\n${f.map((t) => `f ${t.map((x) => x + 1).join(' ')}`).join('\n')}\n`;
