// The view request's split spheres made by the page's spheres worker (moved_spheres.js,
// docs/viewer.md "Spheres from a worker"): the request the page posts and the worker's answer,
// each cloned as postMessage clones it, give the spheres splitSpheres() makes on the page, bit
// for bit — lossless and quantized crash boxes, whole and fractional steps, every split loaded
// or a prefix, arrays copied (a page without shared memory) or shared (nothing copied). The
// same spheres give `dynpm extract --refine view:…`'s bytes (refine_conformance.test.mjs).
import assert from 'node:assert/strict';
import { test } from 'node:test';

import { splitSpheres } from '../src/dpm/view_target.js';
import { spheresAnswer, spheresRequest } from '../src/moved_spheres.js';
import { crashbox } from './selective_fixture.mjs';

// Through the worker's protocol: request cloned (its copies transferred), answered, cloned back.
function viaWorker(mesh, L, t) {
  const { message, transfer } = spheresRequest(mesh, L, t, 7);
  const { answer, transfer: back } = spheresAnswer(structuredClone(message, { transfer }));
  const got = structuredClone(answer, { transfer: back });
  assert.deepEqual([got.id, got.L, got.t], [7, L, t]);
  return { spheres: got.spheres, copied: transfer.length };
}

const bits = (a) => new Uint32Array(a.buffer, a.byteOffset, a.length);

// The mesh with its positions and parents on shared memory, as the decode worker shares them.
function onSharedMemory(mesh) {
  const shared = (a) => {
    const b = new a.constructor(new SharedArrayBuffer(a.byteLength));
    b.set(a);
    return b;
  };
  return Object.assign(Object.create(Object.getPrototypeOf(mesh)), mesh, { q: mesh.q.map(shared), parent: shared(mesh.parent) });
}

for (const [name, options] of [['crashbox-mixed-5k', {}], ['crashbox-fields', {}], ['crashbox-mixed-5k', { quantized: true }]])
  test(`${name}${options.quantized ? ' (quantized)' : ''}: the worker's spheres are the page's, bit for bit`, () => {
    const mesh = crashbox(name, options);
    const { splitCount, stepCount } = mesh.head;
    assert.equal(mesh.lossless, !options.quantized);
    const shared = onSharedMemory(mesh);
    for (const L of [splitCount, Math.floor(splitCount / 3)])
      for (const t of [0, 10.25, stepCount - 1]) {
        const page = splitSpheres(mesh, L, t);
        assert.equal(page.length, 4 * L);
        // Real spheres: finite, radii ≥ 0, a split's sphere holds its new vertex.
        for (let i = 0; i < L; i++) assert.ok(page[4 * i + 3] >= 0 && Number.isFinite(page[4 * i]), `split ${i}`);
        const copied = viaWorker(mesh, L, t);
        assert.ok(copied.copied >= 2, 'positions and parents copied for a page without shared memory');
        assert.deepEqual(bits(copied.spheres), bits(page), `${L} splits at step ${t}, copied`);
        const viaShared = viaWorker(shared, L, t);
        assert.equal(viaShared.copied, 0, 'shared arrays go as they are');
        assert.deepEqual(bits(viaShared.spheres), bits(page), `${L} splits at step ${t}, shared`);
      }
  });

test('a split\'s sphere holds its new vertex and its parent at the step', () => {
  const mesh = crashbox('crashbox-mixed-5k');
  const { baseVertexCount: b, splitCount: L, vertexCount: n } = mesh.head;
  const t = 25.5;
  const s = splitSpheres(mesh, L, t);
  const p = mesh.positionsAt(t, n, new Float32Array(3 * n));
  const inside = (i, v) => Math.hypot(p[3 * v] - s[4 * i], p[3 * v + 1] - s[4 * i + 1], p[3 * v + 2] - s[4 * i + 2]) <= s[4 * i + 3] * (1 + 1e-5) + 1e-4;
  for (let i = 0; i < L; i++) assert.ok(inside(i, b + i) && inside(i, mesh.parent[i]), `split ${i}`);
});
