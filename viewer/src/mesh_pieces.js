// How the decode worker's mesh reaches the page (docs/viewer.md "Decoding in a worker"), in
// one of two ways:
// - shared (the page is cross-origin isolated, as `dynpm view` serves it): at HEAD the worker
//   puts the ProgressiveMesh's typed arrays on SharedArrayBuffers (shareMesh), which the page
//   reads in place (sharedMesh): nothing is copied but the base faces and the wing and
//   moved-face lists, which grow by reallocation (growableTails), and the arrays of every step
//   when they are made anew with more room (regrownSteps);
// - copied (elsewhere): the worker cuts the ranges of the arrays that the base mesh or a run of
//   splits filled (levelPieces) and the page writes them into its own mesh. levelPieces is the
//   one place that knows which array is indexed by vertex, face, split or wing: a new array in
//   ProgressiveMesh or DpmField that the page reads must be listed there.
import { Growable } from './dpm/bytes.js';
import { DpmField, FIELD_ELEMENT } from './dpm/fields.js';
import { ProgressiveMesh } from './dpm/progressive_mesh.js';
import { StepPositions } from './dpm/step_positions.js';

const isTyped = (x) => ArrayBuffer.isView(x) && !(x instanceof DataView);
const isGrowable = (x) => x instanceof Growable;

// A typed array of the same type and length on a SharedArrayBuffer, holding a's first `copy`
// elements (the rest zero).
function shared(a, copy = 0) {
  const b = new a.constructor(new SharedArrayBuffer(a.byteLength));
  if (copy) b.set(a.subarray(0, copy));
  return b;
}

// Worker, at HEAD: the mesh's typed arrays (all zero still: ProgressiveMesh's constructor
// fills none) move to shared memory; returns what the page needs to build its view of the mesh.
export function shareMesh(mesh) {
  const description = { plain: {}, growables: {} };
  for (const [key, value] of Object.entries(mesh)) {
    if (value instanceof StepPositions) {
      value.steps = value.steps.map((a) => shared(a));
      for (const key of ['wide', 'dir', 'runs']) value[key] = value[key].map((a) => a && shared(a, a.length));
    }
    if (isTyped(value)) mesh[key] = shared(value);
    else if (Array.isArray(value) && value.length && value.every(isTyped)) mesh[key] = value.map((a) => shared(a));
    if (isGrowable(value)) description.growables[key] = [value.Type.name, value.data.length];
    else description.plain[key] = mesh[key];
  }
  return description;
}

// Page: the worker's mesh as shareMesh() described it; the growing lists start empty, with the
// worker's room (untouched memory costs nothing until written).
export function sharedMesh({ plain, growables }) {
  const mesh = Object.assign(Object.create(ProgressiveMesh.prototype), plain);
  mesh.positions = StepPositions.from(plain.positions);
  for (const [key, [type, room]] of Object.entries(growables)) mesh[key] = new Growable(globalThis[type], room);
  return mesh;
}

// Worker, at the base mesh: the fields (made at FDEF, their base values in) move to shared
// memory too; returns them for addFields().
export function shareFields(mesh) {
  const { baseVertexCount: b, baseFaceCount: nf } = mesh.head;
  for (const f of mesh.fields) {
    f.q = f.q.map((a) => shared(a, f.perFace ? nf : b));
    f.error = shared(f.error);
  }
  if (mesh.faceHeir) mesh.faceHeir = shared(mesh.faceHeir, mesh.faceHeir.length);
  return mesh.fields.map((f) => ({ ...f }));
}

// Worker: what the growing lists (wings, moved faces) gained since the last call, as pieces
// for applyPieces(); `sent` keeps each list's length sent so far.
export function growableTails(mesh, sent) {
  const pieces = [];
  for (const [key, value] of Object.entries(mesh)) {
    if (!isGrowable(value) || value.length === (sent[key] ?? 0)) continue;
    const first = sent[key] ?? 0;
    pieces.push([key, first, value.data.slice(first, value.length)]);
    sent[key] = value.length;
  }
  return pieces;
}

// The arrays the page reads, by what indexes them; positions and fields are per step.
const PER_VERTEX = ['vertexOriginal', 'nodeId'];
const PER_FACE = ['faceOriginal', 'partId', 'elementId', 'faceHeir'];
const PER_SPLIT = ['parent', 'error'];
const PER_SPLIT_END = ['wingStart', 'movedStart', 'faceCountAt'];  // entry i + 1 after split i
const PER_WING = ['wingFace', 'wingVertex', 'wingFlags'];

