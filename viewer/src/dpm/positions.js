// The positions of a SPLT's new vertices (docs/FORMAT.md "Positions"): one range-coded section
// per step, predicted from the split's quad wings (a parallelogram) at step 0 and later from the
// vertex's own previous position moved as its ring moves (a fitted linear map). The C++ side is
// src/progressive/position_coding.cpp; both follow FORMAT.md.
//
// Speed: one loop per kind of step (step 0, later steps, lossless), the three coordinates of a
// vertex side by side, every model of a step in one Uint16Array, nothing allocated per vertex.
import { Growable } from './bytes.js';
import { bitModels, decodeSigned, RangeDecoder, SIGNED_MODEL_SIZE } from './range_coder.js';
import { WING_SLOT_SHIFT, WING_WAS_TRIANGLE } from './progressive_mesh.js';

// A lossless residual is a signed 32-bit value (FORMAT.md "Positions"): one outside is refused
// (a number is exact below 2^53 only; the C++ reader wraps 64 bits: dpm_format.h residual_fits).
export const residualFits = (r, lossless) => !lossless || (r >= -0x80000000 && r <= 0x7fffffff);
export const LOSSLESS_RESIDUAL = 'a lossless residual outside 32 bits';

// A residual's contexts, as the field sections' (fields.js): the bucket of the same item's
// residual at the step before.
export const CONTEXTS = 5;
// The SignedModel of coordinate c in context x starts at (c · CONTEXTS + x) · SIGNED_MODEL_SIZE.
const COORDINATE_MODELS = CONTEXTS * SIGNED_MODEL_SIZE;

// The models of the position sections, one array per step (coordinate, then context), continued
// from SPLT to SPLT.
export function positionModels(steps) {
  return Array.from({ length: steps }, () => bitModels(3 * COORDINATE_MODELS));
}

// What predicts the new vertices of a SPLT, from the faces right after each split: per split
// (stencilAfterSplit) its parent, its quad wings' w and x (the corner opposite v0), and its ring,
// the vertices sharing an edge with v0 (a set, in ring from ringStart[k]).
export class ChunkStencils {
  constructor(n) {
    this.split = new Int32Array(10 * n);  // parent, quads, w0, x0, …, w3, x3
    this.ringStart = new Int32Array(n + 1);
    this.ring = new Growable(Int32Array, 8 * n);
  }
  add(mesh, k, i, corners) {
    const s = 10 * k;
    const v0 = mesh.head.baseVertexCount + i;
    const ring = this.ring;
    const first = ring.length;
    this.split[s] = mesh.parent[i];
    ring.push(mesh.parent[i]);
    let quads = 0;
    for (let j = mesh.wingStart[i]; j < mesh.wingStart[i + 1]; j++) {
      const flags = mesh.wingFlags.data[j];
      this.addToRing(first, mesh.wingVertex.data[j]);
      if (flags & WING_WAS_TRIANGLE) continue;
      const slot = (flags >> WING_SLOT_SHIFT) & 3;
      this.split[s + 2 + 2 * quads] = mesh.wingVertex.data[j];
      this.split[s + 3 + 2 * quads] = corners[4 * mesh.wingFace.data[j] + ((slot + 2) & 3)];
      quads++;
    }
    this.split[s + 1] = quads;
    for (let j = mesh.movedStart[i]; j < mesh.movedStart[i + 1]; j++) {
      const f = 4 * mesh.movedFaces.data[j];
      const d = corners[f + 3] < 0 ? 3 : 4;
      for (let c = 0; c < d; c++) {
        if (corners[f + c] !== v0) continue;
        this.addToRing(first, corners[f + (c + 1 === d ? 0 : c + 1)]);
        this.addToRing(first, corners[f + (c === 0 ? d - 1 : c - 1)]);
      }
    }
    // Ascending, as position_coding.cpp keeps it: the ring fit sums in this order.
    const data = ring.data;
    for (let j = first + 1; j < ring.length; j++) {
      const u = data[j];
      let h = j;
      for (; h > first && data[h - 1] > u; h--) data[h] = data[h - 1];
      data[h] = u;
    }
    this.ringStart[k + 1] = ring.length;
  }
  // u into the ring that starts at first, unless it is there (a ring has about 6 vertices; the
  // rare long one, of a vertex with many faces, is searched through a Set).
  addToRing(first, u) {
    const ring = this.ring;
    if (ring.length - first > 32) {
      if (!this.long || this.longFirst !== first) {
        this.long = new Set(ring.data.subarray(first, ring.length));
        this.longFirst = first;
      }
      if (this.long.has(u)) return;
      this.long.add(u);
      ring.push(u);
      return;
    }
    const data = ring.data;
    for (let j = first; j < ring.length; j++) if (data[j] === u) return;
    ring.push(u);
  }
}

