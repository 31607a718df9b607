// The records and attributes sections of a SPLT (docs/FORMAT.md "Split records", "Split
// attributes"), decoded as the C++ decoder does (src/progressive/split_records_coding.cpp): each
// split is applied as it is decoded, and every vertex's faces are kept, because the coding
// refers to the mesh as the earlier splits left it. Same checks, same messages.
import { bitModels, RangeDecoder, SignedModel, UnsignedModel } from './range_coder.js';
import {
  applySplit,
  checkSplit,
  touchedFacesValid,
  WING_SLOT_SHIFT,
  WING_V1_FOLLOWS_V0,
  WING_WAS_TRIANGLE,
} from './progressive_mesh.js';
import { DpmError } from './bytes.js';

// Node and element ids lie strictly within ±2^51 (FORMAT.md "BASE payload"; C++ dpm_format.h
// kIdLimit): exact as numbers, also through a split's sum of a guess, an index step and a
// residual. A BASE delta lies strictly within ±2^52: any two valid ids differ by less, and its
// zigzag fits the 53 bits a number holds exactly (a larger one is never mistaken for a fitting one).
export const ID_LIMIT = 2 ** 51;
export const idFits = (id) => id > -ID_LIMIT && id < ID_LIMIT;
export const baseDeltaFits = (delta) => delta > -2 * ID_LIMIT && delta < 2 * ID_LIMIT;

// Split errors on the file's grid: code 0 is 0, code c ≥ 1 is P · (16 + (c−1) mod 16) ·
// 2^((c−1) div 16 − 44), P the power of two at or above HEAD's base_error. Exact in f64 and f32.
// HEAD's base_error is at most 2^1000 (FORMAT.md "HEAD"; C++ kMaxBaseError): P times 31 must be
// finite.
export const MAX_BASE_ERROR = 2 ** 1000;
const ERROR_STEPS = 16;
const ERROR_OCTAVES = 40;
export const TOP_ERROR_CODE = ERROR_STEPS * ERROR_OCTAVES + 1;

export function errorReference(baseError) {
  let p = 1;
  // Above 2^1023 no power of two is ≥ baseError, and the loops below never ended (readDpm hung on
  // such a HEAD: docs/RELIABILITY.md finding 8); the reader refuses it first (MAX_BASE_ERROR).
  if (!(baseError > 0 && baseError <= MAX_BASE_ERROR)) return p;
  while (p < baseError) p *= 2;
  while (p / 2 >= baseError) p /= 2;
  return p;
}

export function errorOfCode(code, reference) {
  if (code === 0) return 0;
  const k = code - 1;
  const mantissa = reference * (ERROR_STEPS + (k % ERROR_STEPS));
  return Math.fround(mantissa * 2 ** (Math.floor(k / ERROR_STEPS) - 44));
}

export function errorCodeAtLeast(e, reference) {
  let lo = 0, hi = TOP_ERROR_CODE;
  while (lo < hi) {
    const mid = (lo + hi) >>> 1;
    if (errorOfCode(mid, reference) >= e) hi = mid;
    else lo = mid + 1;
  }
  return lo;
}

