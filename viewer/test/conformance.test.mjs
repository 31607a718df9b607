// Both decoders give every .dpm the same verdict: the C++ reader (`dynpm info --json`, and
// tests/dpm_verdicts.cpp for the mutants, in one process) and dpm.js (decodeDpm) either accept
// a file with the same counts — and the same selective meshes and the same positions and field
// values at the last step (verdicts.mjs) — or reject it at the same byte (the "byte N" of both
// messages). The files: every .dpm of fuzz/regressions/dpm/,
// fuzz/corpus/dpm/ and tests/bad/, and mutants of the small corpus files made here — chunks
// stored uncompressed (so that records can be changed), files cut at and around every chunk
// boundary, and single bytes changed in every chunk header and in the payloads (checksums
// fixed, so that the payload checks are reached).
import assert from 'node:assert/strict';
import { mkdirSync, readdirSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { test } from 'node:test';

import { decompress } from 'fzstd';

import { deferredPositions } from '../src/dpm/positions.js';
import { chunkBytes, rawChunks, withFields } from './fields_fixture.mjs';
import { chunksOf, cliVerdict, concat, jsVerdictOrCrash, same, toolVerdicts } from './verdicts.mjs';

const CLI = process.env.DYNPM_CLI;
const TOOL = process.env.DYNPM_VERDICTS;
const OUT = join(process.env.DYNPM_TEST_OUT ?? tmpdir(), 'conformance');
const ROOT = new URL('../../', import.meta.url).pathname;

// DYNPM_CONFORMANCE_EXTRA: a folder whose every file joins the corpus (e.g. the inputs a run of
// fuzz_dpm kept: docs/RELIABILITY.md "Both decoders on the fuzzer's corpus").
const EXTRA = process.env.DYNPM_CONFORMANCE_EXTRA;
const extraFiles = () => (EXTRA ? readdirSync(EXTRA).sort() : [])
  .map((f) => ({ name: join(EXTRA, f), bytes: new Uint8Array(readFileSync(join(EXTRA, f))) }));

function dpmFiles(folder) {
  return readdirSync(join(ROOT, folder))
    .filter((f) => f.endsWith('.dpm'))
    .sort()
    .map((f) => ({ name: `${folder}/${f}`, bytes: readFileSync(join(ROOT, folder, f)) }))
    .map(({ name, bytes }) => ({ name, bytes: new Uint8Array(bytes) }));
}

// ---------------------------------------------------------------------------------------------
// Verdicts

// ---------------------------------------------------------------------------------------------
// Mutants

// The file with every chunk stored uncompressed, and files that differ from it in one place.
function mutants(name, bytes) {
  const chunks = chunksOf(bytes);
  const magic = bytes.subarray(0, 12);
  const rebuild = (edit = () => {}) =>
    concat([magic, ...chunks.map((c, k) => chunkBytes(c.tag, edit(k, c.payload.slice()) ?? c.payload))]);
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
  // HEAD's base_error (8 counts, the box, quant_step and max_error before it): the split
  // errors' grid starts there, so neither reader takes one that is not a finite number ≥ 0; a
  // finite one moves the grid, and both decode the same splits on it.
  const head = chunks.findIndex((c) => c.tag === 'HEAD');
  for (const e of [NaN, -1, Infinity, 1e30])
    add(`base_error ${e}`, rebuild((k, p) => {
      if (k !== head) return null;
      new DataView(p.buffer, p.byteOffset).setFloat64(4 * 8 + 8 * 8, e, true);
      return p;
    }));
  // Two faults: a byte near the end of a SPLT (its last step's positions) and the next chunk's
  // tag. Decoded in place the positions fail first; decoded later (a second thread in either
  // reader) they must still be the error told.
  chunks.forEach((c, k) => {
    if (c.tag !== 'SPLT' || k + 1 >= chunks.length) return;
    for (const back of [1, 2, 5, 9]) {
      const i = c.payload.length - back;
      const b = rebuild((kk, p) => (kk === k ? ((p[i] ^= 0x80), p) : null));
      b[starts[k + 1]] = 0x78;  // 'x': no tag
      add(`SPLT payload byte ${i} ^ 0x80, the next tag broken`, b);
    }
  });
  add('a byte after END', concat([plain, Uint8Array.of(0)]));
  add('END twice', concat([plain, chunkBytes('END ', new Uint8Array(0))]));
  const withoutEnd = plain.subarray(0, plain.length - 24);
  add('END not empty', concat([withoutEnd, chunkBytes('END ', Uint8Array.of(0))]));
  return out;
}

// ---------------------------------------------------------------------------------------------

// Both decoders on `files` ({name, bytes}) against the C++ verdicts given: none may differ. And
// dpm.js with each SPLT's positions decoded only when waited for (as the page's second worker
// may deliver them: after the next chunk's records) says exactly what it says decoding in place.
function expectSameVerdicts(files, verdicts) {
  const differences = [];
  files.forEach((f, k) => {
    const js = jsVerdictOrCrash(f.bytes);
    if (!same(verdicts[k], js))
      differences.push(`${f.name}:\n  C++: ${JSON.stringify(verdicts[k])}\n  JS:  ${JSON.stringify(js)}`);
    const deferred = jsVerdictOrCrash(f.bytes, { positions: deferredPositions() });
    if (JSON.stringify(deferred) !== JSON.stringify(js))
      differences.push(`${f.name}:\n  JS:       ${JSON.stringify(js)}\n  deferred: ${JSON.stringify(deferred)}`);
  });
  assert.equal(differences.length, 0,
    `${differences.length} of ${files.length} files get different verdicts:\n` + differences.slice(0, 20).join('\n'));
}

const skip = (!CLI || !TOOL) && 'DYNPM_CLI or DYNPM_VERDICTS not set';
test('the C++ reader and dpm.js give every file the same verdict', { skip }, async () => {
  const corpus = [
    ...dpmFiles('fuzz/regressions/dpm'),
    ...dpmFiles('fuzz/corpus/dpm'),
    ...dpmFiles('tests/bad'),
    ...extraFiles(),
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
    ...(await Promise.all(corpus.map((f, k) => cliVerdict(CLI, files[k].path)))),
    ...toolVerdicts(TOOL, files.slice(corpus.length).map((f) => f.path)),
  ];
  // The tool says what the CLI says.
  const again = toolVerdicts(TOOL, files.slice(0, corpus.length).map((f) => f.path));
  corpus.forEach((f, k) => assert.ok(same(verdicts[k], again[k]), f.name));
  corpus.forEach((f, k) => Object.assign(verdicts[k], { selective: again[k].selective, values: again[k].values }));  // info has neither
  rmSync(OUT, { recursive: true, force: true });
  expectSameVerdicts(files, verdicts);
  const accepted = verdicts.filter((v) => v.counts).length;
  assert.ok(accepted >= 4 && accepted < files.length, `${accepted} of ${files.length} accepted`);
});

// ---------------------------------------------------------------------------------------------
// Fields (FORMAT.md "Fields: FDEF and FLDS"): the small corpus files with a node and an element
// field added (test/fields_fixture.mjs, written from FORMAT.md), their mutants, and damage aimed
// at each check of FDEF and FLDS. Until the C++ reader knows FDEF (branch a18-format) it refuses
// these files at FDEF's tag, and this test is skipped.

const FIELDS = [
  { name: 'node', unit: 'MPa', perFace: false, value: (v, t, m) => m.position(v, t)[2] * 3 + v % 5 },
  { name: 'element', unit: '', perFace: true, value: (f, t) => Math.max(0, Math.sin(f * 0.3) * t) },
];

// Files that differ from a fielded file in one field check each.
function fieldDamage(name, bytes) {
  const magic = bytes.subarray(0, 12);
  const chunks = rawChunks(bytes).map((c) => ({ tag: c.tag, payload: c.bytes[4] & 1 ? decompress(c.bytes.subarray(24)) : c.bytes.slice(24) }));
  const out = [];
  const rebuild = (what, edit) => {
    const list = edit(chunks.map((c) => ({ ...c, payload: c.payload.slice() })));
    const parts = [magic, ...list.map((c) => chunkBytes(c.tag, c.payload))];
    const b = new Uint8Array(parts.reduce((a, p) => a + p.length, 0));
    parts.reduce((at, p) => (b.set(p, at), at + p.length), 0);
    out.push({ name: `${name}, ${what}`, bytes: b });
  };
  const patch = (tag, nth, what, f) => rebuild(what, (list) => {
    const c = list.filter((x) => x.tag === tag)[nth];
    f(new DataView(c.payload.buffer), c);
    return list;
  });
  // The first field: name 'node' (4 bytes), unit 'MPa' (3): location at 15, flags 16, reserved
  // 17, min 19, max 27, quant_step 35, max_error 43, base_error 51.
  patch('FDEF', 0, 'no fields', (d) => d.setUint32(0, 0, true));
  patch('FDEF', 0, 'an empty name', (d, c) => { d.setUint16(4, 0, true); c.payload = c.payload.slice(); });
  patch('FDEF', 0, 'location 2', (d) => d.setUint8(15, 2));
  patch('FDEF', 0, 'flags 2', (d) => d.setUint8(16, 2));
  patch('FDEF', 0, 'reserved 1', (d) => d.setUint16(17, 1, true));
  patch('FDEF', 0, 'min > max', (d) => d.setFloat64(19, 1e30, true));
  patch('FDEF', 0, 'min NaN', (d) => d.setFloat64(19, NaN, true));
  patch('FDEF', 0, 'quant_step 0', (d) => d.setFloat64(35, 0, true));
  patch('FDEF', 0, 'quant_step finer than float32', (d) => d.setFloat64(35, 1e-30, true));
  patch('FDEF', 0, 'base_error 1.5', (d) => d.setFloat32(51, 1.5, true));
  patch('FDEF', 0, 'lossless with a quant_step', (d) => d.setUint8(16, 1));
  patch('FLDS', 1, 'first_split wrong', (d) => d.setUint32(0, 7, true));
  patch('FLDS', 1, 'count wrong', (d) => d.setUint32(4, d.getUint32(4, true) + 1, true));
  patch('FLDS', 0, 'a BASE FLDS with a count', (d) => d.setUint32(4, 1, true));
  rebuild('a byte left over in FLDS', (list) => {
    const c = list.filter((x) => x.tag === 'FLDS')[1];
    c.payload = Uint8Array.from([...c.payload, 0]);
    return list;
  });
  rebuild('a SPLT without its FLDS', (list) => list.filter((c, k) => !(c.tag === 'FLDS' && list[k - 1].tag === 'SPLT' && k < 6)));
  rebuild('FDEF after BASE', (list) => {
    const fdef = list.splice(1, 1)[0];
    list.splice(2, 0, fdef);
    return list;
  });
  rebuild('FLDS twice', (list) => (list.splice(4, 0, list[3]), list));
  rebuild('an unknown optional chunk between SPLT and FLDS', (list) =>
    (list.splice(5, 0, { tag: 'ZZ9 ', payload: Uint8Array.of(1, 2) }), list));
  rebuild('an optional chunk before HEAD', (list) => [{ tag: 'ZZ9 ', payload: new Uint8Array(0) }, ...list]);
  rebuild('an unknown tag that is not optional', (list) =>
    (list.splice(2, 0, { tag: 'zz9 ', payload: new Uint8Array(0) }), list));
  patch('HEAD', 0, 'HEAD field_count 1', (d) => d.setUint32(24, 1, true));
  return out;
}

test('files with fields: the C++ reader and dpm.js give the same verdict', async (t) => {
  // Files without fields of their own (the corpus also holds one written with fields).
  const base = dpmFiles('fuzz/corpus/dpm')
    .filter((f) => f.bytes.length < 65536 && !Buffer.from(f.bytes).includes('FDEF'));
  const fielded = base.map((f) => ({ name: `${f.name} + fields`, bytes: withFields(f.bytes, FIELDS) }));
  if (!CLI || !TOOL) return t.skip('DYNPM_CLI or DYNPM_VERDICTS not set');
  mkdirSync(OUT, { recursive: true });
  const probe = join(OUT, 'fields-probe.dpm');
  writeFileSync(probe, fielded[0].bytes);
  const [verdict] = toolVerdicts(TOOL, [probe]);
  if (verdict.message && /unknown chunk tag/.test(verdict.message))
    return t.skip('the C++ reader does not know FDEF yet (branch a18-format)');
  const files = [
    ...fielded,
    ...fielded.flatMap((f) => fieldDamage(f.name, f.bytes)),
    ...fielded.filter((f) => f.bytes.length < 16384).flatMap((f) => mutants(f.name, f.bytes)),
  ].map((f, k) => ({ ...f, path: join(OUT, `fields-${k}.dpm`) }));
  for (const f of files) writeFileSync(f.path, f.bytes);
  const verdicts = toolVerdicts(TOOL, files.map((f) => f.path));
  rmSync(OUT, { recursive: true, force: true });
  expectSameVerdicts(files, verdicts);
  assert.ok(verdicts.slice(0, fielded.length).every((v) => v.counts?.fields === 2), 'the fielded files are read');
});

// ---------------------------------------------------------------------------------------------
// Part names (FORMAT.md "Part names: PART"): the corpus file with PART (small_grid_parts.dpm,
// `dynpm build` of an OBJ grid whose `o` and `g` statements name its parts), and damage aimed at
// each check of PART. Its generic mutants are made with the corpus's above.

// Files that differ from `bytes` (which has a PART chunk) in one PART check each.
function partDamage(name, bytes) {
  const magic = bytes.subarray(0, 12);
  const chunks = rawChunks(bytes).map((c) => ({ tag: c.tag, payload: c.bytes[4] & 1 ? decompress(c.bytes.subarray(24)) : c.bytes.slice(24) }));
  const k = chunks.findIndex((c) => c.tag === 'PART');
  assert.ok(k > 0, `${name} has a PART chunk`);
  const out = [];
  const rebuild = (what, list) => out.push({ name: `${name}, ${what}`, bytes: concat([magic, ...list.map((c) => chunkBytes(c.tag, c.payload))]) });
  // The first entry: count (u32), id (i32) at 4, name length (u16) at 8, name from 10.
  const payload = chunks[k].payload;
  const first = new DataView(payload.buffer, payload.byteOffset).getUint16(8, true);
  const withPart = (what, p) => rebuild(what, chunks.map((c, i) => (i === k ? { ...c, payload: p } : c)));
  const patched = (f) => {
    const p = payload.slice();
    f(new DataView(p.buffer), p);
    return p;
  };
  // The first name replaced by `bytes` (its length field too).
  const named = (bytesOfName) => concat([payload.subarray(0, 8), Uint8Array.of(bytesOfName.length & 0xff, bytesOfName.length >> 8), bytesOfName, payload.subarray(10 + first)]);
  withPart('count 0', patched((d) => d.setUint32(0, 0, true)));
  withPart('count too large', patched((d) => d.setUint32(0, 1 << 20, true)));
  withPart('ids not ascending', patched((d) => d.setInt32(4, 0x7fffffff, true)));
  withPart('an empty name', named(new Uint8Array(0)));
  withPart('a name of 256 bytes', named(new Uint8Array(256).fill(0x61)));
  withPart('a name of 255 bytes', named(new Uint8Array(255).fill(0x61)));  // accepted
  for (const [what, b] of [['ESC', [0x61, 0x1b, 0x62]], ['NUL', [0x61, 0, 0x62]], ['DEL', [0x61, 0x7f]],
    ['C1 NEL', [0x61, 0xc2, 0x85]], ['a lone continuation byte', [0x61, 0x80]], ['an overlong slash', [0xc0, 0xaf]],
    ['a surrogate', [0xed, 0xa0, 0x80]], ['above U+10FFFF', [0xf4, 0x90, 0x80, 0x80]], ['cut UTF-8', [0x61, 0xe2, 0x80]],
    ['a leading space', [0x20, 0x61]], ['a trailing space', [0x61, 0x20]], ['a BOM', [0xef, 0xbb, 0xbf, 0x61]],
    ['U+FFFD and an umlaut', [0xef, 0xbf, 0xbd, 0xc3, 0xa4]]])
    withPart(`a name with ${what}`, named(Uint8Array.from(b)));
  withPart('a byte left over', concat([payload, Uint8Array.of(0)]));
  withPart('cut short', payload.subarray(0, payload.length - 1));
  // Out of order: after BASE, twice, and before HEAD; an unknown optional chunk beside it is skipped.
  const moved = chunks.slice();
  const [part] = moved.splice(k, 1);
  moved.splice(k + 1, 0, part);
  rebuild('PART after BASE', moved);
  rebuild('PART twice', [...chunks.slice(0, k + 1), chunks[k], ...chunks.slice(k + 1)]);
  rebuild('PART before HEAD', [chunks[k], ...chunks.filter((c, i) => i !== k)]);
  rebuild('an optional chunk before PART', [...chunks.slice(0, k), { tag: 'ZZ9 ', payload: Uint8Array.of(1) }, ...chunks.slice(k)]);
  return out;
}

// Both readers' verdicts on the damaged files (written to OUT for the C++ side) must agree; the
// names of the files both accept, without the corpus file's name, and the C++ verdicts.
function acceptedByBoth(damaged, prefix) {
  const files = damaged.map((f, k) => ({ ...f, path: join(OUT, `${prefix}-${k}.dpm`) }));
  mkdirSync(OUT, { recursive: true });
  for (const f of files) writeFileSync(f.path, f.bytes);
  const verdicts = toolVerdicts(TOOL, files.map((f) => f.path));
  rmSync(OUT, { recursive: true, force: true });
  expectSameVerdicts(files, verdicts);
  const accepted = files.filter((f, k) => verdicts[k].counts).map((f) => f.name.replace(/^.*, /, ''));
  return { accepted, verdicts };
}

test('files with part names: the C++ reader and dpm.js give the same verdict', { skip }, async () => {
  const named = dpmFiles('fuzz/corpus/dpm').filter((f) => Buffer.from(f.bytes).includes('PART'));
  assert.ok(named.length >= 1, 'the corpus holds a file with PART');
  const { accepted, verdicts } = acceptedByBoth(named.flatMap((f) => [f, ...partDamage(f.name, f.bytes)]), 'parts');
  // The file itself, the 255-byte name, U+FFFD with an umlaut, a BOM (U+FEFF is no control
  // character) and the skipped optional chunk; every other damage is refused.
  assert.deepEqual(accepted.slice(1), ['a name of 255 bytes', 'a name with a BOM', 'a name with U+FFFD and an umlaut', 'an optional chunk before PART']);
  assert.ok(verdicts[0].partList.length > 0, 'the names are read');
});

// ---------------------------------------------------------------------------------------------
// Family files (FORMAT.md "Variants: VARI"): the corpus's small_grid_family.dpm
// (bench/family/make_small_grid_family.py) and damage aimed at each check of VARI.

// Files that differ from `bytes` (which has a VARI chunk) in one VARI check each.
function variantDamage(name, bytes) {
  const magic = bytes.subarray(0, 12);
  const chunks = rawChunks(bytes).map((c) => ({ tag: c.tag, payload: c.bytes[4] & 1 ? decompress(c.bytes.subarray(24)) : c.bytes.slice(24) }));
  const k = chunks.findIndex((c) => c.tag === 'VARI');
  assert.ok(k > 0, `${name} has a VARI chunk`);
  const out = [];
  const rebuild = (what, list) => out.push({ name: `${name}, ${what}`, bytes: concat([magic, ...list.map((c) => chunkBytes(c.tag, c.payload))]) });
  const payload = chunks[k].payload;
  const withVari = (what, p) => rebuild(what, chunks.map((c, i) => (i === k ? { ...c, payload: p } : c)));
  const patched = (f) => {
    const p = payload.slice();
    f(new DataView(p.buffer), p);
    return p;
  };
  // The first variant: count (u32), name length (u16) at 4, name, source length, source, steps,
  // times (f64 each), stored steps (u32 each).
  const d = new DataView(payload.buffer, payload.byteOffset);
  const nameLength = d.getUint16(4, true);
  const sourceAt = 6 + nameLength;
  const stepsAt = sourceAt + 2 + d.getUint16(sourceAt, true);
  const steps = d.getUint32(stepsAt, true);
  const timesAt = stepsAt + 4;
  const storedAt = timesAt + 8 * steps;
  withVari('count 0', patched((v) => v.setUint32(0, 0, true)));
  withVari('count too large', patched((v) => v.setUint32(0, 1 << 20, true)));
  withVari('an empty name', concat([payload.subarray(0, 4), Uint8Array.of(0, 0), payload.subarray(6 + nameLength)]));
  withVari('a name with ESC', patched((v, p) => (p[6] = 0x1b)));
  withVari('step count 0', patched((v) => v.setUint32(stepsAt, 0, true)));
  withVari('step count too large', patched((v) => v.setUint32(stepsAt, 1 << 24, true)));
  withVari('a time of NaN', patched((v) => v.setFloat64(timesAt, NaN, true)));
  withVari('a stored step past the file', patched((v) => v.setUint32(storedAt, 99, true)));
  withVari('a stored step no variant uses', patched((v) => v.setUint32(storedAt + 4, d.getUint32(storedAt + 8, true), true)));
  withVari('a byte left over', concat([payload, Uint8Array.of(0)]));
  withVari('cut short', payload.subarray(0, payload.length - 1));
  const second = concat([payload.subarray(0, 4), payload.subarray(4, stepsAt + 4 + 12 * steps)]);
  new DataView(second.buffer).setUint32(0, 1, true);
  withVari('one variant of two', second);  // refused: the second's stored steps are unused
  const moved = chunks.slice();
  const [vari] = moved.splice(k, 1);
  moved.splice(k + 1, 0, vari);
  rebuild('VARI after BASE', moved);
  rebuild('VARI twice', [...chunks.slice(0, k + 1), chunks[k], ...chunks.slice(k + 1)]);
  // A reader that does not know VARI: the same file with the chunk under an unknown tag.
  rebuild('VARI renamed VARX', chunks.map((c, i) => (i === k ? { ...c, tag: 'VARX' } : c)));
  return out;
}

test('family files: the C++ reader and dpm.js give the same verdict', { skip }, async () => {
  const families = dpmFiles('fuzz/corpus/dpm').filter((f) => Buffer.from(f.bytes).includes('VARI'));
  assert.ok(families.length >= 1, 'the corpus holds a family file');
  const { accepted } = acceptedByBoth(families.flatMap((f) => [f, ...variantDamage(f.name, f.bytes)]), 'family');
  assert.deepEqual(accepted.slice(1), ['VARI renamed VARX']);
});
