// The seamd viewer: load an asset (or the bundled sample), see it with its extrema and seam,
// click to add or remove extrema (POST /seam recomputes), view the cut asset with a checker
// on its new UV set and the 2D layout, hide the seam from the camera's view, download the cut
// GLB. Everything is served by seamd itself; the page talks to no other host.
//
// The page exposes its state as window.seamViewer (and data-* attributes on <body>) so the
// browser test can check it against the server's own response.
import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import { DRACOLoader } from 'three/examples/jsm/loaders/DRACOLoader.js';
import { GLTFExporter } from 'three/examples/jsm/exporters/GLTFExporter.js';
import { OBJLoader } from 'three/examples/jsm/loaders/OBJLoader.js';
import { mergeGeometries } from 'three/examples/jsm/utils/BufferGeometryUtils.js';
import { LineSegments2 } from 'three/examples/jsm/lines/LineSegments2.js';
import { LineSegmentsGeometry } from 'three/examples/jsm/lines/LineSegmentsGeometry.js';
import { LineMaterial } from 'three/examples/jsm/lines/LineMaterial.js';
import { parseOff } from './off.js';

const $ = (id) => document.getElementById(id);
const SEAM_COLOR = 0xff2020;
const MARKER_COLOR = 0xffc400;

// ---- what the test and the panels read --------------------------------------------------------

const state = {
  status: 'empty', // empty | loading | computing | ready | error
  assetName: '',
  target: null, // {mesh, primitive}: the primitive being cut
  extrema: [], // POSITION indices of the target primitive; empty = "auto"
  hideFrom: [], // view directions in the primitive's model frame
  requests: 0, // POST /seam requests answered (any status)
  seamEdges: 0,
  seamEdgeList: [],
  seamLength: 0,
  uvChannel: -1,
  uvTriangles: 0,
  error: null, // {status, code, message}
  lastParams: null,
};

function publish() {
  const b = document.body.dataset;
  b.status = state.status;
  b.extrema = String(state.extrema.length);
  b.seamEdges = String(state.seamEdges);
  b.requests = String(state.requests);
  $('status').textContent = statusText();
}

function statusText() {
  switch (state.status) {
    case 'loading': return `loading ${state.assetName}…`;
    case 'computing': return 'computing the seam…';
    case 'ready': return `${state.assetName}: ${state.extrema.length} extrema, ${state.seamEdges} seam edges`;
    case 'error': return 'error (see above)';
    default: return 'Drop a GLB, glTF, Draco, OBJ or OFF file, or load the sample.';
  }
}

function showError(err) {
  state.error = err;
  state.status = 'error';
  const box = $('error');
  box.hidden = false;
  box.textContent = err.status ? `${err.status} ${err.code}: ${err.message}` : err.message;
  publish();
}

function clearError() {
  state.error = null;
  $('error').hidden = true;
}

// ---- the 3D view ------------------------------------------------------------------------------

const view = $('view3d');
// preserveDrawingBuffer: the test reads the canvas pixels after a frame was presented.
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio || 1);
view.appendChild(renderer.domElement);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0x30343c);
const camera = new THREE.PerspectiveCamera(45, 1, 0.01, 1000);
camera.position.set(0, 0, 3);
scene.add(camera);
scene.add(new THREE.HemisphereLight(0xffffff, 0x404850, 2.2));
const sun = new THREE.DirectionalLight(0xffffff, 1.6);
sun.position.set(0.3, 0.5, 1);
camera.add(sun); // the light follows the camera: the side one looks at is lit
const controls = new OrbitControls(camera, renderer.domElement);
controls.enableDamping = false;
controls.addEventListener('change', render);

let assetRoot = null; // the input asset's scene
let inputMesh = null; // the target primitive's THREE.Mesh (raycast target)
let overlay = null; // markers and seam lines, in the target's model frame
let cutMesh = null; // the cut primitive with the checker, in the target's model frame
let cutGlb = null; // Uint8Array of the last cut asset
let markerRadius = 0.01;
const seamMaterial = new LineMaterial({ color: SEAM_COLOR, linewidth: 2.5 }); // linewidth in CSS px

