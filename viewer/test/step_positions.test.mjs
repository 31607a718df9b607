// The compact positions (src/dpm/step_positions.js): every step of every vertex comes back
// exactly, whichever way the cursors walk, with second differences at the edges of their types
// (escapes), lossless bit patterns that wrap, and on a real file a third of the full arrays.
import assert from 'node:assert/strict';
import fs from 'node:fs';
import { test } from 'node:test';
import { readDpm } from '../src/dpm.js';
import { positionBytes, StepPositions } from '../src/dpm/step_positions.js';
import { budgetedVertices, remeasuredBudget } from '../src/model_file.js';

// A seeded generator (xorshift32), so that a failure repeats.
function random(seed) {
  let x = seed >>> 0 || 1;
  return () => {
    x ^= x << 13, x ^= x >>> 17, x ^= x << 5;
    return (x >>> 0) / 2 ** 32;
  };
}

// Paths of V vertices over T steps (full Int32Arrays, one a step): smooth motion, and on chosen
// coordinates the second differences at the types' edges (±127, −128 = Int8's escape, 128,
// ±32767, −32768, 32768) and large jumps.
function paths(V, T, seed, lossless = false, edgeRate = 0.03) {
  const r = random(seed);
  const edges = [127, -127, -128, 128, 32767, -32767, -32768, 32768, 5e6, -5e6];
  const steps = Array.from({ length: T }, () => new Int32Array(3 * V));
  for (let i = 0; i < 3 * V; i++) {
    let x = lossless ? Math.floor((r() - 0.5) * 2 ** 32) : Math.floor(r() * 1e6);
    let v = Math.floor((r() - 0.5) * 40);
    for (let t = 0; t < T; t++) {
      steps[t][i] = x;
      const edge = r() < edgeRate ? edges[Math.floor(r() * edges.length)] : Math.floor((r() - 0.5) * 6);
      v += edge;
      x = lossless ? (x + v * 65537) | 0 : x + v;
    }
  }
  return steps;
}

// A store of those paths, written in two runs of vertices as a decoder does (room first).
function stored(steps, lossless, V, split = Math.floor(V / 3)) {
  const T = steps.length;
  const p = new StepPositions(T, lossless, V);
  for (const [first, count] of [[0, split], [split, V - split]]) {
    p.makeRoom(first + count);
    const at = 3 * first;
    for (let t = 0; t < T; t++)
      p.store(t, first, count, steps[t], t > 0 ? steps[t - 1] : null, t > 1 ? steps[t - 2] : steps[Math.max(t - 1, 0)], at);
  }
  return p;
}

const prefix = (a, n) => Array.from(a.subarray(0, 3 * n));

for (const lossless of [false, true])
  test(`every step comes back exactly, walked any way (${lossless ? 'lossless: 32 bits that wrap' : 'quantized: 16 and 8 bits with escapes'})`, () => {
    const V = 500, T = 12;
    const steps = paths(V, T, lossless ? 7 : 3, lossless);
    const p = stored(steps, lossless, V);
    if (lossless) {
      assert.ok(p.steps.every((a) => a instanceof Int32Array));
      assert.ok(p.wide.every((w) => w[0] === 0), 'nothing escapes');
    } else {
      assert.ok(p.steps[0] instanceof Int32Array && p.steps[1] instanceof Int16Array && p.steps[5] instanceof Uint8Array);
      assert.ok(p.wide[1][0] > 0 && p.wide[5][0] > 0, 'some values escaped at step 1 and later');
      // An escaped value is the type's escape in the step's array, and in its list in index order.
      for (let t = 1; t < T; t++) {
        const w = p.wide[t];
        for (let k = 1; k < w[0]; k++) assert.ok(w[1 + 2 * k] > w[2 * k - 1], `step ${t}: escapes in index order`);
        // Step 1 stores Int16's escape; a packed step gives the value back from the list.
        const stored = (i) => (t === 1 ? p.steps[1][i] : p.differences(t, i, i + 1)[0]);
        for (let k = 0; k < w[0]; k++) assert.equal(stored(w[1 + 2 * k]), t === 1 ? -32768 : w[2 + 2 * k]);
      }
      // Packed: a run a store (two a step), blocks of at most 128 coordinates; only values beyond
      // 16 bits or beyond their block's width escape, so the ±32768 edges (and the jumps) do.
      const edges = new Set();
      for (let t = 2; t < T; t++) {
        assert.equal(p.runs[t][0], 2);
        assert.equal(p.dir[t][0], Math.ceil(3 * Math.floor(V / 3) / 128) + Math.ceil(3 * (V - Math.floor(V / 3)) / 128));
        for (let k = 0; k < p.wide[t][0]; k++) edges.add(Math.abs(p.wide[t][2 + 2 * k]));
      }
      assert.ok(edges.has(32768) && edges.has(5e6), 'the 16-bit edge and the jumps escaped');
    }
    // Forward, backward, jumps, both cursors, and a count of vertices that shrinks and grows.
    const r = random(11);
    for (let k = 0; k < 60; k++) {
      const t = Math.floor(r() * T), n = k % 5 === 0 ? Math.max(1, Math.floor(r() * V)) : V;
      const [a, b] = p.around(t, t, n);
      assert.equal(a, b);
      assert.deepEqual(prefix(b, n), prefix(steps[t], n), `step ${t}, ${n} vertices (request ${k})`);
      if (t + 1 < T) {
        const [q0, q1] = p.around(t, t + 1, n);
        assert.deepEqual([prefix(q0, n), prefix(q1, n)], [prefix(steps[t], n), prefix(steps[t + 1], n)], `steps ${t} and ${t + 1}`);
      }
      const u = Math.floor(r() * T);
      const [x, y] = p.around(u, t, n);  // any two steps
      assert.deepEqual([prefix(x, n), prefix(y, n)], [prefix(steps[u], n), prefix(steps[t], n)], `steps ${u} and ${t}`);
      assert.ok(p.cursors.length <= 2);
    }
    // One vertex at a time: from a cursor that holds it, or walked alone.
    for (let k = 0; k < 200; k++) {
      const v = Math.floor(r() * V), t = Math.floor(r() * T);
      assert.deepEqual(p.position(v, t, [0, 0, 0]), prefix(steps[t].subarray(3 * v), 1), `vertex ${v} at step ${t}`);
    }
    // A decoder's old vertices, every step (gather()).
    const ids = Int32Array.from({ length: 40 }, () => Math.floor(r() * V));
    const out = Array.from({ length: T }, () => new Int32Array(3 + 3 * ids.length));
    p.gather(ids, (t) => out[t], 3);
    for (let t = 0; t < T; t++)
      ids.forEach((v, k) => assert.deepEqual(Array.from(out[t].subarray(3 + 3 * k, 6 + 3 * k)), prefix(steps[t].subarray(3 * v), 1)));
  });

