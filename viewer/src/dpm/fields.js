// Result fields of a .dpm (docs/FORMAT.md "Fields: FDEF and FLDS"): the FDEF chunk (names, units,
// node or element, range, quantization) and the FLDS chunks (heirs of the faces a SPLT creates,
// field errors per split, values per step), with the checks the C++ reader makes
// (src/progressive/dpm_read.cpp). Values are kept as the file's quantized integers, one typed
// array per step (valueArrayType(): 16 bits where they fit; f32 bit patterns when lossless).

import { bucket, CONTEXTS, LOSSLESS_RESIDUAL, residualFits } from './positions.js';
import { bitModels, decodeSigned, RangeDecoder, SIGNED_MODEL_SIZE } from './range_coder.js';

export const FIELD_NODE = 0;
export const FIELD_ELEMENT = 1;
const FIELD_FLAG_LOSSLESS = 1;
// The fewest bytes of one field in FDEF: two string lengths, location, flags, reserved, min,
// max, quant_step, max_error, base_error (a name has at least one byte).
const MIN_FIELD_DEF_BYTES = 2 + 1 + 2 + 1 + 1 + 2 + 4 * 8 + 4;
const MAX_NAME_BYTES = 255;

// The typed array that holds a field's values: a quantized value lies in [−2, (max − min) /
// quant_step + 2] (the decoder refuses any other before storing it), so at the default bound
// (0.1 % of the range: about 500 steps) and down to 1/16383 of the range an Int16Array holds it
// in half the memory; lossless values (f32 bit patterns) and finer grids take 32 bits.
export function valueArrayType(def) {
  return !def.lossless && valueTop(def) <= 0x7fff ? Int16Array : Int32Array;
}

// The largest quantized value a reader accepts (the smallest is −2): the range's grid steps and two.
const valueTop = ({ min, max, quantStep }) => (max - min) / (quantStep || 1) + 2;

// One field (C++: ProgressiveField). q[t]: per item (vertex of a node field, face of an element
// field) its quantized value at step t; error[i]: the field error right after split i.
export class DpmField {
  constructor(def, stepCount, itemCount, splitCount) {
    Object.assign(this, def);
    this.q = [];
    // Each step's values of the items that have arrived (ProgressiveMesh.makeRoom()).
    const Values = valueArrayType(def);
    for (let t = 0; t < stepCount; t++) this.q.push(new Values(0));
    this.error = new Float32Array(splitCount);
  }
  get perFace() {
    return this.location === FIELD_ELEMENT;
  }
  // The field error of the level with k splits applied, a fraction of max − min.
  levelError(k) {
    return k === 0 ? this.baseError : this.error[k - 1];
  }
  // Values of items [0, n) at whole step t, as the f32 the file means, into out.
  valuesAt(t, n, out = new Float32Array(n)) {
    const q = this.q[t];
    if (this.lossless) {
      out.set(new Float32Array(q.buffer, q.byteOffset, n));
      return out;
    }
    const { min, quantStep } = this;
    for (let i = 0; i < n; i++) out[i] = min + q[i] * quantStep;  // f64, rounded by the store
    return out;
  }
}

// FDEF: the field definitions; mesh.fields is set (with room for every item at every step),
// and mesh.faceHeir when a field is per element.
export function parseFieldDefs(r, mesh) {
  const h = mesh.head;
  const count = r.u32();
  if (count === 0) r.fail('FDEF lists no fields');
  if (r.remaining() < count * MIN_FIELD_DEF_BYTES) r.fail(`${count} fields do not fit in FDEF`);
  const fields = [];
  for (let k = 0; k < count; k++) {
    const where = `field ${k}`;
    const nameBytes = textBytes(r);
    if (nameBytes.length === 0 || nameBytes.length > MAX_NAME_BYTES) r.fail(`${where}: name of ${nameBytes.length} bytes`);
    const unitBytes = textBytes(r);
    if (unitBytes.length > MAX_NAME_BYTES) r.fail(`${where}: unit of ${unitBytes.length} bytes`);
    // Shown as text (bytes that are not UTF-8 as U+FFFD); the bytes as the file has them.
    const name = new TextDecoder().decode(nameBytes), unit = new TextDecoder().decode(unitBytes);
    const location = r.u8();
    if (location !== FIELD_NODE && location !== FIELD_ELEMENT) r.fail(`${where}: location ${location}`);
    const flags = r.u8();
    if (flags & ~FIELD_FLAG_LOSSLESS) r.fail(`${where}: unknown flags ${flags}`);
    const reserved = r.u16();
    if (reserved !== 0) r.fail(`${where}: reserved field is ${reserved}, not 0`);
    const min = r.f64(), max = r.f64(), quantStep = r.f64(), maxError = r.f64();
    const baseError = r.f32();
    const lossless = (flags & FIELD_FLAG_LOSSLESS) !== 0;
    if (!(Number.isFinite(min) && Number.isFinite(max) && min <= max))
      r.fail(`${where}: range [${min}, ${max}] is not finite numbers min ≤ max`);
    // As for positions (FORMAT.md "Quantization"): a grid float32 holds at the range's ends.
    const c = Math.max(Math.abs(min), Math.abs(max));
    if (lossless ? quantStep !== 0 || maxError !== 0
      : !(quantStep > 0 && quantStep < Infinity && quantStep >= 4 * c * 2 ** -23))
      r.fail(`${where}: quant_step ${quantStep} is not valid`);
    if (!(maxError >= 0 && maxError < Infinity)) r.fail(`${where}: max_error ${maxError}`);
    if (!(baseError >= 0 && baseError <= 1)) r.fail(`${where}: base_error ${baseError} not in [0, 1]`);
    fields.push({ name, nameBytes, unit, location, lossless, min, max, quantStep, maxError, baseError });
  }
  if (r.remaining() !== 0) r.fail(`${r.remaining()} bytes left over at the end of FDEF`);
  mesh.fields = fields.map((d) => new DpmField(d, h.stepCount,
    d.location === FIELD_ELEMENT ? h.faceCount : h.vertexCount, h.splitCount));
  if (mesh.fields.some((f) => f.perFace)) mesh.faceHeir = new Int32Array(h.faceCount).fill(-1);
}