function resize() {
  const w = view.clientWidth || 1;
  const h = view.clientHeight || 1;
  renderer.setSize(w, h, false);
  renderer.domElement.style.width = `${w}px`;
  renderer.domElement.style.height = `${h}px`;
  camera.aspect = w / h;
  camera.updateProjectionMatrix();
  seamMaterial.resolution.set(w, h);
  render();
}
window.addEventListener('resize', resize);

function render() {
  renderer.render(scene, camera);
}

function disposeObject(obj) {
  if (!obj) return;
  obj.parent?.remove(obj);
  obj.traverse((o) => {
    o.geometry?.dispose();
    const m = o.material;
    (Array.isArray(m) ? m : m ? [m] : []).forEach((x) => {
      if (x === seamMaterial || x.map === checkerTexture) return; // shared, kept for the next answer
      x.dispose();
    });
  });
}

function frameObject(obj) {
  const box = new THREE.Box3().setFromObject(obj);
  const size = box.getSize(new THREE.Vector3()).length() || 1;
  const center = box.getCenter(new THREE.Vector3());
  controls.target.copy(center);
  camera.near = size / 1000;
  camera.far = size * 100;
  camera.position.copy(center).add(new THREE.Vector3(0, 0, size * 1.25));
  camera.updateProjectionMatrix();
  controls.update();
  markerRadius = size * 0.008;
}

// A frame that follows the target primitive's world transform (its node's), so that data in
// model coordinates (POSITION, the seam) lands on the drawn mesh.
function modelFrame() {
  const g = new THREE.Group();
  g.matrixAutoUpdate = false;
  inputMesh.updateWorldMatrix(true, false);
  g.matrix.copy(inputMesh.matrixWorld);
  scene.add(g);
  return g;
}

// ---- loading assets ---------------------------------------------------------------------------

// three's Draco decoder, served by seamd (WebAssembly in a worker), for .drc files and GLBs
// with KHR_draco_mesh_compression.
const draco = new DRACOLoader().setDecoderPath('/draco/');
const asError = (e) => (e instanceof Error ? e : new Error(String(e?.message ?? e)));

function parseGltf(bytes) {
  return new Promise((resolve, reject) => {
    new GLTFLoader().setDRACOLoader(draco).parse(bytes, '', resolve, (e) => reject(asError(e)));
  });
}

// A raw Draco mesh as a one-primitive "asset" (mesh 0, primitive 0, as POST /seam numbers it).
// DRACOLoader and the server both number vertices by Draco point id.
async function parseDrc(bytes) {
  const geometry = await new Promise((resolve, reject) => draco.parse(bytes, resolve, (e) => reject(asError(e))));
  const mesh = new THREE.Mesh(geometry);
  const scene = new THREE.Group();
  scene.add(mesh);
  return { scene, parser: { associations: new Map([[mesh, { meshes: 0, primitives: 0 }]]) } };
}

// The first triangle primitive of the asset, with its glTF mesh and primitive indices.
function firstTrianglePrimitive(gltf) {
  let found = null;
  gltf.scene.traverse((o) => {
    if (found || !o.isMesh) return;
    const a = gltf.parser.associations.get(o);
    if (a && a.meshes !== undefined && o.geometry.attributes.position) {
      found = { object: o, mesh: a.meshes, primitive: a.primitives ?? 0 };
    }
  });
  return found;
}

// OBJ and OFF are not POST /seam's formats: they are converted here to a GLB whose POSITION
// is the file's vertices (OFF keeps its numbering; OBJ as three's OBJLoader reads it).
async function toGlb(name, buffer) {
  const lower = name.toLowerCase();
  if (!lower.endsWith('.obj') && !lower.endsWith('.off')) return buffer;
  const text = new TextDecoder().decode(buffer);
  let geometry;
  if (lower.endsWith('.off')) {
    geometry = parseOff(text);
  } else {
    const parts = [];
    new OBJLoader().parse(text).traverse((o) => {
      if (o.isMesh) parts.push(new THREE.BufferGeometry().setAttribute('position', o.geometry.attributes.position));
    });
    if (!parts.length) throw new Error(`${name}: no faces`);
    geometry = parts.length === 1 ? parts[0] : mergeGeometries(parts);
  }
  const mesh = new THREE.Mesh(geometry, new THREE.MeshStandardMaterial());
  mesh.name = name.replace(/\.[^.]*$/, '');
  return new GLTFExporter().parseAsync(mesh, { binary: true });
}

