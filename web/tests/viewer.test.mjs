// End-to-end test of the viewer: the real seamd on a free 127.0.0.1 port, Debian's chromium
// driven headless by playwright-core (no browser download). The page loads with no console
// errors, the sample loads and its seam is drawn (the page's state matches the server's own
// answer to the same request; the screenshot has seam-red and checker pixels), a click on the
// surface adds an extremum and changes the seam, a click on its marker removes it, "hide seam
// from this view" sends hide_from (the page shows the server's answer, error or not), the cut
// GLB downloads, and no request leaves 127.0.0.1.
//   node viewer.test.mjs SEAMD_BINARY OUT_DIR      (exit 77: chromium is not installed)
import { spawn, spawnSync } from 'node:child_process';
import { existsSync, mkdirSync, writeFileSync, readFileSync } from 'node:fs';
import { join } from 'node:path';
import { createInterface } from 'node:readline';
import { isDeepStrictEqual } from 'node:util';
import { decodePng } from './png.mjs';
import { ellipsoid, toObj, toOff } from './fixtures.mjs';

const SKIP = 77;
const chromiumPath = process.env.SEAM_CHROMIUM || '/usr/bin/chromium';
const [seamdPath, outDir] = process.argv.slice(2);
if (!seamdPath || !outDir) {
  console.error('usage: node viewer.test.mjs SEAMD_BINARY OUT_DIR');
  process.exit(2);
}
if (!existsSync(chromiumPath)) {
  console.log(`SKIP: ${chromiumPath} is not installed (scripts/install-deps.sh --test installs chromium)`);
  process.exit(SKIP);
}
const { chromium } = await import('playwright-core');
mkdirSync(outDir, { recursive: true });

let checks = 0;
function check(cond, message) {
  checks += 1;
  if (!cond) throw new Error(`check failed: ${message}`);
  console.log(`ok ${checks} - ${message}`);
}

// ---- seamd ----------------------------------------------------------------------------------------

function startSeamd() {
  const proc = spawn(seamdPath, ['--bind', '127.0.0.1', '--port', '0', '--workers', '2', '--log-level', 'info'],
    { stdio: ['ignore', 'pipe', 'inherit'] });
  return new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error('seamd did not report its port within 20 s')), 20000);
    proc.on('exit', (code) => reject(new Error(`seamd exited with ${code} before listening`)));
    createInterface({ input: proc.stdout }).on('line', (line) => {
      let j;
      try { j = JSON.parse(line); } catch { return; }
      if (j.event === 'listening') {
        clearTimeout(timer);
        resolve({ proc, port: j.port });
      }
    });
  });
}

// The server's own answer to the request the page made (the multipart form the page sends).
async function serverAnswer(base, asset, params) {
  const form = new FormData();
  form.append('mesh', new Blob([asset]), 'asset.glb');
  form.append('params', JSON.stringify(params));
  const res = await fetch(`${base}/seam`, { method: 'POST', body: form });
  return { status: res.status, body: await res.json() };
}

const seamOf = (body) => body.primitives?.[0]?.seam ?? body.seam;

// ---- the page ---------------------------------------------------------------------------------------

const pageState = (page) => page.evaluate(() => {
  const s = window.seamViewer.state;
  return { status: s.status, extrema: [...s.extrema], edges: s.seamEdgeList, requests: s.requests,
    params: s.lastParams, error: s.error, uvTriangles: s.uvTriangles, uvChannel: s.uvChannel };
});

async function waitAnswered(page, requestsBefore) {
  await page.waitForFunction((n) => {
    const s = window.seamViewer.state;
    return s.requests > n && (s.status === 'ready' || s.status === 'error');
  }, requestsBefore, { timeout: 30000 });
  return pageState(page);
}

function countPixels(png, box, pred) {
  let n = 0;
  const x0 = Math.max(0, Math.floor(box.x)), y0 = Math.max(0, Math.floor(box.y));
  const x1 = Math.min(png.width, Math.ceil(box.x + box.width)), y1 = Math.min(png.height, Math.ceil(box.y + box.height));
  for (let y = y0; y < y1; ++y) {
    for (let x = x0; x < x1; ++x) {
      const i = (y * png.width + x) * png.channels;
      if (pred(png.data[i], png.data[i + 1], png.data[i + 2])) n += 1;
    }
  }
  return n;
}
const seamRed = (r, g, b) => r > 180 && g < 90 && b < 90;
const checkerBlue = (r, g, b) => b > 90 && b > r + 50 && b > g + 20;

