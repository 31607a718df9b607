// The positions of a SPLT's new vertices (docs/FORMAT.md "Positions"): one range-coded section
// per step, predicted from the split's quad wings (a parallelogram) at step 0 and from the
// vertex's own previous position moved by its neighbours' mean motion later. The C++ side is
// src/progressive/position_coding.cpp; both follow FORMAT.md.
//
// Speed: one loop per kind of step (step 0, later steps, lossless), the three coordinates of a
// vertex side by side, every model of a step in one Uint16Array, nothing allocated per vertex.
import { Growable } from './bytes.js';
import { bitModels, decodeSigned, RangeDecoder, SIGNED_MODEL_SIZE } from './range_coder.js';
import { WING_SLOT_SHIFT, WING_WAS_TRIANGLE } from './progressive_mesh.js';

const CONTEXTS = 5;
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
function bucket(r) {
  return 32 - Math.clz32(Math.min(Math.abs(r), 8));  // min(⌊log₂ |r|⌋ + 1, 4), without a branch
}

// ⌊(2 · sum + count) / (2 · count)⌋: the mean rounded half up (exact: |sum| < 2^40).
const roundedMean = (sum, count) => Math.floor((2 * sum + count) / (2 * count));

// Decodes the positions of the n vertices from b + s into mesh.q, section t for step t
// (Uint8Arrays), with the chunk's stencils. Returns null or what is wrong.
export function decodeSplitPositions(mesh, s, n, stencils, models, sections) {
  const q = mesh.q;
  const { baseVertexCount: b, bboxMin, bboxMax, quantStep } = mesh.head;
  // Quantized positions lie within two grid steps of the box (position_coding.cpp checks it too).
  const top = [0, 1, 2].map((c) => (bboxMax[c] - bboxMin[c]) / quantStep + 2);
  let before = new Float64Array(3 * n);  // the residuals at t − 1
  let now = new Float64Array(3 * n);  // and at t
  for (let t = 0; t < q.length; t++) {
    const d = new RangeDecoder(sections[t]);
    if (!d.ok()) return `the positions of step ${t} are cut short`;  // or do not start as coded
    const step = { d, m: models[t], cur: q[t], prev: t > 0 ? q[t - 1] : null, t, first: b + s, n };
    const problem = mesh.lossless ? losslessStep(step, stencils, before)
      : t === 0 ? firstStep(step, stencils, before, top) : laterStep(step, stencils, before, now, top);
    if (problem) return problem;
    if (!mesh.lossless && t > 0) [before, now] = [now, before];
    if (!d.exhausted()) return `the positions of step ${t} leave bytes unread`;
  }
  return null;
}

// What is wrong when a coordinate x of vertex v at step t was decoded past the section's end or lies
// outside the box.
function positionProblem(d, t, v, x, top) {
  if (!d.ok()) return `the positions of step ${t} are cut short`;
  return `step ${t}: vertex ${v}'s position is far outside the bounding box`;
}

// Step 0: the parallelogram over the quad wings, else the parent; context 0.
function firstStep({ d, m, cur, first, n }, stencils, before, top) {
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
      if (d.overrun !== 0 || d.tooLarge || !(x >= -2 && x <= top[c])) return positionProblem(d, 0, v, x, top[c]);
      cur[3 * v + c] = x;
      before[3 * k + c] = r;
    }
  }
  return null;
}

// Step t > 0: its own position moved by its ring's mean motion, plus (t ≥ 2) 3/8 of the last
// step's miss, rounded half up (at t = 1 the miss is step 0's, not a motion's); the context is
// the bucket of the coordinate's last residual. The residuals of `before` become those of `now`.
function laterStep({ d, m, cur, prev, t, first, n }, stencils, before, now, top) {
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
    let mx = 0, my = 0, mz = 0;
    const r0 = ringStart[k], r1 = ringStart[k + 1];
    for (let j = r0; j < r1; j++) {
      const u = 3 * ring[j];
      mx += cur[u] - prev[u];
      my += cur[u + 1] - prev[u + 1];
      mz += cur[u + 2] - prev[u + 2];
    }
    const count = r1 - r0;
    const e = 3 * k;
    const x = prev[v] + roundedMean(mx, count) + later * Math.floor((3 * before[e] + 4) * 0.125) + now[e];
    const y = prev[v + 1] + roundedMean(my, count) + later * Math.floor((3 * before[e + 1] + 4) * 0.125) + now[e + 1];
    const z = prev[v + 2] + roundedMean(mz, count) + later * Math.floor((3 * before[e + 2] + 4) * 0.125) + now[e + 2];
    if (e + 3 > cut || !(x >= -2 && x <= top0 && y >= -2 && y <= top1 && z >= -2 && z <= top2)) {
      const xyz = [x, y, z];
      for (let c = 0; c < 3; c++) {
        if (e + c >= cut) return `the positions of step ${t} are cut short`;
        if (!(xyz[c] >= -2 && xyz[c] <= top[c]))
          return `step ${t}: vertex ${first + k}'s position is far outside the bounding box`;
      }
    }
    cur[v] = x, cur[v + 1] = y, cur[v + 2] = z;
  }
  return null;
}

// Lossless (f32 bit patterns): the parent at step 0, then the vertex's own previous value moved
// by its parent's motion; Int32Array stores wrap modulo 2^32, as the residuals do.
function losslessStep({ d, m, cur, prev, t, first, n }, stencils, before) {
  const split = stencils.split;
  for (let k = 0; k < n; k++) {
    const v = 3 * (first + k);
    const p = 3 * split[10 * k];
    for (let c = 0; c < 3; c++) {
      const guess = t === 0 ? cur[p + c] : prev[v + c] + cur[p + c] - prev[p + c];
      const e = 3 * k + c;
      const r = decodeSigned(d, m, c * COORDINATE_MODELS + (t > 0 ? bucket(before[e]) : 0) * SIGNED_MODEL_SIZE);
      if (!d.ok()) return `the positions of step ${t} are cut short`;
      cur[v + c] = guess + r;
      before[e] = (cur[v + c] - (guess | 0)) | 0;  // modulo 2^32, as a signed value
    }
  }
  return null;
}