let associations = new Map(); // three object -> {meshes, primitives} of the loaded asset
const associationOf = (o) => {
  const a = associations.get(o);
  return a && a.meshes !== undefined ? a : null;
};

// The primitive being cut is drawn plain grey (its seam and markers stand out on it).
function useAsTarget(object) {
  inputMesh = object;
  if (!inputMesh.geometry.attributes.normal) inputMesh.geometry.computeVertexNormals();
  inputMesh.material = new THREE.MeshStandardMaterial({
    color: 0xb8bcc4, roughness: 0.8, side: THREE.DoubleSide,
    polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1,
  });
}

async function loadAsset(name, buffer) {
  clearError();
  state.assetName = name;
  state.status = 'loading';
  publish();
  let gltf;
  try {
    buffer = await toGlb(name, buffer);
    gltf = name.toLowerCase().endsWith('.drc') ? await parseDrc(buffer.slice(0)) : await parseGltf(buffer);
  } catch (e) {
    return showError({ message: `cannot read ${name} in the browser: ${e.message}` });
  }
  const target = firstTrianglePrimitive(gltf);
  if (!target) return showError({ message: `${name} has no triangle mesh to show` });
  [assetRoot, overlay, cutMesh].forEach(disposeObject);
  cutMesh = overlay = null;
  cutGlb = null;
  $('download').disabled = true;
  assetRoot = gltf.scene;
  scene.add(assetRoot);
  associations = gltf.parser.associations;
  useAsTarget(target.object);
  state.asset = new Uint8Array(buffer);
  state.target = { mesh: target.mesh, primitive: target.primitive };
  state.extrema = [];
  state.hideFrom = [];
  $('views').textContent = '0';
  $('unhide').hidden = true;
  frameObject(assetRoot);
  resize();
  await compute();
}

// ---- POST /seam -------------------------------------------------------------------------------

let inFlight = null; // AbortController of the request whose answer is awaited

function seamParams() {
  const p = {
    mesh: state.target.mesh,
    primitive: state.target.primitive,
    extrema: state.extrema.length ? state.extrema : 'auto',
    method: $('method').value,
    uv: $('uv').value,
    draco: false, // the page decodes the cut asset without a Draco decoder
    output: 'json',
  };
  // The hiding parameters go only with hiding asked for: a server without them still answers
  // every other request.
  if (state.hideFrom.length) p.hide_from = state.hideFrom;
  if ($('occluded').checked) p.hide_occluded = true;
  const strength = Number($('strength').value);
  if ((state.hideFrom.length || p.hide_occluded) && Number.isFinite(strength) && strength !== 4) p.hide_strength = strength;
  return p;
}

function seamForm(params) {
  const form = new FormData();
  form.append('mesh', new Blob([state.asset], { type: 'application/octet-stream' }), state.assetName || 'asset');
  form.append('params', JSON.stringify(params));
  return form;
}

// A server error body as the page shows it.
async function errorOf(res) {
  const body = await res.json().catch(() => null);
  const err = body?.error ?? { code: 'http_error', message: `HTTP ${res.status}` };
  return { status: res.status, code: err.code, message: err.message, details: err.details };
}

async function compute() {
  if (!state.asset) return;
  inFlight?.abort();
  const abort = new AbortController();
  inFlight = abort;
  clearError();
  state.status = 'computing';
  publish();
  const params = seamParams();
  state.lastParams = params;
  let res, body;
  try {
    res = await fetch('/seam', { method: 'POST', body: seamForm(params), signal: abort.signal });
    body = res.ok ? await res.json() : await errorOf(res);
  } catch (e) {
    if (abort.signal.aborted) return;
    return showError({ message: `the request failed: ${e.message}` });
  }
  if (inFlight !== abort) return; // a newer request replaced this one
  inFlight = null;
  state.requests += 1;
  if (!res.ok) return showError(body);
  try {
    await showResult(body);
  } catch (e) {
    return showError({ message: `cannot show the answer: ${e.message}` });
  }
  state.status = 'ready';
  publish();
}

