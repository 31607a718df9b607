// Refinement requests → the splits they want (selective refinement, docs/viewer.md). The request
// syntax is the CLI's (`dynpm extract --refine … --elsewhere …`), parsed here and nowhere else
// on this side; C++: src/lod/refine_targets.cpp.
//
//   box:X0,Y0,Z0,X1,Y1,Z1   sphere:X,Y,Z,R   part:3,7   field:NAME>V | field:NAME<V   moved:>D
//   view:EYE=x,y,z;AT=x,y,z;FOV=deg;H=px;PX=p[;UP=x,y,z][;W=px][;BUDGET=vertices]
//   elsewhere: 5% (a ratio of the vertices) | 20000 (vertices) | error:0.01 (absolute error)
//
// What a target wants, at (fractional) step t:
//   box, sphere: every split whose new vertex lies inside, and the last writer of every face
//     whose fully refined corners all lie inside (its closure holds every writer of the face, so
//     such a face comes out with its original corners);
//   part: the splits of the fully refined corners of the parts' faces, and their last writers;
//   field: per node, the splits of the nodes beyond the threshold; per element, as part: for
//     the faces beyond it;
//   moved: the splits of the vertices with |p(t) − p(0)| > D;
//   view: the splits whose screen error exceeds PX pixels (view_target.js), after the others
//     and the level elsewhere, by decreasing error while the vertices are under BUDGET.
// Several requests are a union. The navigator adds the "elsewhere" prefix and the closure.
import { DpmError } from './bytes.js';
import { splitSpheres, viewOrder } from './view_target.js';

// A decimal number as C++ std::from_chars reads one (no blanks, no '+', no hex), finite.
const DECIMAL = /^-?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$/;
const number = (text, what, request) => {
  const x = DECIMAL.test(text) ? Number(text) : NaN;
  if (!Number.isFinite(x)) throw new DpmError(`refine request "${request}": ${what} "${text}" is not a number`);
  return x;
};
const numbers = (text, count, what, request) => {
  const parts = text.split(',');
  if (parts.length !== count) throw new DpmError(`refine request "${request}": ${what}`);
  return parts.map((p) => number(p, 'value', request));
};

// One request's text → {kind, …}; a DpmError naming the request and the problem.
export function parseRequest(text) {
  const at = text.indexOf(':');
  const kind = at < 0 ? text : text.slice(0, at);
  const rest = at < 0 ? '' : text.slice(at + 1);
  switch (kind) {
    case 'box': {
      const x = numbers(rest, 6, 'a box is box:X0,Y0,Z0,X1,Y1,Z1', text);
      if (x[0] > x[3] || x[1] > x[4] || x[2] > x[5])
        throw new DpmError(`refine request "${text}": the box's first corner must be its smallest (X0 ≤ X1, Y0 ≤ Y1, Z0 ≤ Z1)`);
      return { kind, min: x.slice(0, 3), max: x.slice(3) };
    }
    case 'sphere': {
      const x = numbers(rest, 4, 'a sphere is sphere:X,Y,Z,R', text);
      if (x[3] < 0) throw new DpmError(`refine request "${text}": the radius is negative`);
      return { kind, centre: x.slice(0, 3), radius: x[3] };
    }
    case 'part': {
      const ids = rest.split(',').map((p) => number(p, 'part id', text));
      if (ids.some((id) => !Number.isInteger(id))) throw new DpmError(`refine request "${text}": part ids are integers`);
      return { kind, parts: ids };
    }
    case 'field': {
      const op = rest.search(/[<>]/);
      if (op <= 0) throw new DpmError(`refine request "${text}": a field request is field:NAME>V or field:NAME<V`);
      return { kind, name: rest.slice(0, op), above: rest[op] === '>', threshold: number(rest.slice(op + 1), 'threshold', text) };
    }
    case 'moved': {
      if (!rest.startsWith('>')) throw new DpmError(`refine request "${text}": a displacement request is moved:>D`);
      const d = number(rest.slice(1), 'distance', text);
      if (d < 0) throw new DpmError(`refine request "${text}": the distance is negative`);
      return { kind, distance: d };
    }
    case 'view':
      return parseView(rest, text);
    default:
      throw new DpmError(`refine request "${text}": unknown kind "${kind}" (box, sphere, part, field, moved, view)`);
  }
}

