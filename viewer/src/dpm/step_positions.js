// The positions of every step, held compact (docs/viewer.md "Memory"). A coordinate's path over
// the steps is smooth in the file's grid integers, so it is kept as step 0 (32 bits), its first
// motion (16 bits) and from step 2 on the change of its motion, the second difference
// q(t) − 2 q(t − 1) + q(t − 2), packed: in blocks of BLOCK coordinates, each block in as many
// bits a value as pays best ("Packed steps" below), instead of 12 bytes a vertex a step. A value
// that does not fit (16 bits at step 1, its block's width later) is stored as an escape and kept
// beside, in the step's list of (coordinate index, value) pairs in index order (`wide`). A
// lossless file's f32 bit patterns do not change smoothly: it keeps 32 bits, no escapes.
//
// A step is made from the two before it in one pass over the coordinates, forward or backward
// (q(t − 2) = 2 q(t − 1) − q(t) + d(t)), so any step is a walk from a Cursor that holds two
// consecutive steps; the walk goes through Int32Array stores, which wrap modulo 2^32 as the
// lossless differences do. Readers on other threads share `steps` and `wide` (mesh_pieces.js);
// the cursors are each thread's own.
import { withRoom } from './bytes.js';

// The types of steps 0, 1 and the later ones (packed bytes), and the value an escaped
// coordinate's walk adds before its escape is corrected (Int16's escape; a packed step adds 0).
const QUANTIZED_TYPES = [Int32Array, Int16Array, Uint8Array];
const ESCAPE = new Map([[Uint8Array, 0], [Int16Array, -32768], [Int32Array, NaN]]);  // NaN: none
// Cursors a thread keeps (two readers at different steps, as compare's two variants of one file).
const MAX_CURSORS = 2;

// Packed steps (t ≥ 2 of a quantized file). Each store() appends a run of blocks: BLOCK
// coordinates a block (the run's last may hold fewer), each value zigzag-coded (0, −1, 1, −2, …
// as 0, 1, 2, 3, …) in w bits, w ≤ 16, chosen for the block as the fewest bytes with its escapes
// (8 bytes each in `wide`): the all-ones code of w bits is the block's escape. 16·w bytes a full
// block, every block starting on 8 bytes. Per step: steps[t] the bytes, dir[t] = [blocks, bytes
// used, then per block (its first byte / 8) · 32 + w], runs[t] = [runs, then per run its first
// coordinate and first block]. A run starts where a store began (a chunk's vertices, or a page's
// copied piece); readers find a coordinate's run by its first coordinate. Appending writes
// nothing a reader of the stored coordinates reads, and the counts come last, so readers on
// other threads read as the writer appends.
const BLOCK = 128;
const BLOCK_SHIFT = 7;
const MAX_WIDTH = 16;
// A value is read from 24 bits at a time: two bytes of room past the last block.
const PACKED_PAD = 2;
// The bytes a vertex takes a packed step, for the memory budget before any is measured: the
// tiled crash boxes of bench/scale_inputs.py take 1.3, the CalculiX crash boxes 2.2–3.8 with their
// escapes (measured again once an eighth of the budget is loaded: remeasuredBudget()).
const PACKED_ALLOWANCE = 2;

// The bytes a vertex's positions take over `stepCount` steps, for a memory budget: 12 at step 0,
// 6 at step 1, the later steps packed with their escaped values (`later`: measured bytes a
// vertex, StepPositions.laterBytes(); else PACKED_ALLOWANCE a step) and 24 for a cursor's two
// steps; 12 a step in a lossless file.
export function positionBytes(stepCount, lossless, later = PACKED_ALLOWANCE * Math.max(0, stepCount - 1)) {
  if (lossless) return 12 * stepCount + 24;
  return 12 + (stepCount > 1 ? 6 : 0) + later + 24;
}

// Index of the first pair of `wide` (Int32Array: count, then index, value pairs) whose index is
// ≥ i.
function firstPairAtOrAfter(wide, i) {
  let lo = 0, hi = Atomics.load(wide, 0);
  while (lo < hi) {
    const mid = (lo + hi) >> 1;
    if (wide[1 + 2 * mid] < i) lo = mid + 1;
    else hi = mid;
  }
  return lo;
}