// The bucket of a residual's magnitude: the next residual's context.
export function bucket(r) {
  return 32 - Math.clz32(Math.min(Math.abs(r), 8));  // min(⌊log₂ |r|⌋ + 1, 4), without a branch
}

// ⌊(2 · sum + count) / (2 · count)⌋: the mean rounded half up (exact: |sum| < 2^40).
const roundedMean = (sum, count) => Math.floor((2 * sum + count) / (2 * count));

// A SPLT's positions are decoded into staging arrays, one per step, that hold the chunk's old
// vertices (those its stencils name from before the chunk, walked step by step out of the
// compact store: step_positions.js) and then its new ones; the stencils name them by their place
// there (localStencils). storePositions() then keeps the new ones compact. The job is what a
// second worker needs (positions_executor.js): plain arrays, the staging shared.
export function positionJob(mesh, s, n, stencils, sections, models, staging) {
  const { baseVertexCount: b, stepCount } = mesh.head;
  const local = localStencils(stencils, n, b + s);
  // Made anew (shared when it was) if it is too short, nothing copied: what it held is not
  // needed. A quarter more than asked: chunks a little longer than the last made it anew for 18
  // of the 66 chunks of the 1 M × 25 box.
  const need = 3 * (local.first + n) * stepCount;
  if (staging.length < need) {
    const length = Math.ceil(1.25 * need);
    staging = new Int32Array(staging.buffer instanceof ArrayBuffer ? length : new SharedArrayBuffer(4 * length));
  }
  return { head: mesh.head, lossless: mesh.lossless, positions: mesh.positions, s, n, stencils: local, models, sections, staging };
}

// The stencils with each vertex named by its place in the staging arrays: the old vertices
// first (ascending: the walk over them reads the compact arrays in order), then the chunk's own
// from `first` on. Rings keep their order (the ring fit sums in it).
let slotOf = new Int32Array(0);  // per vertex: its place among a job's old vertices, else −1
function localStencils(stencils, n, chunkFirst) {
  const { split, ringStart } = stencils;
  const ring = stencils.ring.data.subarray(0, stencils.ring.length);
  if (slotOf.length < chunkFirst) slotOf = new Int32Array(Math.max(chunkFirst, 2 * slotOf.length)).fill(-1);
  const found = [];
  const note = (v) => {
    if (v < chunkFirst && slotOf[v] < 0) (slotOf[v] = 0), found.push(v);
  };
  for (let k = 0; k < n; k++) {
    const st = 10 * k;
    note(split[st]);
    for (let j = 0; j < 2 * split[st + 1]; j++) note(split[st + 2 + j]);
  }
  for (let j = 0; j < ring.length; j++) note(ring[j]);
  const old = Int32Array.from(found).sort();
  for (let k = 0; k < old.length; k++) slotOf[old[k]] = k;
  const first = old.length, shift = first - chunkFirst;
  const at = (v) => (v >= chunkFirst ? v + shift : slotOf[v]);
  const local = new Int32Array(10 * n);
  for (let k = 0; k < n; k++) {
    const st = 10 * k;
    local[st] = at(split[st]);
    local[st + 1] = split[st + 1];
    for (let j = 0; j < 2 * split[st + 1]; j++) local[st + 2 + j] = at(split[st + 2 + j]);
  }
  const localRing = new Int32Array(ring.length);
  for (let j = 0; j < ring.length; j++) localRing[j] = at(ring[j]);
  for (let k = 0; k < old.length; k++) slotOf[old[k]] = -1;
  return { split: local, ringStart, ring: { data: localRing }, old, first };
}

