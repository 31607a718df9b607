// What each vertex split depends on, derived from the split records as they arrive (no stored
// form, no format change): docs/viewer.md "Selective refinement", docs/selective.md "Face
// creators". C++: src/lod/split_dependencies.cpp; both decoders use the same rule by default
// (SplitReads::kFaceCreators there, 'faceCreators' here) so that they choose the same splits.
//
// The splits are replayed once in stream order on a face array of their own, with each vertex's
// fan. Split i (v1 its parent) writes W(i): its moved faces and its wing faces.
// 'faceCreators' (the default): a split moves a corner by value and a quad wing inserts one by
// slot, so the writes of one face commute and only which of them are applied matters. Split i
// needs the splits that made v1 and its triangle wings' vertices; for each face it writes, the
// split that created it and the one that made it a quad; for each face on a quad wing's
// triangle's sides at v1 as the stream has them right before i, the split that created it.
// 'fan' (the first design): i reads R(i) = W(i) plus v1's whole fan right before it; it depends
// on the last writer of each face of R(i) (read after write), a writer j of f on every reader of
// f since f's previous writer (write after read), and i on the split that created v1. Then a
// closed set applied in ascending order gives each split of it the faces of R(i) exactly as the
// full sequence had them.
// Under both, every dependency is an earlier split, so every prefix of the stream is closed.
import { Growable, withRoom } from './bytes.js';
import { applySplits, DirtyFaces, WING_WAS_TRIANGLE } from './progressive_mesh.js';

// The rules a SplitDependencies can derive; the first is the default.
export const SPLIT_RULES = ['faceCreators', 'fan'];

export class SplitDependencies {
  constructor(mesh, { rule = SPLIT_RULES[0] } = {}) {
    const { splitCount: S, baseFaceCount: nf } = mesh.head;
    if (!SPLIT_RULES.includes(rule)) throw new Error(`unknown split dependency rule '${rule}'`);
    this.mesh = mesh;
    this.rule = rule;
    this.derived = 0;  // splits derived so far (a prefix of the loaded ones)
    // The mesh as the derived splits left it: after the last split, the fully refined mesh.
    // The arrays by face, vertex and split hold those of the splits derived so far (room()).
    this.corners = new Int32Array(0);
    // Dependencies as CSR: split i's are deps[depStart[i], depStart[i + 1]), ascending.
    this.depStart = new Uint32Array(0);
    this.deps = new Growable(Int32Array, Math.min(4 * S, 1 << 16));
    this.lastWriter = new Int32Array(0);  // per face: the last split that wrote it
    this.faceSplit = new Int32Array(0);  // per face: the split that creates it (−1: base)
    this.quadBy = new Int32Array(0);  // per face: the split that made it a quad (−1: none)
    // Per face, the splits that read it since its last writer: a list in a pool (head, next).
    this.readerHead = new Int32Array(0);
    this.readerSplit = new Growable(Int32Array, Math.min(4 * S, 1 << 16));
    this.readerNext = new Growable(Int32Array, Math.min(4 * S, 1 << 16));
    // Per vertex, the faces that hold it (its fan, unordered): a list of (vertex, face) links
    // from fanHead[v] on. A face that moves from v1 to v0 takes its link along, so there are at
    // most 4 per face, allocated once.
    this.fanHead = new Int32Array(0);
    this.linkFace = new Int32Array(0);
    this.linkNext = new Int32Array(0);
    this.links = 0;
    this.seen = new Int32Array(0);  // per split: the split whose dependencies hold it
    this.writtenBy = new Int32Array(0);  // per face: the last split whose W holds it
    this.room(0);
    this.corners.set(mesh.baseCorners);
    for (let f = 0; f < nf; f++)
      for (let k = 0; k < 4; k++) if (this.corners[4 * f + k] >= 0) this.link(this.corners[4 * f + k], f);
    this.dirty = new DirtyFaces(mesh.head.faceCount);
    this.maxCount = 0;
  }

  // Derives the dependencies of the splits loaded since the last call.
  update() {
    const { mesh } = this;
    const to = mesh.splitsLoaded;
    const fan = this.rule === 'fan';
    this.room(to);
    for (let i = this.derived; i < to; i++) {
      const start = this.deps.length;
      if (fan) this.deriveFan(i);
      else this.deriveFaceCreators(i);
      sortRun(this.deps.data, start, this.deps.length);
      this.depStart[i + 1] = this.deps.length;
      this.maxCount = Math.max(this.maxCount, this.deps.length - start);
      this.replay(i, this.mesh.head.baseVertexCount + i, this.mesh.parent[i]);
    }
    this.derived = Math.max(this.derived, to);
    return this;
  }