// A u16-length text's bytes.
function textBytes(r) {
  const n = r.u16();
  r.need(n);
  r.pos += n;
  return r.bytes.slice(r.pos - n, r.pos);
}

// A split section's predictor at t > 0 (FORMAT.md "Fields"): the parent's (heir's) change, or
// the median change of the vertex's ring (node fields on a grid only).
const PREDICTOR_PARENT = 0;
const PREDICTOR_RING_MEDIAN = 1;
const MAX_MEDIAN_RING = 16;  // ring vertices a median reads, the first in ascending order

// The models of the field sections after SPLTs: per field, one array per step (a SignedModel
// per context), continued from FLDS to FLDS.
export function fieldModels(mesh) {
  return mesh.fields.map(() => Array.from({ length: mesh.head.stepCount },
    () => bitModels(CONTEXTS * SIGNED_MODEL_SIZE)));
}

// The most bytes the FLDS after BASE (n = 0) or after a SPLT of splits [s, s + n) can hold, each
// value at its longest encoding (10 bytes a varint).
export function maxFieldValueBytes(mesh, s, n) {
  const h = mesh.head;
  const created = n ? mesh.faceCountAt[s + n] - mesh.faceCountAt[s] : 0;
  const vertices = n || h.baseVertexCount;
  const faces = n ? created : h.baseFaceCount;
  let limit = 8 + (mesh.faceHeir ? 10 * created : 0);
  // After a SPLT, a step's section: a predictor, a size, 5 flushed bytes and at most 64 bytes a
  // value (C++ kMaxCodedInteger); after BASE, varints.
  for (const f of mesh.fields) {
    const items = f.perFace ? faces : vertices;
    limit += n ? 4 * n + h.stepCount * (10 + 64 * items) : 10 * h.stepCount * items;
  }
  return limit;
}

// FLDS: the values (and heirs, errors) of the base mesh (n = 0) or of splits [s, s + n), which
// the SPLT before it has decoded with `stencils` (its rings); `models`: fieldModels(mesh).
export function parseFieldValues(r, mesh, s, n, stencils, models) {
  const first = r.u32();
  const count = r.u32();
  if (first !== (n ? s : 0) || count !== n)
    r.fail(`first_split ${first} and count ${count}, the ${n ? 'SPLT' : 'BASE'} before: ${n ? s : 0} and ${n}`);
  const h = mesh.head;
  const b = h.baseVertexCount;
  const { faceCountAt, faceHeir } = mesh;
  const faces = n ? [faceCountAt[s], faceCountAt[s + n]] : [0, h.baseFaceCount];
  if (n && faceHeir) {
    for (let i = s; i < s + n; i++) {
      const F = faceCountAt[i];
      for (let g = F; g < faceCountAt[i + 1]; g++) {
        const d = r.varint();
        if (d > F - 1) r.fail(`face ${g}: heir ${F - 1 - d} is not a face before split ${i}`);
        faceHeir[g] = F - 1 - d;
      }
    }
  }
  mesh.fields.forEach((f, index) => {
    const [first, end] = f.perFace ? faces : [n ? b + s : 0, n ? b + s + n : b];
    const [parent, offset] = f.perFace ? [faceHeir, 0] : [mesh.parent, b];
    if (!n) return parseBaseValues(r, f, end);
    parseErrors(r, f, s, n);
    const start = r.pos;
    const sections = [];
    for (let t = 0; t < h.stepCount; t++) {
      const predictor = r.u8();
      const size = r.u32();
      r.need(size);
      sections.push({ predictor, bytes: r.bytes.subarray(r.pos, r.pos + size) });
      r.pos += size;
    }
    const ring = f.perFace ? null : { stencils, first: b + s };
    const problem = decodeSplitField(f, first, end, parent, offset, ring, models[index], sections);
    if (problem) {
      r.pos = start;
      r.fail(`${f.name}: ${problem}`);
    }
  });
  if (r.remaining() !== 0) r.fail(`${r.remaining()} bytes left over at the end of FLDS`);
}