// A short list of faces per vertex, all in one Int32Array (C++ ListPool): a million JS arrays
// cost a heap object each and kept the garbage collector busy. A list that outgrows its room
// moves to the end with twice the room; lists are made as vertices arrive (HEAD's vertex count is
// a claim).
export class ListPool {
  constructor(lists, expected) {
    this.start = new Int32Array(Math.max(16, lists));
    this.size = new Int32Array(this.start.length);
    this.room = new Int32Array(this.start.length);
    this.values = new Int32Array(Math.max(64, expected));
    this.used = 0;
    this.lists = lists;
  }
  // List k as a view (valid until the next change to any list).
  of(k) {
    return this.values.subarray(this.start[k], this.start[k] + this.size[k]);
  }
  push(k, value) {
    if (this.size[k] === this.room[k]) this.moveList(k, this.size[k] + 1);
    this.values[this.start[k] + this.size[k]++] = value;
  }
  // List k holds `list`'s values; a list past the last is made, with any before it.
  assign(k, list) {
    while (k >= this.lists) this.addList();
    this.size[k] = 0;
    if (list.length > this.room[k]) this.moveList(k, list.length);
    this.values.set(list, this.start[k]);
    this.size[k] = list.length;
  }
  // Keeps the first n values of list k.
  truncate(k, n) {
    this.size[k] = n;
  }
  addList() {  // internal: one more list
    if (this.lists === this.start.length) {
      for (const name of ['start', 'size', 'room']) {
        const bigger = new Int32Array(2 * this.lists);
        bigger.set(this[name]);
        this[name] = bigger;
      }
    }
    this.lists++;
  }
  moveList(k, needed) {  // internal: list k to the end with room for `needed` and as many again
    const room = Math.max(4, 2 * needed);
    if (this.used + room > this.values.length) {
      const bigger = new Int32Array(Math.max(2 * this.values.length, this.used + room));
      bigger.set(this.values.subarray(0, this.used));
      this.values = bigger;
    }
    this.values.copyWithin(this.used, this.start[k], this.start[k] + this.size[k]);
    this.start[k] = this.used;
    this.room[k] = room;
    this.used += room;
  }
}

// The original indices (of vertices, or of faces) not yet given, in [0, n), so that an index is
// coded by its rank among the free ones (C++ FreeIndices). A bit per index, set when *taken*,
// and a Fenwick tree of each 32-bit word's taken count: the tree is a 32nd of the indices (in
// cache), and both start as zeros, so HEAD's n, which is not trusted, costs no memory written
// (a typed array's zeros are pages not yet touched).
export class FreeIndices {
  constructor(n) {
    this.n = n;
    this.words = new Uint32Array(Math.ceil(n / 32));
    this.tree = new Int32Array(this.words.length + 1);
    this.count = n;
    const w = this.words.length;
    this.top = w > 0 ? 2 ** Math.floor(Math.log2(w)) : 0;
    while (this.top * 2 <= w) this.top *= 2;  // the largest power of two ≤ the word count
    while (this.top > w) this.top /= 2;
  }
  isFree(v) {
    return Number.isInteger(v) && v >= 0 && v < this.n && ((this.words[v >>> 5] >>> (v & 31)) & 1) === 0;
  }
  // Free indices below v.
  below(v) {
    const end = Math.min(v, this.n), w = end >>> 5, bits = end & 31;
    let taken = 0;
    for (let k = w; k > 0; k &= k - 1) taken += this.tree[k];
    if (bits !== 0) taken += popcount(this.words[w] & ((1 << bits) - 1));
    return end - taken;
  }
  // The free index with r free ones below it (r < count). A node of the tree that holds the
  // last word counts its indices past n as free; the descent never steps over it (r < count).
  nth(r) {
    let w = 0;
    for (let step = this.top; step > 0; step >>= 1) {
      if (w + step > this.words.length) continue;
      const free = 32 * step - this.tree[w + step];
      if (free <= r) w += step, r -= free;
    }
    let x = ~this.words[w];  // the free bits of word w: the r-th one
    for (; r > 0; r--) x &= x - 1;
    return 32 * w + 31 - Math.clz32(x & -x);
  }
  take(v) {
    this.words[v >>> 5] |= 1 << (v & 31);
    this.count--;
    for (let k = (v >>> 5) + 1; k <= this.words.length; k += k & -k) this.tree[k]++;
  }
}

function popcount(x) {
  x -= (x >>> 1) & 0x55555555;
  x = (x & 0x33333333) + ((x >>> 2) & 0x33333333);
  return (((x + (x >>> 4)) & 0x0f0f0f0f) * 0x01010101) >>> 24;
}

