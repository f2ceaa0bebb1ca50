#!/usr/bin/env node
// The Khronos glTF-Validator's report on each file named, as one JSON line per file:
// {"file", "errors", "warnings", "unused": [pointers of UNUSED_OBJECT], "messages": [errors]}.
// tests/api/asset_set_test.cpp compares a cut asset's unused objects with its input's (the
// plain tests/validate_gltf.js prints only the errors). External resources are refused.
import { createRequire } from 'node:module';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const require = createRequire(import.meta.url);
const here = path.dirname(fileURLToPath(import.meta.url));
let validator;
try {
  validator = require(path.join(here, '..', 'node_modules', 'gltf-validator'));
} catch {
  console.error('gltf-validator is not installed: run `npm install --prefix ' + path.join(here, '..') + '`');
  process.exit(101);
}

for (const file of process.argv.slice(2)) {
  const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
    maxIssues: 10000,
    externalResourceFunction: () => Promise.reject(new Error('external resources are not allowed')),
  });
  const messages = report.issues.messages;
  console.log(
    JSON.stringify({
      file,
      errors: report.issues.numErrors,
      warnings: report.issues.numWarnings,
      unused: messages.filter((m) => m.code === 'UNUSED_OBJECT').map((m) => m.pointer),
      messages: messages.filter((m) => m.severity === 0).map((m) => `${m.code} at ${m.pointer}: ${m.message}`),
    }),
  );
}
