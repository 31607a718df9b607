import assert from 'node:assert/strict';

// What src/core/validate.cpp checks of a mesh, for the selective-refinement tests: (M3) every
// face has 3 or 4 distinct corners that exist, (M1) every edge is used by at most 2 faces (the
// T-joints a model has are counted separately), consistent orientation, (M2) inner vertices of
// valence ≥ 3, and no vertex in no face; and what must not change: the boundary loops, the parts
// and the connected components.

// mesh: {vertices: n, faces: Int32Array of 4 slots per face (−1 in slot 3 of a triangle),
// partIds: per face}. Returns {problems: [text], boundaryLoops, components, parts, tJoints}.
export function checkMesh({ vertexCount: n, faces, partIds }) {
  const problems = [];
  const F = faces.length / 4;
  const edges = new Map();  // a·n + b (a < b) → [faces, walks a→b]
  const used = new Uint8Array(n);
  const parent = Int32Array.from({ length: n }, (_, v) => v);
  const find = (v) => {
    while (parent[v] !== v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (let f = 0; f < F; f++) {
    const d = faces[4 * f + 3] < 0 ? 3 : 4;
    const c = Array.from(faces.subarray(4 * f, 4 * f + d));
    if (c.some((v) => v < 0 || v >= n)) problems.push(`face ${f} (${c}): a corner does not exist`);
    else if (new Set(c).size !== d) problems.push(`face ${f} (${c}): a vertex appears twice`);
    else
      for (let k = 0; k < d; k++) {
        const a = c[k], b = c[(k + 1) % d];
        used[a] = 1;
        parent[find(a)] = find(b);
        const key = Math.min(a, b) * n + Math.max(a, b);
        const e = edges.get(key) ?? [0, 0];
        e[0]++;
        e[1] += a < b ? 1 : 0;
        edges.set(key, e);
      }
  }
  const valence = new Int32Array(n), boundary = new Uint8Array(n);
  const next = new Map();  // boundary edges: vertex → its boundary neighbours
  let tJoints = 0;
  for (const [key, [count, forward]] of edges) {
    const a = Math.floor(key / n), b = key % n;
    valence[a]++, valence[b]++;
    if (count > 2) tJoints++;
    if (count === 2 && forward !== 1) problems.push(`edge (${a}, ${b}): both faces walk it the same way`);
    if (count === 1) {
      boundary[a] = boundary[b] = 1;
      for (const [x, y] of [[a, b], [b, a]]) next.set(x, [...(next.get(x) ?? []), y]);
    }
  }
  for (let v = 0; v < n; v++) {
    if (!used[v]) problems.push(`vertex ${v}: in no face`);
    else if (!boundary[v] && valence[v] < 3) problems.push(`vertex ${v}: inner vertex of valence ${valence[v]}`);
  }
  // Boundary loops: the connected pieces of the boundary edges.
  let boundaryLoops = 0;
  const seen = new Set();
  for (const start of next.keys()) {
    if (seen.has(start)) continue;
    boundaryLoops++;
    const stack = [start];
    seen.add(start);
    while (stack.length) for (const y of next.get(stack.pop())) if (!seen.has(y)) seen.add(y), stack.push(y);
  }
  let components = 0;
  for (let v = 0; v < n; v++) if (used[v] && find(v) === v) components++;
  const parts = [...new Set(partIds)].sort((x, y) => x - y);
  return { problems, boundaryLoops, components, parts, tJoints };
}

// A small deterministic generator (tests repeat exactly).
export function random(seed) {
  let s = seed >>> 0;
  return () => ((s = (Math.imul(s, 1664525) + 1013904223) >>> 0) / 2 ** 32);
}

export function checkNavigator(nav) {
  const { vertices, faces, faceIds } = nav.activeMesh();
  const partIds = Array.from(faceIds, (f) => nav.mesh.partId[f]);
  return checkMesh({ vertexCount: vertices.length, faces, partIds });
}

// What must hold of every selective mesh: valid, with the original's boundary, parts, pieces.
export function assertLikeOriginal(nav, original, what) {
  const r = checkNavigator(nav);
  assert.deepEqual(r.problems.slice(0, 5), [], what);
  assert.equal(r.boundaryLoops, original.boundaryLoops, `${what}: boundary loops`);
  assert.equal(r.components, original.components, `${what}: components`);
  assert.deepEqual(r.parts, original.parts, `${what}: parts`);
  assert.ok(r.tJoints === 0 || original.tJoints > 0, `${what}: ${r.tJoints} edges of 3 or more faces`);
}