// The models of both sections, continued from one SPLT to the next, and the mesh as the splits
// so far left it: `corners` (4 slots per face, room for every face; the base's filled in, as
// file.js's replay) and each vertex's faces, ascending (C++ RecordModels).
export class RecordModels {
  constructor(mesh, corners) {
    this.parent = new UnsignedModel();
    this.wingCount = new UnsignedModel();
    this.quadFace = new UnsignedModel();
    this.neighbour = new UnsignedModel();
    this.farVertex = new UnsignedModel();
    this.errorStep = new UnsignedModel();
    this.parentStep = new SignedModel();
    this.wasTriangle = bitModels(48);  // by quad wing candidates, wing count and wing number
    this.quad = bitModels(3);  // [0] side, [1] slot at the end, [2] follows
    this.triFollows = bitModels(2);
    this.triSlot = bitModels(2);
    this.moved = bitModels(12);  // triangle? × beside a moved face? × moved so far (0, 1, 2+)
    this.vertexIndex = new SignedModel();
    this.nodeId = new SignedModel();
    this.part = new SignedModel();
    this.faceIndex = new SignedModel();
    this.elementId = new SignedModel();
    this.samePart = bitModels(1);

    this.corners = corners;
    this.faceCount = mesh.head.baseFaceCount;
    // The base's now; a split appends its v0's (HEAD's vertex count is only a claim).
    this.vertexFaces = new ListPool(mesh.head.baseVertexCount, 8 * this.faceCount);
    for (let f = 0; f < this.faceCount; f++)
      for (let k = 0; k < 4; k++) {
        const v = corners[4 * f + k];
        if (v >= 0 && v < this.vertexFaces.lists) this.vertexFaces.push(v, f);
      }
    const { vertexCount: V, faceCount: F, baseVertexCount: b } = mesh.head;
    this.freeVertices = new FreeIndices(V);
    this.freeFaces = new FreeIndices(F);
    for (let v = 0; v < b; v++) {
      const o = mesh.vertexOriginal[v];
      if (this.freeVertices.isFree(o)) this.freeVertices.take(o);
    }
    for (let f = 0; f < this.faceCount; f++) {
      const o = mesh.faceOriginal[f];
      if (this.freeFaces.isFree(o)) this.freeFaces.take(o);
    }
    this.errorReference = errorReference(mesh.head.baseError);
    this.errorCode = errorCodeAtLeast(mesh.head.baseError, this.errorReference);
    this.lastParent = -1;  // the last split's
    // Lists a split's decoding fills, kept from split to split (a million splits would
    // otherwise make and drop several each).
    this.scratch = {
      moved: [], movedSet: new SmallCounts(), fan: new MovedFan(), ofV0: [],
      wingVertex: [], wingFace: [], wingFlags: [],
    };
  }
}

function degree(corners, f) {
  return corners[4 * f + 3] < 0 ? 3 : 4;
}
export function slotOf(corners, f, v) {
  for (let k = 0; k < 4; k++) if (corners[4 * f + k] === v) return k;
  return -1;
}

export function neighbours(st, v) {
  const out = [];
  const c = st.corners;
  for (const f of st.vertexFaces.of(v)) {
    const n = degree(c, f), a = slotOf(c, f, v);
    out.push(c[4 * f + ((a + 1) % n)], c[4 * f + ((a + n - 1) % n)]);
  }
  sortAscending(out);
  let kept = 0;  // each once
  for (let k = 0; k < out.length; k++) if (k === 0 || out[k] !== out[k - 1]) out[kept++] = out[k];
  out.length = kept;
  return out;
}

// 0: no face of v1 on the edge v1–w; 1: one runs v1 → w (v1 not after v0); 2: w → v1. A face
// that is not moved decides; a moved one holds the edge v0–w after the split, so it says the
// other way round and only counts when no other face has the edge.
export function orientationGuess(st, v1, w, movedSet) {
  const c = st.corners;
  let guess = 0;
  for (const f of st.vertexFaces.of(v1)) {
    const n = degree(c, f), a = slotOf(c, f, v1);
    let g = 0;
    if (c[4 * f + ((a + 1) % n)] === w) g = 1;
    if (c[4 * f + ((a + n - 1) % n)] === w) g = 2;
    if (g === 0) continue;
    if (!movedSet.has(f)) return g;
    if (guess === 0) guess = 3 - g;
  }
  return guess;
}

