// The mesh at one level (C++: Navigator, src/lod/navigator.cpp): splits applied or undone in
// place between levels, touching only the faces their records name.
import { DpmError, withRoom } from './bytes.js';
import { DirtyFaces, splitRecords, WING_SLOT_SHIFT, WING_V1_FOLLOWS_V0, WING_WAS_TRIANGLE } from './progressive_mesh.js';

// Holds the current faces (4 corner slots, −1 in slot 3 of a triangle) for levels up to what has
// been loaded. Changes are recorded as a list of touched faces, which the renderer drains
// (takeDirty) to rewrite just those faces' index entries (draw_indices.js).
//
// Its own loops apply and undo the splits (as the C++ navigator's, without applySplits()'s
// checks), and they write faces without reading them: at 1 M vertices nearly every face a split
// names is a cache miss, and JavaScript has no prefetch, so a loop that reads a face waits for
// it (the reorder buffer fills behind the load) while stores drain from the store buffer in the
// background. What a write needs besides the record is learned the first time a split is
// applied (levels are a function of the split count, so it never changes): the slot of the
// parent in each moved face, and for each wing the slots of v1 and w and the fourth corner.
export class Navigator {
  constructor(mesh) {
    if (!mesh.hasBase) throw new DpmError('Navigator needs the BASE chunk');
    this.mesh = mesh;
    const F = mesh.head.faceCount;
    const nf = mesh.head.baseFaceCount;
    // 4 slots per face, −1 in slot 3 of a triangle: the degree is read from the slots, so that a
    // face is one 16-byte record (one cache miss per face a split touches, not two). Room for
    // the faces of the finest level reached so far (makeRoom()).
    this.corners = withRoom(new Int32Array(0), 4 * nf, 4 * F, -1);
    this.corners.set(mesh.baseCorners);
    this.level = 0;  // splits applied
    this.quads = 0;
    for (let f = 0; f < nf; f++) this.quads += mesh.baseDegree[f] === 4 ? 1 : 0;
    // The touched faces, each once.
    this.dirty = new DirtyFaces(F);
    for (let f = 0; f < nf; f++) this.dirty.add(f);
    // Splits [0, learned) have been applied once, and their slots below are known.
    this.learned = 0;
    // per moved face (as mesh.movedFaces): the slot where v1 is (and v0 will be)
    this.movedSlot = new Uint8Array(0);
    // per wing (as mesh.wingFace), in the face with the split applied: v1's slot | w's slot << 2
    this.wingSlots = new Uint8Array(0);
    // per wing: the corner in the remaining slot (6 − the other three): a quad wing's corner
    // opposite v0, −1 (slot 3) for a triangle wing
    this.wingOpposite = new Int32Array(0);
  }

  get vertexCount() {
    return this.mesh.head.baseVertexCount + this.level;
  }
  get faceCount() {
    return this.mesh.faceCountAt[this.level];
  }
  get quadCount() {
    return this.quads;
  }
  get triangleCount() {
    return this.faceCount - this.quads;
  }
  get error() {
    return this.mesh.levelError(this.level);
  }
  // Field f's error at this level, a fraction of its range (FORMAT.md "Field errors").
  fieldError(f) {
    return this.mesh.fields[f].levelError(this.level);
  }

  touch(f) {
    this.dirty.add(f);
  }

  // The faces changed since the last call (may include faces now beyond faceCount).
  takeDirty() {
    return this.dirty.take();
  }

  // Any level in [0, splitsLoaded]; returns the level reached.
  setLevel(k) {
    k = Math.max(0, Math.min(k, this.mesh.splitsLoaded));
    if (k > this.level) this.refine(k);
    else if (k < this.level) this.coarsen(k);
    return this.level;
  }
  setVertexCount(n) {
    return this.setLevel(n - this.mesh.head.baseVertexCount);
  }

  // The coarsest loaded level whose error is ≤ e (ProgressiveMesh.levelForError()).
  levelForError(e) {
    return this.mesh.levelForError(e);
  }

