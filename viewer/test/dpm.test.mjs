// dpm.js on a .dpm written here byte by byte from FORMAT.md: the split of FORMAT.md's figure
// (a quad wing), a triangle wing and a moved face, two time steps; prefixes, byte-at-a-time
// streaming and damaged files.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { crc32 } from 'node:zlib';

import { DpmDecoder, Navigator, readDpm, ShownValues, updateIndices } from '../src/dpm.js';
import { valueArrayType } from '../src/dpm/fields.js';
import { SignedModel } from '../src/dpm/range_coder.js';
import { Bytes } from './fields_fixture.mjs';
import { encodeSigned, RangeEncoder } from './range_encoder.mjs';
import { encodeSplitRecords } from './split_records_encoder.mjs';

// A chunk; with `frame` (payload → zstd frame bytes) stored compressed.
function chunk(out, tag, payload, frame = null) {
  const stored = frame ? frame(payload) : payload;
  for (const c of tag) out.u8(c.charCodeAt(0));
  out.u32(frame ? 1 : 0), out.u32(stored.length), out.u32(payload.length);
  out.u32(crc32(stored)), out.u32(0);
  stored.forEach((x) => out.u8(x));
}

// A zstd frame written by hand (RFC 8878): single segment, the content size in `sizeBytes`
// bytes (1 or 4), the payload as one raw block. `declared` overrides the content size.
function zstdFrame(payload, { declared = payload.length, sizeBytes = 1 } = {}) {
  const out = new Bytes();
  [0x28, 0xb5, 0x2f, 0xfd].forEach((x) => out.u8(x));
  out.u8(sizeBytes === 4 ? 0xa0 : 0x20);
  if (sizeBytes === 4) out.u32(declared);
  else out.u8(declared);
  const header = 1 | (0 << 1) | (payload.length << 3);  // last block, raw
  out.u8(header), out.u8(header >> 8), out.u8(header >> 16);
  payload.forEach((x) => out.u8(x));
  return out.bytes;
}

// Base: w=0, v1=1, x=2, y=3, z=4; faces (0,1,2) and (1,4,3). Split 0 creates v0=5: the quad
// wing (0,1,2) → (0,5,1,2) (slot 1, v1 follows v0), the triangle wing (5,3,1) (slot 0, w=y),
// and moves (1,4,3) → (5,4,3).
const Q = [
  // step 0, step 1: quantized integer positions of vertices 0…5
  [[0, 0, 0], [4, 0, 0], [4, 4, 0], [8, 2, 0], [6, -2, 1], [2, 1, 0]],
  [[0, 0, 1], [4, 0, 2], [4, 4, 3], [8, 2, 5], [6, -2, 1], [2, 1, 9]],
];
const QUANT = 0.25;
const BMIN = [-1, -2, -3];
// Two fields: 'stress' per node (quantized, step 0.5: vertex v at step 0 is v; step 1 moves each
// by its own amount, so that vertex 5's ring {0, 1, 3, 4} changes by 10, 11, 11, 13 and its
// parent 1 by 13) and 'peeq' per element (lossless). Face 2, created by split 0, has face 1 as
// its heir.
const STRESS = [[0, 1, 2, 3, 4, 5], [10, 14, 12, 14, 15, 15.5]];
const PEEQ = [[1, -4, 3], [1.5, -4, 4]];
const f32Bits = (x) => new Int32Array(Float32Array.of(x).buffer)[0];
const bucket = (r) => (r === 0 ? 0 : Math.min(Math.floor(Math.log2(Math.abs(r))) + 1, 4));

