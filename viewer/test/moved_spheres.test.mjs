// A view request's splits made by the page's spheres worker (moved_spheres.js, docs/viewer.md
// "Spheres from a worker"): the request the page posts and the worker's answer, each cloned as
// postMessage clones it. The spheres the worker keeps are the ones splitSpheres() makes on the
// page, bit for bit, and the splits it answers per camera are viewOrder()'s on the page —
// lossless and quantized crash boxes, whole and fractional steps, every split loaded or a
// prefix, arrays copied (a page without shared memory) or shared (nothing copied), cameras
// with and without a budget, the spheres sent once and kept for the next camera. The same
// splits give `dynpm extract --refine view:…`'s bytes (refine_conformance.test.mjs).
import assert from 'node:assert/strict';
import { test } from 'node:test';

import { parseRequest } from '../src/dpm/refine_targets.js';
import { ViewFrustum, splitSpheres, viewOrder } from '../src/dpm/view_target.js';
import { ViewWorker, viewRequest } from '../src/moved_spheres.js';
import { StepPositions } from '../src/dpm/step_positions.js';
import { crashbox } from './selective_fixture.mjs';

// Cameras around the crash boxes (their axis along z, 0 … about 300 mm), one with a budget.
const CAMERAS = ['view:EYE=150,40,300;AT=0,0,180;FOV=35;W=900;H=700;PX=1',
  'view:EYE=20,10,330;AT=0,0,150;UP=0,1,0;FOV=50;H=1080;PX=0.5;BUDGET=1200',
  'view:EYE=-120,0,140;AT=0,0,140;FOV=35;W=1600;H=900;PX=0.2;BUDGET=3400'].map((r) => parseRequest(r));

// Through the worker's protocol: request cloned (its copies transferred), answered, cloned back.
function viaWorker(worker, mesh, L, t, views, withSpheres) {
  const { message, transfer } = viewRequest(mesh, L, t, views, withSpheres, 'k7');
  const { answer, transfer: back } = worker.answer(structuredClone(message, { transfer }));
  const got = structuredClone(answer, { transfer: back });
  assert.equal(got.key, 'k7');
  return { splits: got.splits, copied: transfer.length };
}

const bits = (a) => new Uint32Array(a.buffer, a.byteOffset, a.length);

// The mesh with its positions, parents and errors on shared memory, as the decode worker shares
// them.
function onSharedMemory(mesh) {
  const shared = (a) => {
    const b = new a.constructor(new SharedArrayBuffer(a.byteLength));
    b.set(a);
    return b;
  };
  const positions = StepPositions.from({ ...mesh.positions, steps: mesh.positions.steps.map(shared), wide: mesh.positions.wide.map(shared) });
  return Object.assign(Object.create(Object.getPrototypeOf(mesh)), mesh, { positions, parent: shared(mesh.parent), error: shared(mesh.error) });
}

for (const [name, options] of [['crashbox-mixed-5k', {}], ['crashbox-fields', {}], ['crashbox-mixed-5k', { quantized: true }]])
  test(`${name}${options.quantized ? ' (quantized)' : ''}: the worker's spheres and view splits are the page's`, () => {
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
        const want = CAMERAS.map((view) => viewOrder(mesh, page, L, view));
        assert.ok(want.some((w) => w.length > 0 && w.length < L), 'a camera wants some of the splits, not all');
        for (const [how, m, copies] of [['copied', mesh, 3], ['shared', shared, 0]]) {
          const worker = new ViewWorker();
          const first = viaWorker(worker, m, L, t, CAMERAS.slice(0, 2), true);
          const between = t % 1 !== 0;  // positions of two steps, else of one
          if (copies) assert.equal(first.copied, between ? 4 : 3, 'positions (of the two steps around t, one at a step), parents and errors copied for a page without shared memory');
          // Shared, step 0 is the stored array; other steps are made on the page (a cursor's arrays
          // move with time) and go as copies.
          else assert.equal(first.copied, t === 0 ? 0 : between ? 2 : 1, 'shared arrays go as they are');
          assert.deepEqual(bits(worker.held.spheres), bits(page), `${L} splits at step ${t}, ${how}: the spheres`);
          // The next camera at that step: nothing sent but the view; the spheres kept.
          const next = viaWorker(worker, m, L, t, CAMERAS.slice(2), false);
          assert.equal(next.copied, 0);
          assert.deepEqual([...first.splits, ...next.splits], want, `${L} splits at step ${t}, ${how}: the view splits`);
        }
      }
  });

test('the worker refuses a camera at a step whose spheres it was not sent', () => {
  const mesh = crashbox('crashbox-mixed-5k');
  const L = mesh.head.splitCount;
  const worker = new ViewWorker();
  assert.throws(() => viaWorker(worker, mesh, L, 3, CAMERAS.slice(0, 1), false), /holds no spheres of \d+ splits at step 3/);
  viaWorker(worker, mesh, L, 3, CAMERAS.slice(0, 1), true);
  assert.throws(() => viaWorker(worker, mesh, L, 4, CAMERAS.slice(0, 1), false), /at step 4/);
});

// A budget takes the splits by decreasing screen error, ties by index; without one, ascending.
test('viewOrder: ascending without a budget, by decreasing screen error with one', () => {
  const mesh = crashbox('crashbox-mixed-5k');
  const L = mesh.head.splitCount;
  const spheres = splitSpheres(mesh, L, 20);
  const [free, budgeted] = CAMERAS.slice(0, 2);
  const ascending = viewOrder(mesh, spheres, L, free);
  for (let k = 1; k < ascending.length; k++) assert.ok(ascending[k - 1] < ascending[k]);
  const ordered = viewOrder(mesh, spheres, L, budgeted);
  const same = viewOrder(mesh, spheres, L, { ...budgeted, budget: 0 });
  assert.deepEqual([...ordered].sort((a, b) => a - b), [...same], 'the same splits');
  const frustum = new ViewFrustum(budgeted);
  const error = (i) => frustum.screenError(spheres, i, mesh.levelError(i));
  for (let k = 1; k < ordered.length; k++) {
    const [i, j] = [ordered[k - 1], ordered[k]];
    assert.ok(error(i) > error(j) || (error(i) === error(j) && i < j), `position ${k}: split ${i} before ${j}`);
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