  // Room for the faces, vertices and splits of the first `splits` splits: a page that loaded 100 k
  // of 5 M vertices holds no more (unset entries read −1, as "none").
  room(splits) {
    const { vertexCount: V, faceCount: F, splitCount: S, baseVertexCount: b } = this.mesh.head;
    const faces = this.mesh.faceCountAt[splits];
    const room = (a, n, max, fill = -1) => withRoom(a, n, max, fill);
    this.lastWriter = room(this.lastWriter, faces, F);
    this.faceSplit = room(this.faceSplit, faces, F);
    this.quadBy = room(this.quadBy, faces, F);
    this.readerHead = room(this.readerHead, faces, F);
    this.writtenBy = room(this.writtenBy, faces, F);
    this.corners = room(this.corners, 4 * faces, 4 * F);
    this.linkFace = room(this.linkFace, 4 * faces, 4 * F, 0);
    this.linkNext = room(this.linkNext, 4 * faces, 4 * F, 0);
    this.fanHead = room(this.fanHead, b + splits, V);
    this.seen = room(this.seen, splits, S);
    this.depStart = room(this.depStart, splits + 1, S + 1, 0);
  }

  // Split i's dependencies: deps.data[depStart[i], depStart[i + 1]).
  of(i) {
    return this.deps.data.subarray(this.depStart[i], this.depStart[i + 1]);
  }
  get count() {
    return this.deps.length;
  }
  // Dependencies per split: mean and max (docs and the benchmark).
  stats() {
    const n = this.derived;
    return { splits: n, dependencies: this.deps.length, mean: n ? this.deps.length / n : 0, max: this.maxCount };
  }

  // Split i's dependencies under the face creators' rule, onto deps (unsorted, each once).
  deriveFaceCreators(i) {
    const { mesh, corners, faceSplit, quadBy, lastWriter, fanHead, linkFace, linkNext } = this;
    const b = mesh.head.baseVertexCount;
    const v1 = mesh.parent[i];
    const movedFaces = mesh.movedFaces.data, wingFace = mesh.wingFace.data, wingVertex = mesh.wingVertex.data;
    const m0 = mesh.movedStart[i], m1 = mesh.movedStart[i + 1], w0 = mesh.wingStart[i], w1 = mesh.wingStart[i + 1];
    if (v1 >= b) this.add(v1 - b, i);
    for (let j = m0; j < m1; j++) this.add(faceSplit[movedFaces[j]], i), this.add(quadBy[movedFaces[j]], i);
    for (let j = w0; j < w1; j++) {
      const f = wingFace[j];
      // A triangle wing's face names w, which must exist. The faces on its edge (v1, w) need
      // nothing more: the one moved to v0 is a written face; the one staying at v1, if not
      // made by w's or v1's split, is a triangle some earlier wing put on that same edge, and
      // without it the face that wing moved off the edge takes its place (measured valid:
      // docs/selective.md "Narrower: what a wing reads").
      if (mesh.wingFlags.data[j] & WING_WAS_TRIANGLE) {
        if (wingVertex[j] >= b) this.add(wingVertex[j] - b, i);
        continue;
      }
      // A quad wing inserts v0 by slot and never reads w; its face must exist as the triangle
      // the stream had, and Hoppe's fn0..fn3, the faces of v1's fan on its sides at v1, must
      // exist (without them a vertex can be left with two faces).
      this.add(faceSplit[f], i), this.add(quadBy[f], i);
      for (let e = 0; e < 4; e++) {
        const end = corners[4 * f + e];
        if (end < 0 || end === v1) continue;
        for (let n = fanHead[v1]; n >= 0; n = linkNext[n]) {
          const g = linkFace[n];
          if (corners[4 * g] === end || corners[4 * g + 1] === end || corners[4 * g + 2] === end || corners[4 * g + 3] === end)
            this.add(faceSplit[g], i);
        }
      }
    }
    for (let j = m0; j < m1; j++) lastWriter[movedFaces[j]] = i;
    for (let j = w0; j < w1; j++) {
      lastWriter[wingFace[j]] = i;
      if (!(mesh.wingFlags.data[j] & WING_WAS_TRIANGLE)) quadBy[wingFace[j]] = i;
    }
  }

