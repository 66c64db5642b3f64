#!/usr/bin/env node
// Validates glTF 2.0 files (.glb or .gltf) with the Khronos glTF-Validator (npm package
// gltf-validator, installed into out/npm by tools/setup.sh).
//
//   node tools/validate_gltf.mjs [--max-warnings N] FILE...
//
// For each file it prints one summary line, then one line per error and per warning (at most
// N warnings per file, default 20; errors are never cut):
//
//   <file>: <E> errors, <W> warnings
//     error <CODE> <json pointer>: <message>
//     warning <CODE> <json pointer>: <message>
//
// The summary line is what tests/support/gltf_validator.cpp parses; keep its shape.
// External resources of a .gltf (buffers, images) are read relative to the file.
// Exit codes: 0 every file valid (warnings allowed); 1 some file has errors; 2 usage error or a
// file could not be read / recognised; 3 the gltf-validator package is not installed.
import { createRequire } from 'node:module';
import { readFile } from 'node:fs/promises';
import { existsSync } from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const scriptDir = path.dirname(fileURLToPath(import.meta.url));

// The package: $SYLVA_NPM_DIR/node_modules, then out/npm/node_modules beside the repository
// root, then Node's normal resolution (NODE_PATH, global installs).
function loadValidator() {
  const candidates = [];
  if (process.env.SYLVA_NPM_DIR) candidates.push(path.join(process.env.SYLVA_NPM_DIR, 'node_modules'));
  candidates.push(path.join(scriptDir, '..', 'out', 'npm', 'node_modules'));
  const require = createRequire(import.meta.url);
  for (const dir of candidates) {
    const entry = path.join(dir, 'gltf-validator');
    if (existsSync(entry)) return require(entry);
  }
  try {
    return require('gltf-validator');
  } catch {
    return null;
  }
}

function usage() {
  process.stderr.write('usage: node tools/validate_gltf.mjs [--max-warnings N] FILE...\n');
  process.exit(2);
}

const args = process.argv.slice(2);
let maxWarnings = 20;
const files = [];
for (let i = 0; i < args.length; ++i) {
  if (args[i] === '--max-warnings') {
    maxWarnings = Number.parseInt(args[++i] ?? '', 10);
    if (!Number.isFinite(maxWarnings) || maxWarnings < 0) usage();
  } else if (args[i].startsWith('--')) {
    usage();
  } else {
    files.push(args[i]);
  }
}
if (files.length === 0) usage();

const validator = loadValidator();
if (!validator) {
  process.stderr.write('validate_gltf: the npm package gltf-validator is not installed (run tools/setup.sh)\n');
  process.exit(3);
}

function issueLine(kind, m) {
  const where = m.pointer ? ` ${m.pointer}` : '';
  return `  ${kind} ${m.code}${where}: ${m.message}`;
}

let anyErrors = false;
let anyBroken = false;
for (const file of files) {
  let bytes;
  try {
    bytes = new Uint8Array(await readFile(file));
  } catch (e) {
    process.stdout.write(`${file}: cannot read: ${e.message}\n`);
    anyBroken = true;
    continue;
  }
  const dir = path.dirname(path.resolve(file));
  let report;
  try {
    report = await validator.validateBytes(bytes, {
      uri: path.basename(file),
      maxIssues: 0,
      writeTimestamp: false,
      externalResourceFunction: async (uri) =>
        new Uint8Array(await readFile(path.resolve(dir, decodeURIComponent(uri)))),
    });
  } catch (e) {
    process.stdout.write(`${file}: not a glTF file the validator can read: ${e}\n`);
    anyBroken = true;
    continue;
  }
  const messages = report.issues.messages ?? [];
  const errors = messages.filter((m) => m.severity === 0);
  const warnings = messages.filter((m) => m.severity === 1);
  process.stdout.write(`${file}: ${report.issues.numErrors} errors, ${report.issues.numWarnings} warnings\n`);
  for (const m of errors) process.stdout.write(issueLine('error', m) + '\n');
  for (const m of warnings.slice(0, maxWarnings)) process.stdout.write(issueLine('warning', m) + '\n');
  if (warnings.length > maxWarnings) process.stdout.write(`  (${warnings.length - maxWarnings} more warnings)\n`);
  if (report.issues.numErrors > 0) anyErrors = true;
}
process.exit(anyBroken ? 2 : anyErrors ? 1 : 0);