// FLDS after BASE (n = 0) or after split 0 (n = 1), FORMAT.md "Fields": after BASE svarints;
// after the SPLT per field its error after split 0, then per step a predictor, a size and a
// range-coded section (fresh models: the first SPLT's FLDS; the context at step 1 is the bucket
// of the residual at step 0).
function fieldValues(n) {
  const out = new Bytes();
  out.u32(0), out.u32(n);
  if (n) out.varint(2 - 1 - 1);  // face 2's heir: face 1
  const q = STRESS.map((row) => row.map((x) => x / 0.5));
  const p = PEEQ.map((row) => row.map(f32Bits));
  const steps = (residuals, predictors) => {
    out.f32(0);  // the field error after split 0
    residuals.forEach((r, t) => {
      const e = new RangeEncoder();
      const models = [0, 1, 2, 3, 4].map(() => new SignedModel());
      encodeSigned(e, models[t ? bucket(residuals[0]) : 0], r);
      const bytes = e.finish();
      out.u8(predictors[t]), out.u32(bytes.length);
      bytes.forEach((b) => out.u8(b));
    });
  };
  if (!n) {
    for (let t = 0; t < 2; t++)
      for (let v = 0; v < 5; v++) out.svarint(t ? q[t][v] - q[t - 1][v] : q[0][v] - (v ? q[0][v - 1] : 0));
    for (let t = 0; t < 2; t++)
      for (let f = 0; f < 2; f++) out.svarint(t ? p[t][f] - p[t - 1][f] : p[0][f] - (f ? p[0][f - 1] : 0));
    return out.bytes;
  }
  // stress at step 1: the ring's lower median change (22 of 20, 22, 22, 26 in grid steps), not
  // the parent's 26: predictor 1.
  const changes = [0, 1, 3, 4].map((u) => q[1][u] - q[0][u]).sort((a, b) => a - b);
  steps([q[0][5] - q[0][1], q[1][5] - (q[0][5] + changes[1])], [0, 1]);
  // peeq, lossless per element: the heir's change, modulo 2^32 (predictor 0).
  steps([(p[0][2] - p[0][1]) | 0, (p[1][2] - p[0][2] - (p[1][1] - p[0][1])) | 0], [0, 0]);
  return out.bytes;
}

function fieldDefs() {
  const out = new Bytes();
  out.u32(2);
  out.string('stress'), out.string('MPa'), out.u8(0), out.u8(0), out.u16(0);
  out.f64(0), out.f64(15.5), out.f64(0.5), out.f64(0.25), out.f32(0.3);
  out.string('peeq'), out.string(''), out.u8(1), out.u8(1), out.u16(0);
  out.f64(-4), out.f64(4), out.f64(0), out.f64(0), out.f32(0.75);
  return out.bytes;
}

// FORMAT.md "Positions", the ring fit, step by step: P and Q the ring's q-vectors at t − 1 and t
// (ascending vertex order), p v0's at t − 1.
function ringFit(P, Q, p) {
  const n = P.length;
  const c0 = [0, 1, 2].map((c) => P.reduce((a, x) => a + x[c], 0) / n);
  const c1 = [0, 1, 2].map((c) => Q.reduce((a, x) => a + x[c], 0) / n);
  const B = [[0, 0, 0], [0, 0, 0], [0, 0, 0]], A = [[0, 0, 0], [0, 0, 0], [0, 0, 0]];
  for (let j = 0; j < n; j++) {
    const e = [0, 1, 2].map((c) => P[j][c] - c0[c]), h = [0, 1, 2].map((c) => Q[j][c] - c1[c]);
    for (const [r, c] of [[0, 0], [1, 1], [2, 2], [0, 1], [0, 2], [1, 2]]) B[r][c] += e[r] * e[c];
    for (let r = 0; r < 3; r++) for (let c = 0; c < 3; c++) A[r][c] += h[r] * e[c];
  }
  const lambda = (B[0][0] + B[1][1] + B[2][2]) * 2 ** -10 + 2 ** -10;
  const K = [B[0][0] + lambda, B[1][1] + lambda, B[2][2] + lambda];
  const M = [
    [K[1] * K[2] - B[1][2] * B[1][2], B[0][2] * B[1][2] - B[0][1] * K[2], B[0][1] * B[1][2] - B[0][2] * K[1]],
    [0, K[0] * K[2] - B[0][2] * B[0][2], B[0][1] * B[0][2] - K[0] * B[1][2]],
    [0, 0, K[0] * K[1] - B[0][1] * B[0][1]],
  ];
  M[1][0] = M[0][1], M[2][0] = M[0][2], M[2][1] = M[1][2];
  const det = K[0] * M[0][0] + B[0][1] * M[0][1] + B[0][2] * M[0][2];
  assert.ok(det > 0);
  const d = [0, 1, 2].map((c) => p[c] - c0[c]);
  const y = M.map((row) => (row[0] * d[0] + row[1] * d[1] + row[2] * d[2]) / det);
  return [0, 1, 2].map((r) => Math.floor(c1[r] + ((A[r][0] * y[0] + A[r][1] * y[1] + A[r][2] * y[2]) + lambda * y[r]) + 0.5));
}