// How often each value was added, for the few values of one split: a list searched end to end
// (faster than hashing for a handful), a Map once it holds more than 32 (a hub's fan).
export class SmallCounts {
  constructor() {
    this.keys = [];
    this.counts = [];
    this.map = null;
  }
  clear() {
    this.keys.length = this.counts.length = 0;
    this.map = null;
  }
  add(v) {
    if (this.map) return void this.map.set(v, (this.map.get(v) ?? 0) + 1);
    const at = this.keys.indexOf(v);
    if (at >= 0) return void this.counts[at]++;
    this.keys.push(v), this.counts.push(1);
    if (this.keys.length > 32) this.map = new Map(this.keys.map((k, j) => [k, this.counts[j]]));
  }
  count(v) {
    if (this.map) return this.map.get(v) ?? 0;
    const at = this.keys.indexOf(v);
    return at < 0 ? 0 : this.counts[at];
  }
  has(v) {
    return this.count(v) > 0;
  }
}

// What the moved faces of a split say about its wings (C++ code_record): the corners near v0,
// and v1's edges in moved faces by their far end and how many moved faces hold them. A wing
// vertex ends an edge only one moved face holds (the frontier between v0's and v1's faces)
// and is not yet a wing vertex of this split.
export class MovedFan {
  constructor() {
    this.corners = new SmallCounts();
    this.edgeEnds = new SmallCounts();  // v1's edges in moved faces by their far end: how many
    this.used = [];
  }
  // Empty again, for the next split (the decoder keeps one).
  clear() {
    this.corners.clear();
    this.edgeEnds.clear();
    this.used.length = 0;
  }
  hasCorner(v) {
    return this.corners.has(v);
  }
  add(c, f, v1) {
    const n = degree(c, f), a = slotOf(c, f, v1);
    for (let k = 0; k < 4; k++) {
      const v = c[4 * f + k];
      if (v >= 0 && v !== v1) this.corners.add(v);
    }
    this.edgeEnds.add(c[4 * f + ((a + 1) % n)]);
    this.edgeEnds.add(c[4 * f + ((a + n - 1) % n)]);
  }
  frontier(v) {
    return this.edgeEnds.count(v) === 1 && !this.used.includes(v);
  }
  // A triangle of v1 whose edge from v1 ends on the frontier.
  frontierTriangle(c, f, v1) {
    const a = slotOf(c, f, v1);
    return this.frontier(c[4 * f + ((a + 1) % 3)]) || this.frontier(c[4 * f + ((a + 2) % 3)]);
  }
}

// The values `test` holds for first, then the others, each part in its order.
function partition(list, test) {
  const out = [];
  for (const x of list) if (test(x)) out.push(x);
  if (out.length === list.length) return out;
  for (const x of list) if (!test(x)) out.push(x);
  return out;
}

// A quad wing's candidates: v1's free triangles (not moved, not a wing yet) that hold a corner
// near v0, or all of them when none does; those on the frontier first, each part ascending.
// Also the wing kind's context: 0 no candidate, 1 none on the frontier, 2 some.
export function quadWingCandidates(st, fan, v1, movedSet, moved, quads) {
  const c = st.corners;
  let triangles = [];
  const beside = [];
  let onFrontier = false;
  for (const f of fan) {
    if (c[4 * f + 3] >= 0 || movedSet.has(f) || quads.includes(f)) continue;
    triangles.push(f);
    if (moved.hasCorner(c[4 * f]) || moved.hasCorner(c[4 * f + 1]) || moved.hasCorner(c[4 * f + 2]))
      beside.push(f);
    if (moved.frontierTriangle(c, f, v1)) onFrontier = true;
  }
  if (beside.length > 0) triangles = beside;
  triangles = partition(triangles, (f) => moved.frontierTriangle(c, f, v1));
  return { triangles, kind: triangles.length === 0 ? 0 : onFrontier ? 2 : 1 };
}

// A triangle wing's candidates: v1's neighbours on the frontier, then the other ones near v0,
// then the rest, each part ascending.
export function triangleWingCandidates(st, v1, moved) {
  const near = partition(neighbours(st, v1), (v) => moved.hasCorner(v));
  return partition(near, (v) => moved.frontier(v));
}