// The ranges of splits [s, s + n) (n = 0: the base mesh), as [path, first element, values]
// with values a copy, so that its buffer can be transferred; and the buffers to transfer.
export function levelPieces(mesh, s, n) {
  const h = mesh.head;
  const b = h.baseVertexCount;
  const base = n === 0;
  const [v0, v1] = base ? [0, b] : [b + s, b + s + n];
  const [f0, f1] = base ? [0, h.baseFaceCount] : [mesh.faceCountAt[s], mesh.faceCountAt[s + n]];
  const pieces = [];
  const cut = (path, array, first, end, per = 1) => {
    if (array && end > first) pieces.push([path, per * first, array.slice(per * first, per * end)]);
  };
  mesh.positions.steps.forEach((a, t) => {
    if (!mesh.positions.dir[t]) return cut(`positions.steps.${t}`, a, v0, v1, 3);
    // Packed: the page packs the second differences into runs of its own.
    if (v1 > v0) pieces.push([`positions.packed.${t}`, 3 * v0, mesh.positions.differences(t, 3 * v0, 3 * v1)]);
  });
  mesh.positions.wide.forEach((_, t) => {
    if (mesh.positions.dir[t]) return;  // a packed step's: the page's packing finds them again
    const pairs = mesh.positions.widePairs(t, v0, v1);
    if (pairs.length) pieces.push([`positions.wide.${t}`, null, pairs]);
  });
  for (const name of PER_VERTEX) cut(name, mesh[name], v0, v1);
  for (const name of PER_FACE) cut(name, mesh[name], f0, f1);
  mesh.fields.forEach((field, k) => {
    const [i0, i1] = field.perFace ? [f0, f1] : [v0, v1];
    for (let t = 0; t < field.q.length; t++) cut(`fields.${k}.q.${t}`, field.q[t], i0, i1);
    cut(`fields.${k}.error`, field.error, s, s + n);
  });
  if (base) {
    cut('baseDegree', mesh.baseDegree, 0, h.baseFaceCount);
    cut('baseCorners', mesh.baseCorners, 0, h.baseFaceCount, 4);
    cut('faceCountAt', mesh.faceCountAt, 0, 1);
  } else {
    for (const name of PER_SPLIT) cut(name, mesh[name], s, s + n);
    for (const name of PER_SPLIT_END) cut(name, mesh[name], s + 1, s + n + 1);
    const [w0, w1] = [mesh.wingStart[s], mesh.wingStart[s + n]];
    for (const name of PER_WING) cut(name, mesh[name].data, w0, w1);
    cut('movedFaces', mesh.movedFaces.data, mesh.movedStart[s], mesh.movedStart[s + n]);
  }
  return { pieces, transfer: pieces.map(([, , values]) => values.buffer) };
}

// The field definitions (FDEF) without their values, for addFields() (copied).
export function fieldDefs(mesh) {
  return mesh.fields.map(({ q, error, ...def }) => def);
}

// The page's mesh gets its fields: shared ones (from shareFields) as they are, or definitions
// only, with room for their values as FDEF says.
export function addFields(mesh, fields, faceHeir) {
  const h = mesh.head;
  mesh.fields = fields.map((d) => d.q
    ? Object.assign(Object.create(DpmField.prototype), d)
    : new DpmField(d, h.stepCount, d.location === FIELD_ELEMENT ? h.faceCount : h.vertexCount, h.splitCount));
  if (faceHeir) mesh.faceHeir = faceHeir;
  else if (mesh.fields.some((f) => f.perFace)) mesh.faceHeir = new Int32Array(h.faceCount).fill(-1);
}

// Shared, worker: the arrays of every step (positions, field values) that ProgressiveMesh's
// makeRoom() made anew since the last call, as pieces that replace the page's (first: null);
// `sent` keeps the arrays the page has. Those it had still hold the levels it was told of.
export function regrownSteps(mesh, sent) {
  const pieces = [];
  const { steps, wide, dir, runs } = mesh.positions;
  const lists = [['positions.steps', steps], ['positions.wide', wide], ['positions.dir', dir], ['positions.runs', runs],
    ...mesh.fields.map((f, k) => [`fields.${k}.q`, f.q])];
  for (const [path, list] of lists) {
    if (sent[path] && list.every((a, t) => a === sent[path][t])) continue;
    sent[path] = list.slice();
    pieces.push([path, null, list.slice()]);
  }
  return pieces;
}

// The room a run of copied pieces needs in the arrays of every step: vertices and faces.
function stepRoom(mesh, pieces) {
  let vertices = 0, faces = 0;
  for (const [path, first, values] of pieces) {
    const end = first + values.length;
    if (path.startsWith('positions.steps.')) vertices = Math.max(vertices, end / 3);
    const field = /^fields\.(\d+)\.q\./.exec(path);
    if (field && mesh.fields[field[1]].perFace) faces = Math.max(faces, end);
    else if (field) vertices = Math.max(vertices, end);
  }
  return [vertices, faces];
}

// Writes pieces into the page's mesh: typed arrays in place (the arrays of every step with room
// made first); the base faces whole, and arrays replaced (first: null); the wing and moved-face
// lists (Growable) at their place, their length following.
export function applyPieces(mesh, pieces) {
  mesh.makeRoom(...stepRoom(mesh, pieces));
  for (const [path, first, values] of pieces) {
    const keys = path.split('.');
    const last = keys.pop();
    if (path.startsWith('positions.wide.')) {
      mesh.positions.addWidePairs(Number(last), values);  // escaped values, appended
      continue;
    }
    if (path.startsWith('positions.packed.')) {
      mesh.positions.addDifferences(Number(last), first, values);  // a run, appended
      continue;
    }
    const owner = keys.reduce((o, k) => o[k], mesh);
    const target = owner[last];
    if (target === null || first === null) {
      owner[last] = values;  // baseDegree, baseCorners: whole, once; regrown arrays
    } else if (ArrayBuffer.isView(target)) {
      target.set(values, first);
    } else {
      // A Growable: room for first + values.length, as push() would have made.
      const end = first + values.length;
      if (end > target.data.length) {
        const bigger = new target.Type(Math.max(end, 2 * target.data.length));
        bigger.set(target.data.subarray(0, target.length));
        target.data = bigger;
      }
      target.data.set(values, first);
      target.length = Math.max(target.length, end);
    }
  }
}