// Contract v2 answers per primitive in `primitives`; with one primitive (and in v1) the
// top-level `seam`, `uv`, `cut` are the same objects.
function primitiveEntry(body) {
  const list = Array.isArray(body.primitives) ? body.primitives : [];
  const t = state.target;
  const entry = list.find((p) => p.mesh === t.mesh && p.primitive === t.primitive);
  return {
    seam: entry?.seam ?? body.seam,
    uv: entry?.uv ?? body.uv,
    cut: entry?.cut ?? body.cut,
    topology: entry?.topology ?? body.mesh,
    timings: entry?.timings_ms ?? body.timings_ms ?? {},
    repairs: entry?.repairs ?? body.repairs,
  };
}

async function showResult(body) {
  const p = primitiveEntry(body);
  if (!p.seam) throw new Error('the answer has no seam');
  state.extrema = [...(p.seam.extrema ?? [])];
  state.seamEdgeList = p.seam.edges ?? [];
  state.seamEdges = state.seamEdgeList.length;
  state.seamLength = p.seam.length ?? 0;
  drawOverlay();
  cutGlb = body.asset?.glb_base64 ? base64Bytes(body.asset.glb_base64) : null;
  $('download').disabled = !cutGlb;
  $('svg').disabled = false;
  state.uvChannel = p.uv?.channel ?? -1;
  await showCut(p.uv);
  showStats(p, body);
  render();
}

function base64Bytes(b64) {
  const s = atob(b64);
  const out = new Uint8Array(s.length);
  for (let i = 0; i < s.length; ++i) out[i] = s.charCodeAt(i);
  return out;
}

// ---- markers, seam, checker, UV layout ----------------------------------------------------------

function vertexPosition(i) {
  const pos = inputMesh.geometry.attributes.position;
  return new THREE.Vector3().fromBufferAttribute(pos, i);
}

// The seam's edges (input POSITION indices) as wide lines and a marker per extremum.
function drawOverlay() {
  disposeObject(overlay);
  overlay = modelFrame();
  // Screen-space wide lines (WebGL draws plain lines 1 px wide).
  const points = [];
  for (const [a, b] of state.seamEdgeList) points.push(...vertexPosition(a).toArray(), ...vertexPosition(b).toArray());
  if (points.length) {
    const lines = new LineSegments2(new LineSegmentsGeometry().setPositions(points), seamMaterial);
    lines.name = 'seam';
    overlay.add(lines);
  }
  // Radius in model units: the frame may scale.
  const scale = new THREE.Vector3().setFromMatrixScale(overlay.matrix).x || 1;
  const sphere = new THREE.SphereGeometry(markerRadius / scale, 16, 12);
  const material = new THREE.MeshStandardMaterial({ color: MARKER_COLOR, emissive: 0x553300 });
  for (const v of state.extrema) {
    const m = new THREE.Mesh(sphere, material);
    m.position.copy(vertexPosition(v));
    m.userData.vertex = v;
    m.name = `extremum ${v}`;
    overlay.add(m);
  }
}

let checkerTexture = null;
function checker() {
  if (checkerTexture) return checkerTexture;
  const c = document.createElement('canvas');
  c.width = c.height = 512;
  const g = c.getContext('2d');
  const n = 16;
  for (let y = 0; y < n; ++y) {
    for (let x = 0; x < n; ++x) {
      g.fillStyle = (x + y) % 2 ? '#2f6fd6' : '#f2f2f2';
      g.fillRect((x * c.width) / n, (y * c.height) / n, c.width / n, c.height / n);
    }
  }
  checkerTexture = new THREE.CanvasTexture(c);
  checkerTexture.colorSpace = THREE.SRGBColorSpace;
  checkerTexture.wrapS = checkerTexture.wrapT = THREE.RepeatWrapping;
  return checkerTexture;
}