// Step t's staging array of a job.
function stagingStep({ staging, stencils, n }, t) {
  const width = 3 * (stencils.first + n);
  return staging.subarray(t * width, (t + 1) * width);
}

// Decodes a job's positions (section t for step t, Uint8Arrays) into its staging arrays.
// Returns null or what is wrong.
export function decodeSplitPositions(job) {
  const { head, lossless, positions, s, n, stencils, models, sections } = job;
  const { baseVertexCount: b, bboxMin, bboxMax, quantStep, stepCount } = head;
  positions.gather(stencils.old, (t) => stagingStep(job, t));
  // Quantized positions lie within two grid steps of the box (position_coding.cpp checks it too).
  const top = [0, 1, 2].map((c) => (bboxMax[c] - bboxMin[c]) / quantStep + 2);
  let before = new Float64Array(3 * n);  // the residuals at t − 1
  let now = new Float64Array(3 * n);  // and at t
  for (let t = 0; t < stepCount; t++) {
    const d = new RangeDecoder(sections[t]);
    if (!d.ok()) return `the positions of step ${t} are cut short`;  // or do not start as coded
    const step = { d, m: models[t], cur: stagingStep(job, t), prev: t > 0 ? stagingStep(job, t - 1) : null, t,
      first: stencils.first, n, vertex0: b + s };
    const problem = lossless ? losslessStep(step, stencils, before)
      : t === 0 ? firstStep(step, stencils, before, top) : laterStep(step, stencils, before, now, top);
    if (problem) return problem;
    if (!lossless && t > 0) [before, now] = [now, before];
    if (!d.exhausted()) return `the positions of step ${t} leave bytes unread`;
  }
  return null;
}

// The new vertices of a decoded job into its mesh's compact store (room made for them).
export function storePositions(job) {
  const { head, positions, s, n, stencils } = job;
  for (let t = 0; t < head.stepCount; t++) {
    const before = t > 0 ? stagingStep(job, t - 1) : null;
    positions.store(t, head.baseVertexCount + s, n, stagingStep(job, t), before, t > 1 ? stagingStep(job, t - 2) : before,
      3 * stencils.first);
  }
}

// What is wrong when a coordinate x of vertex v at step t was decoded past the section's end or lies
// outside the box.
function positionProblem(d, t, v, x, top) {
  if (!d.ok()) return `the positions of step ${t} are cut short`;
  return `step ${t}: vertex ${v}'s position is far outside the bounding box`;
}

// DpmDecoder's `positions` executor that decodes a SPLT's positions only when they are waited
// for: the latest a second worker's could come (positions_executor.js), for the tests.
export function deferredPositions() {
  let job = null;
  return {
    start(next) {
      job = next;
    },
    wait() {
      const next = job;
      job = null;
      return decodeSplitPositions(next);
    },
  };
}

// Step 0: the parallelogram over the quad wings, else the parent; context 0.
function firstStep({ d, m, cur, first, n, vertex0 }, stencils, before, top) {
  const split = stencils.split;
  for (let k = 0; k < n; k++) {
    const v = first + k;
    const st = 10 * k;
    const p = 3 * split[st];
    const quads = split[st + 1];
    for (let c = 0; c < 3; c++) {
      let guess = cur[p + c];
      if (quads > 0) {
        let sum = 0;
        for (let j = 0; j < quads; j++)
          sum += cur[3 * split[st + 2 + 2 * j] + c] + guess - cur[3 * split[st + 3 + 2 * j] + c];
        guess = roundedMean(sum, quads);
      }
      const r = decodeSigned(d, m, c * COORDINATE_MODELS);
      const x = guess + r;
      if (d.overrun !== 0 || d.tooLarge || !(x >= -2 && x <= top[c])) return positionProblem(d, 0, vertex0 + k, x, top[c]);
      cur[3 * v + c] = x;
      before[3 * k + c] = r;
    }
  }
  return null;
}

