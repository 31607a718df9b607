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

// The smallest sphere around sphere 4a of `a` and sphere 4b of `b` (x, y, z, r), into `out`
// from 4o.
function enclose(a, i, b, j, out, k) {
  const dx = b[j] - a[i], dy = b[j + 1] - a[i + 1], dz = b[j + 2] - a[i + 2];
  const d = Math.sqrt(dx * dx + dy * dy + dz * dz), ra = a[i + 3], rb = b[j + 3];
  if (d + rb <= ra) copy4(a, i, out, k);
  else if (d + ra <= rb) copy4(b, j, out, k);
  else {
    const r = (d + ra + rb) / 2, f = (r - ra) / d;
    out[k] = a[i] + dx * f, out[k + 1] = a[i + 1] + dy * f, out[k + 2] = a[i + 2] + dz * f, out[k + 3] = r;
  }
}
const copy4 = (from, i, to, k) => ((to[k] = from[i]), (to[k + 1] = from[i + 1]), (to[k + 2] = from[i + 2]), (to[k + 3] = from[i + 3]));

// Spheres (x, y, z, r per split, a Float32Array of 4L) of the first L splits' final descendants
// at fractional step t, over the vertices they make. Only the arrays head, q (the two steps
// around t), parent and the method positionsAt() of `mesh` are read: the decode worker's page
// side sends just those (moved_spheres.js).
export function splitSpheres(mesh, L, t) {
  const b = mesh.head.baseVertexCount, n = b + L;
  // Per vertex, the sphere of itself and what the splits after the current one made of it.
  const vertex = new Float32Array(4 * n), out = new Float32Array(4 * L);
  const p = mesh.positionsAt(t, n, new Float32Array(3 * n));
  for (let v = 0; v < n; v++) (vertex[4 * v] = p[3 * v]), (vertex[4 * v + 1] = p[3 * v + 1]), (vertex[4 * v + 2] = p[3 * v + 2]);
  // Split i turns its parent into the parent and v0: the parent's later splits are merged in
  // already, and v0's are all later.
  const { parent } = mesh;
  for (let i = L - 1; i >= 0; i--) {
    enclose(vertex, 4 * parent[i], vertex, 4 * (b + i), out, 4 * i);
    copy4(out, 4 * i, vertex, 4 * parent[i]);
  }
  return out;
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
    this.planes = Float64Array.from(this.inward.flat());
    this.scale = view.height / (2 * tv);
  }

  // Pixels of error of a split left out (sphere at s[4i]), −1 outside the frustum. The same
  // sums in the same order as C++'s dot(), without an array per split (a million a camera).
  screenError(s, i, error) {
    const { planes: n, eye } = this;
    const qx = s[4 * i] - eye[0], qy = s[4 * i + 1] - eye[1], qz = s[4 * i + 2] - eye[2];
    const r = s[4 * i + 3];
    for (let k = 0; k < 15; k += 3) if (qx * n[k] + qy * n[k + 1] + qz * n[k + 2] < -r) return -1;
    const distance = Math.sqrt(qx * qx + qy * qy + qz * qz) - r;
    if (distance <= 0) return error > 0 ? Infinity : 0;
    return (error / distance) * this.scale;
  }
}

// The splits (of the first L) whose screen error exceeds the view's tolerance, as an Int32Array
// in the order a request takes them: ascending without a budget; with one, by decreasing screen
// error, ties by index (the order the budget takes them in). A split's error is the level's
// before it (errors never increase along the stream). Only mesh.error and mesh.head.baseError are
// read: the page's spheres worker (moved_spheres.js) runs this on what it was sent.
export function viewOrder(mesh, spheres, L, view) {
  const frustum = new ViewFrustum(view);
  const { error } = mesh, base = mesh.head.baseError;
  const splits = new Int32Array(L), errors = view.budget ? new Float64Array(L) : null;
  let n = 0;
  for (let i = 0; i < L; i++) {
    const e = frustum.screenError(spheres, i, i === 0 ? base : error[i - 1]);
    if (e > view.pixels) {
      if (errors) errors[n] = e;
      splits[n++] = i;
    }
  }
  if (!errors) return splits.slice(0, n);
  // Positions k sorted by error, then by k (splits[k] ascends with k); an infinite error (the
  // eye inside a sphere) ties with another by index, as NaN || (a − b) does.
  const order = new Int32Array(n);
  for (let k = 0; k < n; k++) order[k] = k;
  order.sort((a, b) => errors[b] - errors[a] || a - b);
  for (let k = 0; k < n; k++) order[k] = splits[order[k]];
  return order;
}