// The cut primitive from the answer's GLB, its new TEXCOORD_n (uv.channel) as the checker's UVs.
async function showCut(uv) {
  disposeObject(cutMesh);
  cutMesh = null;
  state.uvTriangles = 0;
  drawUvLayout(null);
  if (!cutGlb || !uv || uv.channel === undefined || uv.channel < 0) return applyChecker();
  const gltf = await parseGltf(cutGlb.buffer.slice(cutGlb.byteOffset, cutGlb.byteOffset + cutGlb.byteLength));
  let cut = null;
  gltf.scene.traverse((o) => {
    const a = gltf.parser.associations.get(o);
    if (!cut && o.isMesh && a && a.meshes === state.target.mesh && (a.primitives ?? 0) === state.target.primitive) cut = o;
  });
  if (!cut) throw new Error('the cut asset lacks the target primitive');
  const attr = cut.geometry.attributes[uv.channel === 0 ? 'uv' : `uv${uv.channel}`];
  if (!attr) throw new Error(`the cut asset has no TEXCOORD_${uv.channel}`);
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', cut.geometry.attributes.position);
  geometry.setAttribute('uv', attr);
  geometry.setIndex(cut.geometry.index);
  // Without NORMAL in the asset: smooth normals from the faces. The cut split the vertices
  // along the seam, so its two sides are shaded apart, as a renderer would shade the asset.
  if (cut.geometry.attributes.normal) geometry.setAttribute('normal', cut.geometry.attributes.normal);
  else geometry.computeVertexNormals();
  disposeObject(gltf.scene);
  cutMesh = new THREE.Mesh(geometry, new THREE.MeshStandardMaterial({
    map: checker(), roughness: 0.85, side: THREE.DoubleSide,
    polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1,
  }));
  cutMesh.name = 'cut';
  cutMesh.matrixAutoUpdate = false;
  cutMesh.matrix.copy(overlay.matrix);
  scene.add(cutMesh);
  drawUvLayout(geometry);
  applyChecker();
}

function applyChecker() {
  const on = $('checker').checked && !!cutMesh;
  if (cutMesh) cutMesh.visible = on;
  // Hidden, the input mesh is still the raycast target (three's Raycaster ignores visibility).
  if (inputMesh) inputMesh.visible = !on;
  render();
}

function drawUvLayout(geometry) {
  const canvas = $('uv2d');
  const g = canvas.getContext('2d');
  const s = canvas.width;
  g.fillStyle = '#fff';
  g.fillRect(0, 0, s, s);
  g.strokeStyle = '#bbb';
  g.strokeRect(0.5, 0.5, s - 1, s - 1);
  if (!geometry) return;
  const uv = geometry.attributes.uv;
  const index = geometry.index ? geometry.index.array : [...Array(uv.count).keys()];
  const X = (i) => uv.getX(i) * (s - 2) + 1;
  const Y = (i) => (1 - uv.getY(i)) * (s - 2) + 1;
  // Edges used by one triangle are the chart's boundary: both sides of the seam.
  const uses = new Map();
  g.beginPath();
  for (let t = 0; t + 2 < index.length; t += 3) {
    const tri = [index[t], index[t + 1], index[t + 2]];
    g.moveTo(X(tri[0]), Y(tri[0]));
    g.lineTo(X(tri[1]), Y(tri[1]));
    g.lineTo(X(tri[2]), Y(tri[2]));
    g.closePath();
    for (let k = 0; k < 3; ++k) {
      const a = tri[k], b = tri[(k + 1) % 3];
      const key = a < b ? `${a},${b}` : `${b},${a}`;
      uses.set(key, (uses.get(key) ?? 0) + 1);
    }
  }
  state.uvTriangles = index.length / 3;
  g.fillStyle = 'rgba(47,111,214,0.12)';
  g.fill();
  g.lineWidth = 0.5;
  g.strokeStyle = '#5b6b85';
  g.stroke();
  g.beginPath();
  for (const [key, n] of uses) {
    if (n !== 1) continue;
    const [a, b] = key.split(',').map(Number);
    g.moveTo(X(a), Y(a));
    g.lineTo(X(b), Y(b));
  }
  g.lineWidth = 1.5;
  g.strokeStyle = '#e01010';
  g.stroke();
}

