// Index entries for drawing a Navigator's level (navigator.js) with WebGL.

// Index entries for face f: two triangles (6 entries; a triangle's second one degenerate) and
// four element edges (8 entries; a triangle repeats its last edge). Fixed slots per face mean a
// change of level rewrites only the faces it touched, and drawing `faceCount` faces is a prefix.
export function writeFaceIndices(nav, f, tri, edges) {
  writeFace(nav.corners, f, tri, edges);
}

// Without a branch on the face's kind (quads and triangles come mixed, in random order when a
// move lists its faces): m is −1 for a triangle (slot 3 holds −1), else 0.
function writeFace(k, f, tri, edges) {
  const c = 4 * f;
  const a = k[c], b = k[c + 1], d = k[c + 2], x = k[c + 3];
  const m = x >> 31;
  const xa = (x & ~m) | (a & m), xd = (x & ~m) | (d & m), da = (d & ~m) | (a & m);
  const t = 6 * f;
  const e = 8 * f;
  tri[t] = a, tri[t + 1] = b, tri[t + 2] = d, tri[t + 3] = a, tri[t + 4] = da, tri[t + 5] = xa;
  edges[e] = a, edges[e + 1] = b, edges[e + 2] = b, edges[e + 3] = d;
  edges[e + 4] = d, edges[e + 5] = xa, edges[e + 6] = xd, edges[e + 7] = a;
}

// Rewrites the index entries of the faces changed since the last call; returns the range of
// faces [lo, hi) that changed, for partial buffer uploads, or null. touched.faces: the changed
// faces (a view, valid until the navigator's next change; may hold faces ≥ faceCount), or null
// when every face below the face count was rewritten: a change that touched more than a quarter
// of them rewrites them all in order, since a face written in order costs about an eighth of one
// written at a random place (the 1 M plate's page steps, viewer.md "Index buffers").
export function updateIndices(nav, tri, edges, touched = {}) {
  const dirty = nav.takeDirty();
  const F = nav.faceCount, k = nav.corners;
  if (4 * dirty.length > F) {
    for (let f = 0; f < F; f++) writeFace(k, f, tri, edges);
    touched.faces = null;
    return F > 0 ? [0, F] : null;
  }
  let lo = Infinity, hi = 0;
  for (let i = 0; i < dirty.length; i++) {
    const f = dirty[i];
    if (f >= F) continue;
    writeFace(k, f, tri, edges);
    if (f < lo) lo = f;
    if (f + 1 > hi) hi = f + 1;
  }
  touched.faces = dirty;
  return lo < hi ? [lo, hi] : null;
}
