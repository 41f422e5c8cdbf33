#!/usr/bin/env node
// Validates GLB files with the Khronos glTF validator (npm package `gltf-validator`).
// Usage: node tests/validate-gltf.mjs FILE.glb [FILE.glb ...]
// Prints a summary per file and exits 1 if any file has errors (warnings and infos are
// reported but allowed), 2 if the validator itself is missing or a file cannot be read.
import { readFile } from 'node:fs/promises';
import { basename } from 'node:path';

let validator;
try {
  validator = await import('gltf-validator');
} catch (e) {
  console.error('gltf-validator is not installed: run `npm ci` at the repository root');
  process.exit(2);
}
const validateBytes = validator.validateBytes ?? validator.default?.validateBytes;

const files = process.argv.slice(2);
if (files.length === 0) {
  console.error('usage: node tests/validate-gltf.mjs FILE.glb [FILE.glb ...]');
  process.exit(2);
}

let failed = false;
for (const file of files) {
  let bytes;
  try {
    bytes = new Uint8Array(await readFile(file));
  } catch (e) {
    console.error(`${file}: cannot read: ${e.message}`);
    process.exit(2);
  }
  const report = await validateBytes(bytes, { uri: basename(file), maxIssues: 100 });
  const { numErrors, numWarnings, numInfos, numHints } = report.issues;
  console.log(
    `${file}: ${numErrors} errors, ${numWarnings} warnings, ${numInfos} infos, ${numHints} hints`,
  );
  for (const m of report.issues.messages) {
    const sev = ['error', 'warning', 'info', 'hint'][m.severity] ?? m.severity;
    console.log(`  [${sev}] ${m.code} ${m.pointer ?? ''}: ${m.message}`);
  }
  if (numErrors > 0) failed = true;
}
process.exit(failed ? 1 : 0);