function showStats(p, body) {
  const fmt = (x) => (typeof x === 'number' ? (Number.isInteger(x) ? String(x) : x.toPrecision(4)) : String(x));
  const rows = [
    ['seam length', p.seam.length], ['seam edges', state.seamEdges],
    ['extrema', state.extrema.length], ['terminals', (p.seam.terminals ?? []).length],
  ];
  if (p.seam.cost !== undefined) rows.push(['seam cost', p.seam.cost]);
  if (p.seam.visible_length !== undefined) rows.push(['visible length', p.seam.visible_length]);
  if (p.topology) rows.push(['faces', p.topology.faces], ['genus', p.topology.genus]);
  if (p.uv) {
    for (const k of ['channel', 'area_distortion', 'angle_distortion', 'flipped', 'coverage', 'overlap_area']) {
      if (p.uv[k] !== undefined) rows.push([`uv ${k.replace('_', ' ')}`, p.uv[k]]);
    }
  }
  for (const [k, v] of Object.entries(p.repairs ?? {})) if (v) rows.push([`repaired ${k.replaceAll('_', ' ')}`, v]);
  const timings = body.timings_ms ?? p.timings;
  for (const [k, v] of Object.entries(timings)) rows.push([`${k} ms`, v]);
  const table = $('stats');
  table.replaceChildren(...rows.map(([k, v]) => {
    const tr = document.createElement('tr');
    for (const text of [k, fmt(v)]) {
      const td = document.createElement('td');
      td.textContent = text;
      tr.appendChild(td);
    }
    return tr;
  }));
}

// ---- clicks: add or remove extrema ----------------------------------------------------------------

const raycaster = new THREE.Raycaster();
let downAt = null;

function ndc(event) {
  const r = renderer.domElement.getBoundingClientRect();
  return new THREE.Vector2(((event.clientX - r.left) / r.width) * 2 - 1, -((event.clientY - r.top) / r.height) * 2 + 1);
}

function onClick(event) {
  if (!inputMesh || !state.target || state.status === 'loading') return;
  raycaster.setFromCamera(ndc(event), camera);
  const markers = overlay ? overlay.children.filter((o) => o.userData.vertex !== undefined) : [];
  const hitMarker = raycaster.intersectObjects(markers, false)[0];
  if (hitMarker) {
    state.extrema = state.extrema.filter((v) => v !== hitMarker.object.userData.vertex);
    return compute();
  }
  const hit = raycaster.intersectObject(assetRoot, true).find((h) => h.object.isMesh && h.face && associationOf(h.object));
  if (!hit) return;
  const a = associationOf(hit.object);
  if (a.meshes !== state.target.mesh || (a.primitives ?? 0) !== state.target.primitive) return switchTarget(hit.object, a);
  // The nearest corner of the clicked triangle, compared in world space (the hit may be
  // another instance of the target's glTF mesh).
  let best = -1, bestD = Infinity;
  for (const v of [hit.face.a, hit.face.b, hit.face.c]) {
    const d = hit.object.localToWorld(new THREE.Vector3().fromBufferAttribute(hit.object.geometry.attributes.position, v)).distanceTo(hit.point);
    if (d < bestD) { bestD = d; best = v; }
  }
  if (state.extrema.includes(best)) return;
  state.extrema = [...state.extrema, best];
  compute();
}

// A click on another triangle primitive of the asset makes it the one cut, with automatic
// extrema (the extrema are that primitive's POSITION indices).
function switchTarget(object, a) {
  if (inputMesh) inputMesh.visible = true;
  useAsTarget(object);
  state.target = { mesh: a.meshes, primitive: a.primitives ?? 0 };
  state.extrema = [];
  compute();
}

renderer.domElement.addEventListener('pointerdown', (e) => { downAt = [e.clientX, e.clientY]; });
renderer.domElement.addEventListener('pointerup', (e) => {
  if (downAt && Math.hypot(e.clientX - downAt[0], e.clientY - downAt[1]) < 5) onClick(e);
  downAt = null;
});

// ---- controls -----------------------------------------------------------------------------------

async function openFile(file) {
  await loadAsset(file.name, await file.arrayBuffer());
}

