// Validates api/openapi.json with @apidevtools/swagger-parser (offline: the document has only
// internal $refs) and checks that it names every error code of api/error.cpp with the status
// error.cpp maps it to, and every parameter params.cpp accepts.
//   node validate_openapi.mjs OPENAPI_JSON ERROR_CPP PARAMS_CPP
import SwaggerParser from '@apidevtools/swagger-parser';
import { readFileSync } from 'node:fs';

const [file, errorCpp, paramsCpp] = process.argv.slice(2);
const failures = [];
const fail = (m) => failures.push(m);

const doc = JSON.parse(readFileSync(file, 'utf8'));
try {
  // validate() dereferences a copy and checks the document against the OpenAPI 3.1 schema.
  await SwaggerParser.validate(structuredClone(doc), { resolve: { external: false, http: false } });
} catch (e) {
  fail(`swagger-parser: ${e.message}`);
}

// Every ApiErrorCode: the code_name switch and the http_status switch of api/error.cpp.
const src = readFileSync(errorCpp, 'utf8');
const names = new Map([...src.matchAll(/case ApiErrorCode::(k\w+): return "(\w+)";/g)].map((m) => [m[1], m[2]]));
const statusSrc = src.slice(src.indexOf('int http_status('));
const statusOf = new Map();
let pending = [];
for (const m of statusSrc.matchAll(/case ApiErrorCode::(k\w+):(?:\s*return (\d+);)?/g)) {
  pending.push(m[1]);
  if (m[2]) {
    pending.forEach((k) => statusOf.set(k, Number(m[2])));
    pending = [];
  }
}
if (names.size < 20) fail(`found only ${names.size} error codes in ${errorCpp}: has its format changed?`);
const enumCodes = doc.components.schemas.Error.properties.error.properties.code.enum;
const table = doc.info['x-error-codes'];
for (const [k, name] of names) {
  if (!enumCodes.includes(name)) fail(`error code ${name} (${k}) is not in Error.code's enum`);
  if (table[name] !== statusOf.get(k)) fail(`error code ${name}: status ${table[name]} in the document, ${statusOf.get(k)} in error.cpp`);
  const status = statusOf.get(k);
  if (status !== 499 && !JSON.stringify(doc.components.responses[`E${status}`] ?? {}).includes(name)) {
    fail(`error code ${name} is not described in the ${status} response`);
  }
}
for (const name of enumCodes) if (![...names.values()].includes(name)) fail(`the document names ${name}, which error.cpp does not`);

// Every parameter name params.cpp accepts: the names of its parameter_setters() table.
const params = readFileSync(paramsCpp, 'utf8');
const setterTable = params.slice(params.indexOf('parameter_setters() {'), params.indexOf('return setters;'));
const known = [...setterTable.matchAll(/\{"([a-z_]+)", \[\]\(SeamParams/g)].map((m) => m[1]);
if (known.length < 10) fail(`found ${known.length} parameters in ${paramsCpp}'s parameter_setters(): has its format changed?`);
const documented = Object.keys(doc.components.schemas.SeamParams.properties);
for (const p of known) {
  if (!documented.includes(p)) fail(`parameter ${p} (accepted by params.cpp) is not in SeamParams`);
}

// Every route the server registers is a path of the document.
for (const route of ['/seam', '/', '/viewer.js', '/viewer.css', '/draco/draco_wasm_wrapper.js', '/draco/draco_decoder.wasm', '/sample.glb', '/openapi.json', '/healthz', '/readyz', '/metrics', '/version']) {
  if (!doc.paths[route]) fail(`route ${route} is not documented`);
}

if (failures.length) {
  console.error(failures.map((f) => `FAIL ${f}`).join('\n'));
  process.exit(1);
}
console.log(`openapi: valid OpenAPI ${doc.openapi}; ${names.size} error codes, ${documented.length} parameters, ${Object.keys(doc.paths).length} paths`);
