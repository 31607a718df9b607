// Index entries for drawing a Navigator's level (navigator.js) with WebGL.

// Index entries for face f: two triangles (6 entries; a triangle's second one degenerate) and
// four element edges (8 entries; a triangle repeats its last edge). Fixed slots per face mean a
// change of level rewrites only the faces it touched, and drawing `faceCount` faces is a prefix.
export function writeFaceIndices(nav, f, tri, edges) {
  const k = nav.corners;
  const c = 4 * f;
  const a = k[c], b = k[c + 1], d = k[c + 2];
  const t = 6 * f;
  const e = 8 * f;
  tri[t] = a, tri[t + 1] = b, tri[t + 2] = d;
  edges[e] = a, edges[e + 1] = b, edges[e + 2] = b, edges[e + 3] = d;
  const x = k[c + 3];
  if (x >= 0) {
    tri[t + 3] = a, tri[t + 4] = d, tri[t + 5] = x;
    edges[e + 4] = d, edges[e + 5] = x, edges[e + 6] = x, edges[e + 7] = a;
  } else {
    tri[t + 3] = a, tri[t + 4] = a, tri[t + 5] = a;
    edges[e + 4] = d, edges[e + 5] = a, edges[e + 6] = d, edges[e + 7] = a;
  }
}

// Rewrites the index entries of the faces changed since the last call; returns the range of
// faces [lo, hi) that changed, for partial buffer uploads, or null. touched.faces: the changed
// faces (a view, valid until the navigator's next change; may hold faces ≥ faceCount).
export function updateIndices(nav, tri, edges, touched = {}) {
  const dirty = nav.takeDirty();
  const F = nav.faceCount;
  let lo = Infinity, hi = 0;
  for (let i = 0; i < dirty.length; i++) {
    const f = dirty[i];
    if (f >= F) continue;
    writeFaceIndices(nav, f, tri, edges);
    if (f < lo) lo = f;
    if (f + 1 > hi) hi = f + 1;
  }
  touched.faces = dirty;
  return lo < hi ? [lo, hi] : null;
}