function makeFile(baseFrame = null, { fields = true, extra = null, upToBase = false } = {}) {
  const out = new Bytes();
  [0x89, 0x44, 0x50, 0x4d, 0x0d, 0x0a, 0x1a, 0x0a].forEach((x) => out.u8(x));
  out.u32(7);
  const head = new Bytes();
  [6, 3, 5, 2, 1, 2, 0, 0].forEach((x) => head.u32(x));
  BMIN.forEach((x) => head.f64(x));
  [2, 1, 0].forEach((x) => head.f64(x));
  head.f64(QUANT), head.f64(QUANT * 0.866), head.f64(0.5);
  head.f64(0), head.f64(0.001);
  head.u32(1), head.u32(1);
  head.string('dpm.test.mjs');
  chunk(out, 'HEAD', head.bytes);
  if (extra) chunk(out, extra, Uint8Array.of(1, 2, 3));  // an optional chunk of a later version
  if (fields) chunk(out, 'FDEF', fieldDefs());

  const base = new Bytes();
  // Original indices must be < V (the C++ reader checks them): an input order 1, 0, 3, 2, 4, 5.
  [[1, 100], [0, 101], [3, 102], [2, 103], [4, 104]].reduce((prev, [o, n]) => {
    base.svarint(o - prev[0]), base.svarint(n - prev[1]);
    return [o, n];
  }, [0, 0]);
  base.u8(3), [0, 1, 2].forEach((c) => base.varint(c));
  base.u8(3), [1, 4, 3].forEach((c) => base.varint(c));
  // part, element (delta), original (delta)
  base.svarint(7), base.svarint(500), base.svarint(0);
  base.svarint(8), base.svarint(1), base.svarint(1);
  for (let t = 0; t < 2; t++)
    for (let v = 0; v < 5; v++)
      for (let c = 0; c < 3; c++)
        base.svarint(t === 0 ? Q[0][v][c] - (v ? Q[0][v - 1][c] : 0) : Q[t][v][c] - Q[t - 1][v][c]);
  chunk(out, 'BASE', base.bytes, baseFrame);
  if (fields) chunk(out, 'FLDS', fieldValues(0), baseFrame);
  if (upToBase) return out.bytes;

  // SPLT: first_split, count, 2 + m sections (records, attributes, positions of each step).
  // The split's record and attributes against the mesh a reader has after BASE (stored plain).
  const reader = new DpmDecoder();
  reader.push(makeFile(null, { fields, extra, upToBase: true }));
  const { records, attributes } = encodeSplitRecords(reader.mesh, reader.recordModels(), 0, [{
    parent: 1,  // v1 = 1
    error: 0,
    wings: [
      { flags: 2 | (1 << 2), vertex: 0, face: 0 },  // quad wing: face 0, w = 0
      { flags: 1 | (0 << 2), vertex: 3 },  // triangle wing, w = 3
    ],
    moved: [1],
    vertexOriginal: 5, nodeId: 105,
    faces: [{ part: 9, element: 3, original: 2 }],
  }]);
  // Positions: after the split the quad wing is (w, v0, v1, x) = (0, 5, 1, 2), so step 0 guesses
  // q(0) + q(1) − q(2); step 1 moves q_0(5) as 5's ring {0, 1, 3, 4} moves (its wing vertices,
  // its parent, and its neighbours 4 and 3 in the moved face (5, 4, 3)): the ring fit, written
  // here from FORMAT.md's steps. Contexts: 0 at step 0, then the bucket of the residual at step 0.
  const ring = [0, 1, 3, 4];
  const fit = ringFit(ring.map((u) => Q[0][u]), ring.map((u) => Q[1][u]), Q[0][5]);
  const guess = (t, c) => (t === 0 ? Q[0][0][c] + Q[0][1][c] - Q[0][2][c] : fit[c]);
  const positions = [0, 1].map((t) => {
    const e = new RangeEncoder();
    const models = [0, 1, 2].map(() => [0, 1, 2, 3, 4].map(() => new SignedModel()));
    for (let c = 0; c < 3; c++) {
      const r0 = Q[0][5][c] - guess(0, c);
      if (t === 0) encodeSigned(e, models[c][0], r0);
      else encodeSigned(e, models[c][bucket(r0)], Q[1][5][c] - guess(1, c));
    }
    return e.finish();
  });
  const sections = [records, attributes, ...positions];
  const split = new Bytes();
  split.u32(0), split.u32(1), split.u32(sections.length);
  sections.forEach((x) => split.u32(x.length));
  sections.forEach((x) => x.forEach((b) => split.u8(b)));
  chunk(out, 'SPLT', split.bytes);
  if (fields) chunk(out, 'FLDS', fieldValues(1));
  chunk(out, 'END ', new Uint8Array(0));
  return out.bytes;
}