  // Applies splits [level, k): split i re-creates v0 = b + i from its parent.
  refine(k = this.level + 1) {
    const track = this.tracks(this.level, k);
    const known = Math.min(k, this.learned);
    const records = splitRecords(this.mesh);
    if (this.level < known) {
      this.quads += applyKnown(this, records, this.level, known, track);
      this.level = known;
    }
    if (known < k) {
      this.makeRoom(k);
      // Applied for the first time, one by one: each split's slots are learned from the faces as
      // the splits before it left them; those applied count even if a later one is refused.
      for (let i = known; i < k; i++) {
        learnSlots(this, records, i);
        this.quads += applyKnown(this, records, i, i + 1, track);
        this.learned = this.level = i + 1;
      }
    }
  }

  // Undoes splits [k, level) from the last: each is the collapse v0 → v1.
  coarsen(k = this.level - 1) {
    this.quads -= undoKnown(this, splitRecords(this.mesh), this.level, k, this.tracks(k, this.level));
    this.level = k;
  }

  // Whether a move over splits [from, to) lists the faces it touches: one whose records name
  // more faces than half the mesh has marks every face touched instead, since the renderer
  // then rewrites every face in order, cheaper than half of them in random order.
  tracks(from, to) {
    const { movedStart, wingStart } = this.mesh;
    const named = movedStart[to] - movedStart[from] + wingStart[to] - wingStart[from];
    if (named <= this.mesh.head.faceCount >> 1) return true;
    this.dirty.addAll();
    return false;
  }

  // Face f's corners at this level (for tests and exports).
  face(f) {
    return Array.from(this.corners.subarray(4 * f, 4 * f + this.degree(f)));
  }

  degree(f) {
    return this.corners[4 * f + 3] < 0 ? 3 : 4;
  }

  // Room in the learned slots for the records of splits [0, k) (grown by doubling: the records
  // grow as the file arrives), and in the faces for level k.
  makeRoom(k) {
    this.corners = withRoom(this.corners, 4 * this.mesh.faceCountAt[k], 4 * this.mesh.head.faceCount, -1);
    const moved = this.mesh.movedStart[k], wings = this.mesh.wingStart[k];
    this.movedSlot = withRoom(this.movedSlot, moved, Infinity);
    this.wingSlots = withRoom(this.wingSlots, wings, Infinity);
    this.wingOpposite = withRoom(this.wingOpposite, wings, Infinity);
  }
}

// Splits [from, to), all learned (r: splitRecords()): nothing but stores to the faces and, when
// tracking, to the touched-face list; returns the quads they make.
function applyKnown(nav, r, from, to, track) {
  const { corners, dirty, movedSlot, wingSlots, wingOpposite } = nav;
  const touched = dirty.list, seen = dirty.mark;
  let count = dirty.count, quads = 0;
  for (let i = from, v0 = r.b + from; i < to; i++, v0++) {
    const v1 = r.parent[i];
    for (let j = r.movedStart[i], jEnd = r.movedStart[i + 1]; j < jEnd; j++) {
      const f = r.movedFaces[j];
      corners[4 * f + movedSlot[j]] = v0;
      if (track) (touched[count] = f), (count += 1 - seen[f]), (seen[f] = 1);
    }
    // Both kinds of wing alike: v0, v1, w and the fourth corner (the quad's, or −1 in slot 3 of
    // a re-created triangle) each to its slot.
    for (let j = r.wingStart[i], jEnd = r.wingStart[i + 1]; j < jEnd; j++) {
      const flags = r.wingFlags[j];
      const f = r.wingFace[j];
      const s = (flags >> WING_SLOT_SHIFT) & 3;
      const s1 = wingSlots[j] & 3, sw = wingSlots[j] >> 2;
      const c = 4 * f;
      corners[c + s] = v0;
      corners[c + s1] = v1;
      corners[c + sw] = r.wingVertex[j];
      corners[c + 6 - s - s1 - sw] = wingOpposite[j];
      quads += 1 - (flags & WING_WAS_TRIANGLE);
      if (track) (touched[count] = f), (count += 1 - seen[f]), (seen[f] = 1);
    }
  }
  dirty.count = count;
  return quads;
}