test("a page that is sent pieces (the escaped values of a run of vertices) holds the same positions", () => {
  const V = 300, T = 6;
  const steps = paths(V, T, 5);
  const worker = stored(steps, false, V, 120);
  const page = new StepPositions(T, false, V);
  // Cut where the worker's runs are not (its stores: 0–120, 120–300), so runs and blocks differ.
  for (const [v0, v1] of [[0, 50], [50, 190], [190, 300]]) {
    page.makeRoom(v1);
    worker.steps.forEach((a, t) => {
      if (t < 2) page.steps[t].set(a.subarray(3 * v0, 3 * v1), 3 * v0);
      else page.addDifferences(t, 3 * v0, worker.differences(t, 3 * v0, 3 * v1));  // finds its escapes
    });
    for (let t = 0; t < 2; t++) page.addWidePairs(t, worker.widePairs(t, v0, v1));
  }
  assert.equal(page.runs[T - 1][0], 3);
  for (let t = 0; t < T; t++) assert.deepEqual(prefix(page.around(t, t, V)[1], V), prefix(steps[t], V), `step ${t}`);
  // Another thread's reader: the arrays alone, cursors of its own.
  const { steps: s, wide, dir, runs } = worker;
  const other = StepPositions.from(structuredClone({ vertexCount: V, steps: s, wide, dir, runs }));
  assert.deepEqual(prefix(other.around(T - 1, T - 1, V)[1], V), prefix(steps[T - 1], V));
  assert.equal(other.cursors.length, 1);
});

// The sample file (ctest's viewer_sample_dpm): the positions of every step in about a quarter of
// the bytes of one Int32Array a step, the same as walking each vertex alone.
test('the sample model holds its positions compact', { skip: !process.env.DYNPM_DPM && 'DYNPM_DPM not set' }, () => {
  const { mesh } = readDpm(new Uint8Array(fs.readFileSync(process.env.DYNPM_DPM)));
  const { vertexCount: V, stepCount: T } = mesh.head;
  const { steps } = mesh.positions;
  const stored = steps[0].byteLength + steps[1].byteLength + mesh.positions.laterBytes();
  const full = 12 * V * T;
  assert.ok(stored < 0.4 * full, `${stored} bytes for ${V} vertices × ${T} steps (full: ${full})`);
  const last = mesh.positions.around(T - 1, T - 1, V)[1];
  const alone = StepPositions.from(mesh.positions);  // no cursor: each vertex walked alone
  for (let v = 0; v < V; v += 97) assert.deepEqual(alone.position(v, T - 1, [0, 0, 0]), prefix(last.subarray(3 * v), 1));
});

// The decode worker's budget (model_file.js): measured again once an eighth of it is loaded, with
// the packed and escaped positions of the loaded vertices instead of positionBytes()'s allowance.
test('the memory budget is lowered for positions that take more than its allowance, never raised', () => {
  const V = 600, T = 12, budget = 2 ** 20;
  const head = { stepCount: T, flags: 0, fieldCount: 0, baseVertexCount: 10, vertexCount: 100000 };
  const target = budgetedVertices(head, budget);
  assert.equal(target, Math.floor(budget / (positionBytes(T, false) + 200)));
  assert.ok(8 * V >= target && 8 * 400 < target, 'an eighth of the target lies between 400 and 600 vertices');
  const calm = stored(paths(V, T, 21, false, 0), false, V);
  const wild = stored(paths(V, T, 22, false, 0.5), false, V);
  assert.equal(calm.escapedBytes(), 0);
  const escaped = wild.escapedBytes() / V;
  assert.ok(escaped > 4 * (T - 1), `${escaped} bytes a vertex escaped, four times the allowance`);
  assert.equal(remeasuredBudget(head, budget, target, calm, V), target, 'not raised');
  assert.equal(remeasuredBudget(head, budget, target, wild, 400), target, 'not before an eighth is loaded');
  // Second differences within ±3: 3 bits a value (−3 … 3 need no escape code of all ones), and
  // the blocks' entries.
  const calmBytes = calm.laterBytes() / (V * (T - 2));
  assert.ok(calmBytes > 9 / 8 && calmBytes < 9 / 8 + 0.2, `calm paths: ${calmBytes} bytes a vertex a packed step`);
  const lowered = remeasuredBudget(head, budget, target, wild, V);
  assert.equal(lowered, Math.floor(budget / (12 + 6 + wild.laterBytes() / V + 24 + 200)));
  assert.ok(lowered < 0.8 * target, `${lowered} of ${target}`);
});
