// glTF-Validator (Khronos, npm gltf-validator) on every GLB of an exported tileset folder:
// `node validate_gltf.mjs DIR` prints one line per GLB with errors and a summary; exit 0 when no
// GLB has an error, 1 otherwise, 77 (skip) when the npm packages are not installed (npm ci).
// The validator does not decode Draco payloads (KHR_draco_mesh_compression is reported as an
// unsupported extension, an info): the C++ tests decode every exported mesh instead.
import fs from 'node:fs';
import path from 'node:path';

let validator;
try {
  validator = await import('gltf-validator');
} catch {
  console.log('validate_gltf: gltf-validator not installed (cd tests/export && npm ci): skipped');
  process.exit(77);
}

const dir = process.argv[2];
if (!dir) {
  console.error('usage: node validate_gltf.mjs TILESET_DIR');
  process.exit(2);
}
const files = [];
const walk = (d) => {
  for (const e of fs.readdirSync(d, { withFileTypes: true })) {
    const p = path.join(d, e.name);
    if (e.isDirectory()) walk(p);
    else if (e.name.endsWith('.glb')) files.push(p);
  }
};
walk(dir);
if (files.length === 0) {
  console.error(`validate_gltf: ${dir}: no GLB found`);
  process.exit(1);
}
let errors = 0, warnings = 0, failed = 0;
const messages = new Map();
for (const file of files) {
  const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
    uri: file,
    externalResourceFunction: () => Promise.reject(new Error('external resources are not allowed')),
  });
  errors += report.issues.numErrors;
  warnings += report.issues.numWarnings;
  for (const m of report.issues.messages) {
    if (m.severity > 1) continue;  // 0 error, 1 warning, 2 info, 3 hint
    const key = `${m.severity === 0 ? 'error' : 'warning'} ${m.code}: ${m.message}`;
    messages.set(key, (messages.get(key) || 0) + 1);
  }
  if (report.issues.numErrors > 0) {
    failed += 1;
    if (failed <= 5) console.log(`${file}: ${report.issues.numErrors} error(s)`);
  }
}
for (const [key, count] of messages) console.log(`  ${key} (${count} GLBs)`);
console.log(`validate_gltf: ${files.length} GLBs, ${errors} errors, ${warnings} warnings, ${failed} GLBs with errors`);
process.exit(errors === 0 ? 0 : 1);
