// Both decoders' verdicts on a .dpm, to compare them (conformance.test.mjs, differential_fuzz.mjs):
// the C++ reader through `dynpm info --json` or tests/dpm_verdicts (many files in one process),
// dpm.js through decodeDpm, a Navigator and a SelectiveNavigator.
import assert from 'node:assert/strict';
import { execFile, execFileSync } from 'node:child_process';

import { decompress } from 'fzstd';

import { decodeDpm, Navigator } from '../src/dpm.js';
import { SelectiveNavigator } from '../src/dpm/selective_navigator.js';
import { SplitDependencies } from '../src/dpm/split_dependencies.js';

// What both compare of an accepted file (the names of `dynpm info --json`).
export const COUNTS = ['complete', 'vertices', 'faces', 'vertices_present', 'faces_present',
  'quads_present', 'triangles_present', 'base_vertices', 'base_faces', 'splits', 'steps',
  'key_steps', 'fields', 'parts', 'lossless'];
export const byteOf = (message) => Number(/: byte (\d+):/.exec(message)?.[1] ?? NaN);

// options: the decoder's (`positions`).
export function jsVerdict(bytes, options = {}) {
  let mesh, complete;
  try {
    ({ mesh, complete } = decodeDpm(bytes, 'x.dpm', options));
  } catch (e) {
    if (e.constructor.name !== 'DpmError') throw e;  // a crash is a difference, shown as one
    return { byte: byteOf(e.message), message: e.message };
  }
  const h = mesh.head;
  const nav = new Navigator(mesh);
  nav.setLevel(mesh.splitsLoaded);
  const parts = new Set(mesh.partId.subarray(0, nav.faceCount));
  return {
    counts: {
      complete,
      vertices: h.vertexCount,
      faces: h.faceCount,
      vertices_present: mesh.vertexCountLoaded,
      faces_present: nav.faceCount,
      quads_present: nav.quadCount,
      triangles_present: nav.triangleCount,
      base_vertices: h.baseVertexCount,
      base_faces: h.baseFaceCount,
      splits: mesh.splitsLoaded,
      steps: h.stepCount,
      key_steps: h.keySteps.length,
      fields: mesh.fields.length,
      parts: parts.size,
      lossless: mesh.lossless,
    },
    fieldList: fieldList(mesh, nav),
    selective: selectiveCounts(mesh),
    values: valuesHash(mesh, nav),
    partList: [...mesh.partNames].map(([id, name]) => `${id}:${escaped(new TextEncoder().encode(name))}`).join(','),
  };
}

// As dpm_verdicts prints it: NAME:LOCATION:COUNT per field (bytes of the name other than
// A-Z a-z 0-9 _ . - as %XX), COUNT the values per step present.
const escaped = (bytes) => Array.from(bytes, (c) =>
  /[A-Za-z0-9_.-]/.test(String.fromCharCode(c)) ? String.fromCharCode(c) : `%${c.toString(16).toUpperCase().padStart(2, '0')}`).join('');
function fieldList(mesh, nav) {
  return mesh.fields.map((f) =>
    `${escaped(f.nameBytes)}:${f.perFace ? 'element' : 'node'}:${f.perFace ? nav.faceCount : nav.vertexCount}`).join(',');
}

// As dpm_verdicts' selective_counts(): vertices/faces/quads of the selective navigator's mesh
// for every other split (closed), the first half, and the last split with what it needs.
function selectiveCounts(mesh) {
  const n = mesh.splitsLoaded;
  const deps = new SplitDependencies(mesh).update();
  const nav = new SelectiveNavigator(mesh, deps);
  const show = (wanted) => {
    nav.setTarget(wanted);
    const { vertices, faces } = nav.activeMesh();
    let quads = 0;
    for (let k = 3; k < faces.length; k += 4) quads += faces[k] >= 0 ? 1 : 0;
    return `${vertices.length}/${faces.length / 4}/${quads}`;
  };
  const odd = [];
  for (let i = 1; i < n; i += 2) odd.push(i);
  const half = new Uint8Array(mesh.head.splitCount).fill(1, 0, Math.floor(n / 2));
  const last = new Uint8Array(mesh.head.splitCount);
  if (n > 0) deps.addWithDependencies(n - 1, last);
  return [deps.close(odd, new Uint8Array(mesh.head.splitCount)), half, last].map(show).join(',');
}

