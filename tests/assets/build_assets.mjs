#!/usr/bin/env node
// Builds the real-looking glTF test assets (issue 11 item 7) from CGAL's meshes, the way DCC
// tools export them: several materials as several primitives of one mesh, node hierarchies
// with transforms, one mesh instanced by several nodes, vertices split at normal and UV seams,
// a skin with an animation, morph targets, Draco and KHR_mesh_quantization variants, and the
// defects real files carry (a fin, a flipped patch, faces degenerate after welding, many small
// closed parts in one primitive). Plus one 6-primitive, ~100k-face asset for bench/asset_bench.
//
//   node tests/assets/build_assets.mjs MESH_DIR OUT_DIR
//   node tests/assets/build_assets.mjs --check MESH_DIR OUT_DIR   (CTest asset_set_built)
//
// Writes OUT_DIR/<name>.glb and OUT_DIR/manifest.json: per asset its triangle primitives, the
// defects planted in which primitive (what `repairs` must report) and the Khronos validator's
// own report on it (errors must be 0; its UNUSED_OBJECT warnings are the baseline the cut
// asset must not exceed). Idempotent: does nothing when the manifest's stamp (a hash of this
// file and the package versions) matches and every asset is present.
import { createHash } from 'node:crypto';
import { createRequire } from 'node:module';
import fs from 'node:fs';
import zlib from 'node:zlib';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

import { Document, NodeIO, Primitive } from '@gltf-transform/core';
import { KHRDracoMeshCompression, KHRMeshQuantization } from '@gltf-transform/extensions';
import { draco, quantize } from '@gltf-transform/functions';
import draco3d from 'draco3dgltf';

const require = createRequire(import.meta.url);
const here = path.dirname(fileURLToPath(import.meta.url));
const validator = require(path.join(here, '..', 'node_modules', 'gltf-validator'));

const args = process.argv.slice(2);
const checkOnly = args[0] === '--check';
const [meshDir, outDir] = checkOnly ? args.slice(1) : args;
if (!meshDir || !outDir) {
  console.error('usage: build_assets.mjs [--check] MESH_DIR OUT_DIR');
  process.exit(2);
}

// ---------------------------------------------------------------------------------------------
// Stamp: rebuild only when this builder or the packages it uses change.
function stamp() {
  const h = createHash('sha256');
  h.update(fs.readFileSync(fileURLToPath(import.meta.url)));
  for (const pkg of ['@gltf-transform/core', '@gltf-transform/functions', 'draco3dgltf', 'gltf-validator']) {
    h.update(pkg + require(path.join(here, '..', 'node_modules', pkg, 'package.json')).version);
  }
  return h.digest('hex').slice(0, 16);
}