async function run() {
  const started = Date.now();
  const { proc, port } = await startSeamd();
  const base = `http://127.0.0.1:${port}`;
  const browser = await chromium.launch({
    executablePath: chromiumPath,
    headless: true,
    args: ['--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
      '--disable-quic', '--no-first-run', '--disable-background-networking', '--disable-component-update',
      '--disable-sync'],
  });
  try {
    const context = await browser.newContext({ viewport: { width: 1280, height: 800 }, acceptDownloads: true });
    const page = await context.newPage();
    const requests = [];
    const consoleErrors = [];
    page.on('request', (r) => requests.push(r.url()));
    page.on('console', (m) => { if (m.type() === 'error') consoleErrors.push(m.text()); });
    page.on('pageerror', (e) => consoleErrors.push(`page error: ${e.message}`));

    await page.goto(`${base}/`);
    if ((await page.content()).includes('viewer was not built')) {
      throw new Error('seamd was built without the viewer (node and web/node_modules were missing at configure time)');
    }
    await page.waitForFunction(() => !!window.seamViewer, null, { timeout: 15000 });
    check((await pageState(page)).status === 'empty', 'the page loads and waits for an asset');

    // The sample: loaded, seam computed with automatic extrema, drawn.
    await page.click('#sample');
    const first = await waitAnswered(page, 0);
    check(first.status === 'ready', `the sample's seam is computed (${first.error?.message ?? 'no error'})`);
    check(first.extrema.length >= 2 && first.edges.length > 0, `${first.extrema.length} extrema and ${first.edges.length} seam edges shown`);
    const asset = new Uint8Array(await (await fetch(`${base}/sample.glb`)).arrayBuffer());
    const expected = await serverAnswer(base, asset, first.params);
    check(expected.status === 200, 'the server answers the page\'s request by itself');
    check(isDeepStrictEqual(first.edges, seamOf(expected.body).edges), 'the page draws the edges of the server\'s seam');
    check(isDeepStrictEqual(first.extrema, seamOf(expected.body).extrema), 'the page marks the server\'s extrema');
    check(first.uvChannel >= 0 && first.uvTriangles > 5000, `the checker uses TEXCOORD_${first.uvChannel} of the cut asset (${first.uvTriangles} triangles in the 2D layout)`);

    // The sample's seam runs on its back: orbit half a turn, as a user drags (OrbitControls
    // turns 2*pi per view height of horizontal drag).
    const view = await page.locator('#view3d').boundingBox();
    const drag = [view.x + view.width * 0.3, view.y + view.height * 0.8];
    await page.mouse.move(drag[0], drag[1]);
    await page.mouse.down();
    for (let k = 1; k <= 10; ++k) await page.mouse.move(drag[0] + (k * view.height) / 20, drag[1] - k * 3);
    await page.mouse.up();
    check((await pageState(page)).requests === first.requests, 'a drag orbits the view without adding an extremum');
    const shot = await page.screenshot({ path: join(outDir, 'viewer.png') });
    const png = decodePng(shot);
    const uv2d = await page.locator('#uv2d').boundingBox();
    const red = countPixels(png, view, seamRed);
    const blue = countPixels(png, view, checkerBlue);
    const uvRed = countPixels(png, uv2d, seamRed);
    check(red > 100, `the seam is drawn in the 3D view (${red} seam-red pixels)`);
    check(blue > 5000, `the cut mesh shows the checker (${blue} checker-blue pixels)`);
    check(uvRed > 50, `the 2D layout marks the seam (${uvRed} seam-red pixels)`);

    // A click on the surface (the starfish's body, at the centre of the view) adds an extremum.
    const cx = view.x + view.width / 2 + 7, cy = view.y + view.height / 2 + 5;
    await page.mouse.click(cx, cy);
    const added = await waitAnswered(page, first.requests);
    check(added.status === 'ready', 'the seam is recomputed after a click on the surface');
    const newVertex = added.extrema.find((v) => !first.extrema.includes(v));
    check(added.extrema.length === first.extrema.length + 1 && newVertex !== undefined, `the click added extremum ${newVertex}`);
    check(!isDeepStrictEqual(added.edges, first.edges), `the seam changed (${first.edges.length} -> ${added.edges.length} edges)`);
    const expectedAdded = await serverAnswer(base, asset, added.params);
    check(isDeepStrictEqual(added.edges, seamOf(expectedAdded.body).edges), 'the new seam is the server\'s');
    check(seamOf(expectedAdded.body).extrema.includes(newVertex), 'the new extremum is one the server used');

    // A click on its marker removes it again.
    const at = await page.evaluate((v) => window.seamViewer.vertexScreenPosition(v), newVertex);
    check(at !== null, 'the new marker is in view');
    await page.mouse.click(at.x, at.y);
    const removed = await waitAnswered(page, added.requests);
    check(removed.status === 'ready' && !removed.extrema.includes(newVertex), 'a click on the marker removed the extremum');
    check(isDeepStrictEqual([...removed.extrema].sort(), [...first.extrema].sort()), 'the extrema are the first ones again');
    const expectedRemoved = await serverAnswer(base, asset, removed.params);
    check(isDeepStrictEqual(removed.edges, seamOf(expectedRemoved.body).edges), 'the seam is the server\'s for those extrema');
    check(consoleErrors.length === 0, `no console errors so far (${consoleErrors.join(' | ') || 'none'})`);

    // The cut GLB downloads.
    const [download] = await Promise.all([page.waitForEvent('download'), page.click('#download')]);
    const glb = readFileSync(await download.path());
    check(download.suggestedFilename() === 'sample-cut.glb' && glb.subarray(0, 4).toString() === 'glTF',
      `the cut GLB downloads (${download.suggestedFilename()}, ${glb.length} bytes)`);

    // "UV layout SVG": the same request with output "svg"; the page saves the server's SVG or
    // shows its refusal (a server without output "svg" refuses it).
    const svgExpected = await fetch(`${base}/seam`, { method: 'POST', body: (() => {
      const f = new FormData();
      f.append('mesh', new Blob([asset]), 'asset.glb');
      f.append('params', JSON.stringify({ ...removed.params, output: 'svg' }));
      return f;
    })() });
    const svgText = await svgExpected.text();
    if (svgExpected.status === 200) {
      const [svgDownload] = await Promise.all([page.waitForEvent('download'), page.click('#svg')]);
      const svg = readFileSync(await svgDownload.path(), 'utf8');
      check(svgDownload.suggestedFilename() === 'sample-uv.svg' && svg === svgText && svg.includes('<polygon'),
        `the UV layout SVG downloads (${svg.length} bytes, the server's)`);
    } else {
      await page.click('#svg');
      await page.waitForFunction(() => !document.getElementById('error').hidden, null, { timeout: 30000 });
      const shown = await page.locator('#error').innerText();
      check(shown.includes(JSON.parse(svgText).error.message), `output svg: the server's refusal is shown: "${shown}"`);
    }

    // "Hide seam from this view": the page sends hide_from and shows what the server says.
    await page.click('#hide');
    const hidden = await waitAnswered(page, removed.requests);
    check(Array.isArray(hidden.params.hide_from) && hidden.params.hide_from.length === 1, `hide_from sent: ${JSON.stringify(hidden.params.hide_from)}`);
    const expectedHidden = await serverAnswer(base, asset, hidden.params);
    if (expectedHidden.status === 200) {
      check(hidden.status === 'ready' && isDeepStrictEqual(hidden.edges, seamOf(expectedHidden.body).edges), 'the seam hidden from the view is the server\'s');
    } else {
      const shown = await page.locator('#error').innerText();
      check(hidden.status === 'error' && shown.includes(expectedHidden.body.error.message),
        `the server's refusal is shown: "${shown}"`);
    }

    // A dropped file: the cut sample as a Draco-compressed GLB (decoded by the page's
    // WebAssembly Draco decoder, sent as it is to the server).
    const dracoRes = await fetch(`${base}/seam?extrema=auto&method=mst&uv=none&draco=true&output=glb`,
      { method: 'POST', headers: { 'Content-Type': 'model/gltf-binary' }, body: asset });
    const dracoGlb = new Uint8Array(await dracoRes.arrayBuffer());
    check(dracoRes.status === 200 && Buffer.from(dracoGlb).includes('KHR_draco_mesh_compression'), `a Draco GLB to open (${dracoGlb.length} bytes)`);
    await page.setInputFiles('#file', { name: 'starfish-draco.glb', mimeType: 'model/gltf-binary', buffer: Buffer.from(dracoGlb) });
    const opened = await waitAnswered(page, hidden.requests);
    check(opened.status === 'ready', `the Draco GLB is shown and cut (${opened.error?.message ?? 'no error'})`);
    const expectedOpened = await serverAnswer(base, dracoGlb, opened.params);
    check(opened.edges.length > 0 && isDeepStrictEqual(opened.edges, seamOf(expectedOpened.body).edges), `its seam is the server's (${opened.edges.length} edges)`);

    // OFF, OBJ (made into a GLB by the page) and raw Draco files.
    const shape = ellipsoid();
    const files = [['ellipsoid.off', Buffer.from(toOff(shape))], ['ellipsoid.obj', Buffer.from(toObj(shape))]];
    const objPath = join(outDir, 'ellipsoid.obj'), drcPath = join(outDir, 'ellipsoid.drc');
    writeFileSync(objPath, toObj(shape));
    const encoded = spawnSync('draco_encoder', ['-i', objPath, '-o', drcPath], { encoding: 'utf8' });
    if (encoded.status === 0) files.push(['ellipsoid.drc', readFileSync(drcPath)]);
    else console.log('# draco_encoder (Debian package draco) not found: the raw .drc case is not checked');
    let last = opened;
    for (const [name, bytes] of files) {
      await page.setInputFiles('#file', { name, mimeType: 'application/octet-stream', buffer: bytes });
      const shown = await waitAnswered(page, last.requests);
      last = shown;
      check(shown.status === 'ready' && shown.extrema.length === 2, `${name}: shown and cut, extrema ${JSON.stringify(shown.extrema)} (${shown.error?.message ?? 'no error'})`);
      const sent = new Uint8Array(await page.evaluate(() => window.seamViewer.assetBytes()));
      const answer = await serverAnswer(base, sent, shown.params);
      check(isDeepStrictEqual(shown.edges, seamOf(answer.body).edges), `${name}: the seam is the server's (${shown.edges.length} edges)`);
      // The extrema lie at the two tips (|x| near 3), and for OFF the page keeps the file's numbering.
      const at = await page.evaluate((vs) => vs.map((v) => window.seamViewer.vertexOf(v)), shown.extrema);
      check(at.every((p) => Math.abs(p[0]) > 2.5) && at[0][0] * at[1][0] < 0, `${name}: one extremum at each tip`);
      if (name.endsWith('.off')) {
        check(shown.extrema.every((v, k) => shape.v[v].every((x, c) => Math.abs(x - at[k][c]) < 1e-6)), 'ellipsoid.off: extrema are the file\'s vertex indices');
      }
    }

    const foreign = requests.filter((u) => !u.startsWith(`${base}/`) && !u.startsWith('data:') && !u.startsWith('blob:'));
    check(foreign.length === 0, `every request went to ${base} (${requests.length} requests${foreign.length ? `; foreign: ${foreign.join(', ')}` : ''})`);
    const unexpected = consoleErrors.filter((m) => !/status of 400/.test(m));
    check(unexpected.length === 0, `no console errors but the refused request's (${unexpected.join(' | ') || 'none'})`);
    writeFileSync(join(outDir, 'viewer-state.json'), JSON.stringify({ first, added, removed, hidden, opened, last }, null, 1));
    console.log(`viewer test: ${checks} checks passed in ${((Date.now() - started) / 1000).toFixed(1)} s; screenshot ${join(outDir, 'viewer.png')}`);
  } finally {
    await browser.close();
    proc.kill('SIGTERM');
  }
}

run().catch((e) => {
  console.error(`FAIL ${e.stack || e.message}`);
  process.exit(1);
});