async function loadSample() {
  clearError();
  state.status = 'loading';
  state.assetName = 'sample.glb';
  publish();
  try {
    const res = await fetch('/sample.glb');
    if (!res.ok) {
      const body = await res.json().catch(() => null);
      return showError({ status: res.status, code: body?.error?.code ?? 'http_error', message: body?.error?.message ?? 'GET /sample.glb failed' });
    }
    await loadAsset('sample.glb', await res.arrayBuffer());
  } catch (e) {
    showError({ message: `cannot load the sample: ${e.message}` });
  }
}

// hide_from takes the direction in which the camera looks, in the primitive's model frame.
function viewDirection() {
  const d = camera.getWorldDirection(new THREE.Vector3());
  const toModel = new THREE.Matrix3().setFromMatrix4(inputMesh.matrixWorld).invert();
  d.applyMatrix3(toModel).normalize();
  return [d.x, d.y, d.z].map((x) => Math.round(x * 1e6) / 1e6);
}

$('file').addEventListener('change', (e) => { if (e.target.files[0]) openFile(e.target.files[0]); });
$('sample').addEventListener('click', loadSample);
$('method').addEventListener('change', compute);
$('uv').addEventListener('change', compute);
$('checker').addEventListener('change', applyChecker);
$('auto').addEventListener('click', () => { state.extrema = []; compute(); });
$('hide').addEventListener('click', () => {
  if (!inputMesh) return;
  state.hideFrom = [...state.hideFrom, viewDirection()];
  $('views').textContent = String(state.hideFrom.length);
  $('unhide').hidden = false;
  compute();
});
$('unhide').addEventListener('click', () => {
  state.hideFrom = [];
  $('unhide').hidden = true;
  compute();
});
function saveBlob(blob, suffix) {
  const a = document.createElement('a');
  a.href = URL.createObjectURL(blob);
  a.download = `${state.assetName.replace(/\.[^.]*$/, '') || 'asset'}${suffix}`;
  a.click();
  setTimeout(() => URL.revokeObjectURL(a.href), 1000);
}
$('download').addEventListener('click', () => {
  if (cutGlb) saveBlob(new Blob([cutGlb], { type: 'model/gltf-binary' }), '-cut.glb');
});
// The UV layout as the server draws it (output "svg"): the same request, another output.
$('svg').addEventListener('click', async () => {
  if (!state.asset || !state.lastParams) return;
  clearError();
  const params = { ...state.lastParams, output: 'svg' };
  try {
    const res = await fetch('/seam', { method: 'POST', body: seamForm(params) });
    if (!res.ok) return showError(await errorOf(res));
    saveBlob(new Blob([await res.text()], { type: 'image/svg+xml' }), '-uv.svg');
  } catch (e) {
    showError({ message: `the request failed: ${e.message}` });
  }
});
view.addEventListener('dragover', (e) => { e.preventDefault(); view.classList.add('drop'); });
view.addEventListener('dragleave', () => view.classList.remove('drop'));
view.addEventListener('drop', (e) => {
  e.preventDefault();
  view.classList.remove('drop');
  const f = e.dataTransfer?.files?.[0];
  if (f) openFile(f);
});

// ---- for the test -------------------------------------------------------------------------------

// Where vertex v of the target primitive is drawn, in CSS pixels of the page (or null when
// it is outside the view).
function vertexScreenPosition(v) {
  if (!inputMesh) return null;
  const p = inputMesh.localToWorld(vertexPosition(v)).project(camera);
  const r = renderer.domElement.getBoundingClientRect();
  if (Math.abs(p.x) > 1 || Math.abs(p.y) > 1) return null;
  return { x: r.left + ((p.x + 1) / 2) * r.width, y: r.top + ((1 - p.y) / 2) * r.height };
}

// The model-space position of vertex v of the target primitive, as the page has it.
const vertexOf = (v) => (inputMesh ? vertexPosition(v).toArray() : null);
// The bytes the page sends as the asset (OBJ and OFF: the GLB it made of them).
const assetBytes = () => (state.asset ? Array.from(state.asset) : null);

window.seamViewer = { state, vertexScreenPosition, vertexOf, assetBytes, render, loadAsset };
resize();
publish();
