// The CalculiX crash boxes of ../shared/data built with the dynpm CLI (DYNPM_CLI), lossless,
// once per test run (into DYNPM_TEST_OUT/selective), for the selective-refinement tests:
// crashbox-mixed-5k (quads and a few triangles, crushed) and crashbox-fields (19 % triangles,
// bent, with node fields PEEQ and others).
import { execFileSync } from 'node:child_process';
import { existsSync, mkdirSync, readFileSync, statSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { gunzipSync } from 'node:zlib';

import { readDpm } from '../src/dpm.js';

export const cli = process.env.DYNPM_CLI;
const out = join(process.env.DYNPM_TEST_OUT ?? tmpdir(), 'selective');
const data = (path) => fileURLToPath(new URL(`../../../shared/data/${path}`, import.meta.url));

const INPUTS = {
  'crashbox-mixed-5k': () => data('crashbox-mixed-5k/obj/frame_*.obj'),
  'crashbox-fields': () => {
    const frd = join(out, 'crashbox-fields.frd');
    if (!existsSync(frd)) writeFileSync(frd, gunzipSync(readFileSync(data('crashbox-fields/crashbox-fields.frd.gz'))));
    return frd;
  },
};

// The .dpm's path, built if it is not there yet or older than the CLI (a build folder kept
// across a format change would otherwise hand the tests a file of the previous version).
// quantized: built without --lossless (positions on the file's grid).
export function crashboxDpm(name, { quantized = false } = {}) {
  if (!cli) throw new Error('selective tests need DYNPM_CLI (the dynpm binary)');
  mkdirSync(out, { recursive: true });
  const path = join(out, `${name}${quantized ? '-quantized' : ''}.dpm`);
  const stale = !existsSync(path) || statSync(path).mtimeMs < statSync(cli).mtimeMs;
  if (stale) execFileSync(cli, ['build', INPUTS[name](), '-o', path, ...(quantized ? [] : ['--lossless']), '--quiet'], { stdio: 'pipe' });
  return path;
}

// The decoded mesh (every split loaded).
export function crashbox(name, options) {
  const path = crashboxDpm(name, options);
  return readDpm(new Uint8Array(readFileSync(path)), path).mesh;
}

export const CRASHBOXES = Object.keys(INPUTS);
