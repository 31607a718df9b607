// The mesh at one level (C++: Navigator, src/lod/navigator.cpp): splits applied or undone in
// place between levels, touching only the faces their records name.
import { DpmError } from './bytes.js';
import { DirtyFaces, applySplits, undoSplits } from './progressive_mesh.js';

// Holds the current faces (4 corner slots, −1 in slot 3 of a triangle) for levels up to what has
// been loaded. Changes are recorded as a list of touched faces, which the renderer drains
// (takeDirty) to rewrite just those faces' index entries (draw_indices.js).
export class Navigator {
  constructor(mesh) {
    if (!mesh.hasBase) throw new DpmError('Navigator needs the BASE chunk');
    this.mesh = mesh;
    const F = mesh.head.faceCount;
    const nf = mesh.head.baseFaceCount;
    // 4 slots per face, −1 in slot 3 of a triangle: the degree is read from the slots, so that a
    // face is one 16-byte record (one cache miss per face a split touches, not two).
    this.corners = new Int32Array(4 * F).fill(-1);
    this.corners.set(mesh.baseCorners);
    this.level = 0;  // splits applied
    this.quads = 0;
    for (let f = 0; f < nf; f++) this.quads += mesh.baseDegree[f] === 4 ? 1 : 0;
    // The touched faces, each once.
    this.dirty = new DirtyFaces(F);
    for (let f = 0; f < nf; f++) this.dirty.add(f);
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
    this.quads += applySplits(this.mesh, this.level, k, this.corners, this.dirty);
    this.level = k;
  }

  // Undoes splits [k, level) from the last: each is the collapse v0 → v1.
  coarsen(k = this.level - 1) {
    this.quads -= undoSplits(this.mesh, this.level, k, this.corners, this.dirty);
    this.level = k;
  }

  // Face f's corners at this level (for tests and exports).
  face(f) {
    return Array.from(this.corners.subarray(4 * f, 4 * f + this.degree(f)));
  }

  degree(f) {
    return this.corners[4 * f + 3] < 0 ? 3 : 4;
  }
}
