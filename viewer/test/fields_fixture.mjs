// Adds result fields to a .dpm that has none, written here from docs/FORMAT.md "Fields: FDEF and
// FLDS" (not by the C++ writer): an FDEF after HEAD and an FLDS after BASE and after each SPLT,
// the other chunks kept byte for byte. After a SPLT every section takes the parent's (heir's)
// change (predictor 0; a writer may choose it for any section). For tests and the docs' screenshots of the viewer, on
// models whose inputs carry no element field. Heirs: a quad wing of the split, else a moved face,
// else any face that holds the parent before it; field errors computed as FORMAT.md defines them.
import { crc32 } from 'node:zlib';

import { DpmDecoder, Navigator } from '../src/dpm.js';
import { SignedModel } from '../src/dpm/range_coder.js';
import { encodeSigned, RangeEncoder } from './range_encoder.mjs';

// Little-endian bytes of FORMAT.md's types, for writing test files.
export class Bytes {
  constructor() {
    this.b = [];
  }
  u8(v) {
    this.b.push(v & 0xff);
  }
  u16(v) {
    this.u8(v), this.u8(v >> 8);
  }
  u32(v) {
    for (let i = 0; i < 4; i++) this.u8(v >>> (8 * i));
  }
  f32(v) {
    const d = new DataView(new ArrayBuffer(4));
    d.setFloat32(0, v, true);
    for (let i = 0; i < 4; i++) this.u8(d.getUint8(i));
  }
  f64(v) {
    const d = new DataView(new ArrayBuffer(8));
    d.setFloat64(0, v, true);
    for (let i = 0; i < 8; i++) this.u8(d.getUint8(i));
  }
  varint(v) {
    while (v >= 0x80) this.u8((v & 0x7f) | 0x80), (v = Math.floor(v / 128));
    this.u8(v);
  }
  svarint(v) {
    this.varint(v >= 0 ? 2 * v : -2 * v - 1);
  }
  string(s) {
    const e = new TextEncoder().encode(s);
    this.u16(e.length), e.forEach((x) => this.u8(x));
  }
  get bytes() {
    return Uint8Array.from(this.b);
  }
}

export function chunkBytes(tag, payload) {
  const out = new Uint8Array(24 + payload.length);
  const view = new DataView(out.buffer);
  for (let i = 0; i < 4; i++) out[i] = tag.charCodeAt(i);
  view.setUint32(8, payload.length, true);
  view.setUint32(12, payload.length, true);
  view.setUint32(16, crc32(payload), true);
  out.set(payload, 24);
  return out;
}

// [{tag, bytes}] of every chunk, header included (the file's magic and version are bytes 0–11).
export function rawChunks(file) {
  const view = new DataView(file.buffer, file.byteOffset, file.byteLength);
  const out = [];
  for (let at = 12; at + 24 <= file.length; ) {
    const end = at + 24 + view.getUint32(at + 8, true);
    out.push({ tag: String.fromCharCode(...file.subarray(at, at + 4)), bytes: file.subarray(at, end) });
    at = end;
  }
  return out;
}

function heirs(mesh) {
  const heir = new Int32Array(mesh.head.faceCount).fill(-1);
  const nav = new Navigator(mesh);
  for (let i = 0; i < mesh.splitsLoaded; i++) {
    const first = mesh.faceCountAt[i], end = mesh.faceCountAt[i + 1];
    if (end > first) {
      let h = -1;
      for (let j = mesh.wingStart[i]; j < mesh.wingStart[i + 1] && h < 0; j++)
        if (!(mesh.wingFlags.data[j] & 1)) h = mesh.wingFace.data[j];
      if (h < 0 && mesh.movedStart[i + 1] > mesh.movedStart[i]) h = mesh.movedFaces.data[mesh.movedStart[i]];
      for (let f = 0; f < first && h < 0; f++) if (nav.face(f).includes(mesh.parent[i])) h = f;
      heir.fill(h, first, end);
    }
    nav.setLevel(i + 1);
  }
  return heir;
}

// The field errors (FORMAT.md "Field errors") of every level: per item and step the smallest and
// largest value it stands for, coarsening from the full mesh.
function fieldErrors(mesh, values, perFace, heir, range) {
  const S = mesh.splitsLoaded, m = values.length, b = mesh.head.baseVertexCount;
  const lo = values.map((v) => Float64Array.from(v)), hi = values.map((v) => Float64Array.from(v));
  const errors = new Float32Array(S);
  let worst = 0;
  for (let i = S - 1; i >= 0; i--) {
    errors[i] = range > 0 ? worst / range : 0;
    const merges = perFace
      ? Array.from({ length: mesh.faceCountAt[i + 1] - mesh.faceCountAt[i] }, (_, k) => [heir[mesh.faceCountAt[i] + k], mesh.faceCountAt[i] + k])
      : [[mesh.parent[i], b + i]];
    for (const [into, from] of merges)
      for (let t = 0; t < m; t++) {
        lo[t][into] = Math.min(lo[t][into], lo[t][from]);
        hi[t][into] = Math.max(hi[t][into], hi[t][from]);
        worst = Math.max(worst, hi[t][into] - lo[t][into]);
      }
  }
  return { errors, base: range > 0 ? worst / range : 0 };
}

