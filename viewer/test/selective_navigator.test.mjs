// The selective navigator (selective_navigator.js) on real crash boxes built by the CLI: random
// sequences of requests (a level elsewhere and random wanted splits, closed under their
// dependencies) in both directions; after each, the mesh is valid as validate.cpp checks and its
// boundary loops, parts and components are the original's. A prefix gives the level navigator's
// faces exactly.
import assert from 'node:assert/strict';
import { test } from 'node:test';

import { Navigator, ShownValues } from '../src/dpm.js';
import { applySplits, DirtyFaces } from '../src/dpm/progressive_mesh.js';
import { SelectiveNavigator } from '../src/dpm/selective_navigator.js';
import { SelectiveShownValues } from '../src/dpm/selective_values.js';
import { SplitDependencies } from '../src/dpm/split_dependencies.js';
import { assertLikeOriginal, checkNavigator, random } from './mesh_checks.mjs';
import { crashbox, CRASHBOXES } from './selective_fixture.mjs';

// Every active split's dependencies are active.
function assertClosed(nav, what) {
  for (let i = 0; i < nav.top; i++)
    if (nav.active[i]) for (const j of nav.dependencies.of(i)) assert.equal(nav.active[j], 1, `${what}: split ${i} needs ${j}`);
}

// The splits of `wanted` applied from scratch in ascending order: before each, `check(i,
// corners)`. Returns the faces (4 slots each) of the active ones, undone triangles left out.
function ascending(mesh, wanted, check = () => {}) {
  const corners = new Int32Array(4 * mesh.head.faceCount).fill(-1);
  corners.set(mesh.baseCorners);
  const dirty = new DirtyFaces(mesh.head.faceCount);
  for (let i = 0; i < mesh.splitsLoaded; i++)
    if (wanted[i]) check(i, corners), applySplits(mesh, i, i + 1, corners, dirty), dirty.clear();
  return corners;
}

// Per split, R(i) as the full sequence has it right before i: [face, its 4 slots] of every face
// that holds the parent, found by scanning every face, and of the faces it re-creates.
function readFaces(mesh) {
  const nav = new Navigator(mesh);
  const out = [];
  for (let i = 0; i < mesh.splitsLoaded; i++) {
    const v1 = mesh.parent[i], k = nav.corners, faces = [];
    for (let f = 0; f < nav.faceCount; f++)
      if (k[4 * f] === v1 || k[4 * f + 1] === v1 || k[4 * f + 2] === v1 || k[4 * f + 3] === v1) faces.push([f, Array.from(k.subarray(4 * f, 4 * f + 4))]);
    out.push(faces);
    nav.refine(i + 1);
  }
  return out;
}

// Active faces only: the selective navigator's corners against ascending()'s.
function assertSameActiveFaces(nav, corners, what) {
  for (let f = 0; f < nav.faceCount; f++)
    if (nav.faceActive(f)) assert.deepEqual(nav.face(f), Array.from(corners.subarray(4 * f, 4 * f + nav.degree(f))), `${what}: face ${f}`);
}

