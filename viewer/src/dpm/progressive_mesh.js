// The progressive mesh as far as it has arrived, and the vertex split and its inverse on a face
// array (docs/FORMAT.md "Applying a split"). The C++ side: ProgressiveMesh in
// include/dynpm/progressive.h, apply_split()/undo_split() in src/progressive/progressive_mesh.cpp;
// the names of the split record are the same on both sides.
//
// Positions are kept as the file's quantized integers, compact (step_positions.js), so that any
// level at any (fractional) step is a prefix of a step made in one pass; they hold the vertices
// that have arrived (makeRoom()). Faces are 4 corner slots each, −1 in slot 3 of a triangle (one
// 16-byte record per face).
import { DpmError, Growable, withRoom } from './bytes.js';
import { StepPositions } from './step_positions.js';

// A wing's flags (FORMAT.md "SPLT payload"; C++ SplitWing::kWasTriangle, kV1FollowsV0,
// kSlotShift): the face was a triangle (re-created), v1 followed v0 in its corner order, and
// v0's corner slot in bits 2–3.
export const WING_WAS_TRIANGLE = 1;
export const WING_V1_FOLLOWS_V0 = 2;
export const WING_SLOT_SHIFT = 2;
export const HEAD_FLAG_LOSSLESS = 1;
// A browser tab cannot hold more; a HEAD asking for it is refused before anything is allocated.
const MAX_ARRAY_ELEMENTS = 2 ** 31 - 1;

export class ProgressiveMesh {
  constructor(head) {
    this.head = head;
    const { vertexCount: V, faceCount: F, stepCount: m } = head;
    if (3 * V * 1 > MAX_ARRAY_ELEMENTS || 4 * F > MAX_ARRAY_ELEMENTS)
      throw new DpmError(`HEAD: ${V} vertices, ${F} faces, ${m} steps: more than a browser holds`);
    // every step's positions: quantized integers (or f32 bit patterns when lossless)
    this.positions = new StepPositions(m, (head.flags & HEAD_FLAG_LOSSLESS) !== 0, V);
    this.fields = [];  // result fields (DpmField, fields.js), from FDEF
    this.partNames = new Map();  // part id → name, from PART (parts.js)
    // per face a split re-creates: the face that stands for it while the split is undone
    // (Int32Array(F), −1 for base faces; only when a field is per element)
    this.faceHeir = null;
    // Original indices lie in [0, V) and [0, F), part ids in int32 (both readers refuse others);
    // node and element ids need 53 bits (±2^51).
    this.vertexOriginal = new Int32Array(V);  // per vertex: its position in the input's order
    this.nodeId = new Float64Array(V);  // per vertex: the FE node id
    // Faces as the base mesh has them; splits re-create the others (Navigator).
    this.baseDegree = null;  // per base face: 3 or 4 (Uint8Array, from BASE)
    this.baseCorners = null;  // per base face: 4 slots, −1 in slot 3 of a triangle (Int32Array)
    this.faceOriginal = new Int32Array(F);  // per face: its position in the input's order
    this.partId = new Int32Array(F);  // per face: the FE part id
    this.elementId = new Float64Array(F);  // per face: the FE element id
    // The split records (paper §4's vsp), flat; split i creates vertex v0 = b + i.
    const S = head.splitCount;
    this.parent = new Int32Array(S);  // per split: v1, the vertex v0 was collapsed into
    this.error = new Float32Array(S);  // per split: the error of the mesh right after it
    this.wingStart = new Uint32Array(S + 1);  // split i's wings: [wingStart[i], wingStart[i+1])
    // per wing: the quad's face (a triangle until the split), or the re-created triangle's face
    this.wingFace = new Growable(Int32Array, S * 2);
    this.wingVertex = new Growable(Int32Array, S * 2);  // per wing: w, v0's other neighbour in it
    // per wing: WING_WAS_TRIANGLE | WING_V1_FOLLOWS_V0 | v0's corner slot << WING_SLOT_SHIFT
    this.wingFlags = new Growable(Uint8Array, S * 2);
    // split i's moved faces: [movedStart[i], movedStart[i+1])
    this.movedStart = new Uint32Array(S + 1);
    this.movedFaces = new Growable(Int32Array, S * 2);  // faces that hold v1 and take v0 instead
    this.faceCountAt = new Uint32Array(S + 1);  // faces after k splits
    this.hasBase = false;
    this.splitsLoaded = 0;
    this.complete = false;
    // Delta chains that continue across chunks.
    this.lastVertexOriginal = 0;
    this.lastNodeId = 0;
    this.lastElementId = 0;
    this.lastFaceOriginal = 0;
  }