// The value coordinate i escaped to in `wide` (it is there: the writer put it).
function wideValue(wide, i) {
  return wide[2 + 2 * firstPairAtOrAfter(wide, i)];
}

// The run of `runs` (a packed step's) that holds coordinate i: the last whose first is ≤ i.
function runAt(runs, i) {
  let lo = 0, hi = Atomics.load(runs, 0) - 1;
  while (lo < hi) {
    const mid = (lo + hi + 1) >> 1;
    if (runs[1 + 2 * mid] <= i) lo = mid;
    else hi = mid - 1;
  }
  return lo;
}

// The value at coordinate i of a packed step, whose run r holds it (an escape's from `wide`).
function packedValue(bytes, dir, runs, wide, r, i) {
  const rel = i - runs[1 + 2 * r];
  const entry = dir[2 + runs[2 + 2 * r] + (rel >>> BLOCK_SHIFT)];
  const w = entry & 31;
  if (w === 0) return 0;
  const bit = (rel & (BLOCK - 1)) * w, mask = (1 << w) - 1;
  const p = (entry >>> 5) * 8 + (bit >>> 3);
  const z = ((bytes[p] | (bytes[p + 1] << 8) | (bytes[p + 2] << 16)) >>> (bit & 7)) & mask;
  return z === mask ? wideValue(wide, i) : (z >>> 1) ^ -(z & 1);
}

// The bits a value needs in a block so as not to be its escape: bits of (zigzag + 1); more than
// MAX_WIDTH for any beyond.
function bitsFor(d) {
  const z = ((d << 1) ^ (d >> 31)) >>> 0;
  return z >= 2 ** MAX_WIDTH - 1 ? MAX_WIDTH + 1 : 32 - Math.clz32(z + 1);
}

// Two consecutive steps of the first n vertices: prev = q(t − 1) (q(0) at t = 0) and cur = q(t).
class Cursor {
  constructor() {
    this.t = 0;
    this.n = 0;
    this.prev = new Int32Array(0);
    this.cur = new Int32Array(0);
  }
}

export class StepPositions {
  constructor(stepCount, lossless, vertexCount) {
    this.vertexCount = vertexCount;
    const types = lossless ? [Int32Array, Int32Array, Int32Array] : QUANTIZED_TYPES;
    // steps[0]: step 0; steps[t]: the first motion (t = 1) or the second difference at t.
    this.steps = Array.from({ length: stepCount }, (_, t) => new types[Math.min(t, 2)](0));
    this.wide = Array.from({ length: stepCount }, () => new Int32Array(1));  // [0] unused
    // A packed step's blocks and runs (null for the others).
    const packed = (t) => !lossless && t >= 2;
    this.dir = Array.from({ length: stepCount }, (_, t) => (packed(t) ? new Uint32Array(2) : null));
    this.runs = Array.from({ length: stepCount }, (_, t) => (packed(t) ? new Uint32Array(1) : null));
    this.cursors = [];
    this.values = new Int32Array(0);  // store()'s differences of a run, before they are packed
  }

  // The object as another thread received it (structured clone of the arrays): a reader with
  // cursors of its own.
  static from({ vertexCount, steps, wide, dir, runs }) {
    return Object.assign(Object.create(StepPositions.prototype),
      { vertexCount, steps, wide, dir, runs, cursors: [], values: new Int32Array(0) });
  }

  // Room in every unpacked step's array for the first `vertices` vertices (the arrays may be new
  // ones). A packed step grows as it is written, by a quarter (pack()): what its coordinates take
  // is not known before they come (the coarse splits' motion changes more than the fine ones').
  makeRoom(vertices, doubling = true) {
    const max = 3 * this.vertexCount;
    for (let t = 0; t < this.steps.length; t++) {
      if (!this.dir[t]) this.steps[t] = withRoom(this.steps[t], 3 * vertices, max, 0, doubling);
    }
  }