// ---------------------------------------------------------------------------------------------
// Meshes: CGAL's OFF files, polygons fanned into triangles, normalized to a bounding-box
// diagonal of 2 centred at the origin (so node transforms read like a scene's).
function readOff(name) {
  const lines = fs
    .readFileSync(path.join(meshDir, name + '.off'), 'utf8')
    .split('\n')
    .map((l) => l.replace(/#.*/, '').trim())
    .filter((l) => l.length)
    .map((l) => l.split(/\s+/));
  let i = 0;
  let head = lines[i++];
  if (/OFF$/.test(head[0])) head = head.length > 1 ? head.slice(1) : lines[i++];
  const [nv, nf] = [+head[0], +head[1]];
  const pos = [];
  for (let v = 0; v < nv; ++v) pos.push(lines[i++].slice(0, 3).map(Number));
  const tris = [];
  for (let f = 0; f < nf; ++f) {
    const l = lines[i++].map(Number);
    // Fan the polygon; colours or other values after the indices are ignored.
    for (let k = 2; k < l[0]; ++k) tris.push([l[1], l[k], l[k + 1]]);
  }
  return normalize({ pos, tris });
}

function normalize(m) {
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  for (const p of m.pos) for (let c = 0; c < 3; ++c) (lo[c] = Math.min(lo[c], p[c])), (hi[c] = Math.max(hi[c], p[c]));
  const diag = Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
  const s = 2 / diag;
  const mid = [0, 1, 2].map((c) => 0.5 * (lo[c] + hi[c]));
  return { pos: m.pos.map((p) => p.map((v, c) => (v - mid[c]) * s)), tris: m.tris };
}

const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const unit = (a) => {
  const n = Math.hypot(a[0], a[1], a[2]);
  return n > 0 ? a.map((v) => v / n) : [0, 0, 1];
};

function faceNormal(m, t) {
  return unit(cross(sub(m.pos[t[1]], m.pos[t[0]]), sub(m.pos[t[2]], m.pos[t[0]])));
}

// Area-weighted vertex normals (smooth shading).
function vertexNormals(m) {
  const n = m.pos.map(() => [0, 0, 0]);
  for (const t of m.tris) {
    const c = cross(sub(m.pos[t[1]], m.pos[t[0]]), sub(m.pos[t[2]], m.pos[t[0]]));
    for (const v of t) for (let k = 0; k < 3; ++k) n[v][k] += c[k];
  }
  return n.map(unit);
}

function longestAxis(m) {
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  for (const p of m.pos) for (let c = 0; c < 3; ++c) (lo[c] = Math.min(lo[c], p[c])), (hi[c] = Math.max(hi[c], p[c]));
  const ext = [0, 1, 2].map((c) => hi[c] - lo[c]);
  const axis = ext.indexOf(Math.max(...ext));
  return { axis, lo: lo[axis], hi: hi[axis] };
}

// Cylindrical UVs around the longest axis, per face corner: a face across the wrap gets u + 1
// on its low corners, so vertices on the wrap line are stored twice (a UV seam, as exporters
// write it).
function cylindricalUv(m, t) {
  m.axis ??= longestAxis(m);
  const { axis, lo, hi } = m.axis;
  const a = (axis + 1) % 3, b = (axis + 2) % 3;
  const uv = t.map((v) => {
    const p = m.pos[v];
    return [Math.atan2(p[b], p[a]) / (2 * Math.PI) + 0.5, (p[axis] - lo) / (hi - lo)];
  });
  const us = uv.map((x) => x[0]);
  if (Math.max(...us) - Math.min(...us) > 0.5) for (const x of uv) if (x[0] < 0.5) x[0] += 1;
  // u spans [0, 1.5) with the wrapped copies: halved, every UV is in [0, 1] (quantizable).
  return uv.map(([u, v]) => [0.5 * u, v]);
}

// ---------------------------------------------------------------------------------------------
// Exporting: a face set becomes a primitive the way DCC exporters write one. Each face corner
// yields a vertex record (position index + shading attributes); equal records share one
// vertex, different ones at one position are split vertices.
//   corner(f, k) -> {p: position index, NORMAL?, TEXCOORD_0?, ...} ; attribute values arrays
//   perPosition: {NAME: (posIndex) -> array} attributes that depend on the position only
//   targets: [{POSITION: (posIndex) -> [dx,dy,dz], NORMAL?: ...}]
function exportFaces(faces, corner) {
  const index = new Map();
  const records = [];
  const indices = [];
  for (const f of faces) {
    for (let k = 0; k < 3; ++k) {
      const r = corner(f, k);
      const key = JSON.stringify(r);
      let v = index.get(key);
      if (v === undefined) {
        v = records.length;
        index.set(key, v);
        records.push(r);
      }
      indices.push(v);
    }
  }
  return { records, indices };
}

function makePrimitive(doc, buffer, m, exported, { material, perPosition = {}, targets = [], attributeTypes = {} }) {
  const { records, indices } = exported;
  const prim = doc.createPrimitive().setMode(Primitive.Mode.TRIANGLES);
  const position = new Float32Array(records.length * 3);
  records.forEach((r, i) => position.set(m.pos[r.p], 3 * i));
  prim.setAttribute('POSITION', doc.createAccessor().setType('VEC3').setArray(position).setBuffer(buffer));
  const names = Object.keys(records[0] ?? {}).filter((k) => k !== 'p');
  const put = (name, values, size) => {
    const Array_ = attributeTypes[name]?.array ?? Float32Array;
    const data = new Array_(records.length * size);
    values.forEach((x, i) => data.set(x, size * i));
    const acc = doc.createAccessor().setType(size === 2 ? 'VEC2' : size === 3 ? 'VEC3' : 'VEC4').setArray(data).setBuffer(buffer);
    if (attributeTypes[name]?.normalized) acc.setNormalized(true);
    return acc;
  };
  for (const name of names) prim.setAttribute(name, put(name, records.map((r) => r[name]), records[0][name].length));
  for (const [name, fn] of Object.entries(perPosition)) {
    const values = records.map((r) => fn(r.p));
    prim.setAttribute(name, put(name, values, values[0].length));
  }
  for (const t of targets) {
    const target = doc.createPrimitiveTarget();
    for (const [name, fn] of Object.entries(t)) target.setAttribute(name, put(name, records.map((r) => fn(r.p)), 3));
    prim.addTarget(target);
  }
  const IndexArray = records.length > 65535 ? Uint32Array : Uint16Array;
  prim.setIndices(doc.createAccessor().setType('SCALAR').setArray(new IndexArray(indices)).setBuffer(buffer));
  if (material) prim.setMaterial(material);
  return prim;
}

// Shading styles.
function smoothWithUvSeam(m) {
  const normals = vertexNormals(m);
  return (f, k) => {
    const t = m.tris[f];
    return { p: t[k], NORMAL: normals[t[k]], TEXCOORD_0: cylindricalUv(m, t)[k] };
  };
}
// Flat shading with box-mapped UVs (projected along the face's dominant normal axis).
function flatShaded(m) {
  return (f, k) => {
    const n = faceNormal(m, m.tris[f]);
    const a = [0, 1, 2].reduce((best, c) => (Math.abs(n[c]) > Math.abs(n[best]) ? c : best), 0);
    const p = m.pos[m.tris[f][k]];
    return { p: m.tris[f][k], NORMAL: n, TEXCOORD_0: [0.5 + 0.5 * p[(a + 1) % 3], 0.5 + 0.5 * p[(a + 2) % 3]] };
  };
}
function positionsOnly(m) {
  return (f, k) => ({ p: m.tris[f][k] });
}

// Faces grouped into `n` material bands along the longest axis (by face centroid).
function bands(m, n) {
  const { axis, lo, hi } = longestAxis(m);
  const groups = Array.from({ length: n }, () => []);
  m.tris.forEach((t, f) => {
    const c = (m.pos[t[0]][axis] + m.pos[t[1]][axis] + m.pos[t[2]][axis]) / 3;
    groups[Math.min(n - 1, Math.floor(((c - lo) / (hi - lo)) * n))].push(f);
  });
  return groups;
}
const allFaces = (m) => m.tris.map((_, f) => f);

// A 2x2 checker PNG, so materials sample TEXCOORD_0 as a textured asset's do.
function crc32(bytes) {
  let c = ~0;
  for (const b of bytes) {
    c ^= b;
    for (let k = 0; k < 8; ++k) c = (c >>> 1) ^ (0xedb88320 & -(c & 1));
  }
  return ~c >>> 0;
}
function checkerPng() {
  const chunk = (type, data) => {
    const body = Buffer.concat([Buffer.from(type, 'ascii'), data]);
    const out = Buffer.alloc(12 + data.length);
    out.writeUInt32BE(data.length, 0);
    body.copy(out, 4);
    out.writeUInt32BE(crc32(body), 8 + data.length);
    return out;
  };
  const ihdr = Buffer.alloc(13);
  ihdr.writeUInt32BE(2, 0);
  ihdr.writeUInt32BE(2, 4);
  ihdr.set([8, 2, 0, 0, 0], 8);  // 8-bit RGB
  const rows = Buffer.from([0, 255, 255, 255, 40, 40, 40, 0, 40, 40, 40, 255, 255, 255]);
  return Buffer.concat([
    Buffer.from([137, 80, 78, 71, 13, 10, 26, 10]),
    chunk('IHDR', ihdr),
    chunk('IDAT', zlib.deflateSync(rows)),
    chunk('IEND', Buffer.alloc(0)),
  ]);
}

function materials(doc, names, textured = true) {
  const texture = textured && doc.createTexture('checker').setMimeType('image/png').setImage(new Uint8Array(checkerPng()));
  return names.map((name, i) =>
    doc
      .createMaterial(name)
      .setBaseColorTexture(textured ? texture : null)
      .setBaseColorFactor([0.3 + 0.2 * (i % 3), 0.5, 0.8 - 0.2 * (i % 3), 1])
      .setRoughnessFactor(0.6)
      .setMetallicFactor(i % 2 ? 0.8 : 0.0),
  );
}

function newDocument(name) {
  const doc = new Document();
  doc.getRoot().getAsset().generator = 'seam tests/assets/build_assets.mjs';
  const buffer = doc.createBuffer();
  const scene = doc.createScene(name);
  doc.getRoot().setDefaultScene(scene);
  return { doc, buffer, scene };
}

const quat = (axis, angle) => {
  const s = Math.sin(angle / 2);
  return [axis[0] * s, axis[1] * s, axis[2] * s, Math.cos(angle / 2)];
};

// ---------------------------------------------------------------------------------------------
// Defects, planted as exporters and scanners leave them.

// A fin: a third face on an existing edge, with its own apex off the surface.
function addFin(m) {
  const t = m.tris[Math.floor(m.tris.length / 3)];
  const n = faceNormal(m, t);
  const mid = [0, 1, 2].map((c) => 0.5 * (m.pos[t[0]][c] + m.pos[t[1]][c]));
  m.pos.push(mid.map((v, c) => v + 0.15 * n[c]));
  m.tris.push([t[0], t[1], m.pos.length - 1]);
  return 1;
}

// A patch of `count` faces around a seed (breadth-first over shared edges) written reversed.
function flipPatch(m, count) {
  const byEdge = new Map();
  m.tris.forEach((t, f) => {
    for (let k = 0; k < 3; ++k) {
      const key = Math.min(t[k], t[(k + 1) % 3]) + ',' + Math.max(t[k], t[(k + 1) % 3]);
      (byEdge.get(key) ?? byEdge.set(key, []).get(key)).push(f);
    }
  });
  const seed = Math.floor(m.tris.length / 2);
  const seen = new Set([seed]);
  const queue = [seed];
  while (queue.length && seen.size < count) {
    const f = queue.shift();
    const t = m.tris[f];
    for (let k = 0; k < 3 && seen.size < count; ++k) {
      const key = Math.min(t[k], t[(k + 1) % 3]) + ',' + Math.max(t[k], t[(k + 1) % 3]);
      for (const g of byEdge.get(key)) {
        if (!seen.has(g) && seen.size < count) {
          seen.add(g);
          queue.push(g);
        }
      }
    }
  }
  for (const f of seen) m.tris[f] = [m.tris[f][0], m.tris[f][2], m.tris[f][1]];
  return seen.size;
}

// Faces degenerate after welding: each repeats a position through a second stored copy of a
// vertex (as a split-vertex export does), so it is a triangle in the index buffer but collapses
// when positions are welded.
function addCollapsedFaces(m, count) {
  for (let i = 0; i < count; ++i) {
    const t = m.tris[(i * 97) % m.tris.length];
    m.pos.push([...m.pos[t[1]]]);
    m.tris.push([t[0], t[1], m.pos.length - 1]);
  }
  return count;
}

// `count` small closed parts (bolts and nuts) laid on a grid in one mesh.
function smallParts(count) {
  const ball = readOff('geosphere');
  const ring = readOff('pipe');
  const out = { pos: [], tris: [] };
  for (let i = 0; i < count; ++i) {
    const part = i % 2 ? ring : ball;
    const base = out.pos.length;
    const scale = i % 2 ? [0.12, 0.12, 0.12] : [0.05, 0.05, 0.16];
    const at = [-0.9 + 0.25 * (i % 8), -0.5 + 0.25 * Math.floor(i / 8), 0];
    for (const p of part.pos) out.pos.push(p.map((v, c) => v * scale[c] + at[c]));
    for (const t of part.tris) out.tris.push(t.map((v) => v + base));
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// The assets. Each returns {doc, expect}: expect.defects maps "mesh/primitive" to the repairs
// that must be reported there (at least the given counts), expect.components likewise.

function props(doc, buffer, scene) {
  // The body: three materials as three primitives, smooth normals with a UV seam.
  const body = readOff('elephant');
  const mats = materials(doc, ['skin', 'cloth', 'metal', 'paint']);
  const bodyMesh = doc.createMesh('body');
  bands(body, 3).forEach((faces, i) =>
    bodyMesh.addPrimitive(makePrimitive(doc, buffer, body, exportFaces(faces, smoothWithUvSeam(body)), { material: mats[i] })),
  );
  // A flat-shaded part (every vertex split per face), instanced by three nodes.
  const wheel = readOff('pinion');
  const wheelMesh = doc.createMesh('wheel').addPrimitive(
    makePrimitive(doc, buffer, wheel, exportFaces(allFaces(wheel), flatShaded(wheel)), { material: mats[3] }),
  );
  // A second multi-primitive mesh: the cow (a pinched vertex) in two materials.
  const cow = readOff('cow');
  const cowMesh = doc.createMesh('cow');
  bands(cow, 2).forEach((faces, i) =>
    cowMesh.addPrimitive(makePrimitive(doc, buffer, cow, exportFaces(faces, smoothWithUvSeam(cow)), { material: mats[i + 2] })),
  );
  // Guide lines: not triangles, left unchanged.
  const lines = doc.createPrimitive().setMode(Primitive.Mode.LINES);
  lines.setAttribute('POSITION', doc.createAccessor().setType('VEC3').setArray(new Float32Array([0, 0, 0, 0, 1, 0, 1, 1, 0])).setBuffer(buffer));
  lines.setIndices(doc.createAccessor().setType('SCALAR').setArray(new Uint16Array([0, 1, 1, 2])).setBuffer(buffer));
  const guides = doc.createMesh('guides').addPrimitive(lines);
  // A ribbon as older exporters write bands: one TRIANGLE_STRIP around an open tube (two
  // boundary loops), its wrap's vertices stored twice (u = 0 and u = 1).
  const ring = 48;
  const ribbonPos = [], ribbonNormal = [], ribbonUv = [], ribbonIndex = [];
  for (let i = 0; i <= ring; ++i) {
    const a = i === ring ? 0 : (2 * Math.PI * i) / ring;  // the wrap at exactly the first positions
    for (const y of [0, 0.3]) {
      ribbonPos.push(0.5 * Math.cos(a), y + 0.05 * Math.sin(3 * a), 0.5 * Math.sin(a));
      ribbonNormal.push(Math.cos(a), 0, Math.sin(a));
      ribbonUv.push(i / ring, y / 0.3);
    }
  }
  for (let i = 0; i < 2 * (ring + 1); ++i) ribbonIndex.push(i);
  const strip = doc.createPrimitive().setMode(Primitive.Mode.TRIANGLE_STRIP).setMaterial(mats[1]);
  strip.setAttribute('POSITION', doc.createAccessor().setType('VEC3').setArray(new Float32Array(ribbonPos)).setBuffer(buffer));
  strip.setAttribute('NORMAL', doc.createAccessor().setType('VEC3').setArray(new Float32Array(ribbonNormal)).setBuffer(buffer));
  strip.setAttribute('TEXCOORD_0', doc.createAccessor().setType('VEC2').setArray(new Float32Array(ribbonUv)).setBuffer(buffer));
  strip.setIndices(doc.createAccessor().setType('SCALAR').setArray(new Uint16Array(ribbonIndex)).setBuffer(buffer));
  guides.addPrimitive(strip);

  const root = doc.createNode('root').setTranslation([0, 0.5, 0]).setScale([2, 2, 2]);
  scene.addChild(root);
  root.addChild(doc.createNode('body').setMesh(bodyMesh).setRotation(quat([0, 1, 0], 0.4)));
  const axle = doc.createNode('axle').setTranslation([0, -1, 0]);
  root.addChild(axle);
  [-1, 0, 1].forEach((x, i) =>
    axle.addChild(
      doc.createNode('wheel_' + i).setMesh(wheelMesh).setTranslation([x, 0, 0.6]).setRotation(quat([1, 0, 0], 0.3 * i)).setScale([0.3, 0.3, 0.3]),
    ),
  );
  root.addChild(doc.createNode('cow').setMesh(cowMesh).setTranslation([3, 0, 0]));
  root.addChild(doc.createNode('guides').setMesh(guides));
  return { doc, expect: { defects: {}, instanced: { 1: 3 } } };
}

function skinned(doc, buffer, scene, { morph = false } = {}) {
  const m = readOff(morph ? 'bull' : 'dino');
  const { axis, lo, hi } = longestAxis(m);
  const mats = materials(doc, ['hide', 'belly']);
  // Four joints in a chain along the longest axis; each vertex weighted to its two nearest.
  const jointAt = [0, 1, 2, 3].map((j) => lo + ((hi - lo) * (j + 0.5)) / 4);
  const jointsOf = (p) => {
    const x = m.pos[p][axis];
    const d = jointAt.map((a) => Math.abs(x - a));
    const order = [0, 1, 2, 3].sort((a, b) => d[a] - d[b]);
    const w0 = Math.round((d[order[1]] / (d[order[0]] + d[order[1]] + 1e-12)) * 255) / 255;
    // A joint with weight 0 is joint 0, as exporters write it (else a validator warning).
    return { j: [w0 > 0 ? order[0] : 0, w0 < 1 ? order[1] : 0, 0, 0], w: [w0, 1 - w0, 0, 0] };
  };
  const perPosition = {
    JOINTS_0: (p) => jointsOf(p).j,
    WEIGHTS_0: (p) => jointsOf(p).w,
  };
  const normals = vertexNormals(m);
  const targets = morph
    ? [
        { POSITION: (p) => normals[p].map((v) => 0.03 * v), NORMAL: (p) => [0, 0, 0] },
        { POSITION: (p) => [0, 1, 2].map((c) => (c === axis ? 0.1 * m.pos[p][c] : 0)) },
      ]
    : [];
  const mesh = doc.createMesh(morph ? 'creature_morph' : 'creature');
  bands(m, 2).forEach((faces, i) =>
    mesh.addPrimitive(
      makePrimitive(doc, buffer, m, exportFaces(faces, smoothWithUvSeam(m)), {
        material: mats[i],
        perPosition,
        targets,
        attributeTypes: { JOINTS_0: { array: Uint8Array } },
      }),
    ),
  );
  if (morph) mesh.setWeights([0.25, 0]);
  // The armature: a chain of joint nodes, and the skinned mesh's node at the scene root.
  const joints = [];
  let parent = doc.createNode('armature');
  scene.addChild(parent);
  let previous = 0;
  for (let j = 0; j < 4; ++j) {
    const t = [0, 0, 0];
    t[axis] = jointAt[j] - previous;
    previous = jointAt[j];
    const node = doc.createNode('joint_' + j).setTranslation(t);
    parent.addChild(node);
    joints.push(node);
    parent = node;
  }
  const ibm = new Float32Array(16 * 4);
  jointAt.forEach((a, j) => {
    const mat = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1];
    mat[12 + axis] = -a;
    ibm.set(mat, 16 * j);
  });
  const skin = doc.createSkin('rig').setInverseBindMatrices(doc.createAccessor().setType('MAT4').setArray(ibm).setBuffer(buffer));
  joints.forEach((n) => skin.addJoint(n));
  skin.setSkeleton(joints[0]);
  scene.addChild(doc.createNode(mesh.getName()).setMesh(mesh).setSkin(skin));
  // An animation: the second and third joints bend, and with morph targets the weights move.
  const anim = doc.createAnimation('walk');
  const times = doc.createAccessor().setType('SCALAR').setArray(new Float32Array([0, 0.5, 1])).setBuffer(buffer);
  const bend = [0, 1, 2].map((c) => (c === axis ? 0 : c === (axis + 1) % 3 ? 1 : 0));
  for (const j of [1, 2]) {
    const rot = doc.createAccessor().setType('VEC4').setBuffer(buffer)
      .setArray(new Float32Array([...quat(bend, 0), ...quat(bend, 0.3 * j), ...quat(bend, 0)]));
    const sampler = doc.createAnimationSampler().setInput(times).setOutput(rot).setInterpolation('LINEAR');
    anim.addSampler(sampler);
    anim.addChannel(doc.createAnimationChannel().setTargetNode(joints[j]).setTargetPath('rotation').setSampler(sampler));
  }
  if (morph) {
    const w = doc.createAccessor().setType('SCALAR').setBuffer(buffer).setArray(new Float32Array([0.25, 0, 1, 0.5, 0.25, 0]));
    const sampler = doc.createAnimationSampler().setInput(times).setOutput(w).setInterpolation('LINEAR');
    anim.addSampler(sampler);
    const node = scene.listChildren().find((n) => n.getMesh() === mesh);
    anim.addChannel(doc.createAnimationChannel().setTargetNode(node).setTargetPath('weights').setSampler(sampler));
  }
  return { doc, expect: { defects: {}, instanced: {} } };
}

function defects(doc, buffer, scene) {
  const [painted] = materials(doc, ['painted']);
  const [scanned] = materials(doc, ['scanned'], false);
  const expect = { defects: {}, components: {}, instanced: {} };
  const add = (name, m, shading, x) => {
    const material = shading === positionsOnly ? scanned : painted;
    const mesh = doc.createMesh(name).addPrimitive(makePrimitive(doc, buffer, m, exportFaces(allFaces(m), shading(m)), { material }));
    scene.addChild(doc.createNode(name).setMesh(mesh).setTranslation([x, 0, 0]));
    return doc.getRoot().listMeshes().indexOf(mesh);
  };
  const fin = readOff('sphere966');
  const fins = addFin(fin);
  expect.defects[add('fin', fin, positionsOnly, 0) + '/0'] = { non_manifold_edges: fins };
  const flipped = readOff('elephant');
  const patch = flipPatch(flipped, 40);
  expect.defects[add('flipped_patch', flipped, smoothWithUvSeam, 3) + '/0'] = { reoriented_faces: patch };
  const collapsed = readOff('hand');
  const degenerate = addCollapsedFaces(collapsed, 6);
  expect.defects[add('collapsed_faces', collapsed, positionsOnly, 6) + '/0'] = { degenerate_faces: degenerate };
  const parts = smallParts(40);
  expect.components[add('parts_40', parts, flatShaded, 9) + '/0'] = 40;
  return { doc, expect };
}

// Six primitives, ~100k faces: two meshes of three parts each (one material per part).
function bench6(doc, buffer, scene) {
  const mats = materials(doc, ['a', 'b', 'c', 'd', 'e', 'f']);
  const parts = [['camel', 'lion-head', 'blade'], ['ChineseDragon-10kv', 'turbine', 'bull']];
  parts.forEach((names, i) => {
    const mesh = doc.createMesh('assembly_' + i);
    names.forEach((name, j) => {
      const m = readOff(name);
      m.pos = m.pos.map((p) => [p[0] + 2.2 * j, p[1], p[2]]);
      mesh.addPrimitive(makePrimitive(doc, buffer, m, exportFaces(allFaces(m), smoothWithUvSeam(m)), { material: mats[3 * i + j] }));
    });
    scene.addChild(doc.createNode('assembly_' + i).setMesh(mesh).setTranslation([0, 2.5 * i, 0]));
  });
  return { doc, expect: { defects: {}, instanced: {} } };
}

// ---------------------------------------------------------------------------------------------

async function validate(bytes) {
  const report = await validator.validateBytes(new Uint8Array(bytes), {
    maxIssues: 1000,
    externalResourceFunction: () => Promise.reject(new Error('external resources are not allowed')),
  });
  const unused = report.issues.messages.filter((m) => m.code === 'UNUSED_OBJECT').map((m) => m.pointer);
  return {
    errors: report.issues.numErrors,
    warnings: report.issues.numWarnings,
    unused_objects: unused.length,
    error_messages: report.issues.messages.filter((m) => m.severity === 0).map((m) => `${m.code} ${m.pointer}: ${m.message}`),
  };
}

function triangleCount(doc) {
  let faces = 0;
  for (const mesh of doc.getRoot().listMeshes())
    for (const p of mesh.listPrimitives()) {
      const n = p.getIndices().getCount();
      if (p.getMode() === Primitive.Mode.TRIANGLES) faces += n / 3;
      else if (p.getMode() === Primitive.Mode.TRIANGLE_STRIP || p.getMode() === Primitive.Mode.TRIANGLE_FAN) faces += n - 2;
    }
  return faces;
}

// --check: the set in OUT_DIR is the current builder's, and every asset is still what the
// manifest says (faces, valid, the same unused objects).
async function check(manifestPath, want) {
  if (!fs.existsSync(manifestPath)) throw new Error(`no ${manifestPath}: run scripts/fetch-test-data.sh`);
  const manifest = JSON.parse(fs.readFileSync(manifestPath, 'utf8'));
  if (manifest.stamp !== want) throw new Error(`${manifestPath} is from another builder: run scripts/fetch-test-data.sh`);
  let bad = 0;
  for (const a of manifest.assets) {
    const bytes = fs.readFileSync(path.join(outDir, a.file));
    const doc = await new NodeIO().registerExtensions([KHRDracoMeshCompression, KHRMeshQuantization]).registerDependencies({
      'draco3d.decoder': await draco3d.createDecoderModule(),
    }).readBinary(new Uint8Array(bytes));
    const report = await validate(bytes);
    const ok = report.errors === 0 && report.unused_objects === a.validator.unused_objects && triangleCount(doc) === a.faces;
    console.log(`${ok ? 'ok' : 'BAD'} ${a.file}: ${triangleCount(doc)} faces, ${report.errors} errors, ${report.unused_objects} unused objects`);
    bad += !ok;
  }
  if (bad) throw new Error(`${bad} assets differ from the manifest`);
}

async function main() {
  const manifestPath = path.join(outDir, 'manifest.json');
  const want = stamp();
  if (checkOnly) return check(manifestPath, want);
  if (fs.existsSync(manifestPath)) {
    const old = JSON.parse(fs.readFileSync(manifestPath, 'utf8'));
    if (old.stamp === want && old.assets.every((a) => fs.existsSync(path.join(outDir, a.file)))) return;
  }
  fs.mkdirSync(outDir, { recursive: true });
  const io = new NodeIO().registerExtensions([KHRDracoMeshCompression, KHRMeshQuantization]).registerDependencies({
    'draco3d.encoder': await draco3d.createEncoderModule(),
    'draco3d.decoder': await draco3d.createDecoderModule(),
  });

  const recipes = [
    ['props', 'multi-mesh, multi-primitive (3+1+2 triangle primitives, 4 materials), node hierarchy, a mesh instanced by 3 nodes, UV and flat-shading splits, a LINES primitive beside a TRIANGLE_STRIP one', props, null],
    ['props_draco', 'props, KHR_draco_mesh_compression (edgebreaker, 14-bit positions)', props, 'draco'],
    ['props_quantized', 'props, KHR_mesh_quantization (int16 positions, int8 normals, uint16 UVs)', props, 'quantize'],
    ['skinned', 'a skinned creature (2 primitives): JOINTS_0 (u8), WEIGHTS_0, 4-joint skin, inverseBindMatrices, a rotation animation', skinned, null],
    ['skinned_draco', 'skinned, Draco-compressed', skinned, 'draco'],
    ['morph', 'skinned and morphed (2 primitives): 2 targets (POSITION+NORMAL, POSITION), mesh weights, a weights animation', (d, b, s) => skinned(d, b, s, { morph: true }), null],
    ['morph_quantized', 'morph, KHR_mesh_quantization', (d, b, s) => skinned(d, b, s, { morph: true }), 'quantize'],
    ['defects', 'a fin, a 40-face flipped patch, 6 faces degenerate after welding, 40 small closed parts in one primitive (one mesh each)', defects, null],
    ['bench6', 'six real meshes as 6 primitives of 2 meshes (~100k faces), for bench/asset_bench', bench6, null],
  ];
  const manifest = { stamp: want, assets: [] };
  for (const [name, description, build, variant] of recipes) {
    const t0 = Date.now();
    const { doc, buffer, scene } = newDocument(name);
    const { expect } = build(doc, buffer, scene);
    if (variant === 'draco') {
      await doc.transform(draco({ method: 'edgebreaker' }));
    } else if (variant === 'quantize') {
      await doc.transform(quantize({ quantizePosition: 14, quantizeNormal: 8, quantizeTexcoord: 16 }));
    }
    const bytes = await io.writeBinary(doc);
    const file = name + '.glb';
    fs.writeFileSync(path.join(outDir, file), bytes);
    const report = await validate(bytes);
    if (report.errors) {
      console.error(`build_assets: ${file} is not valid glTF:\n  ${report.error_messages.join('\n  ')}`);
      process.exit(1);
    }
    manifest.assets.push({
      file,
      description,
      faces: triangleCount(doc),
      bytes: bytes.length,
      variant: variant ?? 'plain',
      expect,
      validator: { errors: report.errors, warnings: report.warnings, unused_objects: report.unused_objects },
    });
    console.log(`build_assets: ${file} ${triangleCount(doc)} faces, ${bytes.length} bytes, ${report.warnings} warnings (${report.unused_objects} unused objects), ${Date.now() - t0} ms`);
  }
  fs.writeFileSync(manifestPath, JSON.stringify(manifest, null, 1) + '\n');
}

main().catch((e) => {
  console.error('build_assets: ' + (e.stack || e));
  process.exit(1);
});