// Split i's record into mesh's arrays; a problem, or null.
function decodeRecord(d, st, mesh, i) {
  const v0 = mesh.head.baseVertexCount + i;
  // The error first: how many grid steps down from the split before.
  const down = st.errorStep.decode(d);
  if (down > st.errorCode) return `split ${i}: error is not valid`;
  st.errorCode -= down;
  mesh.error[i] = errorOfCode(st.errorCode, st.errorReference);
  // The parent: within a run of equal errors a step from the parent before, else v0 − 1 − v1.
  let v1;
  if (down === 0 && st.lastParent >= 0) {
    v1 = st.lastParent + st.parentStep.decode(d);
    if (!(v1 >= 0 && v1 < v0)) return `split ${i}: parent out of range`;
  } else {
    const dp = st.parent.decode(d);
    if (dp >= v0) return `split ${i}: parent out of range`;
    v1 = v0 - 1 - dp;
  }
  st.lastParent = v1;
  mesh.parent[i] = v1;
  const fan = st.vertexFaces.of(v1);
  const c = st.corners;
  // Moved faces first: a bit per face of v1 (ascending), by its kind, whether it shares a
  // corner with a face moved before it, and how many moved so far.
  mesh.movedStart[i] = mesh.movedFaces.length;
  const movedList = st.scratch.moved, movedSet = st.scratch.movedSet, moved = st.scratch.fan;
  movedList.length = 0;
  movedSet.clear();
  moved.clear();
  for (const f of fan) {
    let beside = false;
    for (let k = 0; k < 4 && movedList.length > 0; k++) {  // none is beside before one moved
      const v = c[4 * f + k];
      if (v >= 0 && v !== v1 && moved.hasCorner(v)) beside = true;
    }
    const ctx = (c[4 * f + 3] < 0 ? 6 : 0) + (beside ? 3 : 0) + Math.min(movedList.length, 2);
    if (!d.bit(st.moved, ctx)) continue;
    movedList.push(f);
    movedSet.add(f);
    mesh.movedFaces.push(f);
    moved.add(c, f, v1);
  }
  mesh.movedStart[i + 1] = mesh.movedFaces.length;

  const wings = st.wingCount.decode(d);
  if (wings > 4) return `split ${i}: more than 4 wings`;
  const { wingVertex, wingFace, wingFlags } = st.scratch;
  wingVertex.length = wingFace.length = wingFlags.length = 0;
  let created = 0;
  for (let k = 0; k < wings; k++) {
    const { triangles, kind } = quadWingCandidates(st, fan, v1, movedSet, moved, wingFace);
    if (!d.bit(st.wasTriangle, 16 * kind + 4 * (wings - 1) + k)) {
      const index = st.quadFace.decode(d);
      if (index >= triangles.length) return `split ${i}: quad wing face out of range`;
      const f = triangles[index];
      const a = slotOf(c, f, v1);
      const after = c[4 * f + ((a + 1) % 3)], before = c[4 * f + ((a + 2) % 3)];
      const guessBefore = moved.hasCorner(before) && !moved.hasCorner(after);
      const w = d.bit(st.quad, 0) !== (guessBefore ? 1 : 0) ? before : after;
      const b = slotOf(c, f, w);
      let slot = Math.max(a, b);
      if (Math.min(a, b) === 0 && slot === 2) slot = d.bit(st.quad, 1) ? 3 : 0;
      const follows = (b + 1) % 3 === a ? 1 : 0;
      const flag = d.bit(st.quad, 2) ^ follows;
      wingVertex.push(w), wingFace.push(f), moved.used.push(w);
      wingFlags.push((flag ? WING_V1_FOLLOWS_V0 : 0) | (slot << WING_SLOT_SHIFT));
      continue;
    }
    const near = triangleWingCandidates(st, v1, moved);
    const index = st.neighbour.decode(d);
    if (index > near.length) return `split ${i}: wing vertex out of range`;
    let w;
    if (index < near.length) {
      w = near[index];
    } else {
      const dv = st.farVertex.decode(d);
      if (dv >= v0) return `split ${i}: wing vertex out of range`;
      w = v0 - 1 - dv;
    }
    const guess = orientationGuess(st, v1, w, movedSet);
    const follows = d.bit(st.triFollows, guess !== 0 ? 1 : 0) ^ (guess === 2 ? 1 : 0);
    let slot = d.bit(st.triSlot, 0);
    if (slot) slot += d.bit(st.triSlot, 1);
    wingVertex.push(w), wingFace.push(st.faceCount + created++), moved.used.push(w);
    wingFlags.push(WING_WAS_TRIANGLE | (follows ? WING_V1_FOLLOWS_V0 : 0) | (slot << WING_SLOT_SHIFT));
  }
  mesh.wingStart[i] = mesh.wingFlags.length;
  for (let k = 0; k < wings; k++) {
    mesh.wingFlags.push(wingFlags[k]);
    mesh.wingVertex.push(wingVertex[k]);
    mesh.wingFace.push(wingFace[k]);
  }
  mesh.wingStart[i + 1] = mesh.wingFlags.length;

  mesh.faceCountAt[i + 1] = st.faceCount + created;
  return null;
}