for (const name of CRASHBOXES) {
  const mesh = crashbox(name);
  const deps = new SplitDependencies(mesh).update();
  const S = mesh.splitsLoaded;
  const full = new SelectiveNavigator(mesh, deps);
  full.setTarget(full.wanted(S), S);
  const original = checkNavigator(full);

  test(`${name}: the original is valid; prefixes give the level navigator's faces`, () => {
    assert.deepEqual(original.problems, []);
    assert.ok(original.boundaryLoops >= 2 && original.components >= 1, JSON.stringify(original));
    const nav = new SelectiveNavigator(mesh, deps);
    const levels = new Navigator(mesh);
    for (const k of [S, 0, Math.floor(S / 3), Math.floor(S / 2), 7]) {
      nav.setTarget(nav.wanted(k), k);
      levels.setLevel(k);
      assert.equal(nav.vertexCount, levels.vertexCount);
      assert.equal(nav.activeVertexCount, levels.vertexCount);
      assert.equal(nav.faceCount, levels.faceCount);
      assert.equal(nav.activeFaceCount, levels.faceCount);
      assert.equal(nav.quadCount, levels.quadCount);
      assert.deepEqual(nav.corners.subarray(0, 4 * nav.faceCount), levels.corners.subarray(0, 4 * levels.faceCount), `level ${k}`);
      assertLikeOriginal(nav, original, `level ${k}`);
    }
  });

  test(`${name}: random requests in both directions keep the mesh valid`, () => {
    const rand = random(22);
    const nav = new SelectiveNavigator(mesh, deps);
    let applied = 0, undone = 0;
    for (let round = 0; round < 40; round++) {
      // A level elsewhere (often coarse) and a few random splits with their dependencies; now
      // and then a neighbourhood: the splits of a run of vertices (a region in stream order).
      const level = Math.floor(S * rand() ** 3);
      const targets = [];
      for (let k = Math.floor(20 * rand()); k > 0; k--) targets.push(Math.floor(S * rand()));
      if (rand() < 0.5) {
        const from = Math.floor(S * rand());
        for (let i = from; i < Math.min(S, from + 300); i++) targets.push(i);
      }
      const wanted = nav.wanted(level, targets);
      const before = nav.activeCount;
      const moved = nav.setTarget(wanted, level);
      applied += moved.applied, undone += moved.undone;
      const what = `round ${round}: level ${level}, ${targets.length} targets, ${nav.activeVertexCount} vertices`;
      assert.equal(nav.activeCount, before + moved.applied - moved.undone, what);
      for (let i = 0; i < S; i++) assert.equal(nav.active[i], wanted[i], `${what}: split ${i}`);
      for (const i of targets) assert.equal(nav.active[i], 1, what);
      assertClosed(nav, what);
      assertSameActiveFaces(nav, ascending(mesh, wanted), what);
      assertLikeOriginal(nav, original, what);
    }
    assert.ok(applied > 1000 && undone > 1000, `applied ${applied}, undone ${undone}`);
    // Back to the full mesh and to the base: the original's faces, the base's.
    nav.setTarget(nav.wanted(S), S);
    assert.deepEqual(nav.corners, full.corners);
    nav.setTarget(nav.wanted(0), 0);
    const base = new Navigator(mesh);
    assert.deepEqual(nav.corners.subarray(0, 4 * mesh.head.baseFaceCount), base.corners.subarray(0, 4 * mesh.head.baseFaceCount));
    assert.equal(nav.activeFaceCount, mesh.head.baseFaceCount);
  });

  // The fan rule's claim; under the face creators (the default) a face is as its applied writers
  // make it, and the test above checks those sets through validity.
  test(`${name}, fan rule: a closed set applied in ascending order gives each split the faces it read in the full sequence`, () => {
    const reads = readFaces(mesh);
    const rand = random(7);
    const nav = new SelectiveNavigator(mesh, new SplitDependencies(mesh, { rule: 'fan' }).update());
    let checked = 0;
    for (let round = 0; round < 6; round++) {
      const targets = Array.from({ length: 1 + round * round }, () => Math.floor(S * rand()));
      const wanted = nav.wanted(Math.floor(S * rand() ** 4), targets);
      ascending(mesh, wanted, (i, corners) => {
        for (const [f, slots] of reads[i]) {
          assert.ok(nav.dependencies.faceSplit[f] < 0 || wanted[nav.dependencies.faceSplit[f]], `round ${round}, split ${i}: face ${f} exists`);
          assert.deepEqual(Array.from(corners.subarray(4 * f, 4 * f + 4)), slots, `round ${round}, split ${i}: face ${f}`);
          checked++;
        }
      });
    }
    assert.ok(checked > 1000, `${checked} faces checked`);
  });
}

test('shown field values: a prefix shows the level\'s, any set keeps the peak (crashbox-fields PEEQ)', () => {
  const mesh = crashbox('crashbox-fields');
  const deps = new SplitDependencies(mesh).update();
  const S = mesh.splitsLoaded;
  const field = mesh.fields.find((f) => f.name === 'PEEQ');
  const nav = new SelectiveNavigator(mesh, deps);
  const rand = random(3);
  for (const aggregate of ['max', 'mean']) {
    const level = new ShownValues(mesh, field, aggregate);
    const selective = new SelectiveShownValues(mesh, field, aggregate, nav);
    for (const [t, k] of [[14, 0], [14, 300], [7, 2000], [14, S]]) {
      nav.setTarget(nav.wanted(k), k);
      level.set(t, k);
      selective.set(t, k);
      const n = mesh.head.baseVertexCount + k;
      assert.deepEqual(selective.values.subarray(0, n), level.values.subarray(0, n), `${aggregate}, step ${t}, level ${k}`);
      assert.equal(selective.peak(), level.peak());
    }
  }
  const shown = new SelectiveShownValues(mesh, field, 'max', nav);
  for (let round = 0; round < 5; round++) {
    const targets = Array.from({ length: 30 }, () => Math.floor(S * rand()));
    nav.setTarget(nav.wanted(Math.floor(S * rand() ** 3), targets));
    const t = Math.floor(rand() * mesh.head.stepCount);
    shown.set(t, nav.level);
    const raw = field.valuesAt(t, mesh.head.vertexCount);
    const top = raw.reduce((a, x) => Math.max(a, Math.abs(x)), 0);
    assert.equal(Math.abs(shown.values[shown.peak()]), top, `round ${round}: the peak is shown`);
    for (let v = 0; v < nav.vertexCount; v++) if (nav.exists(v)) assert.ok(Math.abs(shown.values[v]) >= Math.abs(raw[v]), `round ${round}: vertex ${v}`);
  }
});