  // Split i's dependencies under the fan rule, onto deps (unsorted, each once).
  deriveFan(i) {
    const { mesh, lastWriter, readerHead, writtenBy } = this;
    const b = mesh.head.baseVertexCount;
    const v1 = mesh.parent[i];
    // W(i), marked: the moved faces, then the wing faces (a quad's face or a re-created triangle).
    const movedFaces = mesh.movedFaces.data, wingFace = mesh.wingFace.data;
    const m0 = mesh.movedStart[i], m1 = mesh.movedStart[i + 1], w0 = mesh.wingStart[i], w1 = mesh.wingStart[i + 1];
    for (let j = m0; j < m1; j++) writtenBy[movedFaces[j]] = i;
    for (let j = w0; j < w1; j++) writtenBy[wingFace[j]] = i;
    if (v1 >= b) this.add(v1 - b, i);
    // Read after write: over v1's fan (moved faces and quad wings are in it; re-created
    // triangles are new faces, never written before).
    const { fanHead, linkFace, linkNext } = this;
    for (let n = fanHead[v1]; n >= 0; n = linkNext[n]) this.add(lastWriter[linkFace[n]], i);
    // Write after read: the readers of each written face since its last writer.
    const readerSplit = this.readerSplit.data, readerNext = this.readerNext.data;
    for (let j = m0; j < m1; j++) for (let r = readerHead[movedFaces[j]]; r >= 0; r = readerNext[r]) this.add(readerSplit[r], i);
    for (let j = w0; j < w1; j++) for (let r = readerHead[wingFace[j]]; r >= 0; r = readerNext[r]) this.add(readerSplit[r], i);
    // Now split i is the last writer of W(i) and a reader of the rest of v1's fan.
    for (let n = fanHead[v1]; n >= 0; n = linkNext[n]) {
      const f = linkFace[n];
      if (writtenBy[f] === i) continue;
      this.readerSplit.push(i);
      this.readerNext.push(readerHead[f]);
      readerHead[f] = this.readerSplit.length - 1;
    }
    for (let j = m0; j < m1; j++) (lastWriter[movedFaces[j]] = i), (readerHead[movedFaces[j]] = -1);
    for (let j = w0; j < w1; j++) (lastWriter[wingFace[j]] = i), (readerHead[wingFace[j]] = -1);
  }

  // Split j (≥ 0) among split i's dependencies, once.
  add(j, i) {
    if (j >= 0 && this.seen[j] !== i) {
      this.seen[j] = i;
      this.deps.push(j);
    }
  }

  // Applies split i to this replay's faces and moves the faces between fans: moved faces leave
  // v1's fan for v0's, quad wings join v0's, re-created triangles join v0's, v1's and w's.
  replay(i, v0, v1) {
    const { mesh, fanHead, linkFace, linkNext } = this;
    applySplits(mesh, i, i + 1, this.corners, this.dirty);
    this.dirty.clear();
    for (let j = mesh.movedStart[i]; j < mesh.movedStart[i + 1]; j++) {
      const f = mesh.movedFaces.data[j];
      let n = fanHead[v1], before = -1;
      while (linkFace[n] !== f) (before = n), (n = linkNext[n]);
      if (before < 0) fanHead[v1] = linkNext[n];
      else linkNext[before] = linkNext[n];
      (linkNext[n] = fanHead[v0]), (fanHead[v0] = n);
    }
    for (let j = mesh.wingStart[i]; j < mesh.wingStart[i + 1]; j++) {
      const f = mesh.wingFace.data[j];
      this.link(v0, f);
      if (mesh.wingFlags.data[j] & WING_WAS_TRIANGLE) {
        this.faceSplit[f] = i;
        this.link(v1, f);
        this.link(mesh.wingVertex.data[j], f);
      }
    }
  }

  // Face f joins vertex v's fan.
  link(v, f) {
    const n = this.links++;
    this.linkFace[n] = f;
    this.linkNext[n] = this.fanHead[v];
    this.fanHead[v] = n;
  }

  // The splits of T (indices, any order) and every split they depend on, transitively: marks
  // set to 1 in `wanted` (Uint8Array per split), which may already hold a closed set.
  close(T, wanted) {
    const stack = [];
    for (const i of T) if (!wanted[i]) (wanted[i] = 1), stack.push(i);
    this.flagDependencies(stack, wanted);
    return wanted;
  }

  // Split i and what it depends on into `wanted` (a closed set): how many splits it flagged.
  addWithDependencies(i, wanted) {
    if (wanted[i]) return 0;
    wanted[i] = 1;
    return 1 + this.flagDependencies([i], wanted);
  }

  // Flags what the splits on `stack` depend on, transitively; returns how many it flagged.
  flagDependencies(stack, wanted) {
    const { depStart } = this;
    const deps = this.deps.data;
    let flagged = 0;
    while (stack.length) {
      const i = stack.pop();
      for (let k = depStart[i], end = depStart[i + 1]; k < end; k++) {
        const j = deps[k];
        if (!wanted[j]) (wanted[j] = 1), flagged++, stack.push(j);
      }
    }
    return flagged;
  }
}

// Sorts a[from, to) ascending in place: a split's few dependencies (an insertion sort, no view).
function sortRun(a, from, to) {
  for (let k = from + 1; k < to; k++) {
    const x = a[k];
    let j = k - 1;
    while (j >= from && a[j] > x) (a[j + 1] = a[j]), j--;
    a[j + 1] = x;
  }
}