const untouched = () => {};  // the replay does not ask which faces a split touched

// Applies split i to st.corners with the file reader's checks, and updates each vertex's faces.
export function applyToModels(st, mesh, i) {
  if (mesh.faceCountAt[i + 1] > mesh.head.faceCount)
    return `split ${i}: the splits create more faces than the header says`;
  let problem = checkSplit(mesh, i, st.corners);
  if (problem) return problem;
  try {
    applySplit(mesh, i, st.corners, untouched);
  } catch (e) {
    if (!(e instanceof DpmError)) throw e;
    return e.message;
  }
  problem = touchedFacesValid(mesh, i, st.corners);
  if (problem) return problem;
  st.faceCount = mesh.faceCountAt[i + 1];
  const v0 = mesh.head.baseVertexCount + i, v1 = mesh.parent[i];
  // v1 keeps its faces that did not move; both lists ascend, so one pass removes them in place.
  const movedFaces = mesh.movedFaces.data, movedEnd = mesh.movedStart[i + 1];
  const fans = st.vertexFaces, fan = fans.of(v1);
  const ofV0 = st.scratch.ofV0;
  ofV0.length = 0;
  let kept = 0;
  for (let k = 0, j = mesh.movedStart[i]; k < fan.length; k++) {
    const f = fan[k];
    while (j < movedEnd && movedFaces[j] < f) j++;
    if (j < movedEnd && movedFaces[j] === f) ofV0.push(f);
    else fan[kept++] = f;
  }
  fans.truncate(v1, kept);
  for (let k = mesh.wingStart[i]; k < mesh.wingStart[i + 1]; k++) {
    const f = mesh.wingFace.data[k];
    insertAscending(ofV0, f);
    if (!(mesh.wingFlags.data[k] & WING_WAS_TRIANGLE)) continue;
    fans.push(v1, f);  // the newest face: the list stays ascending
    fans.push(mesh.wingVertex.data[k], f);
  }
  fans.assign(v0, ofV0);
  return null;
}

// Sorted in place: by insertion when short (a vertex's ring), else by sort() (a hub's).
function sortAscending(list) {
  if (list.length > 16) return void list.sort((x, y) => x - y);
  for (let k = 1; k < list.length; k++) {
    const x = list[k];
    let j = k;
    for (; j > 0 && list[j - 1] > x; j--) list[j] = list[j - 1];
    list[j] = x;
  }
}

function insertAscending(list, x) {
  let k = list.length;
  list.push(x);
  for (; k > 0 && list[k - 1] > x; k--) list[k] = list[k - 1];
  list[k] = x;
}