  // Room in the arrays of every step (positions, field values) for the first `vertices`
  // vertices and `faces` faces; the decoder asks before a chunk writes them. The arrays may be
  // new ones: read a field's q[t] after a chunk, not before. `doubling`: as withRoom().
  makeRoom(vertices, faces, doubling = true) {
    const { vertexCount: V, faceCount: F } = this.head;
    this.positions.makeRoom(vertices, doubling);
    for (const f of this.fields) {
      const [n, max] = f.perFace ? [faces, F] : [vertices, V];
      for (let t = 0; t < f.q.length; t++) f.q[t] = withRoom(f.q[t], n, max, 0, doubling);
    }
  }

  get lossless() {
    return (this.head.flags & HEAD_FLAG_LOSSLESS) !== 0;
  }
  // Vertices available: the base plus the splits that have arrived.
  get vertexCountLoaded() {
    return this.hasBase ? this.head.baseVertexCount + this.splitsLoaded : 0;
  }
  // The error of the level with k splits applied.
  levelError(k) {
    return k === 0 ? this.head.baseError : this.error[k - 1];
  }
  // The coarsest loaded level whose error is ≤ e (errors never increase along the stream).
  levelForError(e) {
    if (this.head.baseError <= e) return 0;
    let lo = 0, hi = this.splitsLoaded;  // search the first split i with error[i] ≤ e
    while (lo < hi) {
      const mid = (lo + hi) >> 1;
      if (this.error[mid] <= e) hi = mid;
      else lo = mid + 1;
    }
    return Math.min(lo + 1, this.splitsLoaded);
  }
  // The same level as a vertex count (the panel's max error box, setLevel({error}), compare's
  // link by error).
  vertexCountForError(e) {
    return this.head.baseVertexCount + this.levelForError(e);
  }
  // Position of vertex v at integer step t, as the f32 the file means.
  position(v, t, out = [0, 0, 0]) {
    const q = this.positions.position(v, this.storedStep(t), out);
    if (this.lossless) {
      bits.set(q);
      out[0] = bitsAsFloat[0], out[1] = bitsAsFloat[1], out[2] = bitsAsFloat[2];
    } else {
      const { bboxMin, quantStep } = this.head;
      for (let c = 0; c < 3; c++) out[c] = Math.fround(bboxMin[c] + q[c] * quantStep);
    }
    return out;
  }

  // The step of the stored positions that step t shows (a variant's view maps them: variants.js).
  storedStep(t) {
    return t;
  }

  // The steps around fractional step t (clamped to the animation) and the weight of the later:
  // a value at t is v[t0] + (v[t1] - v[t0]) * a.
  stepsAround(t) {
    const m = this.head.stepCount;
    t = Math.min(Math.max(t, 0), m - 1);
    const t0 = Math.floor(t);
    return { t0, t1: Math.min(t0 + 1, m - 1), a: t - t0 };
  }

  // Positions of vertices [0, n) at fractional step t (linear between the two steps around it),
  // into out (Float32Array, ≥ 3n). This is the per-frame work while time changes: one pass over
  // a prefix of two steps (made from the step before in one more pass when time crosses a step).
  positionsAt(t, n, out) {
    const { t0, t1, a } = this.stepsAround(t);
    const [q0, q1] = this.positions.around(this.storedStep(t0), this.storedStep(a === 0 ? t0 : t1), n);
    return positionsBetween(this.head, q0, q1, a, n, out);
  }

  // |p − p(0)| of vertices [0, n), given their positions now and at step 0.
  static displacement(positions, base, n, out) {
    for (let v = 0, i = 0; v < n; v++, i += 3) {
      const dx = positions[i] - base[i];
      const dy = positions[i + 1] - base[i + 1];
      const dz = positions[i + 2] - base[i + 2];
      out[v] = Math.sqrt(dx * dx + dy * dy + dz * dz);
    }
    return out;
  }
}

