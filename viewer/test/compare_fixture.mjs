// Models to compare, built from the shipped sample (DYNPM_SAMPLE_DIR) by the dynpm CLI
// (DYNPM_CLI) into DYNPM_TEST_OUT/compare, once per CLI build:
//   fine.dpm    the default position grid (within 3.8e-6 of the diagonal)
//   coarse.dpm  a coarse grid (--position-error 1e-3: within 0.4 model units). The hierarchy is
//               computed from the input's floats before positions are put on a grid
//               (src/pipeline/build.cpp), so both files hold one hierarchy and differ only in
//               their positions' quantization, which bounds their difference.
//   keys3.dpm   other key steps (--key-steps auto:3): another hierarchy of the same input.
import { execFileSync } from 'node:child_process';
import { existsSync, mkdirSync, readFileSync, statSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';

import { readDpm } from '../src/dpm.js';

export const cli = process.env.DYNPM_CLI;
const out = join(process.env.DYNPM_TEST_OUT ?? tmpdir(), 'compare');
export const COARSE_POSITION_ERROR = 1e-3;  // in diagonals
const FLAGS = {
  fine: [],
  coarse: ['--position-error', String(COARSE_POSITION_ERROR)],
  keys3: ['--key-steps', 'auto:3'],
};

export function compareDpm(name) {
  const sample = process.env.DYNPM_SAMPLE_DIR;
  if (!cli || !sample) throw new Error('the compare tests need DYNPM_CLI and DYNPM_SAMPLE_DIR');
  mkdirSync(out, { recursive: true });
  const path = join(out, `${name}.dpm`);
  if (!existsSync(path) || statSync(path).mtimeMs < statSync(cli).mtimeMs)
    execFileSync(cli, ['build', join(sample, 'frame_*.obj'), '-o', path, '--quiet', ...FLAGS[name]], { stdio: 'pipe' });
  return path;
}

export function compareMesh(name) {
  const path = compareDpm(name);
  return readDpm(new Uint8Array(readFileSync(path)), path).mesh;
}

export const outDir = out;