// The ring fit's pull toward the identity and the largest guess it may give (position_coding.cpp).
const RING_FIT_PULL = 1 / 1024;
const RING_FIT_LIMIT = 2 ** 40;
const fit = new Float64Array(3);  // ringMotionGuess()'s result

// Step t > 0's guess (FORMAT.md "Positions", in SPLT): the least-squares linear map of the ring's
// offsets from its centre at t − 1 to those at t, pulled toward the identity, applied to v0's
// offset (v: 3 · v0) and added to the centre at t; into fit. Binary64, operation by operation as
// position_coding.cpp's ring_motion_guess(); false (the mean motion is used) as there.
function ringMotionGuess(cur, prev, ring, r0, r1, v) {
  const count = r1 - r0;
  if (count < 3) return false;
  let s0x = 0, s0y = 0, s0z = 0, s1x = 0, s1y = 0, s1z = 0;
  for (let j = r0; j < r1; j++) {
    const u = 3 * ring[j];
    s0x += prev[u], s0y += prev[u + 1], s0z += prev[u + 2];
    s1x += cur[u], s1y += cur[u + 1], s1z += cur[u + 2];
  }
  const c0x = s0x / count, c0y = s0y / count, c0z = s0z / count;
  const c1x = s1x / count, c1y = s1y / count, c1z = s1z / count;
  let b00 = 0, b11 = 0, b22 = 0, b01 = 0, b02 = 0, b12 = 0;
  let a00 = 0, a01 = 0, a02 = 0, a10 = 0, a11 = 0, a12 = 0, a20 = 0, a21 = 0, a22 = 0;
  for (let j = r0; j < r1; j++) {
    const u = 3 * ring[j];
    const ex = prev[u] - c0x, ey = prev[u + 1] - c0y, ez = prev[u + 2] - c0z;
    const fx = cur[u] - c1x, fy = cur[u + 1] - c1y, fz = cur[u + 2] - c1z;
    b00 += ex * ex, b11 += ey * ey, b22 += ez * ez;
    b01 += ex * ey, b02 += ex * ez, b12 += ey * ez;
    a00 += fx * ex, a01 += fx * ey, a02 += fx * ez;
    a10 += fy * ex, a11 += fy * ey, a12 += fy * ez;
    a20 += fz * ex, a21 += fz * ey, a22 += fz * ez;
  }
  const lambda = (b00 + b11 + b22) * RING_FIT_PULL + RING_FIT_PULL;
  const k00 = b00 + lambda, k11 = b11 + lambda, k22 = b22 + lambda;
  const m00 = k11 * k22 - b12 * b12, m01 = b02 * b12 - b01 * k22, m02 = b01 * b12 - b02 * k11;
  const m11 = k00 * k22 - b02 * b02, m12 = b01 * b02 - k00 * b12, m22 = k00 * k11 - b01 * b01;
  const det = k00 * m00 + b01 * m01 + b02 * m02;
  if (!(det > 0)) return false;
  const dx = prev[v] - c0x, dy = prev[v + 1] - c0y, dz = prev[v + 2] - c0z;
  const y0 = (m00 * dx + m01 * dy + m02 * dz) / det;
  const y1 = (m01 * dx + m11 * dy + m12 * dz) / det;
  const y2 = (m02 * dx + m12 * dy + m22 * dz) / det;
  const x = Math.floor(c1x + ((a00 * y0 + a01 * y1 + a02 * y2) + lambda * y0) + 0.5);
  const y = Math.floor(c1y + ((a10 * y0 + a11 * y1 + a12 * y2) + lambda * y1) + 0.5);
  const z = Math.floor(c1z + ((a20 * y0 + a21 * y1 + a22 * y2) + lambda * y2) + 0.5);
  if (!(Math.abs(x) < RING_FIT_LIMIT && Math.abs(y) < RING_FIT_LIMIT && Math.abs(z) < RING_FIT_LIMIT))
    return false;
  fit[0] = x, fit[1] = y, fit[2] = z;
  return true;
}

