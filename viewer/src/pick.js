// What a pick names and what a history plots (docs/viewer.md "Picking, history, section, measure"),
// on the decoder's ProgressiveMesh alone, so that Node runs it as the page does.
//
// A pick always names an ORIGINAL element and node, whatever level is shown: the decoder holds
// every split that has arrived, so the finest loaded level exists beside the one on screen.
// OriginalMesh keeps its own Navigator at that level (made on the first pick at a coarser level)
// and its positions at the step of the last pick; the ray is tested against all of its faces.
import { Navigator } from './dpm.js';

// Position of vertex v at fractional step t (linear between the steps around it), into out;
// with a deformation scale s, where the page draws it: p(0) + s · (p(t) − p(0)).
export function vertexAt(mesh, v, t, out = [0, 0, 0], scale = 1) {
  const { t0, t1, a } = mesh.stepsAround(t);
  const p0 = mesh.position(v, t0), p1 = mesh.position(v, t1);
  for (let c = 0; c < 3; c++) out[c] = p0[c] + (p1[c] - p0[c]) * a;
  if (scale !== 1) scaleFromFirst(mesh, v, out, 0, scale);
  return out;
}

// p[at … at + 2] (vertex v's position) moved to p(0) + s · (p − p(0)).
function scaleFromFirst(mesh, v, p, at, s) {
  const q = mesh.position(v, 0);
  for (let c = 0; c < 3; c++) p[at + c] = q[c] + (p[at + c] - q[c]) * s;
}

// Field f's value at item i (a vertex of a node field, a face of an element field) at whole step
// t, as the f32 the file means (DpmField.valuesAt for one item).
export function fieldValue(field, t, i) {
  const q = field.q[t];
  if (field.lossless) return new Float32Array(q.buffer, q.byteOffset + 4 * i, 1)[0];
  return Math.fround(field.min + q[i] * field.quantStep);
}

// The whole step whose field values are shown at t (as FieldView: never an interpolated value).
export const shownStep = (mesh, t) => Math.min(Math.max(Math.round(t), 0), mesh.head.stepCount - 1);

const distance = (p, q) => Math.hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]);

// One value per step: 'displacement' (|p(t) − p(0)| of vertex `item`), 'distance' (|p(t) − q(t)|
// of vertices item and other), or the field named (at vertex `item`, or face `item` for an
// element field).
export function historyOf(mesh, item, quantity, other = -1) {
  const m = mesh.head.stepCount;
  const out = new Float64Array(m);
  if (quantity === 'displacement' || quantity === 'distance') {
    const p0 = mesh.position(item, 0, [0, 0, 0]);
    for (let t = 0; t < m; t++) {
      const p = mesh.position(item, t, [0, 0, 0]);
      out[t] = quantity === 'distance' ? distance(p, mesh.position(other, t)) : distance(p, p0);
    }
    return out;
  }
  const field = mesh.fields.find((f) => f.name === quantity);
  if (!field) throw new Error(`no field named "${quantity}" (fields: ${mesh.fields.map((f) => f.name).join(', ') || 'none'})`);
  for (let t = 0; t < m; t++) out[t] = fieldValue(field, t, item);
  return out;
}

// Loaded vertex (face) of a file's node (element) number, or −1; maps made on first use and
// extended as splits arrive.
export class Ids {
  constructor(mesh) {
    this.mesh = mesh;
    this.nodes = new Map();
    this.elements = new Map();
    this.vertexCount = 0;
    this.faceCount = 0;
  }
  vertexOfNode(node) {
    const n = this.mesh.vertexCountLoaded;
    for (; this.vertexCount < n; this.vertexCount++) this.nodes.set(this.mesh.nodeId[this.vertexCount], this.vertexCount);
    return this.nodes.get(node) ?? -1;
  }
  faceOfElement(element) {
    const F = this.mesh.faceCountAt[this.mesh.splitsLoaded];
    for (; this.faceCount < F; this.faceCount++) this.elements.set(this.mesh.elementId[this.faceCount], this.faceCount);
    return this.elements.get(element) ?? -1;
  }
}