// As dpm_verdicts' values_hash(): FNV-1a over the float bits of every present vertex's position
// at the last step T, then of each field's values there, then over the node and element ids as
// int64, as hex, "@T"; "-" without steps.
function valuesHash(mesh, nav) {
  const steps = mesh.head.stepCount;
  if (steps === 0) return '-';
  const t = steps - 1, n = mesh.vertexCountLoaded;
  let hash = 2166136261;
  const add = (floats) => {
    for (const b of new Uint8Array(floats.buffer, floats.byteOffset, floats.byteLength))
      hash = Math.imul(hash ^ b, 16777619) >>> 0;
  };
  add(mesh.positionsAt(t, n, new Float32Array(3 * n)));
  for (const f of mesh.fields) add(f.valuesAt(t, f.perFace ? nav.faceCount : nav.vertexCount));
  for (const [ids, count] of [[mesh.nodeId, nav.vertexCount], [mesh.elementId, nav.faceCount]])
    add(BigInt64Array.from(ids.subarray(0, count), (id) => BigInt(id)));
  return `${hash.toString(16).padStart(8, '0')}@${t}`;
}

// `dynpm info --json FILE` (cli: the dynpm binary).
export function cliVerdict(cli, path) {
  return new Promise((resolve) => {
    execFile(cli, ['info', '--json', path], (error, stdout, stderr) => {
      if (error?.code === 1) return resolve({ byte: byteOf(stderr), message: stderr.trim() });
      assert.equal(error, null, `dynpm info ${path}: ${stderr}`);
      const j = JSON.parse(stdout);
      const counts = {};
      for (const key of COUNTS) counts[key] = j[key];
      counts.key_steps = j.key_steps.length;
      counts.fields = j.fields.length;
      resolve({ counts });
    });
  });
}

// `dpm_verdicts FILE...` (tool: tests/dpm_verdicts): a line per file, "error MESSAGE" or
// "counts name=value …".
export function toolVerdicts(tool, paths) {
  const lines = execFileSync(tool, paths, { encoding: 'utf8', maxBuffer: 1 << 26 }).split('\n');
  assert.equal(lines.length, paths.length + 1, 'dpm_verdicts prints one line per file');
  return paths.map((_, k) => {
    const [kind, ...rest] = lines[k].split(' ');
    if (kind === 'error') return { byte: byteOf(lines[k]), message: rest.join(' ') };
    const counts = {};
    for (const pair of rest) {
      const [key, value] = pair.split('=');
      counts[key] = key === 'complete' || key === 'lossless' ? value === '1' : key.endsWith('_list') || key === 'selective' || key === 'values' ? value : Number(value);
    }
    return { counts: Object.fromEntries(COUNTS.map((key) => [key, counts[key]])), fieldList: counts.field_list, partList: counts.part_list, selective: counts.selective, values: counts.values };
  });
}

// The chunks of a file that has its magic and version: [{at, tag, flags, stored, raw, payload}].
export function chunksOf(bytes) {
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  const chunks = [];
  for (let at = 12; at + 24 <= bytes.length; ) {
    const stored = view.getUint32(at + 8, true);
    const tag = String.fromCharCode(...bytes.subarray(at, at + 4));
    const body = bytes.subarray(at + 24, at + 24 + stored);
    const flags = view.getUint32(at + 4, true);
    chunks.push({ at, tag, flags, payload: flags & 1 ? decompress(body) : body });
    at += 24 + stored;
  }
  return chunks;
}

export function concat(parts) {
  const out = new Uint8Array(parts.reduce((n, p) => n + p.length, 0));
  let at = 0;
  for (const p of parts) out.set(p, at), (at += p.length);
  return out;
}

// The C++ verdict and dpm.js's agree: the same counts (fields, parts, selective meshes where
// the C++ side gave them), or a refusal at the same byte.
export function same(cpp, js) {
  if (cpp.counts && cpp.selective !== undefined && cpp.selective !== js.selective) return false;
  if (cpp.counts && cpp.values !== undefined && cpp.values !== js.values) return false;
  if (cpp.counts && cpp.fieldList !== undefined && cpp.fieldList !== js.fieldList) return false;
  if (cpp.counts && cpp.partList !== undefined && cpp.partList !== js.partList) return false;
  if (cpp.counts) return JSON.stringify(js.counts) === JSON.stringify(cpp.counts);
  return !Number.isNaN(cpp.byte) && js.byte === cpp.byte;
}

export function jsVerdictOrCrash(bytes, options = {}) {
  try {
    return jsVerdict(bytes, options);
  } catch (e) {
    return { crash: `${e.constructor.name}: ${e.message}` };
  }
}