const FILE = makeFile();
const HEAD_END = 12 + 24 + FILE.slice(12 + 8, 12 + 12).reduce((a, x, i) => a + x * 256 ** i, 0);

test('decodes HEAD, BASE, the split and its attributes', () => {
  const { mesh, complete } = readDpm(FILE);
  assert.equal(complete, true);
  assert.equal(mesh.head.vertexCount, 6);
  assert.deepEqual(mesh.fields.map((f) => [f.name, f.unit, f.location]), [['stress', 'MPa', 0], ['peeq', '', 1]]);
  assert.equal(mesh.head.note, 'dpm.test.mjs');
  assert.deepEqual(Array.from(mesh.nodeId), [100, 101, 102, 103, 104, 105]);
  assert.deepEqual(Array.from(mesh.vertexOriginal), [1, 0, 3, 2, 4, 5]);
  assert.deepEqual(Array.from(mesh.partId), [7, 8, 9]);
  assert.deepEqual(Array.from(mesh.elementId), [500, 501, 3]);
  assert.deepEqual(Array.from(mesh.faceOriginal), [0, 1, 2]);
  assert.deepEqual(Array.from(mesh.fields[0].valuesAt(1, 6)), STRESS[1]);
  assert.deepEqual(Array.from(mesh.fields[1].valuesAt(0, 3)), PEEQ[0]);
  assert.deepEqual(Array.from(mesh.fields[1].valuesAt(1, 3)), PEEQ[1]);
  assert.deepEqual(Array.from(mesh.faceHeir), [-1, -1, 1]);
  for (let t = 0; t < 2; t++)
    for (let v = 0; v < 6; v++)
      assert.deepEqual(
        mesh.position(v, t),
        Q[t][v].map((q, c) => Math.fround(BMIN[c] + q * QUANT)),
        `vertex ${v} step ${t}`,
      );
});

test('refine and coarsen follow FORMAT.md (quad wing, triangle wing, moved face)', () => {
  const { mesh } = readDpm(FILE);
  const nav = new Navigator(mesh);
  const faces = () => Array.from({ length: nav.faceCount }, (_, f) => nav.face(f));
  assert.deepEqual(faces(), [[0, 1, 2], [1, 4, 3]]);
  assert.equal(nav.error, 0.5);
  nav.setLevel(1);
  assert.deepEqual(faces(), [[0, 5, 1, 2], [5, 4, 3], [5, 3, 1]]);
  assert.equal([nav.quadCount, nav.triangleCount, nav.error].join(), '1,2,0');
  const tri = new Uint32Array(18), edges = new Uint32Array(24);
  assert.deepEqual(updateIndices(nav, tri, edges), [0, 3]);
  assert.deepEqual(Array.from(tri.subarray(0, 6)), [0, 5, 1, 0, 1, 2]);
  assert.deepEqual(Array.from(edges.subarray(0, 8)), [0, 5, 5, 1, 1, 2, 2, 0]);
  nav.setLevel(0);
  assert.deepEqual(faces(), [[0, 1, 2], [1, 4, 3]]);
  assert.equal(nav.quadCount, 0);
});

test('positions at a fractional step interpolate linearly', () => {
  const { mesh } = readDpm(FILE);
  const out = mesh.positionsAt(0.25, 6, new Float32Array(18));
  for (let v = 0; v < 6; v++)
    for (let c = 0; c < 3; c++) {
      const p0 = BMIN[c] + Q[0][v][c] * QUANT, p1 = BMIN[c] + Q[1][v][c] * QUANT;
      assert.ok(Math.abs(out[3 * v + c] - (0.75 * p0 + 0.25 * p1)) < 1e-6);
    }
});