// The attributes of split i's vertex and created faces, against the mesh after it.
function decodeAttributes(d, st, mesh, i) {
  const v0 = mesh.head.baseVertexCount + i, v1 = mesh.parent[i];
  // The original index by its rank among the free ones, from the parent's; the node id moves
  // with it.
  const free = st.freeVertices;
  const indexGuess = mesh.vertexOriginal[v1];
  const rank = free.below(indexGuess) + st.vertexIndex.decode(d);
  if (!(rank >= 0 && rank < free.count)) return `split ${i}: a vertex's original index is out of range`;
  const index = free.nth(rank);
  free.take(index);
  mesh.vertexOriginal[v0] = index;
  const node = mesh.nodeId[v1] + (index - indexGuess) + st.nodeId.decode(d);
  if (!idFits(node)) return `split ${i}: node id ${node} is not within ±2^51`;
  mesh.nodeId[v0] = node;

  const firstCreated = mesh.faceCountAt[i];
  let like = -1;
  for (let k = mesh.wingStart[i]; k < mesh.wingStart[i + 1] && like < 0; k++)
    if (!(mesh.wingFlags.data[k] & WING_WAS_TRIANGLE)) like = mesh.wingFace.data[k];
  if (like < 0 && mesh.movedStart[i + 1] > mesh.movedStart[i])
    like = mesh.movedFaces.data[mesh.movedStart[i]];
  const fans = st.vertexFaces;  // v1's first face, without a view of its list
  const first = fans.size[v1] > 0 ? fans.values[fans.start[v1]] : -1;
  if (like < 0 && first >= 0 && first < firstCreated) like = first;
  const partGuess = like < 0 ? 0 : mesh.partId[like];
  const faceGuess = like < 0 ? 0 : mesh.faceOriginal[like];
  const elementGuess = like < 0 ? 0 : mesh.elementId[like];
  const freeFaces = st.freeFaces;
  const rankGuess = freeFaces.below(faceGuess);
  for (let g = firstCreated; g < st.faceCount; g++) {
    let part = partGuess;
    if (d.bit(st.samePart, 0)) part = partGuess + st.part.decode(d);
    const faceRank = rankGuess + st.faceIndex.decode(d);
    if (!(faceRank >= 0 && faceRank < freeFaces.count))
      return `split ${i}: a face's original index is out of range`;
    const face = freeFaces.nth(faceRank);
    freeFaces.take(face);
    const element = elementGuess + (face - faceGuess) + st.elementId.decode(d);
    if (!(part >= -2147483648 && part <= 2147483647)) return `split ${i}: a part id is out of range`;
    if (!idFits(element)) return `split ${i}: element id ${element} is not within ±2^51`;
    mesh.partId[g] = part;
    mesh.faceOriginal[g] = face;
    mesh.elementId[g] = element;
  }
  return null;
}

// Decodes splits [first, first + count) from the two sections (Uint8Arrays) into mesh's arrays
// (parent, error, wingStart, wingFace, wingVertex, wingFlags, movedStart, movedFaces,
// faceCountAt, vertexOriginal, nodeId, faceOriginal, partId, elementId), applying each split to
// models.corners with the reader's checks, then calling afterSplit(i) (the reader takes the
// positions' stencils there). Returns what is wrong, or null.
export function decodeSplitRecords(records, attributes, first, count, mesh, models, afterSplit) {
  const rd = new RangeDecoder(records);
  const ad = new RangeDecoder(attributes);
  for (let i = first; i < first + count; i++) {
    let problem = decodeRecord(rd, models, mesh, i);
    if (!rd.ok()) return 'the split records section is cut short or damaged';
    if (problem) return problem;
    problem = applyToModels(models, mesh, i);
    if (problem) return problem;
    problem = decodeAttributes(ad, models, mesh, i);
    if (!ad.ok()) return 'the split attributes section is cut short or damaged';
    if (problem) return problem;
    afterSplit?.(i);
  }
  if (first + count === mesh.head.splitCount && models.faceCount !== mesh.head.faceCount)
    return 'the splits create fewer faces than the header says';
  if (!rd.exhausted()) return 'bytes left over after the split records';
  if (!ad.exhausted()) return 'bytes left over after the split attributes';
  return null;
}
