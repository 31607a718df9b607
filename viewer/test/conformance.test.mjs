// Both decoders give every .dpm the same verdict: the C++ reader (`dynpm info --json`, and
// tests/dpm_verdicts.cpp for the mutants, in one process) and dpm.js (decodeDpm) either accept
// a file with the same counts, or reject it at the same byte (the "byte N" of both messages). The files: every .dpm of fuzz/regressions/dpm/,
// fuzz/corpus/dpm/ and tests/bad/, and mutants of the small corpus files made here — chunks
// stored uncompressed (so that records can be changed), files cut at and around every chunk
// boundary, and single bytes changed in every chunk header and in the payloads (checksums
// fixed, so that the payload checks are reached).
import assert from 'node:assert/strict';
import { execFile, execFileSync } from 'node:child_process';
import { mkdirSync, readdirSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { test } from 'node:test';
import { crc32 } from 'node:zlib';

import { decompress } from 'fzstd';

import { decodeDpm, Navigator } from '../src/dpm.js';

const CLI = process.env.DYNPM_CLI;
const TOOL = process.env.DYNPM_VERDICTS;
const OUT = join(process.env.DYNPM_TEST_OUT ?? tmpdir(), 'conformance');
const ROOT = new URL('../../', import.meta.url).pathname;

function dpmFiles(folder) {
  return readdirSync(join(ROOT, folder))
    .filter((f) => f.endsWith('.dpm'))
    .sort()
    .map((f) => ({ name: `${folder}/${f}`, bytes: readFileSync(join(ROOT, folder, f)) }))
    .map(({ name, bytes }) => ({ name, bytes: new Uint8Array(bytes) }));
}

// ---------------------------------------------------------------------------------------------
// Verdicts

// What both compare of an accepted file (the names of `dynpm info --json`).
const COUNTS = ['complete', 'vertices', 'faces', 'vertices_present', 'faces_present',
  'quads_present', 'triangles_present', 'base_vertices', 'base_faces', 'splits', 'steps',
  'key_steps', 'fields', 'parts', 'lossless'];
const byteOf = (message) => Number(/: byte (\d+):/.exec(message)?.[1] ?? NaN);

function jsVerdict(bytes) {
  let mesh, complete;
  try {
    ({ mesh, complete } = decodeDpm(bytes, 'x.dpm'));
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
      fields: h.fieldNames.length,
      parts: parts.size,
      lossless: mesh.lossless,
    },
  };
}