  // The bytes the escaped values of every step take (8 a value).
  escapedBytes() {
    return this.wide.reduce((sum, w) => sum + 8 * Atomics.load(w, 0), 0);
  }

  // The bytes the steps after step 1 take as written (packed bytes, blocks and runs) with every
  // step's escaped values: the memory budget's measure (model_file.js).
  laterBytes() {
    let bytes = this.escapedBytes();
    for (let t = 2; t < this.steps.length; t++) {
      const dir = this.dir[t];
      bytes += dir ? dir[1] + 4 * dir[0] + 8 * Atomics.load(this.runs[t], 0) : this.steps[t].byteLength;
    }
    return bytes;
  }

  // The bytes held: every step's array, the escaped values, the blocks and runs and the cursors.
  arrays() {
    return [...this.steps, ...this.wide, ...this.dir.filter(Boolean), ...this.runs.filter(Boolean),
      ...this.cursors.flatMap((c) => [c.prev, c.cur])];
  }

  // Stores step t of the vertices [first, first + count) from staging arrays that hold steps t,
  // t − 1 and t − 2 (at step 1 the step-0 array twice: q(−1) = q(0)) of the same vertices,
  // starting at coordinate `at`. Vertices are stored in increasing order, as the file brings them,
  // so each step's escaped values stay in index order and its runs follow each other. Room was
  // made (makeRoom()).
  store(t, first, count, now, before, before2, at) {
    const i0 = 3 * first, i1 = 3 * (first + count);
    if (t === 0) {
      this.steps[0].set(now.subarray(at, at + i1 - i0), i0);
      return;
    }
    if (this.dir[t]) {
      if (this.values.length < i1 - i0) this.values = new Int32Array(i1 - i0);
      const values = this.values;
      for (let i = 0, j = at; i < i1 - i0; i++, j++) values[i] = (now[j] - 2 * before[j] + before2[j]) | 0;
      this.pack(t, i0, values, i1 - i0);
      return;
    }
    const out = this.steps[t];
    const escape = ESCAPE.get(out.constructor);
    for (let i = i0, j = at; i < i1; i++, j++) {
      const d = (now[j] - 2 * before[j] + before2[j]) | 0;
      out[i] = d;
      if (out[i] !== d || d === escape) {
        out[i] = escape;
        this.addWide(t, i, d);
      }
    }
  }

  // Appends values[0, n) as coordinates [i0, i0 + n) of packed step t: a run of blocks, each in
  // the width that takes the fewest bytes with its escapes (appended to `wide`), room grown by a
  // quarter as needed.
  pack(t, i0, values, n) {
    if (n === 0) return;
    const blocks = Math.ceil(n / BLOCK);
    let dir = this.dir[t], runs = this.runs[t];
    const count = dir[0], runCount = runs[0];
    dir = this.dir[t] = withRoom(dir, 2 + count + blocks, Infinity);
    runs = this.runs[t] = withRoom(runs, 3 + 2 * runCount, Infinity);
    // Each block's width first (into its entry), so that the bytes grow once, by what they need.
    const over = new Int32Array(MAX_WIDTH + 2);  // per width: the block's values that need it
    let need = 0;
    for (let k = 0; k < blocks; k++) {
      const a = k * BLOCK, b = Math.min(n, a + BLOCK);
      over.fill(0);
      let zero = true;
      for (let i = a; i < b; i++) {
        over[bitsFor(values[i])]++;
        zero &&= values[i] === 0;
      }
      let w = 0, bytes = 0;
      if (!zero) {
        // escaped(w): values needing more than w bits; bytes(w) = 8 per 64 bits of values, rounded up.
        let escaped = b - a - over[0], best = Infinity;
        for (let width = 1; width <= MAX_WIDTH; width++) {
          escaped -= over[width];
          const size = 8 * Math.ceil(((b - a) * width) / 64) + 8 * escaped;
          if (size < best) (best = size), (w = width), (bytes = size - 8 * escaped);
        }
      }
      dir[2 + count + k] = w;
      need += bytes;
    }
    let used = dir[1];
    let bytes = this.steps[t];
    if (bytes.length < used + need + PACKED_PAD) {
      const room = Math.max(used + need + PACKED_PAD, Math.ceil(1.25 * bytes.length));
      bytes = this.steps[t] = withRoom(bytes, room, Infinity, 0, false);
    }
    for (let k = 0; k < blocks; k++) {
      const a = k * BLOCK, b = Math.min(n, a + BLOCK);
      const w = dir[2 + count + k], mask = (1 << w) - 1;
      dir[2 + count + k] = (used / 8) * 32 + w;
      let acc = 0, bits = 0;
      for (let i = a; i < b && w > 0; i++) {
        const d = values[i];
        let z = mask;
        if (bitsFor(d) <= w) z = (d << 1) ^ (d >> 31);
        else this.addWide(t, i0 + i, d);
        acc |= z << bits;
        for (bits += w; bits >= 8; bits -= 8, acc >>>= 8) bytes[used++] = acc & 255;
      }
      if (bits > 0) bytes[used++] = acc & 255;
      used = Math.ceil(used / 8) * 8;
    }
    dir[1] = used;
    dir[0] = count + blocks;
    runs[1 + 2 * runCount] = i0;
    runs[2 + 2 * runCount] = count;
    Atomics.store(runs, 0, runCount + 1);  // last: a reader that sees the run sees its blocks
  }