const VIEW_SYNTAX = 'a view is view:EYE=x,y,z;AT=x,y,z;FOV=deg;H=px;PX=p (and UP=x,y,z, W=px, BUDGET=vertices)';
const VIEW_KEYS = { EYE: 'eye', AT: 'at', UP: 'up', FOV: 'fov', W: 'width', H: 'height', PX: 'pixels', BUDGET: 'budget' };

// view:KEY=VALUE;… → {kind: 'view', eye, at, up, fov, width, height, pixels, budget (0: none)}.
function parseView(rest, text) {
  const fail = (problem) => {
    throw new DpmError(`refine request "${text}": ${problem}`);
  };
  const r = { kind: 'view', up: [0, 0, 1], width: 0, budget: 0 };
  const seen = new Set();
  for (const item of rest ? rest.split(';') : []) {
    const eq = item.indexOf('=');
    if (eq < 0) fail(`"${item}" is not KEY=VALUE: ${VIEW_SYNTAX}`);
    const key = item.slice(0, eq);
    if (!Object.hasOwn(VIEW_KEYS, key)) fail(`unknown key "${key}": ${VIEW_SYNTAX}`);
    if (seen.has(key)) fail(`${key} is given twice`);
    seen.add(key);
    const values = item.slice(eq + 1).split(',');
    const point = key === 'EYE' || key === 'AT' || key === 'UP';
    if (values.length !== (point ? 3 : 1)) fail(point ? `${key} needs 3 numbers x,y,z` : `${key} needs one number`);
    const x = values.map((v) => number(v, key, text));
    r[VIEW_KEYS[key]] = point ? x : x[0];
  }
  for (const key of ['EYE', 'AT', 'FOV', 'H', 'PX']) if (!seen.has(key)) fail(`no ${key}: ${VIEW_SYNTAX}`);
  if (seen.has('BUDGET') && !(Number.isInteger(r.budget) && r.budget >= 1 && r.budget <= 0xffffffff)) fail('BUDGET is a vertex count, a whole number ≥ 1');
  if (!(r.fov > 0 && r.fov < 180)) fail('FOV is in degrees, in (0, 180)');
  if (r.height < 1 || r.width < 0 || (r.width > 0 && r.width < 1)) fail('W and H are pixels, at least 1');
  if (!(r.pixels > 0)) fail('PX, the tolerance in pixels, must be > 0');
  const d = [r.at[0] - r.eye[0], r.at[1] - r.eye[1], r.at[2] - r.eye[2]];
  const u = r.up;
  if (d.every((x) => x === 0)) fail('EYE and AT are the same point');
  if (d[1] * u[2] - d[2] * u[1] === 0 && d[2] * u[0] - d[0] * u[2] === 0 && d[0] * u[1] - d[1] * u[0] === 0)
    fail('UP is along the view direction (or zero): give another UP');
  return r;
}

// The "elsewhere" level's text → {ratio} | {vertices} | {error}.
export function parseElsewhere(text) {
  const where = `elsewhere "${text}"`;
  if (text.startsWith('error:')) {
    const error = number(text.slice(6), 'error', where);
    if (error < 0) throw new DpmError(`${where}: the error is negative`);
    return { error };
  }
  if (text.endsWith('%')) {
    const percent = number(text.slice(0, -1), 'ratio', where);
    if (percent <= 0 || percent > 100) throw new DpmError(`${where}: a ratio is a percentage in (0, 100]`);
    return { ratio: percent / 100 };
  }
  const vertices = number(text, 'vertex count', where);
  if (!Number.isInteger(vertices) || vertices < 1) throw new DpmError(`${where}: a vertex count is a whole number ≥ 0 (or give N% or error:E)`);
  return { vertices };
}