// `dynpm info --json FILE`.
function cliVerdict(path) {
  return new Promise((resolve) => {
    execFile(CLI, ['info', '--json', path], (error, stdout, stderr) => {
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

// `dpm_verdicts FILE...`: a line per file, "error MESSAGE" or "counts name=value …".
function toolVerdicts(paths) {
  const lines = execFileSync(TOOL, paths, { encoding: 'utf8', maxBuffer: 1 << 26 }).split('\n');
  return paths.map((_, k) => {
    const [kind, ...rest] = lines[k].split(' ');
    if (kind === 'error') return { byte: byteOf(lines[k]), message: rest.join(' ') };
    const counts = {};
    for (const pair of rest) {
      const [key, value] = pair.split('=');
      counts[key] = key === 'complete' || key === 'lossless' ? value === '1' : Number(value);
    }
    return { counts: Object.fromEntries(COUNTS.map((key) => [key, counts[key]])) };
  });
}

// ---------------------------------------------------------------------------------------------
// Mutants

// The chunks of a file that has its magic and version: [{at, tag, flags, stored, raw, payload}].
function chunksOf(bytes) {
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

function chunk(tag, payload) {
  const out = new Uint8Array(24 + payload.length);
  const view = new DataView(out.buffer);
  for (let i = 0; i < 4; i++) out[i] = tag.charCodeAt(i);
  view.setUint32(8, payload.length, true);
  view.setUint32(12, payload.length, true);
  view.setUint32(16, crc32(payload), true);
  out.set(payload, 24);
  return out;
}

function concat(parts) {
  const out = new Uint8Array(parts.reduce((n, p) => n + p.length, 0));
  let at = 0;
  for (const p of parts) out.set(p, at), (at += p.length);
  return out;
}

// The file with every chunk stored uncompressed, and files that differ from it in one place.
function mutants(name, bytes) {
  const chunks = chunksOf(bytes);
  const magic = bytes.subarray(0, 12);
  const rebuild = (edit = () => {}) =>
    concat([magic, ...chunks.map((c, k) => chunk(c.tag, edit(k, c.payload.slice()) ?? c.payload))]);
  const plain = rebuild();
  const out = [{ name: `${name} stored`, bytes: plain }];
  const add = (what, b) => out.push({ name: `${name} stored, ${what}`, bytes: b });
  const set = (at, f) => {
    const b = plain.slice();
    b[at] = f(b[at]);
    return b;
  };
  const starts = chunksOf(plain).map((c) => c.at);
  for (const at of [...starts, plain.length]) {
    for (const d of [-1, 0, 1, 23, 24, 25]) {
      const n = at + d;
      if (n >= 0 && n < plain.length) add(`cut at ${n}`, plain.subarray(0, n));
    }
  }
  // One change per byte, the kinds taking turns: the low bit, the high bit, all bits set.
  const changes = [['^ 1', (x) => x ^ 1], ['^ 0x80', (x) => x ^ 0x80], ['= 0xff', () => 0xff]];
  for (const at of starts)
    for (let i = 0; i < 24; i++) {
      const [what, f] = changes[i % 3];
      add(`header byte ${at + i} ${what}`, set(at + i, f));
    }
  chunks.forEach((c, k) => {
    // Every byte of HEAD; every fourth of the others (positions and fields are most of them).
    const step = c.tag === 'HEAD' ? 1 : 4;
    for (let i = 0; i < c.payload.length; i += step) {
      const [what, f] = changes[(i / step) % 3];
      add(`${c.tag} payload byte ${i} ${what}`,
        rebuild((kk, p) => (kk === k ? ((p[i] = f(p[i])), p) : null)));
    }
  });
  // The first split's error (after first_split, count and the parent varint).
  const splt = chunks.findIndex((c) => c.tag === 'SPLT');
  for (const e of [NaN, -1, Infinity])
    add(`split 0 error ${e}`, rebuild((k, p) => {
      if (k !== splt) return null;
      const at = 8 + (p[8] < 0x80 ? 1 : 2);
      new DataView(p.buffer).setFloat32(at, e, true);
      return p;
    }));
  add('a byte after END', concat([plain, Uint8Array.of(0)]));
  add('END twice', concat([plain, chunk('END ', new Uint8Array(0))]));
  const withoutEnd = plain.subarray(0, plain.length - 24);
  add('END not empty', concat([withoutEnd, chunk('END ', Uint8Array.of(0))]));
  return out;
}

// ---------------------------------------------------------------------------------------------

function same(cpp, js) {
  if (cpp.counts) return JSON.stringify(js.counts) === JSON.stringify(cpp.counts);
  return !Number.isNaN(cpp.byte) && js.byte === cpp.byte;
}

function jsVerdictOrCrash(bytes) {
  try {
    return jsVerdict(bytes);
  } catch (e) {
    return { crash: `${e.constructor.name}: ${e.message}` };
  }
}

const skip = (!CLI || !TOOL) && 'DYNPM_CLI or DYNPM_VERDICTS not set';
test('the C++ reader and dpm.js give every file the same verdict', { skip }, async () => {
  const corpus = [
    ...dpmFiles('fuzz/regressions/dpm'),
    ...dpmFiles('fuzz/corpus/dpm'),
    ...dpmFiles('tests/bad'),
  ];
  assert.ok(corpus.length >= 9, 'the corpus folders hold .dpm files');
  const mutated = corpus
    .filter((f) => f.bytes.length < 4096 && f.name.startsWith('fuzz/corpus'))
    .flatMap((f) => mutants(f.name, f.bytes));
  rmSync(OUT, { recursive: true, force: true });
  mkdirSync(OUT, { recursive: true });
  const files = [...corpus, ...mutated].map((f, k) => ({ ...f, path: join(OUT, `${k}.dpm`) }));
  for (const f of files) writeFileSync(f.path, f.bytes);
  const verdicts = [
    ...(await Promise.all(corpus.map((f, k) => cliVerdict(files[k].path)))),
    ...toolVerdicts(files.slice(corpus.length).map((f) => f.path)),
  ];
  // The tool says what the CLI says.
  const again = toolVerdicts(files.slice(0, corpus.length).map((f) => f.path));
  corpus.forEach((f, k) => assert.ok(same(verdicts[k], again[k]), f.name));
  const differences = [];
  files.forEach((f, k) => {
    const cpp = verdicts[k];
    const js = jsVerdictOrCrash(f.bytes);
    if (!same(cpp, js))
      differences.push(`${f.name}:\n  C++: ${JSON.stringify(cpp)}\n  JS:  ${JSON.stringify(js)}`);
  });
  rmSync(OUT, { recursive: true, force: true });
  assert.equal(differences.length, 0,
    `${differences.length} of ${files.length} files get different verdicts:\n` +
      differences.slice(0, 20).join('\n'));
  const accepted = verdicts.filter((v) => v.counts).length;
  assert.ok(accepted >= 4 && accepted < files.length, `${accepted} of ${files.length} accepted`);
});