// Undoes splits [to, from) from the last (all learned): stores only; returns the quads they turn
// back into triangles.
function undoKnown(nav, r, from, to, track) {
  const { corners, dirty, movedSlot, wingSlots, wingOpposite } = nav;
  const touched = dirty.list, seen = dirty.mark;
  let count = dirty.count, quads = 0;
  for (let i = from - 1; i >= to; i--) {
    const v1 = r.parent[i];
    for (let j = r.wingStart[i + 1] - 1; j >= r.wingStart[i]; j--) {
      const flags = r.wingFlags[j];
      const f = r.wingFace[j];
      const c = 4 * f;
      // A quad wing loses v0: the corners after slot s move one slot down. A re-created triangle
      // is removed (it lies beyond the face count now), so the same stores may scribble on it:
      // no branch on the wing's kind, which is random on a large mesh (as in the C++ navigator).
      const s = (flags >> WING_SLOT_SHIFT) & 3;
      const s1 = wingSlots[j] & 3, sw = wingSlots[j] >> 2, sx = 6 - s - s1 - sw;
      corners[c + s1 - ((s - s1) >>> 31)] = v1;
      corners[c + sw - ((s - sw) >>> 31)] = r.wingVertex[j];
      corners[c + sx - ((s - sx) >>> 31)] = wingOpposite[j];
      corners[c + 3] = -1;
      quads += 1 - (flags & WING_WAS_TRIANGLE);
      if (track) (touched[count] = f), (count += 1 - seen[f]), (seen[f] = 1);
    }
    for (let j = r.movedStart[i], jEnd = r.movedStart[i + 1]; j < jEnd; j++) {
      const f = r.movedFaces[j];
      corners[4 * f + movedSlot[j]] = v1;
      if (track) (touched[count] = f), (count += 1 - seen[f]), (seen[f] = 1);
    }
  }
  dirty.count = count;
  return quads;
}

// What applyKnown() needs of split i, read from the faces before it is applied. The records
// passed the decoder's checks (checkSplit(), touchedFacesValid()); what those rule out is still
// refused: a moved face without the parent or named twice (applied face by face, the second
// would find the parent gone), a quad wing that is not a triangle holding v1 and w.
function learnSlots(nav, r, i) {
  const { corners, movedSlot, wingSlots, wingOpposite } = nav;
  const v1 = r.parent[i];
  const firstMoved = r.movedStart[i];
  for (let j = firstMoved; j < r.movedStart[i + 1]; j++) {
    const f = r.movedFaces[j];
    const c = 4 * f;
    let named = 0;
    for (let k = firstMoved; k < j; k++) named |= r.movedFaces[k] === f;
    const holds = (corners[c] === v1) | (corners[c + 1] === v1) | (corners[c + 2] === v1) | (corners[c + 3] === v1);
    if (named || !holds) throw new DpmError(`split ${i}: moved face ${f} is named twice`);
    movedSlot[j] = (corners[c + 1] === v1 ? 1 : 0) + (corners[c + 2] === v1 ? 2 : 0) + (corners[c + 3] === v1 ? 3 : 0);
  }
  for (let j = r.wingStart[i]; j < r.wingStart[i + 1]; j++) {
    const flags = r.wingFlags[j];
    const w = r.wingVertex[j];
    const s = (flags >> WING_SLOT_SHIFT) & 3;
    if (flags & WING_WAS_TRIANGLE) {
      // [s] = v0, [s+1] = v1, [s+2] = w (mod 3) when v1 follows v0, else w and v1 swapped.
      const follows = (flags & WING_V1_FOLLOWS_V0) !== 0;
      wingSlots[j] = ((s + (follows ? 1 : 2)) % 3) | (((s + (follows ? 2 : 1)) % 3) << 2);
      wingOpposite[j] = -1;
      continue;
    }
    // A quad wing: the triangle's corners from slot s on move one slot up.
    const c = 4 * r.wingFace[j];
    const x1 = corners[c + 1], x2 = corners[c + 2];
    const t1 = (x1 === v1 ? 1 : 0) + (x2 === v1 ? 2 : 0), tw = (x1 === w ? 1 : 0) + (x2 === w ? 2 : 0);
    if (corners[c + t1] !== v1 || corners[c + tw] !== w || corners[c + 3] >= 0)
      throw new DpmError(`split ${i}: wing face ${r.wingFace[j]} is not a triangle holding the parent and the wing vertex`);
    wingSlots[j] = (t1 + (t1 >= s ? 1 : 0)) | ((tw + (tw >= s ? 1 : 0)) << 2);
    wingOpposite[j] = corners[c + 3 - t1 - tw];
  }
}
