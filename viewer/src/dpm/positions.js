// The positions of a SPLT's new vertices (docs/FORMAT.md "Positions"): one range-coded section
// per step, predicted from the split's quad wings (a parallelogram) at step 0 and from the
// vertex's own previous position moved by its neighbours' mean motion later. The C++ side is
// src/progressive/position_coding.cpp; both follow FORMAT.md.
import { RangeDecoder, SignedModel } from './range_coder.js';
import { WING_SLOT_SHIFT, WING_WAS_TRIANGLE } from './progressive_mesh.js';

const CONTEXTS = 5;

// The models of the position sections, one set per step ([step][coordinate][context]), continued
// from SPLT to SPLT.
export function positionModels(steps) {
  return Array.from({ length: steps }, () =>
    Array.from({ length: 3 }, () => Array.from({ length: CONTEXTS }, () => new SignedModel())));
}

// What predicts the new vertices of a SPLT, from the faces right after each split: per split
// (stencilAfterSplit) its parent, its quad wings' w and x (the corner opposite v0), and its ring,
// the vertices sharing an edge with v0 (a sorted set, in ring from ringStart[k]).
export class ChunkStencils {
  constructor(n) {
    this.split = new Int32Array(10 * n);  // parent, quads, w0, x0, …, w3, x3
    this.ringStart = new Int32Array(n + 1);
    this.ring = [];
  }
  add(mesh, k, i, corners) {
    const s = 10 * k;
    const v0 = mesh.head.baseVertexCount + i;
    const ring = [mesh.parent[i]];
    this.split[s] = mesh.parent[i];
    let quads = 0;
    for (let j = mesh.wingStart[i]; j < mesh.wingStart[i + 1]; j++) {
      const flags = mesh.wingFlags.data[j];
      ring.push(mesh.wingVertex.data[j]);
      if (flags & WING_WAS_TRIANGLE) continue;
      const slot = (flags >> WING_SLOT_SHIFT) & 3;
      this.split[s + 2 + 2 * quads] = mesh.wingVertex.data[j];
      this.split[s + 3 + 2 * quads] = corners[4 * mesh.wingFace.data[j] + ((slot + 2) % 4)];
      quads++;
    }
    this.split[s + 1] = quads;
    for (let j = mesh.movedStart[i]; j < mesh.movedStart[i + 1]; j++) {
      const f = 4 * mesh.movedFaces.data[j];
      const d = corners[f + 3] < 0 ? 3 : 4;
      for (let c = 0; c < d; c++)
        if (corners[f + c] === v0) ring.push(corners[f + ((c + 1) % d)], corners[f + ((c + d - 1) % d)]);
    }
    for (const u of new Set(ring)) this.ring.push(u);
    this.ringStart[k + 1] = this.ring.length;
  }
}

// The bucket of a residual's magnitude: the next residual's context.
function bucket(r) {
  const m = r < 0 ? -r : r;
  return m < 2 ? m : m < 4 ? 2 : m < 8 ? 3 : 4;  // min(⌊log₂ m⌋ + 1, 4)
}

// ⌊(2 · sum + count) / (2 · count)⌋: the mean rounded half up (exact: |sum| < 2^40).
const roundedMean = (sum, count) => Math.floor((2 * sum + count) / (2 * count));

// Decodes the positions of the n vertices from b + s into mesh.q, section t for step t
// (Uint8Arrays), with the chunk's stencils. Returns null or what is wrong.
export function decodeSplitPositions(mesh, s, n, stencils, models, sections) {
  const q = mesh.q;
  const { baseVertexCount: b, bboxMin, bboxMax, quantStep } = mesh.head;
  const lossless = mesh.lossless;
  const { split, ring, ringStart } = stencils;
  // Quantized positions lie within two grid steps of the box (position_coding.cpp checks it too).
  const top = [0, 1, 2].map((c) => (bboxMax[c] - bboxMin[c]) / quantStep + 2);
  const before = new Float64Array(3 * n);  // the residuals at t − 1
  for (let t = 0; t < q.length; t++) {
    const cur = q[t];
    const prev = t > 0 ? q[t - 1] : null;
    const d = new RangeDecoder(sections[t]);
    const m = models[t];
    for (let k = 0; k < n; k++) {
      const v = b + s + k;
      const st = 10 * k;
      const p = 3 * split[st];
      const quads = split[st + 1];
      for (let c = 0; c < 3; c++) {
        let guess;
        if (lossless) {  // the parent, and its motion (Int32Array wraps modulo 2^32)
          guess = t === 0 ? cur[p + c] : prev[3 * v + c] + cur[p + c] - prev[p + c];
        } else if (t === 0) {  // the parallelogram over the quad wings, else the parent
          guess = cur[p + c];
          if (quads > 0) {
            let sum = 0;
            for (let j = 0; j < quads; j++)
              sum += cur[3 * split[st + 2 + 2 * j] + c] + cur[p + c] - cur[3 * split[st + 3 + 2 * j] + c];
            guess = roundedMean(sum, quads);
          }
        } else {  // its own position moved by its ring's mean motion
          let motion = 0;
          for (let j = ringStart[k]; j < ringStart[k + 1]; j++)
            motion += cur[3 * ring[j] + c] - prev[3 * ring[j] + c];
          guess = prev[3 * v + c] + roundedMean(motion, ringStart[k + 1] - ringStart[k]);
          // 3/8 of the last step's miss, rounded half up (at t = 1 it is step 0's, not a motion's).
          if (t >= 2) guess += Math.floor((3 * before[3 * k + c] + 4) / 8);
        }
        const r = m[c][t > 0 ? bucket(before[3 * k + c]) : 0].decode(d);
        if (!d.ok()) return `the positions of step ${t} are cut short`;
        const x = guess + r;
        if (!lossless && (x < -2 || x > top[c]))
          return `step ${t}: vertex ${v}'s position is far outside the bounding box`;
        cur[3 * v + c] = x;
        // This residual for the next step (lossless: modulo 2^32, as a signed value).
        before[3 * k + c] = lossless ? (cur[3 * v + c] - (guess | 0)) | 0 : r;
      }
    }
    if (!d.exhausted()) return `the positions of step ${t} leave bytes unread`;
  }
  return null;
}