// fields: [{name, unit, perFace, value(item, t, mesh) → number}] (items in the progressive
// numbering). Returns the new file's bytes.
export function withFields(file, fields, { bound = 0.001 } = {}) {
  const chunkSplits = [];  // [first, count] of each SPLT, in order
  const decoder = new DpmDecoder({ name: 'fixture', onSplits: (_, s, n) => chunkSplits.push([s, n]) });
  decoder.push(file);
  const { mesh } = decoder;
  const h = mesh.head, m = h.stepCount, b = h.baseVertexCount;
  const heir = fields.some((f) => f.perFace) ? heirs(mesh) : null;
  const defs = new Bytes();
  defs.u32(fields.length);
  const coded = fields.map((f) => {
    const n = f.perFace ? h.faceCount : h.vertexCount;
    const values = Array.from({ length: m }, (_, t) => Float32Array.from({ length: n }, (_, x) => f.value(x, t, mesh)));
    let min = Infinity, max = -Infinity;
    for (const row of values) for (const x of row) (min = Math.min(min, x)), (max = Math.max(max, x));
    const c = Math.max(Math.abs(min), Math.abs(max));
    let step = Math.max(2 * bound * (max - min), 4 * c * 2 ** -23);
    if (step === 0) step = 1;
    const q = values.map((row) => Int32Array.from(row, (x) => Math.round((x - min) / step)));
    const { errors, base } = fieldErrors(mesh, values, f.perFace, heir, max - min);
    defs.string(f.name), defs.string(f.unit ?? ''), defs.u8(f.perFace ? 1 : 0), defs.u8(0), defs.u16(0);
    defs.f64(min), defs.f64(max), defs.f64(step), defs.f64(step / 2), defs.f32(base);
    return { ...f, q, errors };
  });
  // The split sections' models: per field and step, a SignedModel per context, continued from
  // FLDS to FLDS.
  const models = coded.map(() => Array.from({ length: m }, () => [0, 1, 2, 3, 4].map(() => new SignedModel())));
  const bucket = (r) => (r === 0 ? 0 : Math.min(Math.floor(Math.log2(Math.abs(r))) + 1, 4));
  // One FLDS: items [first, end) of each field; after BASE svarints, after a SPLT a range-coded
  // section per step, each item predicted from its parent (heir).
  const flds = (s, n) => {
    const out = new Bytes();
    out.u32(s), out.u32(n);
    const faces = n ? [mesh.faceCountAt[s], mesh.faceCountAt[s + n]] : [0, h.baseFaceCount];
    if (n && heir) for (let g = faces[0]; g < faces[1]; g++) {
      let i = s;
      while (mesh.faceCountAt[i + 1] <= g) i++;
      out.varint(mesh.faceCountAt[i] - 1 - heir[g]);
    }
    coded.forEach((f, index) => {
      const [first, end] = f.perFace ? faces : n ? [b + s, b + s + n] : [0, b];
      const parent = (x) => (f.perFace ? heir[x] : mesh.parent[x - b]);
      const residual = (x, t) => {
        const q = f.q[t], p = f.q[t - 1];
        return t ? q[x] - p[x] - (q[parent(x)] - p[parent(x)]) : q[x] - q[parent(x)];
      };
      if (!n) {
        for (let t = 0; t < m; t++)
          for (let x = first; x < end; x++) out.svarint(t ? f.q[t][x] - f.q[t - 1][x] : f.q[0][x] - (x ? f.q[0][x - 1] : 0));
        return;
      }
      for (let i = s; i < s + n; i++) out.f32(f.errors[i]);
      for (let t = 0; t < m; t++) {
        const e = new RangeEncoder();
        for (let x = first; x < end; x++)
          encodeSigned(e, models[index][t][t ? bucket(residual(x, t - 1)) : 0], residual(x, t));
        const bytes = e.finish();
        out.u8(0), out.u32(bytes.length);
        bytes.forEach((c) => out.u8(c));
      }
    });
    return chunkBytes('FLDS', out.bytes);
  };
  const parts = [file.subarray(0, 12)];
  let splits = 0;  // SPLT chunks so far
  for (const c of rawChunks(file)) {
    parts.push(c.bytes);
    if (c.tag === 'HEAD') parts.push(chunkBytes('FDEF', defs.bytes));
    if (c.tag === 'BASE') parts.push(flds(0, 0));
    if (c.tag === 'SPLT') parts.push(flds(...chunkSplits[splits++]));
  }
  const out = new Uint8Array(parts.reduce((a, p) => a + p.length, 0));
  let at = 0;
  for (const p of parts) out.set(p, at), (at += p.length);
  return out;
}

// Fields for the browser test and the docs' screenshots, from the motion: a nodal 'stress' [MPa]
// from each vertex's displacement, and an element 'plastic strain' [mm/mm] from its corners'
// mean displacement past a threshold (zero where the part has not moved much).
const displacement = (m, v, t) => {
  const p = m.position(v, t), q = m.position(v, 0);
  return Math.hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]);
};
const fullFaces = new WeakMap();
function cornersOf(m, f) {
  if (!fullFaces.has(m)) {
    const nav = new Navigator(m);
    nav.setLevel(m.splitsLoaded);
    fullFaces.set(m, nav);
  }
  return fullFaces.get(m).face(f);
}
export const DEMO_FIELDS = [
  { name: 'stress', unit: 'MPa', perFace: false, value: (v, t, m) => 40 * displacement(m, v, t) },
  {
    name: 'plastic strain', unit: 'mm/mm', perFace: true,
    value: (f, t, m) => {
      const c = cornersOf(m, f);
      const u = c.reduce((a, v) => a + displacement(m, v, t), 0) / c.length;
      return Math.max(0, u - 2) * 0.004;
    },
  },
];
