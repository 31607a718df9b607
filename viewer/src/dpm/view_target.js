// The view-dependent request (docs/selective.md "View-dependent"): per split a bounding sphere of
// its final descendants at the step, bottom-up over the vertex hierarchy as in Hoppe's VDPM
// (1997), and its screen-space error for a camera; a split is wanted when the error exceeds the
// tolerance and the sphere meets the frustum. C++: src/lod/view_target.cpp — the same arithmetic
// in the same order (doubles, spheres stored as float32), so both decoders want the same splits.

const minus = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const normalized = (a) => {
  const n = Math.sqrt(dot(a, a));
  return [a[0] / n, a[1] / n, a[2] / n];
};
const scaledPlus = (a, s, b) => [a[0] * s + b[0], a[1] * s + b[1], a[2] * s + b[2]];
const negated = (a) => [-a[0], -a[1], -a[2]];

// The smallest sphere around spheres a and b of `s` (x, y, z, r from 4a, 4b), into s from 4o.
function enclose(s, a, b, o) {
  const i = 4 * a, j = 4 * b, k = 4 * o;
  const dx = s[j] - s[i], dy = s[j + 1] - s[i + 1], dz = s[j + 2] - s[i + 2];
  const d = Math.sqrt(dx * dx + dy * dy + dz * dz), ra = s[i + 3], rb = s[j + 3];
  if (d + rb <= ra) copy4(s, i, k);
  else if (d + ra <= rb) copy4(s, j, k);
  else {
    const r = (d + ra + rb) / 2, f = (r - ra) / d;
    const x = s[i] + dx * f, y = s[i + 1] + dy * f, z = s[i + 2] + dz * f;
    s[k] = x, s[k + 1] = y, s[k + 2] = z, s[k + 3] = r;
  }
}
const copy4 = (s, from, to) => ((s[to] = s[from]), (s[to + 1] = s[from + 1]), (s[to + 2] = s[from + 2]), (s[to + 3] = s[from + 3]));

// Spheres (x, y, z, r per split, Float32Array) of the first L splits' final descendants at
// fractional step t, over the vertices they make.
export function splitSpheres(mesh, L, t) {
  const b = mesh.head.baseVertexCount, n = b + L;
  // Per vertex then per split, in one array: vertex v at v, split i at n + i.
  const s = new Float32Array(4 * (n + L));
  const p = mesh.positionsAt(t, n, new Float32Array(3 * n));
  for (let v = 0; v < n; v++) (s[4 * v] = p[3 * v]), (s[4 * v + 1] = p[3 * v + 1]), (s[4 * v + 2] = p[3 * v + 2]);
  // Split i turns its parent into the parent and v0: the parent's later splits are merged in
  // already, and v0's are all later.
  const { parent } = mesh;
  for (let i = L - 1; i >= 0; i--) {
    enclose(s, parent[i], b + i, n + i);
    copy4(s, 4 * (n + i), 4 * parent[i]);
  }
  return s.subarray(4 * n);
}

// The camera's frustum and projection; view: a parsed view request.
export class ViewFrustum {
  constructor(view) {
    const f = normalized(minus(view.at, view.eye));
    const right = normalized(cross(f, view.up)), up = cross(right, f);
    const tv = Math.tan((view.fov * Math.PI) / 360);
    const width = view.width > 0 ? view.width : view.height;
    const th = (tv * width) / view.height;
    this.eye = view.eye;
    // Inward normals: near (at the eye), top, bottom, right, left.
    this.inward = [f, normalized(scaledPlus(f, tv, negated(up))), normalized(scaledPlus(f, tv, up)),
      normalized(scaledPlus(f, th, negated(right))), normalized(scaledPlus(f, th, right))];
    this.scale = view.height / (2 * tv);
  }

  // Pixels of error of a split left out (sphere at s[4i]), −1 outside the frustum.
  screenError(s, i, error) {
    const q = [s[4 * i] - this.eye[0], s[4 * i + 1] - this.eye[1], s[4 * i + 2] - this.eye[2]];
    const r = s[4 * i + 3];
    for (const n of this.inward) if (dot(q, n) < -r) return -1;
    const distance = Math.sqrt(dot(q, q)) - r;
    if (distance <= 0) return error > 0 ? Infinity : 0;
    return (error / distance) * this.scale;
  }
}

// The splits (of the first L) a view wants: [screen error, split], `sorted` by decreasing error,
// ties by index (the order a budget takes them in). A split's error is the level's before it
// (errors never increase along the stream).
export function viewSplits(mesh, spheres, L, view, sorted = true) {
  const frustum = new ViewFrustum(view);
  const out = [];
  for (let i = 0; i < L; i++) {
    const e = frustum.screenError(spheres, i, mesh.levelError(i));
    if (e > view.pixels) out.push([e, i]);
  }
  return sorted ? out.sort((a, b) => b[0] - a[0] || a[1] - b[1]) : out;
}