// Splits applied by the elsewhere level (a prefix of the loaded ones), as `dynpm extract` reads
// --ratio (rounded to the nearest vertex), --vertices and --max-error.
export function elsewhereLevel(mesh, elsewhere) {
  const { baseVertexCount: b, vertexCount: V } = mesh.head;
  const L = mesh.splitsLoaded;
  if (elsewhere.error !== undefined) return mesh.levelForError(elsewhere.error);
  const n = elsewhere.ratio !== undefined ? Math.round(elsewhere.ratio * V) : elsewhere.vertices;
  return Math.max(0, Math.min(n - b, L));
}

// The splits the requests want (parsed, or their text), at step t: an array of split indices,
// each once. dependencies: a SplitDependencies derived as far as the splits to consider. level:
// the level elsewhere, which a view's budget counts (the others do not need it). views: how a
// view request's splits are had — null: made here (spheres once per step, screen errors per
// camera); {spheres}: the split spheres at t (splitSpheres() of dependencies.derived splits)
// made elsewhere; {splits}: per view request, its viewOrder() made elsewhere (the page's spheres
// worker, moved_spheres.js). With a view the result is closed and holds the level's splits'
// dependants above it (a budget counts the closed set); without one it is not closed.
export function requestedSplits(mesh, dependencies, requests, t = 0, level = 0, views = null) {
  const { others, viewRequests } = targets(mesh, dependencies, requests, t);
  if (!viewRequests.length) return others;
  const L = dependencies.derived;
  const closed = wantedWithViews(mesh, dependencies, others, viewRequests, t, Math.max(0, Math.min(level, L)), views);
  const out = [];
  for (let i = Math.max(0, Math.min(level, L)); i < L; i++) if (closed[i]) out.push(i);
  return out;
}

// The closed set a SelectiveNavigator moves to (its setTarget()): the first `level` splits and
// the requests' splits at step t with everything they depend on, a Uint8Array per split — the
// same as nav.wanted(level, requestedSplits(…)), closed once (a view's set is closed as it is
// made, and closing it again cost 8.5 ms at a million vertices).
export function wantedSet(mesh, dependencies, requests, t = 0, level = 0, views = null) {
  const { others, viewRequests } = targets(mesh, dependencies, requests, t);
  const L = Math.min(mesh.splitsLoaded, dependencies.derived);
  return wantedWithViews(mesh, dependencies, others, viewRequests, t, Math.max(0, Math.min(level, L)), views);
}

// The requests parsed: the splits all but the views want (`others`, ascending, not closed), and
// the view requests.
function targets(mesh, dependencies, requests, t) {
  const L = dependencies.derived;
  const b = mesh.head.baseVertexCount;
  const n = b + L;
  const F = mesh.faceCountAt[L];
  const want = new Uint8Array(L);
  const wantVertex = (v) => v >= b && (want[v - b] = 1);
  // A face with all it stands for: its last writer (whose closure holds its other writers) and
  // the splits of its fully refined corners.
  const { corners, lastWriter } = dependencies;
  const wantFace = (f) => {
    if (lastWriter[f] >= 0) want[lastWriter[f]] = 1;
    for (let k = 0; k < 4; k++) if (corners[4 * f + k] >= 0) wantVertex(corners[4 * f + k]);
  };
  let p = null;
  const positions = () => (p ??= mesh.positionsAt(t, n, new Float32Array(3 * n)));
  const parsed = requests.map((x) => (typeof x === 'string' ? parseRequest(x) : x));
  for (const r of parsed) {
    if (r.kind === 'box' || r.kind === 'sphere') {
      const inside = new Uint8Array(n);
      const at = positions();
      const test = r.kind === 'box' ? boxTest(r) : sphereTest(r);
      for (let v = 0; v < n; v++) if ((inside[v] = test(at[3 * v], at[3 * v + 1], at[3 * v + 2]))) wantVertex(v);
      for (let f = 0; f < F; f++) {
        const c = 4 * f;
        if (inside[corners[c]] && inside[corners[c + 1]] && inside[corners[c + 2]] && (corners[c + 3] < 0 || inside[corners[c + 3]]) && lastWriter[f] >= 0)
          want[lastWriter[f]] = 1;
      }
    } else if (r.kind === 'part') {
      const ids = new Set(r.parts);
      for (const id of ids) if (!mesh.partId.includes(id)) throw new DpmError(`refine request "part:${r.parts.join(',')}": the model has no part ${id}`);
      for (let f = 0; f < F; f++) if (ids.has(mesh.partId[f])) wantFace(f);
    } else if (r.kind === 'field') {
      const field = fieldNamed(mesh, r.name);
      const count = field.perFace ? F : n;
      const values = fieldValuesAt(mesh, field, t, count);
      const beyond = (x) => (r.above ? x > r.threshold : x < r.threshold);
      for (let x = 0; x < count; x++) if (beyond(values[x])) (field.perFace ? wantFace : wantVertex)(x);
    } else if (r.kind === 'moved') {
      const at = positions();
      const p0 = mesh.positionsAt(0, n, new Float32Array(3 * n));
      for (let v = b; v < n; v++) {
        const dx = at[3 * v] - p0[3 * v], dy = at[3 * v + 1] - p0[3 * v + 1], dz = at[3 * v + 2] - p0[3 * v + 2];
        if (Math.sqrt(dx * dx + dy * dy + dz * dz) > r.distance) want[v - b] = 1;  // as C++ compares
      }
    }
  }
  const others = [];
  for (let i = 0; i < L; i++) if (want[i]) others.push(i);
  return { others, viewRequests: parsed.filter((r) => r.kind === 'view') };
}