// Distance along the ray (origin o, unit direction d) to triangle (a, b, c) of flat positions p,
// or Infinity (Möller–Trumbore, both sides).
function rayTriangle(o, d, p, a, b, c) {
  const ax = p[3 * a], ay = p[3 * a + 1], az = p[3 * a + 2];
  const e1x = p[3 * b] - ax, e1y = p[3 * b + 1] - ay, e1z = p[3 * b + 2] - az;
  const e2x = p[3 * c] - ax, e2y = p[3 * c + 1] - ay, e2z = p[3 * c + 2] - az;
  const px = d[1] * e2z - d[2] * e2y, py = d[2] * e2x - d[0] * e2z, pz = d[0] * e2y - d[1] * e2x;
  const det = e1x * px + e1y * py + e1z * pz;
  if (Math.abs(det) < 1e-30) return Infinity;
  const inv = 1 / det;
  const sx = o[0] - ax, sy = o[1] - ay, sz = o[2] - az;
  const u = (sx * px + sy * py + sz * pz) * inv;
  if (u < 0 || u > 1) return Infinity;
  const qx = sy * e1z - sz * e1y, qy = sz * e1x - sx * e1z, qz = sx * e1y - sy * e1x;
  const w = (d[0] * qx + d[1] * qy + d[2] * qz) * inv;
  if (w < 0 || u + w > 1) return Infinity;
  const s = (e2x * qx + e2y * qy + e2z * qz) * inv;
  return s >= 0 ? s : Infinity;
}

// Each vertex's two coordinates across the ray (in a plane normal to it, the ray at 0, 0): a face
// the ray crosses has 0, 0 within its corners' box there, a test of a few reads that skips nearly
// every face before the exact one.
let acrossRay = new Float32Array(0);
function across(n, p, o, d) {
  if (acrossRay.length < 2 * n) acrossRay = new Float32Array(2 * n);
  const e1 = Math.abs(d[0]) < 0.9 ? [0, d[2], -d[1]] : [-d[2], 0, d[0]];  // ⟂ d
  const l = Math.hypot(...e1);
  for (let c = 0; c < 3; c++) e1[c] /= l;
  const e2 = [d[1] * e1[2] - d[2] * e1[1], d[2] * e1[0] - d[0] * e1[2], d[0] * e1[1] - d[1] * e1[0]];
  const uv = acrossRay;
  for (let v = 0, i = 0; v < n; v++, i += 3) {
    const x = p[i] - o[0], y = p[i + 1] - o[1], z = p[i + 2] - o[2];
    uv[2 * v] = x * e1[0] + y * e1[1] + z * e1[2];
    uv[2 * v + 1] = x * e2[0] + y * e2[1] + z * e2[2];
  }
  return uv;
}

function aroundRay(uv, k, c, slack) {
  const d = k[c + 3] < 0 ? 3 : 4;
  let uLo = Infinity, uHi = -Infinity, wLo = Infinity, wHi = -Infinity;
  for (let i = 0; i < d; i++) {
    const v = 2 * k[c + i];
    const u = uv[v], w = uv[v + 1];
    if (u < uLo) uLo = u;
    if (u > uHi) uHi = u;
    if (w < wLo) wLo = w;
    if (w > wHi) wHi = w;
  }
  return uLo <= slack && uHi >= -slack && wLo <= slack && wHi >= -slack;
}

// Of the faces of a level (nav, flat positions p) that the ray (origin, unit direction) crosses at
// a point keep(point, face) accepts, the one whose distance s along the ray has the least score(s)
// (s itself: the first crossing): {face, s, point}, or null. One pass over vertices and faces.
export function rayCrossing(nav, p, origin, direction, keep = () => true, score = (s) => s) {
  const k = nav.corners;
  const uv = across(nav.vertexCount, p, origin, direction);
  const mesh = nav.mesh;
  const slack = 1e-6 * Math.hypot(...mesh.head.bboxMax.map((x, c) => x - mesh.head.bboxMin[c]));
  const at = (s) => origin.map((x, c) => x + direction[c] * s);
  let best = null, bestScore = Infinity;
  for (let f = 0; f < nav.faceCount; f++) {
    const c = 4 * f;
    if (!aroundRay(uv, k, c, slack)) continue;
    let s = rayTriangle(origin, direction, p, k[c], k[c + 1], k[c + 2]);
    if (k[c + 3] >= 0) s = Math.min(s, rayTriangle(origin, direction, p, k[c], k[c + 2], k[c + 3]));
    if (s === Infinity || score(s) >= bestScore || !keep(at(s), f)) continue;
    best = { face: f, s, point: at(s) }, bestScore = score(s);
  }
  return best;
}