test('every prefix is a coarser file; byte-at-a-time streaming gives the same mesh', () => {
  let levels = [];
  for (let n = 0; n <= FILE.length; n++) {
    const d = new DpmDecoder();
    d.push(FILE.subarray(0, n));
    levels.push(d.mesh ? d.mesh.vertexCountLoaded : -1);
    if (n < FILE.length) assert.equal(d.complete, false);
  }
  assert.equal(levels[HEAD_END - 1], -1);
  assert.equal(levels[HEAD_END], 0);
  assert.equal(levels.at(-1), 6);
  assert.ok(levels.includes(5));
  const seen = [];
  const d = new DpmDecoder({
    onBase: (m) => seen.push(`base ${m.vertexCountLoaded}`),
    onSplits: (m, s, n) => seen.push(`splits ${s}+${n}`),
    onEnd: () => seen.push('end'),
  });
  for (let i = 0; i < FILE.length; i++) d.push(FILE.subarray(i, i + 1));
  assert.deepEqual(seen, ['base 5', 'splits 0+1', 'end']);
});

test('damage is reported with its byte, not decoded', () => {
  const bad = FILE.slice();
  bad[HEAD_END + 30] ^= 1;  // inside FDEF's payload
  assert.throws(() => readDpm(bad, 'x.dpm'), /x\.dpm: byte \d+: FDEF chunk: wrong checksum/);
  const magic = FILE.slice();
  magic[1] = 0x45;
  assert.throws(() => readDpm(magic), /wrong magic/);
  const tag = FILE.slice();
  tag[HEAD_END] = 0x78;  // "xDEF": not a tag a later version may add (A–Z, 0–9, space)
  assert.throws(() => readDpm(tag), /unknown chunk tag/);
});

test('a zstd chunk is decoded only when its one frame declares the chunk\'s raw size', () => {
  const plain = readDpm(FILE).mesh;
  const packed = readDpm(makeFile((p) => zstdFrame(p))).mesh;
  assert.deepEqual(Array.from(packed.nodeId), Array.from(plain.nodeId));
  assert.deepEqual(packed.position(4, 1), plain.position(4, 1));
  // A frame declaring 1 GiB in a chunk whose header says ~100 bytes: fzstd would allocate the
  // gigabyte before the size check after decompression.
  const bomb = makeFile((p) => zstdFrame(p, { declared: 2 ** 30, sizeBytes: 4 }));
  assert.throws(() => readDpm(bomb, 'x.dpm'),
    /x\.dpm: byte \d+: BASE chunk: the zstd frame declares 1073741824 bytes, the chunk header \d+/);
  const second = makeFile((p) => Uint8Array.from([...zstdFrame(p), ...zstdFrame(p)]));
  assert.throws(() => readDpm(second), /BASE chunk: bytes after the zstd frame/);
  const noSize = makeFile((p) => zstdFrame(p).map((x, i) => (i === 4 ? 0x00 : x)));
  assert.throws(() => readDpm(noSize), /BASE chunk: the zstd frame does not declare its size/);
});

// ---------------------------------------------------------------------------------------------
// Fields

test('an unknown optional chunk is skipped; one before HEAD or with a bad checksum is not', () => {
  const { mesh } = readDpm(makeFile(null, { extra: 'NOTE' }));
  assert.equal(mesh.complete, true);
  assert.equal(mesh.fields.length, 2);
  const damaged = makeFile(null, { extra: 'NOTE' });
  damaged[HEAD_END + 24] ^= 1;
  assert.throws(() => readDpm(damaged), /NOTE chunk: wrong checksum/);
  const withoutFields = readDpm(makeFile(null, { fields: false })).mesh;
  assert.equal(withoutFields.fields.length, 0);
  assert.equal(withoutFields.vertexCountLoaded, 6);
});

test('a HEAD that lists fields is from an older dynpm', () => {
  const old = FILE.slice();
  old[12 + 24 + 24] = 1;  // field_count
  const view = new DataView(old.buffer);
  view.setUint32(12 + 16, crc32(old.subarray(36, HEAD_END)), true);
  assert.throws(() => readDpm(old, 'x.dpm'), /x\.dpm: byte 36: .*written by an older dynpm: build it again/);
});

