#!/usr/bin/env node
// Runs the Khronos glTF-Validator on every file named on the command line.
// Prints one line per file: "<path> errors=<n> warnings=<n>" followed by the error messages,
// and exits with the total number of errors (capped at 100), 0 when all files are valid.
// External resources are refused: the assets we validate must be self-contained.
'use strict';
const fs = require('fs');
const path = require('path');

let validator;
try {
  validator = require(path.join(__dirname, 'node_modules', 'gltf-validator'));
} catch (e) {
  console.error('gltf-validator is not installed: run `npm install --prefix ' + __dirname + '`');
  process.exit(101);
}

async function main() {
  const files = process.argv.slice(2);
  if (files.length === 0) {
    console.error('usage: validate_gltf.js FILE.glb [FILE.gltf ...]');
    process.exit(102);
  }
  let total = 0;
  for (const file of files) {
    const bytes = new Uint8Array(fs.readFileSync(file));
    const report = await validator.validateBytes(bytes, {
      uri: file,
      maxIssues: 100,
      externalResourceFunction: () => Promise.reject(new Error('external resources are not allowed')),
    });
    const issues = report.issues;
    console.log(`${file} errors=${issues.numErrors} warnings=${issues.numWarnings}`);
    for (const m of issues.messages) {
      if (m.severity === 0) console.log(`  error ${m.code} at ${m.pointer || ''}: ${m.message}`);
    }
    total += issues.numErrors;
  }
  process.exit(Math.min(total, 100));
}

main().catch((e) => {
  console.error(String(e));
  process.exit(103);
});
