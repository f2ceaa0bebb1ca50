// Bundles the viewer (src/viewer.js with three.js from node_modules) into one script and
// copies the page and its stylesheet next to it: `node build.mjs OUT_DIR`. Runs offline:
// everything comes from node_modules (npm ci --prefix web). CMake runs it at build time and
// embeds OUT_DIR's files into seamd (server/web_assets.cmake).
import { build } from 'esbuild';
import { copyFileSync, mkdirSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
const out = process.argv[2];
if (!out) {
  console.error('usage: node build.mjs OUT_DIR');
  process.exit(2);
}
mkdirSync(out, { recursive: true });
await build({
  entryPoints: [join(here, 'src', 'viewer.js')],
  bundle: true,
  minify: true,
  format: 'esm', // a module script: three's loaders use import.meta.url
  target: ['es2020'],
  legalComments: 'eof',
  outfile: join(out, 'viewer.js'),
  logLevel: 'warning',
});
for (const f of ['index.html', 'viewer.css']) copyFileSync(join(here, 'src', f), join(out, f));
// three's Draco decoder (WebAssembly), which DRACOLoader runs in a worker: for .drc files and
// GLBs with KHR_draco_mesh_compression.
const draco = join(here, 'node_modules', 'three', 'examples', 'jsm', 'libs', 'draco');
mkdirSync(join(out, 'draco'), { recursive: true });
for (const f of ['draco_wasm_wrapper.js', 'draco_decoder.wasm']) copyFileSync(join(draco, f), join(out, 'draco', f));
