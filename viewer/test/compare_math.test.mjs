// compare_math.js on the sample built three ways (compare_fixture.mjs): two position grids of
// one hierarchy are recognised as one, with their per-vertex difference within the grids'
// bounds at every level and step; other key steps are another hierarchy, named where they part;
// damage to one record of a copy is found at that split.
import assert from 'node:assert/strict';
import { test } from 'node:test';

import { hierarchyDifference, linkedVertexCount, positionDifference } from '../src/compare_math.js';
import { compareMesh } from './compare_fixture.mjs';

const fine = compareMesh('fine'), coarse = compareMesh('coarse'), keys3 = compareMesh('keys3');
const S = fine.head.splitCount;

test('two position grids of one input hold one hierarchy', () => {
  assert.equal(hierarchyDifference(fine, coarse, S), null);
  assert.equal(hierarchyDifference(coarse, fine, 100), null);
  const step5 = (mesh) => mesh.positionsAt(5, 10, new Float32Array(30));
  assert.notDeepEqual(step5(fine), step5(coarse), 'the grids differ');
});

test('other key steps are another hierarchy, and the first difference is named', () => {
  const why = hierarchyDifference(fine, keys3, keys3.head.splitCount);
  assert.ok(why, 'keys3 differs');
  assert.match(why, /Count|base face|vertex \d+ is node|split \d+/);
});

test('one changed record in a copy is found at its split', () => {
  const twin = compareMesh('coarse');
  twin.parent[700] = twin.parent[700] + 1;
  assert.equal(hierarchyDifference(fine, twin, 700), null, 'before split 700 they agree');
  assert.equal(hierarchyDifference(fine, twin, S), 'split 700 has another parent');
  const wings = compareMesh('coarse');
  const k = wings.wingStart[1200];
  wings.wingVertex.data[k] += 1;
  assert.equal(hierarchyDifference(fine, wings, S), 'split 1200 has other wings');
  const moved = compareMesh('coarse');
  const m = moved.movedStart[900];
  assert.ok(moved.movedStart[901] > m, 'split 900 moves faces');
  moved.movedFaces.data[m] += 1;
  assert.equal(hierarchyDifference(fine, moved, S), 'split 900 has other moved faces');
  const fewer = compareMesh('coarse');
  fewer.splitsLoaded = 10;
  assert.match(hierarchyDifference(fine, fewer, 11), /only 10 splits/);
});

test('the difference is within both grids\' errors at every level and step, and its max is where it says', () => {
  const h = fine.head;
  const bound = fine.head.maxError + coarse.head.maxError;
  const V = h.vertexCount;
  const a = new Float32Array(3 * V), b = new Float32Array(3 * V), d = new Float32Array(V);
  let largest = 0;
  for (const n of [h.baseVertexCount, Math.round(0.1 * V), V])
    for (const t of [0, 7, 12.5, h.stepCount - 1]) {
      fine.positionsAt(t, n, a);
      coarse.positionsAt(t, n, b);
      const max = positionDifference(a, b, n, d);
      let brute = 0, at = -1;
      for (let v = 0; v < n; v++) {
        const e = Math.hypot(a[3 * v] - b[3 * v], a[3 * v + 1] - b[3 * v + 1], a[3 * v + 2] - b[3 * v + 2]);
        assert.ok(Math.abs(d[v] - e) <= 1e-6 * e + 1e-12, `vertex ${v}`);
        if (e > brute) (brute = e), (at = v);
      }
      assert.ok(Math.abs(max.value - brute) <= 1e-12 * brute, `${max.value} vs ${brute}`);
      assert.equal(max.vertex, at);
      assert.ok(max.value <= bound * (1 + 1e-6), `n ${n}, t ${t}: ${max.value} > ${bound}`);
      largest = Math.max(largest, max.value);
    }
  assert.ok(largest > 0.25 * coarse.head.maxError, `the coarse grid shows: ${largest} of ${coarse.head.maxError}`);
  assert.deepEqual(positionDifference(a, b, 0, d), { value: 0, vertex: -1 });
});

test('the linked level: the same count in one hierarchy, the same fraction otherwise, within what is loaded', () => {
  const h = fine.head;
  assert.equal(linkedVertexCount(1000, h.vertexCount, coarse.head, coarse.vertexCountLoaded), 1000);
  const other = { vertexCount: 2 * h.vertexCount, baseVertexCount: 20 };
  assert.equal(linkedVertexCount(1000, h.vertexCount, other, Infinity), 2000);
  assert.equal(linkedVertexCount(1000, h.vertexCount, other, 1500), 1500);
  assert.equal(linkedVertexCount(1, h.vertexCount, other, Infinity), 20);
});