  // Coordinates [i0, i1) of packed step t as second differences, for a page that keeps packed
  // steps of its own (mesh_pieces.js: copied, not shared); and their append on the other side,
  // which finds its own escapes.
  differences(t, i0, i1) {
    const out = new Int32Array(i1 - i0);
    const runs = this.runs[t];
    let r = runAt(runs, i0);
    const runCount = Atomics.load(runs, 0);
    for (let i = i0; i < i1; i++) {
      while (r + 1 < runCount && runs[3 + 2 * r] <= i) r++;
      out[i - i0] = this.difference(t, i, r);
    }
    return out;
  }
  addDifferences(t, i0, values) {
    this.pack(t, i0, values, values.length);
  }

  // Appends (i, d) to step t's escaped values; the count last, so that a reader on another
  // thread never counts a pair not written yet.
  addWide(t, i, d) {
    let wide = this.wide[t];
    const count = wide[0];
    if (2 * count + 3 > wide.length) {
      wide = this.wide[t] = withRoom(wide, Math.max(2 * count + 3, 64), Infinity);
    }
    wide[1 + 2 * count] = i;
    wide[2 + 2 * count] = d;
    Atomics.store(wide, 0, count + 1);
  }

  // Copied pages (mesh_pieces.js): the escaped values of the vertices [first, end) at step t,
  // as index, value pairs, and their append on the other side.
  widePairs(t, first, end) {
    const wide = this.wide[t];
    const a = firstPairAtOrAfter(wide, 3 * first), b = firstPairAtOrAfter(wide, 3 * end);
    return wide.slice(1 + 2 * a, 1 + 2 * b);
  }
  addWidePairs(t, pairs) {
    for (let k = 0; k < pairs.length; k += 2) this.addWide(t, pairs[k], pairs[k + 1]);
  }

  // Step t's second difference (or first motion, at t = 1) at coordinate i, its escape resolved;
  // `run`: a packed step's run that holds i, if known.
  difference(t, i, run = -1) {
    const step = this.steps[t], runs = this.runs[t];
    if (runs) return packedValue(step, this.dir[t], runs, this.wide[t], run >= 0 ? run : runAt(runs, i), i);
    return step[i] === ESCAPE.get(step.constructor) ? wideValue(this.wide[t], i) : step[i];
  }

