// The positions of every step, held compact (docs/viewer.md "Memory"). A coordinate's path over
// the steps is smooth in the file's grid integers, so it is kept as step 0 (32 bits), its first
// motion (16 bits) and from step 2 on the change of its motion, the second difference
// q(t) − 2 q(t − 1) + q(t − 2) (8 bits): 3 bytes a vertex a step instead of 12. A value that
// does not fit is stored as its type's escape (its most negative value) and kept beside, in the
// step's list of (coordinate index, value) pairs in index order (`wide`). A lossless file's f32
// bit patterns do not change smoothly: it keeps 32 bits, no escapes.
//
// A step is made from the two before it in one pass over the coordinates, forward or backward
// (q(t − 2) = 2 q(t − 1) − q(t) + d(t)), so any step is a walk from a Cursor that holds two
// consecutive steps; the walk goes through Int32Array stores, which wrap modulo 2^32 as the
// lossless differences do. Readers on other threads share `steps` and `wide` (mesh_pieces.js);
// the cursors are each thread's own.
import { withRoom } from './bytes.js';

// The types of steps 0, 1 and the later ones, and each type's escape.
const QUANTIZED_TYPES = [Int32Array, Int16Array, Int8Array];
const ESCAPE = new Map([[Int8Array, -128], [Int16Array, -32768], [Int32Array, NaN]]);  // NaN: none
// Cursors a thread keeps (two readers at different steps, as compare's two variants of one file).
const MAX_CURSORS = 2;

// The bytes a vertex's positions take over `stepCount` steps, for a memory budget: 12 at step 0,
// 6 at step 1 and 3 a step after (32 bits each in a lossless file), the escaped values (8 bytes
// each; 0.1–11 % of the coordinates on the crash data: a byte a step unless measured) and 24 for
// a cursor's two steps.
export function positionBytes(stepCount, lossless, escaped = Math.max(0, stepCount - 1)) {
  if (lossless) return 12 * stepCount + 24;
  return 12 + (stepCount > 1 ? 6 : 0) + 3 * Math.max(0, stepCount - 2) + escaped + 24;
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
    this.cursors = [];
  }

  // The object as another thread received it (structured clone of the arrays): a reader with
  // cursors of its own.
  static from({ vertexCount, steps, wide }) {
    return Object.assign(Object.create(StepPositions.prototype), { vertexCount, steps, wide, cursors: [] });
  }

  // Room in every step's array for the first `vertices` vertices (the arrays may be new ones).
  makeRoom(vertices, doubling = true) {
    const max = 3 * this.vertexCount;
    for (let t = 0; t < this.steps.length; t++) this.steps[t] = withRoom(this.steps[t], 3 * vertices, max, 0, doubling);
  }

  // The bytes the escaped values of every step take (8 a value).
  escapedBytes() {
    return this.wide.reduce((sum, w) => sum + 8 * Atomics.load(w, 0), 0);
  }

  // The bytes held: every step's array, the escaped values and the cursors.
  arrays() {
    return [...this.steps, ...this.wide, ...this.cursors.flatMap((c) => [c.prev, c.cur])];
  }

  // Stores step t of the vertices [first, first + count) from staging arrays that hold steps t,
  // t − 1 and t − 2 (at step 1 the step-0 array twice: q(−1) = q(0)) of the same vertices,
  // starting at coordinate `at`. Vertices are stored in increasing order, as the file brings them, so each
  // step's escaped values stay in index order. Room was made (makeRoom()).
  store(t, first, count, now, before, before2, at) {
    const out = this.steps[t];
    const i0 = 3 * first, i1 = 3 * (first + count);
    if (t === 0) {
      out.set(now.subarray(at, at + i1 - i0), i0);
      return;
    }
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
      const escape = ESCAPE.get(step.constructor);
      const wide = this.wide[t];
      for (let k = 0, j = at; k < count; k++, j += 3) {
        const i = 3 * ids[k];
        let dx = step[i], dy = step[i + 1], dz = step[i + 2];
        if (dx === escape) dx = wideValue(wide, i);
        if (dy === escape) dy = wideValue(wide, i + 1);
        if (dz === escape) dz = wideValue(wide, i + 2);
        now[j] = 2 * before[j] - before2[j] + dx;
        now[j + 1] = 2 * before[j + 1] - before2[j + 1] + dy;
        now[j + 2] = 2 * before[j + 2] - before2[j + 2] + dz;
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
        let d = this.steps[s][i];
        if (d === ESCAPE.get(this.steps[s].constructor)) d = wideValue(this.wide[s], i);
        const next = (2 * now - before + d) | 0;
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
    for (let i = from; i < to; i++) older[i] = 2 * newer[i] - older[i] + d[i];
    if (Number.isNaN(escape)) return;
    const wide = this.wide[s];
    const count = Atomics.load(wide, 0);
    for (let k = firstPairAtOrAfter(wide, from); k < count; k++) {
      const i = wide[1 + 2 * k];
      if (i >= to) break;
      older[i] += wide[2 + 2 * k] - escape;
    }
  }
}
