// The mesh with any dependency-closed set of splits applied, not only a prefix (selective
// refinement, docs/viewer.md): full resolution where it is wanted, a coarse level elsewhere.
// C++: SelectiveNavigator in src/lod/selective_navigator.cpp; the design both follow is in
// docs/viewer.md "Selective refinement".
//
// Faces keep their progressive ids (4 corner slots each, as Navigator): a base face is always
// active, a re-created triangle is active iff its split is; a vertex b + i exists iff split i is
// active. Splits are applied and undone by the same applySplits()/undoSplits() as the level
// navigator: a split's re-created triangles have their ids in the record (face_count_after(i)
// on), so a split does the same to its faces whether it comes in order or not.
import { DpmError } from './bytes.js';
import { Navigator } from './navigator.js';
import { DirtyFaces, applySplits, undoSplits } from './progressive_mesh.js';
import { SelectiveShownValues } from './selective_values.js';

export class SelectiveNavigator {
  // dependencies: a SplitDependencies of mesh (split_dependencies.js), derived as far as the
  // splits this navigator is to apply.
  constructor(mesh, dependencies) {
    if (!mesh.hasBase) throw new DpmError('SelectiveNavigator needs the BASE chunk');
    this.mesh = mesh;
    this.dependencies = dependencies;
    const { faceCount: F, splitCount: S, baseFaceCount: nf } = mesh.head;
    this.corners = new Int32Array(4 * F).fill(-1);
    this.corners.set(mesh.baseCorners);
    this.active = new Uint8Array(S);  // per split: applied
    this.activeCount = 0;
    this.top = 0;  // 1 + the largest active split: vertices [0, b + top) hold every existing one
    this.level = 0;  // the prefix asked for by the last request (the "elsewhere" level)
    this.quads = 0;
    for (let f = 0; f < nf; f++) this.quads += mesh.baseDegree[f] === 4 ? 1 : 0;
    this.faces = nf;  // active faces
    this.dirty = new DirtyFaces(F);
    for (let f = 0; f < nf; f++) this.dirty.add(f);
  }

  // Vertices [0, vertexCount) hold every existing vertex (some in between may not exist): the
  // prefix whose positions a renderer needs. Faces [0, faceCount) likewise.
  get selective() {
    return true;
  }
  // The shown values of a field on this navigator's faces (field_view.js).
  get ShownValues() {
    return SelectiveShownValues;
  }
  get vertexCount() {
    return this.mesh.head.baseVertexCount + this.top;
  }
  get faceCount() {
    return this.mesh.faceCountAt[this.top];
  }
  get activeVertexCount() {
    return this.mesh.head.baseVertexCount + this.activeCount;
  }
  get activeFaceCount() {
    return this.faces;
  }
  get quadCount() {
    return this.quads;
  }
  get triangleCount() {
    return this.faces - this.quads;
  }
  // The error of the "elsewhere" level: the refined region is finer than that.
  get error() {
    return this.mesh.levelError(this.level);
  }
  exists(v) {
    const i = v - this.mesh.head.baseVertexCount;
    return i < 0 || this.active[i] === 1;
  }
  faceActive(f) {
    const i = this.dependencies.faceSplit[f];
    return i < 0 || this.active[i] === 1;
  }

  // The splits wanted for a request: the first `level` splits (the level elsewhere) and the
  // splits of `targets` (any order), closed under the dependencies. A Uint8Array per split.
  wanted(level, targets = []) {
    const L = Math.min(this.mesh.splitsLoaded, this.dependencies.derived);
    const wanted = new Uint8Array(this.mesh.head.splitCount);
    wanted.fill(1, 0, Math.max(0, Math.min(level, L)));
    return this.dependencies.close(targets, wanted);
  }

  // Moves to the closed set `wanted` (Uint8Array per split, from wanted()): undoes the active
  // splits not in it from the last (their dependants are later splits, undone before them), then
  // applies the wanted ones not active from the first. Returns the splits applied and undone.
  setTarget(wanted, level = this.level) {
    const L = Math.min(this.mesh.splitsLoaded, this.dependencies.derived);
    const { active, mesh, corners, dirty } = this;
    const { faceCountAt } = mesh;
    let undone = 0, applied = 0;
    // Runs of consecutive splits go to undoSplits()/applySplits() in one call each.
    for (let i = this.top - 1; i >= 0; i--) {
      if (!active[i] || wanted[i]) continue;
      let j = i;
      while (j > 0 && active[j - 1] && !wanted[j - 1]) j--;
      this.quads -= undoSplits(mesh, i + 1, j, corners, dirty);
      this.hideCreated(faceCountAt[j], faceCountAt[i + 1]);
      this.faces -= faceCountAt[i + 1] - faceCountAt[j];
      active.fill(0, j, i + 1);
      undone += i + 1 - j;
      i = j;
    }
    let top = 0;
    for (let i = 0; i < L; i++) {
      if (!wanted[i]) continue;
      if (!active[i]) {
        let j = i + 1;
        while (j < L && wanted[j] && !active[j]) j++;
        this.quads += applySplits(mesh, i, j, corners, dirty);
        this.faces += faceCountAt[j] - faceCountAt[i];
        active.fill(1, i, j);
        applied += j - i;
        i = j - 1;
      }
      top = i + 1;
    }
    this.top = top;
    this.activeCount += applied - undone;
    this.level = level;
    return { applied, undone };
  }

  // The re-created triangles of undone splits, faces [from, to), get three equal corners
  // (vertex 0, which always exists), so that whatever draws faces [0, faceCount) draws nothing
  // for them.
  hideCreated(from, to) {
    const { corners } = this;
    for (let f = from; f < to; f++) corners[4 * f] = corners[4 * f + 1] = corners[4 * f + 2] = 0;
  }

  // The mesh as the two decoders give it (docs/viewer.md "Selective refinement", the same order
  // as `dynpm extract --refine`): the existing vertices in ascending progressive id, and the
  // active faces in ascending progressive id, each face's corners in slot order, renumbered
  // 0 … n−1 in the vertices' order. faces: 4 per face, −1 in slot 3 of a triangle.
  activeMesh() {
    const b = this.mesh.head.baseVertexCount;
    const vertices = new Int32Array(b + this.activeCount);
    const compact = new Int32Array(b + this.top).fill(-1);
    let n = 0;
    for (let v = 0; v < b + this.top; v++) if (v < b || this.active[v - b]) (compact[v] = n), (vertices[n++] = v);
    const faceIds = new Int32Array(this.faces);
    const faces = new Int32Array(4 * this.faces);
    let m = 0;
    for (let f = 0; f < this.faceCount; f++) {
      if (!this.faceActive(f)) continue;
      faceIds[m] = f;
      for (let k = 0; k < 4; k++) {
        const v = this.corners[4 * f + k];
        faces[4 * m + k] = v < 0 ? -1 : compact[v];
      }
      m++;
    }
    return { vertices, faces, faceIds };
  }
}

// As the level navigator: a face's corners and degree, the faces changed since the last call,
// a field's error at the level (here the level elsewhere).
for (const name of ['face', 'degree', 'takeDirty', 'fieldError']) SelectiveNavigator.prototype[name] = Navigator.prototype[name];
