// The index buffers the page draws (draw_indices.js) against entries written from each face's
// corners, on real crash boxes built by the CLI, after moves of every size in both directions:
// small moves rewrite the faces they list, moves over more than a quarter of the faces rewrite
// every face in order. The range to upload covers every face whose entries changed, and the
// touched faces name each of them (or are null: every face).
import assert from 'node:assert/strict';
import { test } from 'node:test';

import { Navigator, updateIndices } from '../src/dpm.js';
import { random } from './mesh_checks.mjs';
import { crashbox, CRASHBOXES } from './selective_fixture.mjs';

// A quad as two triangles (a b d, a d x) and its four edges; a triangle with a degenerate second
// triangle and its last two edges repeated.
function expectedEntries(face) {
  const [a, b, d, x] = face;
  return face.length === 4
    ? { tri: [a, b, d, a, d, x], edges: [a, b, b, d, d, x, x, a] }
    : { tri: [a, b, d, a, a, a], edges: [a, b, b, d, d, a, d, a] };
}

function sameEntries(tri, edges, before, f) {
  for (let k = 0; k < 6; k++) if (tri[6 * f + k] !== before.tri[6 * f + k]) return false;
  for (let k = 0; k < 8; k++) if (edges[8 * f + k] !== before.edges[8 * f + k]) return false;
  return true;
}

for (const name of CRASHBOXES) {
  test(`${name}: the index entries of every face after moves of every size`, () => {
    const mesh = crashbox(name);
    const S = mesh.splitsLoaded, F = mesh.head.faceCount;
    const nav = new Navigator(mesh);
    const tri = new Uint32Array(6 * F), edges = new Uint32Array(8 * F);
    updateIndices(nav, tri, edges);
    const rand = random(7);
    let listed = 0, whole = 0;
    for (let move = 0; move < 80; move++) {
      // Mostly moves of a few splits (listed faces), some across much of the mesh.
      const span = move % 4 === 0 ? S : Math.max(1, Math.floor(S / 64));
      const k = Math.max(0, Math.min(S, nav.level + Math.round((2 * rand() - 1) * span)));
      const before = { tri: tri.slice(), edges: edges.slice() };
      nav.setLevel(k);
      const touched = {};
      const range = updateIndices(nav, tri, edges, touched);
      const named = touched.faces ? new Set(touched.faces) : null;
      if (named) listed++;
      else whole++, assert.deepEqual(range, [0, nav.faceCount], `level ${k}`);
      for (let f = 0; f < nav.faceCount; f++) {
        const want = expectedEntries(nav.face(f));
        const got = { tri: Array.from(tri.subarray(6 * f, 6 * f + 6)), edges: Array.from(edges.subarray(8 * f, 8 * f + 8)) };
        assert.deepEqual(got, want, `level ${k}, face ${f}`);
        if (sameEntries(tri, edges, before, f)) continue;
        assert.ok(range && range[0] <= f && f < range[1], `level ${k}: face ${f} changed outside the range ${range}`);
        if (named) assert.ok(named.has(f), `level ${k}: face ${f} changed and is not among the touched faces`);
      }
    }
    assert.ok(listed >= 20 && whole >= 10, `${listed} moves listed their faces, ${whole} rewrote every face`);
  });
}