  // Steps 0 … m − 1 of the vertices in `ids` (ascending reads the arrays in order), one after
  // the other into out(t) (an Int32Array with 3 per id from coordinate `at`); out(t − 1) and
  // out(t − 2) are read back. A walk per step over just these vertices: the positions decoder's
  // old vertices.
  gather(ids, out, at = 0) {
    const count = ids.length;
    for (let t = 0; t < this.steps.length; t++) {
      const now = out(t), step = this.steps[t];
      if (t === 0) {
        for (let k = 0, j = at; k < count; k++, j += 3) {
          const i = 3 * ids[k];
          now[j] = step[i], now[j + 1] = step[i + 1], now[j + 2] = step[i + 2];
        }
        continue;
      }
      // q(t) = 2 q(t − 1) − q(t − 2) + d(t), with q(−1) = q(0).
      const before = out(t - 1), before2 = t > 1 ? out(t - 2) : before;
      const runs = this.runs[t], runCount = runs ? Atomics.load(runs, 0) : 0;
      let r = 0;  // a packed step's run of the last id (a vertex's three coordinates share one)
      for (let k = 0, j = at; k < count; k++, j += 3) {
        const i = 3 * ids[k];
        if (runs) {
          if (runs[1 + 2 * r] > i) r = runAt(runs, i);  // ids that do not ascend
          while (r + 1 < runCount && runs[3 + 2 * r] <= i) r++;
        }
        for (let c = 0; c < 3; c++) now[j + c] = 2 * before[j + c] - before2[j + c] + this.difference(t, i + c, r);
      }
    }
  }

  // Vertex v at step t, as the file's integer of each coordinate (out: 3 numbers): from a cursor
  // that holds it, else a walk over the steps.
  position(v, t, out) {
    for (const c of this.cursors) {
      if (v >= c.n) continue;
      const from = c.t === t ? c.cur : c.t - 1 === t ? c.prev : null;
      if (!from) continue;
      for (let k = 0; k < 3; k++) out[k] = from[3 * v + k];
      return out;
    }
    const q0 = this.steps[0];
    for (let k = 0; k < 3; k++) {
      const i = 3 * v + k;
      let before = q0[i], now = q0[i];
      for (let s = 1; s <= t; s++) {
        const next = (2 * now - before + this.difference(s, i)) | 0;
        before = now;
        now = next;
      }
      out[k] = now;
    }
    return out;
  }
  // Steps t0 and t1 (t1 = t0 or t0 + 1, or any two) of the first n vertices, as Int32Arrays of
  // at least 3n; valid until the next call. Step 0 is the stored array itself.
  around(t0, t1, n) {
    const step = (t) => (t === 0 ? this.steps[0] : this.cursorAt(t, n).cur);
    if (t0 === t1) return [step(t0), step(t0)];
    if (t1 === t0 + 1) {
      const c = this.cursorAt(t1, n);
      return [c.prev, c.cur];
    }
    const first = t0 === 0 ? this.steps[0] : step(t0).slice(0, 3 * n);
    return [first, step(t1)];
  }

  // A cursor at step t holding the first n vertices: the one that gets there with the fewest
  // coordinates walked (its missing vertices from step 0 to its step, then all to t), unless
  // starting from step 0 walks fewer: then a new one while there are fewer than MAX_CURSORS, else
  // the one used least recently, started again.
  cursorAt(t, n) {
    let best = null, cost = t * n;
    for (const c of this.cursors) {
      const walk = Math.max(0, n - c.n) * c.t + Math.abs(c.t - t) * n;
      if (walk < cost) (best = c), (cost = walk);
    }
    if (!best) {
      best = this.cursors.length < MAX_CURSORS ? new Cursor() : this.cursors[0];
      best.t = best.n = 0;
    }
    const i = this.cursors.indexOf(best);
    if (i >= 0) this.cursors.splice(i, 1);
    this.cursors.push(best);  // the latest used last
    if (best.t !== t && best.n > n) best.n = n;  // the rest would be carried for nothing
    this.extend(best, n);
    while (best.t < t) this.forward(best);
    while (best.t > t) this.backward(best);
    return best;
  }

