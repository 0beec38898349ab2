#!/usr/bin/env node
// Applies patches/rp2040js+<version>.patch (a plain unified diff against the
// published package) to node_modules/rp2040js. Runs as the `postinstall` script,
// so `npm ci` / `npm install` leave a patched emulator behind.
//
// Each hunk must match exactly once (its context and removed lines); a hunk whose
// result is already in the file is skipped, so running this twice is harmless. Any
// mismatch (another rp2040js version, a changed file) fails loudly instead of
// leaving a half-patched emulator.
import { readFileSync, writeFileSync, existsSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = join(dirname(fileURLToPath(import.meta.url)), '..');
const pkgDir = join(root, 'node_modules', 'rp2040js');
if (!existsSync(pkgDir)) {
  console.error('apply-patch: node_modules/rp2040js is missing (run npm ci)');
  process.exit(1);
}
const { version } = JSON.parse(readFileSync(join(pkgDir, 'package.json'), 'utf8'));
const patchFile = join(root, 'patches', `rp2040js+${version}.patch`);
if (!existsSync(patchFile)) {
  console.error(`apply-patch: no patch for rp2040js ${version} (expected ${patchFile})`);
  process.exit(1);
}

/** Parses a unified diff into [{ file, hunks: [{ oldLines, newLines }] }]. */
function parseDiff(text) {
  const files = [];
  let file = null;
  let hunk = null;
  for (const line of text.split('\n')) {
    if (line.startsWith('--- ')) {
      continue;
    } else if (line.startsWith('+++ ')) {
      file = { file: line.slice(4).trim().replace(/^b\//, ''), hunks: [] };
      files.push(file);
      hunk = null;
    } else if (line.startsWith('@@')) {
      hunk = { oldLines: [], newLines: [] };
      file.hunks.push(hunk);
    } else if (hunk) {
      const body = line.slice(1);
      if (line.startsWith(' ')) {
        hunk.oldLines.push(body);
        hunk.newLines.push(body);
      } else if (line.startsWith('-')) {
        hunk.oldLines.push(body);
      } else if (line.startsWith('+')) {
        hunk.newLines.push(body);
      }
    }
  }
  return files;
}

function countOccurrences(haystack, needle) {
  let count = 0;
  for (let at = haystack.indexOf(needle); at >= 0; at = haystack.indexOf(needle, at + 1)) {
    count++;
  }
  return count;
}

let applied = 0;
let skipped = 0;
for (const { file, hunks } of parseDiff(readFileSync(patchFile, 'utf8'))) {
  const path = join(pkgDir, file);
  let source = readFileSync(path, 'utf8');
  for (const { oldLines, newLines } of hunks) {
    const before = oldLines.join('\n');
    const after = newLines.join('\n');
    if (countOccurrences(source, after) === 1 && countOccurrences(source, before) === 0) {
      skipped++;
      continue;
    }
    const found = countOccurrences(source, before);
    if (found !== 1) {
      console.error(`apply-patch: hunk does not apply to ${file} (context found ${found} times)`);
      process.exit(1);
    }
    source = source.replace(before, () => after);
    applied++;
  }
  writeFileSync(path, source);
}
console.log(`apply-patch: rp2040js ${version}: ${applied} hunk(s) applied, ${skipped} already applied`);