const bits = new Int32Array(3);
const bitsAsFloat = new Float32Array(bits.buffer);

// Positions of vertices [0, n) a fraction a of the way from the integers q0 to q1 (Int32Arrays,
// 3 a vertex: quantized, or f32 bit patterns in a lossless file), into out.
export function positionsBetween(head, q0, q1, a, n, out) {
  const count = 3 * n;
  if (head.flags & HEAD_FLAG_LOSSLESS) {
    const p0 = new Float32Array(q0.buffer, q0.byteOffset, count);
    const p1 = new Float32Array(q1.buffer, q1.byteOffset, count);
    if (a === 0) out.set(p0);
    else for (let i = 0; i < count; i++) out[i] = p0[i] + (p1[i] - p0[i]) * a;
    return out;
  }
  const s = head.quantStep;
  const [x0, y0, z0] = head.bboxMin;
  if (a === 0) {
    for (let i = 0; i < count; i += 3) {
      out[i] = x0 + q0[i] * s;
      out[i + 1] = y0 + q0[i + 1] * s;
      out[i + 2] = z0 + q0[i + 2] * s;
    }
  } else {
    const b0 = (1 - a) * s;
    const b1 = a * s;
    for (let i = 0; i < count; i += 3) {
      out[i] = x0 + q0[i] * b0 + q1[i] * b1;
      out[i + 1] = y0 + q0[i + 1] * b0 + q1[i + 1] * b1;
      out[i + 2] = z0 + q0[i + 2] * b0 + q1[i + 2] * b1;
    }
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// The vertex split and its inverse on a face array: corners holds 4 slots per face (−1 in slot 3
// of a triangle) and room for every face of the mesh; its first faceCountAt[i] faces are the
// current ones when split i is applied. touch(f) hears of every face that changes.

function slotOf(corners, f, v) {
  const c = 4 * f;
  for (let k = 0; k < 4; k++) if (corners[c + k] === v) return k;
  return -1;
}

// What is wrong with split i on these faces, or null: indices in range, moved faces hold the
// parent, quad wings are triangles holding the parent and the wing vertex. For decoders of
// untrusted files, before applySplit() (C++: check_split()).
export function checkSplit(mesh, i, corners) {
  const v0 = mesh.head.baseVertexCount + i;
  const v1 = mesh.parent[i];
  const faceCount = mesh.faceCountAt[i];
  const where = `split ${i}: `;
  if (v1 >= v0) return `${where}parent ${v1} does not exist yet`;
  const movedFaces = mesh.movedFaces.data;
  for (let j = mesh.movedStart[i]; j < mesh.movedStart[i + 1]; j++) {
    const f = movedFaces[j];
    if (f >= faceCount) return `${where}moved face ${f} does not exist`;
    if (slotOf(corners, f, v1) < 0) return `${where}moved face ${f} does not hold the parent`;
  }
  let created = faceCount;
  for (let j = mesh.wingStart[i]; j < mesh.wingStart[i + 1]; j++) {
    const flags = mesh.wingFlags.data[j];
    const w = mesh.wingVertex.data[j];
    const f = mesh.wingFace.data[j];
    if (w >= v0 || w === v1) return `${where}wing vertex ${w} is not valid`;
    if (flags & WING_WAS_TRIANGLE) {
      if (f !== created || 4 * created >= corners.length)
        return `${where}re-created face ${f} is out of order`;
      if (flags >> WING_SLOT_SHIFT > 2) return `${where}a triangle has no corner slot 3`;
      created++;
      continue;
    }
    if (f >= faceCount) return `${where}wing face ${f} does not exist`;
    if (corners[4 * f + 3] >= 0 || slotOf(corners, f, v1) < 0 || slotOf(corners, f, w) < 0)
      return `${where}wing face ${f} is not a triangle holding the parent and the wing vertex`;
  }
  return null;
}

// The faces touched since the last take(), each once: a mark per face and a list with room for
// every face, so that adding one is branch-free (a branch on the mark, a random byte, would be
// mispredicted half the time in a full refine).
export class DirtyFaces {
  constructor(faceCount) {
    this.mark = new Uint8Array(faceCount);
    this.list = new Uint32Array(faceCount + 1);  // + 1: add() writes before it counts
    this.count = 0;
    this.all = false;  // every face counts as touched (addAll())
  }
  add(f) {
    this.list[this.count] = f;
    this.count += 1 - this.mark[f];
    this.mark[f] = 1;
  }
  // Every face counts as touched: for a change that touches most of them, which then need not
  // be listed one by one.
  addAll() {
    this.all = true;
  }
  // The faces touched since the last call (a view, valid until the next change).
  take() {
    if (this.all) {
      const { list } = this, n = list.length - 1;
      this.clear();
      for (let f = 0; f < n; f++) list[f] = f;
      return list.subarray(0, n);
    }
    const list = this.list.subarray(0, this.count);
    this.clear();
    return list;
  }
  // Forgets the touched faces (list[0, count) stays as it was until the next add()).
  clear() {
    const { list, mark } = this;
    if (this.all) mark.fill(0), (this.all = false);
    else for (let i = 0; i < this.count; i++) mark[list[i]] = 0;
    this.count = 0;
  }
}

// Split i re-creates v0 = b + i from its parent v1 (FORMAT.md "Applying a split"); returns the
// quads it makes (its quad wings) and calls touch(f) for each face it changes. Records are
// applied unchecked: checkSplit() and touchedFacesValid() ran when they were decoded.
export function applySplit(mesh, i, corners, touch) {
  const dirty = dirtyFor(corners);
  try {
    return applySplits(mesh, i, i + 1, corners, dirty);
  } finally {
    // Not take(): the decoder's replay calls this for every split, and a view is an allocation.
    const { list, count } = dirty;
    dirty.clear();
    for (let k = 0; k < count; k++) touch(list[k]);
  }
}

// The inverse of applySplit(): the collapse v0 → v1. Returns the quads it turns back into
// triangles.
export function undoSplit(mesh, i, corners, touch) {
  const dirty = dirtyFor(corners);
  const quads = undoSplits(mesh, i + 1, i, corners, dirty);
  for (const f of dirty.take()) touch(f);
  return quads;
}

let single = null;  // applySplit()'s and undoSplit()'s touched faces
function dirtyFor(corners) {
  if (!single || 4 * single.mark.length < corners.length) single = new DirtyFaces(corners.length >> 2);
  return single;
}

// The split records as the loops over them take them: each array in a local (the Growables'
// current arrays), b the base vertex count (split i creates v0 = b + i).
export function splitRecords(mesh) {
  const { parent, movedStart, wingStart } = mesh;
  return {
    b: mesh.head.baseVertexCount, parent, movedStart, wingStart, movedFaces: mesh.movedFaces.data,
    wingFlags: mesh.wingFlags.data, wingVertex: mesh.wingVertex.data, wingFace: mesh.wingFace.data,
  };
}

// Splits [from, to) in order, the faces they change added to `dirty`; the quads they make. The
// navigator's hot path: every array in a local, and no branch on a face's contents (at 1 M
// vertices nearly every face a split names is a cache miss; a mispredicted branch on what one
// holds would hold back the next one's load until it arrived).
export function applySplits(mesh, from, to, corners, dirty) {
  const { b, parent, movedStart, wingStart, movedFaces, wingFlags, wingVertex, wingFace } = splitRecords(mesh);
  const { mark, list } = dirty;
  let n = dirty.count;
  let quads = 0;
  for (let i = from; i < to; i++) {
    const v0 = b + i;
    const v1 = parent[i];
    // 1. Moved faces: the corner holding v1 takes v0.
    for (let j = movedStart[i], end = movedStart[i + 1]; j < end; j++) {
      const f = movedFaces[j];
      const c = 4 * f;
      const x0 = corners[c], x1 = corners[c + 1], x2 = corners[c + 2], x3 = corners[c + 3];
      if (((x0 === v1) | (x1 === v1) | (x2 === v1) | (x3 === v1)) === 0) {
        dirty.count = n;
        throw new DpmError(`split ${i}: moved face ${f} is named twice`);
      }
      corners[c] = x0 === v1 ? v0 : x0;
      corners[c + 1] = x1 === v1 ? v0 : x1;
      corners[c + 2] = x2 === v1 ? v0 : x2;
      corners[c + 3] = x3 === v1 ? v0 : x3;
      list[n] = f;
      n += 1 - mark[f];
      mark[f] = 1;
    }
    for (let j = wingStart[i], end = wingStart[i + 1]; j < end; j++) {
      const flags = wingFlags[j];
      const w = wingVertex[j];
      const f = wingFace[j];
      const s = (flags >> WING_SLOT_SHIFT) & 3;
      const c = 4 * f;
      if (flags & WING_WAS_TRIANGLE) {
        // 2. Triangle wing: the face the collapse removed comes back, v0 at slot s.
        const v1Follows = (flags & WING_V1_FOLLOWS_V0) !== 0;
        corners[c + s] = v0;
        corners[c + ((s + 1) % 3)] = v1Follows ? v1 : w;
        corners[c + ((s + 2) % 3)] = v1Follows ? w : v1;
        corners[c + 3] = -1;
      } else {
        // 3. Quad wing: the triangle becomes the quad again, v0 back into slot s.
        for (let k = 3; k > s; k--) corners[c + k] = corners[c + k - 1];
        corners[c + s] = v0;
        quads++;
      }
      list[n] = f;
      n += 1 - mark[f];
      mark[f] = 1;
    }
  }
  dirty.count = n;
  return quads;
}

// Undoes splits [to, from) from the last (from > to): each is the collapse v0 → v1; the quads
// they turn back into triangles.
export function undoSplits(mesh, from, to, corners, dirty) {
  const { b, parent, movedStart, wingStart, movedFaces, wingFlags, wingFace } = splitRecords(mesh);
  const { mark, list } = dirty;
  let n = dirty.count;
  let quads = 0;
  for (let i = from - 1; i >= to; i--) {
    const v0 = b + i;
    const v1 = parent[i];
    for (let j = wingStart[i + 1] - 1; j >= wingStart[i]; j--) {
      const f = wingFace[j];
      const flags = wingFlags[j];
      const c = 4 * f;
      if (!(flags & WING_WAS_TRIANGLE)) {
        for (let k = (flags >> WING_SLOT_SHIFT) & 3; k < 3; k++) corners[c + k] = corners[c + k + 1];
        quads++;
      }
      corners[c + 3] = -1;  // a re-created triangle is removed: beyond the face count now
      list[n] = f;
      n += 1 - mark[f];
      mark[f] = 1;
    }
    for (let j = movedStart[i], end = movedStart[i + 1]; j < end; j++) {
      const f = movedFaces[j];
      const c = 4 * f;
      const x0 = corners[c], x1 = corners[c + 1], x2 = corners[c + 2], x3 = corners[c + 3];
      corners[c] = x0 === v0 ? v1 : x0;
      corners[c + 1] = x1 === v0 ? v1 : x1;
      corners[c + 2] = x2 === v0 ? v1 : x2;
      corners[c + 3] = x3 === v0 ? v1 : x3;
      list[n] = f;
      n += 1 - mark[f];
      mark[f] = 1;
    }
  }
  dirty.count = n;
  return quads;
}

// After a checked split: every face it touched has distinct corners (a face named twice, or
// both moved and a wing, would not). What is wrong, or null (C++: touched_faces_valid()).
export function touchedFacesValid(mesh, i, corners) {
  const distinct = (f) => {
    const c = 4 * f;
    const a = corners[c], b = corners[c + 1], d = corners[c + 2], x = corners[c + 3];
    return !(a === b || a === d || b === d || a === x || b === x || d === x);
  };
  for (let j = mesh.movedStart[i]; j < mesh.movedStart[i + 1]; j++)
    if (!distinct(mesh.movedFaces.data[j]))
      return `split ${i}: face ${mesh.movedFaces.data[j]} is named twice`;
  for (let j = mesh.wingStart[i]; j < mesh.wingStart[i + 1]; j++)
    if (!distinct(mesh.wingFace.data[j]))
      return `split ${i}: face ${mesh.wingFace.data[j]} is named twice`;
  return null;
}