// Step t > 0: its own position moved by its ring (the fitted map above, else the ring's mean
// motion), plus (t ≥ 2) 3/8 of the last
// step's miss, rounded half up (at t = 1 the miss is step 0's, not a motion's); the context is
// the bucket of the coordinate's last residual. The residuals of `before` become those of `now`.
function laterStep({ d, m, cur, prev, t, first, n, vertex0 }, stencils, before, now, top) {
  // 1. The residuals first, in a loop that does nothing else: their contexts are the last step's
  //    residuals, not positions. cut: the first one decoded past the end or too large.
  let cut = 3 * n;
  for (let e = 0, c = 0; e < 3 * n; e++) {
    now[e] = decodeSigned(d, m, c * COORDINATE_MODELS + bucket(before[e]) * SIGNED_MODEL_SIZE);
    if (d.overrun !== 0 || d.tooLarge) {
      cut = e;
      break;
    }
    c = c === 2 ? 0 : c + 1;
  }
  // 2. The positions, each coordinate checked in the order it was decoded.
  const { ringStart } = stencils;
  const ring = stencils.ring.data;
  const [top0, top1, top2] = top;
  const later = t >= 2 ? 1 : 0;
  for (let k = 0; k < n; k++) {
    const v = 3 * (first + k);
    const r0 = ringStart[k], r1 = ringStart[k + 1];
    let gx, gy, gz;
    if (ringMotionGuess(cur, prev, ring, r0, r1, v)) {
      gx = fit[0], gy = fit[1], gz = fit[2];
    } else {
      let mx = 0, my = 0, mz = 0;
      for (let j = r0; j < r1; j++) {
        const u = 3 * ring[j];
        mx += cur[u] - prev[u];
        my += cur[u + 1] - prev[u + 1];
        mz += cur[u + 2] - prev[u + 2];
      }
      const count = r1 - r0;
      gx = prev[v] + roundedMean(mx, count);
      gy = prev[v + 1] + roundedMean(my, count);
      gz = prev[v + 2] + roundedMean(mz, count);
    }
    const e = 3 * k;
    const x = gx + later * Math.floor((3 * before[e] + 4) * 0.125) + now[e];
    const y = gy + later * Math.floor((3 * before[e + 1] + 4) * 0.125) + now[e + 1];
    const z = gz + later * Math.floor((3 * before[e + 2] + 4) * 0.125) + now[e + 2];
    if (e + 3 > cut || !(x >= -2 && x <= top0 && y >= -2 && y <= top1 && z >= -2 && z <= top2)) {
      const xyz = [x, y, z];
      for (let c = 0; c < 3; c++) {
        if (e + c >= cut) return `the positions of step ${t} are cut short`;
        if (!(xyz[c] >= -2 && xyz[c] <= top[c]))
          return `step ${t}: vertex ${vertex0 + k}'s position is far outside the bounding box`;
      }
    }
    cur[v] = x, cur[v + 1] = y, cur[v + 2] = z;
  }
  return null;
}

// Lossless (f32 bit patterns): the parent at step 0, then the vertex's own previous value moved
// by its parent's motion; Int32Array stores wrap modulo 2^32, as the residuals do.
function losslessStep({ d, m, cur, prev, t, first, n, vertex0 }, stencils, before) {
  const split = stencils.split;
  for (let k = 0; k < n; k++) {
    const v = 3 * (first + k);
    const p = 3 * split[10 * k];
    for (let c = 0; c < 3; c++) {
      const guess = t === 0 ? cur[p + c] : prev[v + c] + cur[p + c] - prev[p + c];
      const e = 3 * k + c;
      const r = decodeSigned(d, m, c * COORDINATE_MODELS + (t > 0 ? bucket(before[e]) : 0) * SIGNED_MODEL_SIZE);
      if (!d.ok()) return `the positions of step ${t} are cut short`;
      if (!residualFits(r, true)) return `step ${t}: vertex ${vertex0 + k}: ${LOSSLESS_RESIDUAL}`;
      cur[v + c] = guess + r;
      before[e] = (cur[v + c] - (guess | 0)) | 0;  // modulo 2^32, as a signed value
    }
  }
  return null;
}