function parseErrors(r, f, s, n) {
  let last = f.levelError(s);
  for (let i = s; i < s + n; i++) {
    const e = r.f32();
    if (!(e >= 0 && e <= last)) r.fail(`${f.name}: field error ${e} after split ${i} (before: ${last})`);
    f.error[i] = last = e;
  }
}

// The values of the base mesh's items [0, end) as FORMAT.md "Fields" codes them after BASE: each
// against the previous item at step 0 and its own previous step later (as the base positions).
function parseBaseValues(r, f, end) {
  const checked = !f.lossless;
  const top = valueTop(f);
  for (let t = 0; t < f.q.length; t++) {
    const cur = f.q[t];
    const asFloat = f.lossless ? new Float32Array(cur.buffer) : null;
    const prev = t > 0 ? f.q[t - 1] : null;
    for (let v = 0; v < end; v++) {
      const residual = r.svarint();
      if (!residualFits(residual, f.lossless)) r.fail(`${f.name}: item ${v} step ${t}: ${LOSSLESS_RESIDUAL}`);
      const x = residual + (t > 0 ? prev[v] : v > 0 ? cur[v - 1] : 0);
      if (checked && (x < -2 || x > top))
        r.fail(`${f.name}: item ${v} step ${t}: a value far outside [min, max]`);
      cur[v] = x;  // lossless: Int32Array wraps modulo 2^32, as the residual arithmetic requires
      // A lossless value is a finite f32 within [min, max].
      if (!checked && !(asFloat[v] >= f.min && asFloat[v] <= f.max))
        r.fail(`${f.name}: item ${v} step ${t}: a value outside [min, max]`);
    }
  }
}

// A split chunk's values of field f, items [first, end), section t for step t; the guess at t > 0
// is the parent's change or the ring's median change, as each section says (FORMAT.md
// "Fields"; C++ field_coding.cpp). `ring`: the chunk's stencils and its first split vertex
// (null for an element field). Returns null or what is wrong.
function decodeSplitField(f, first, end, parent, offset, ring, models, sections) {
  const checked = !f.lossless;
  const top = valueTop(f);
  const before = new Float64Array(end - first);  // the residuals at t − 1
  const change = new Float64Array(MAX_MEDIAN_RING);
  const ringStart = ring?.stencils.ringStart, data = ring?.stencils.ring.data;
  for (let t = 0; t < sections.length; t++) {
    const { predictor, bytes } = sections[t];
    if (predictor !== PREDICTOR_PARENT &&
        !(predictor === PREDICTOR_RING_MEDIAN && t > 0 && ring && checked))
      return `step ${t}: predictor ${predictor} is not valid here`;
    const d = new RangeDecoder(bytes);
    const cur = f.q[t];
    const prev = t > 0 ? f.q[t - 1] : null;
    const asFloat = f.lossless ? new Float32Array(cur.buffer) : null;
    for (let v = first; v < end; v++) {
      const e = v - first;
      const r = decodeSigned(d, models[t], (t > 0 ? bucket(before[e]) : 0) * SIGNED_MODEL_SIZE);
      if (!d.ok()) return `step ${t}: the values are cut short`;
      if (!residualFits(r, f.lossless)) return `step ${t}: item ${v}: ${LOSSLESS_RESIDUAL}`;
      let guess;
      if (t === 0) guess = cur[parent[v - offset]];
      else if (predictor === PREDICTOR_PARENT) {
        const j = parent[v - offset];
        guess = prev[v] + cur[j] - prev[j];
      } else {
        const k = v - ring.first;
        const count = Math.min(ringStart[k + 1] - ringStart[k], MAX_MEDIAN_RING);
        for (let j = 0; j < count; j++) {
          const u = data[ringStart[k] + j];
          change[j] = cur[u] - prev[u];
        }
        guess = prev[v] + lowerMedian(change, count);
      }
      const x = guess + r;
      if (checked && (x < -2 || x > top)) return `step ${t}: item ${v}'s value is far outside the field's range`;
      cur[v] = x;  // lossless: Int32Array wraps modulo 2^32, as the residual arithmetic requires
      if (!checked && !(asFloat[v] >= f.min && asFloat[v] <= f.max))
        return `step ${t}: item ${v}'s value is far outside the field's range`;
      before[e] = r;
    }
    if (!d.exhausted()) return `step ${t}: the values leave bytes unread`;
  }
  return null;
}

// The lower median of a[0, n): the ((n − 1) / 2)-th smallest (insertion sort: n ≤ 16).
function lowerMedian(a, n) {
  for (let i = 1; i < n; i++) {
    const x = a[i];
    let j = i;
    for (; j > 0 && a[j - 1] > x; j--) a[j] = a[j - 1];
    a[j] = x;
  }
  return a[(n - 1) >> 1];
}