  // The cursor's vertices [c.n, n) at its step: step 0, walked forward to c.t.
  extend(c, n) {
    if (c.n >= n) return;
    const from = 3 * c.n, to = 3 * n;
    if (c.cur.length < to) {
      const room = Math.min(3 * this.vertexCount, Math.max(to, 2 * c.cur.length));
      const [prev, cur] = [new Int32Array(room), new Int32Array(room)];
      prev.set(c.prev.subarray(0, from));
      cur.set(c.cur.subarray(0, from));
      Object.assign(c, { prev, cur });
    }
    const q0 = this.steps[0].subarray(from, to);
    c.prev.set(q0, from);
    c.cur.set(q0, from);
    // prev and cur both hold q(0); each pass makes the next step into the older array.
    let [prev, cur] = [c.prev, c.cur];
    for (let s = 1; s <= c.t; s++) {
      this.pass(prev, cur, s, from, to);
      [prev, cur] = [cur, prev];
    }
    if (prev !== c.prev) {  // the newer step lies in c.prev: move this range across
      const tmp = c.cur.slice(from, to);
      c.cur.set(c.prev.subarray(from, to), from);
      c.prev.set(tmp, from);
    }
    c.n = n;
  }

  forward(c) {
    this.pass(c.prev, c.cur, c.t + 1, 0, 3 * c.n);
    [c.prev, c.cur] = [c.cur, c.prev];
    c.t++;
  }

  backward(c) {
    // q(t − 2) = 2 q(t − 1) − q(t) + d(t) into cur, which becomes prev; at t = 1, q(−1) = q(0).
    this.pass(c.cur, c.prev, c.t, 0, 3 * c.n);
    [c.prev, c.cur] = [c.cur, c.prev];
    c.t--;
  }

  // older[i] = 2 · newer[i] − older[i] + d(s)[i] over coordinates [from, to): one step forward
  // (older = q(s − 2), newer = q(s − 1): makes q(s)) or back (older = q(s), newer = q(s − 1):
  // makes q(s − 2)); the escaped coordinates are then corrected by their values minus the escape.
  pass(older, newer, s, from, to) {
    const d = this.steps[s];
    const escape = ESCAPE.get(d.constructor);
    // s = 1: q(1) = q(0) + d(1) and back; both as above with q(−1) = q(0).
    if (this.dir[s]) this.passPacked(older, newer, s, from, to);
    else for (let i = from; i < to; i++) older[i] = 2 * newer[i] - older[i] + d[i];
    if (Number.isNaN(escape)) return;
    const wide = this.wide[s];
    const count = Atomics.load(wide, 0);
    for (let k = firstPairAtOrAfter(wide, from); k < count; k++) {
      const i = wide[1 + 2 * k];
      if (i >= to) break;
      older[i] += wide[2 + 2 * k] - escape;
    }
  }

  // pass() over a packed step: block by block, each value read from the three bytes that hold
  // it; an escape adds 0 here (pass() adds its value).
  passPacked(older, newer, s, from, to) {
    const bytes = this.steps[s], dir = this.dir[s], runs = this.runs[s];
    const runCount = Atomics.load(runs, 0);
    let i = from;
    for (let r = runAt(runs, from); i < to; r++) {
      if (r >= runCount) {  // not stored yet (as unwritten room was): no change of motion
        for (; i < to; i++) older[i] = 2 * newer[i] - older[i];
        break;
      }
      const start = runs[1 + 2 * r], first = runs[2 + 2 * r];
      const end = Math.min(to, r + 1 < runCount ? runs[3 + 2 * r] : to);
      while (i < end) {
        const rel = i - start, block = rel >>> BLOCK_SHIFT;
        const blockEnd = Math.min(end, start + (block + 1) * BLOCK);
        const entry = dir[2 + first + block], w = entry & 31;
        if (w === 0) {
          for (; i < blockEnd; i++) older[i] = 2 * newer[i] - older[i];
          continue;
        }
        const base = (entry >>> 5) * 8, mask = (1 << w) - 1;
        for (let bit = (rel & (BLOCK - 1)) * w; i < blockEnd; i++, bit += w) {
          const p = base + (bit >>> 3);
          const z = ((bytes[p] | (bytes[p + 1] << 8) | (bytes[p + 2] << 16)) >>> (bit & 7)) & mask;
          older[i] = 2 * newer[i] - older[i] + (z === mask ? 0 : (z >>> 1) ^ -(z & 1));
        }
      }
    }
  }
}