test('a SPLT whose FLDS has not arrived is not applied', () => {
  const ends = [];  // chunk ends
  for (let at = 12; at < FILE.length; ) {
    at += 24 + new DataView(FILE.buffer).getUint32(at + 8, true);
    ends.push(at);
  }
  // HEAD, FDEF, BASE, FLDS, SPLT, FLDS, END
  const loaded = (n) => readDpm(FILE.subarray(0, n)).mesh;
  assert.equal(loaded(ends[2]).hasBase, false, 'BASE without its FLDS');
  assert.equal(loaded(ends[3]).vertexCountLoaded, 5);
  assert.equal(loaded(ends[4]).vertexCountLoaded, 5, 'SPLT without its FLDS');
  assert.equal(loaded(ends[5] - 1).vertexCountLoaded, 5);
  assert.equal(loaded(ends[5]).vertexCountLoaded, 6);
});

test('field values in 16 bits where every value the decoder accepts fits, else in 32', () => {
  const { mesh } = readDpm(FILE);
  const [stress, peeq] = mesh.fields;
  assert.ok(stress.q.every((a) => a instanceof Int16Array), 'quantized, 31 steps of 0.5');
  assert.ok(peeq.q.every((a) => a instanceof Int32Array), 'lossless: f32 bit patterns');
  assert.deepEqual(Array.from(stress.valuesAt(1, 6)), STRESS[1]);
  // The decoder accepts [−2, (max − min) / quant_step + 2]: 16 bits while that ends at 32767.
  const def = (max, quantStep) => ({ lossless: false, min: 0, max, quantStep });
  assert.equal(valueArrayType(def(32765, 1)), Int16Array);
  assert.equal(valueArrayType(def(32765.5, 1)), Int32Array);
  assert.equal(valueArrayType(def(1, 2 * 0.001)), Int16Array, 'the default bound, 0.1 % of the range');
  assert.equal(valueArrayType({ lossless: true, min: 0, max: 1, quantStep: 0 }), Int32Array);
});

test('shown values: max |value| and mean of what each vertex and face stands for', () => {
  const { mesh } = readDpm(FILE);
  const [stress, peeq] = mesh.fields;
  const shown = (field, aggregate, t, k) => {
    const s = new ShownValues(mesh, field, aggregate);
    s.set(t, k);
    return Array.from(s.values.subarray(0, s.itemCount(k)));
  };
  // Coarse: vertex 1 stands for 1 and 5; face 1 for faces 1 and 2.
  assert.deepEqual(shown(stress, 'max', 1, 0), [10, 15.5, 12, 14, 15]);
  assert.deepEqual(shown(stress, 'mean', 1, 0), [10, 14.75, 12, 14, 15]);
  assert.deepEqual(shown(peeq, 'max', 0, 0), [1, -4]);
  assert.deepEqual(shown(peeq, 'max', 1, 0), [1.5, 4]);
  assert.deepEqual(shown(peeq, 'mean', 0, 0), [1, -0.5]);
  assert.deepEqual(shown(stress, 'max', 1, 1), STRESS[1]);
  assert.deepEqual(shown(peeq, 'mean', 1, 1), PEEQ[1]);
  // Refining and coarsening in place give what the direct pass gives.
  for (const field of mesh.fields)
    for (const aggregate of ['max', 'mean']) {
      const s = new ShownValues(mesh, field, aggregate);
      s.set(1, 0);
      s.setLevel(1);
      assert.deepEqual(Array.from(s.values.subarray(0, s.itemCount(1))), shown(field, aggregate, 1, 1));
      s.setLevel(0);
      assert.deepEqual(Array.from(s.values.subarray(0, s.itemCount(0))), shown(field, aggregate, 1, 0));
    }
  const nav = new Navigator(mesh);
  assert.equal(nav.fieldError(0), Math.fround(0.3));
  nav.setLevel(1);
  assert.equal(nav.fieldError(1), 0);
});

test('a file of version 1 to 6 is refused with what to do about it', () => {
  for (const version of [1, 2, 3, 4, 5, 6]) {
    const old = FILE.slice();
    old[8] = version;
    assert.throws(() => readDpm(old, 'old.dpm'), new RegExp(
      `^Error: old\\.dpm: byte 8: written by an older dynpm \\(version ${version}\\): build it again$`));
  }
});