// The first `prefix` splits and the other requests' splits, closed; then each view's splits in
// viewOrder(), each with its closure — all of them without a budget, else while the vertices are
// fewer than the budget (the last closure may pass it). A Uint8Array per split.
function wantedWithViews(mesh, dependencies, others, views, t, prefix, given) {
  const L = dependencies.derived;
  const closed = new Uint8Array(mesh.head.splitCount);
  closed.fill(1, 0, prefix);
  dependencies.close(others, closed);
  views.forEach((view, k) => {
    const splits = given?.splits?.[k] ?? viewOrder(mesh, given?.spheres ?? cachedSpheres(mesh, dependencies, t), L, view);
    if (!view.budget) {
      dependencies.close(splits, closed);
      return;
    }
    let vertices = mesh.head.baseVertexCount;
    for (let i = 0; i < L; i++) vertices += closed[i];
    for (const i of splits) {
      if (vertices >= view.budget) break;
      vertices += dependencies.addWithDependencies(i, closed);
    }
  });
  return closed;
}

// The spheres of the last step asked, per dependencies (re-made when the step or the splits
// derived change): one bottom-up pass per step, not per camera.
const sphereCache = new WeakMap();
function cachedSpheres(mesh, dependencies, t) {
  const c = sphereCache.get(dependencies);
  if (c && c.t === t && c.L === dependencies.derived) return c.spheres;
  const spheres = splitSpheres(mesh, dependencies.derived, t);
  sphereCache.set(dependencies, { t, L: dependencies.derived, spheres });
  return spheres;
}

const boxTest = ({ min, max }) => (x, y, z) =>
  x >= min[0] && x <= max[0] && y >= min[1] && y <= max[1] && z >= min[2] && z <= max[2] ? 1 : 0;
const sphereTest = ({ centre: [cx, cy, cz], radius }) => (x, y, z) =>
  (x - cx) ** 2 + (y - cy) ** 2 + (z - cz) ** 2 <= radius * radius ? 1 : 0;

function fieldNamed(mesh, name) {
  const field = mesh.fields.find((f) => f.name === name);
  if (!field) throw new DpmError(`refine request "field:${name}…": no field "${name}" (the file has: ${mesh.fields.map((f) => f.name).join(', ') || 'none'})`);
  return field;
}

// Items [0, count) of a field at fractional step t: linear between the steps around it.
function fieldValuesAt(mesh, field, t, count) {
  const { t0, t1, a } = mesh.stepsAround(t);
  const v0 = field.valuesAt(t0, count);
  if (a === 0) return v0;
  const v1 = field.valuesAt(t1, count);
  for (let x = 0; x < count; x++) v0[x] += (v1[x] - v0[x]) * a;
  return v0;
}