// The finest loaded level and its positions at one step.
export class OriginalMesh {
  constructor(mesh) {
    this.mesh = mesh;
    this.nav = null;
    this.positions = null;
    this.key = '';
  }

  // Faces and positions at step t of the finest loaded level; `shown`: the page's navigator,
  // used as it is when it already shows that level (no second copy of the faces).
  level(t, shown, scale = 1) {
    const { mesh } = this;
    let nav = shown;
    if (shown?.level !== mesh.splitsLoaded || !(shown instanceof Navigator)) {
      this.nav ??= new Navigator(mesh);
      this.nav.setLevel(mesh.splitsLoaded);
      this.nav.takeDirty();  // nobody draws it: keep its list of touched faces empty
      nav = this.nav;
    }
    const n = nav.vertexCount;
    const key = `${t} ${n} ${scale}`;
    if (this.key !== key) {
      if (!this.positions || this.positions.length < 3 * n) this.positions = new Float32Array(3 * mesh.head.vertexCount);
      mesh.positionsAt(t, n, this.positions);
      if (scale !== 1) for (let v = 0; v < n; v++) scaleFromFirst(mesh, v, this.positions, 3 * v, scale);
      this.key = key;
    }
    return { nav, positions: this.positions };
  }

  // The original face and node under a ray at step t: of the faces the ray crosses on the kept
  // side (keep(point) → bool), the one whose distance along the ray is nearest `near` (where the
  // ray met the level on screen); if it crosses none there (a coarse level stands off the
  // original), the face of the original vertex nearest that point. The node is the face's corner
  // nearest the point. Returns {face, vertex, point} or null.
  pick(t, origin, direction, near, keep = () => true, shown = null, scale = 1) {
    const { nav, positions: p } = this.level(t, shown, scale);
    const k = nav.corners;
    const hit = rayCrossing(nav, p, origin, direction, keep, (s) => Math.abs(s - near));
    const point = hit ? hit.point : origin.map((x, c) => x + direction[c] * near);
    const face = hit ? hit.face : this.faceNearest(nav, p, point);
    if (face < 0) return null;
    let vertex = -1, d = Infinity;
    for (let i = 0; i < nav.degree(face); i++) {
      const v = k[4 * face + i];
      const e = distance(point, p.subarray(3 * v, 3 * v + 3));
      if (e < d) (d = e), (vertex = v);
    }
    return { face, vertex, point };
  }

  // A face that holds the vertex nearest `point`, or −1.
  faceNearest(nav, p, point) {
    let vertex = -1, d = Infinity;
    for (let v = 0; v < nav.vertexCount; v++) {
      const e = distance(point, p.subarray(3 * v, 3 * v + 3));
      if (e < d) (d = e), (vertex = v);
    }
    const k = nav.corners;
    for (let f = 0; f < nav.faceCount; f++) for (let i = 0; i < 4; i++) if (k[4 * f + i] === vertex) return f;
    return -1;
  }
}

// Everything a pick shows about original face f and vertex v at fractional step t: the file's
// numbers, the position and displacement at t, every field's value at the shown step.
export function describePick(mesh, face, vertex, t) {
  const step = shownStep(mesh, t);
  const position = vertexAt(mesh, vertex, t);
  const p0 = mesh.position(vertex, 0);
  const vector = position.map((x, c) => x - p0[c]);
  const values = {};
  for (const field of mesh.fields) values[field.name] = fieldValue(field, step, field.perFace ? face : vertex);
  return {
    node: mesh.nodeId[vertex],
    element: mesh.elementId[face],
    part: mesh.partId[face],
    partName: mesh.partNames?.get(mesh.partId[face]) ?? null,  // from the file's PART chunk
    vertex: mesh.vertexOriginal[vertex],  // 0-based, in the input's order (as `extract --full` writes)
    face: mesh.faceOriginal[face],
    position,
    displacement: Math.hypot(...vector),
    displacementVector: vector,
    step,
    t,
    values,
    dpm: { vertex, face },  // the .dpm's own numbering (FORMAT.md "Numbering")
  };
}
