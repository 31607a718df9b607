// The split dependencies (split_dependencies.js) on real crash boxes built by the CLI: derived
// as the file arrives they equal those derived at once, each points to an earlier split, and
// under both rules (face creators, the default, and the fan) they equal a brute-force derivation
// that scans every face for the parent's fan.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { test } from 'node:test';

import { DpmDecoder, Navigator, WING_WAS_TRIANGLE } from '../src/dpm.js';
import { SPLIT_RULES, SplitDependencies } from '../src/dpm/split_dependencies.js';
import { crashbox, crashboxDpm, CRASHBOXES } from './selective_fixture.mjs';

// v1's fan right before the split the navigator is at: every face holding it, by a scan.
function fanOf(nav, v1) {
  const k = nav.corners, fan = [];
  for (let f = 0; f < nav.faceCount; f++)
    if (k[4 * f] === v1 || k[4 * f + 1] === v1 || k[4 * f + 2] === v1 || k[4 * f + 3] === v1) fan.push(f);
  return fan;
}

// The face creators' rule (docs/selective.md "Face creators", narrowed in "Narrower: what a
// wing reads"), the slow way: creators and quad-makers in maps, the fan and the quad wings'
// side faces found by scanning every face.
function bruteForceFaceCreators(mesh) {
  const nav = new Navigator(mesh);
  const b = mesh.head.baseVertexCount;
  const createdBy = new Map(), quadBy = new Map();
  const out = [];
  for (let i = 0; i < mesh.splitsLoaded; i++) {
    const v1 = mesh.parent[i];
    const deps = new Set();
    const needFace = (f) => [createdBy.get(f), quadBy.get(f)].forEach((s) => s !== undefined && deps.add(s));
    if (v1 >= b) deps.add(v1 - b);
    for (let j = mesh.movedStart[i]; j < mesh.movedStart[i + 1]; j++) needFace(mesh.movedFaces.data[j]);
    const fan = fanOf(nav, v1);
    for (let j = mesh.wingStart[i]; j < mesh.wingStart[i + 1]; j++) {
      const w = mesh.wingVertex.data[j], f = mesh.wingFace.data[j];
      const triangle = mesh.wingFlags.data[j] & WING_WAS_TRIANGLE;
      if (triangle) {
        if (w >= b) deps.add(w - b);
        continue;
      }
      needFace(f);
      const ends = nav.face(f).filter((e) => e !== v1);
      for (const g of fan) if (ends.some((e) => nav.face(g).includes(e)) && createdBy.has(g)) deps.add(createdBy.get(g));
    }
    const created = nav.faceCount;
    for (let j = mesh.wingStart[i]; j < mesh.wingStart[i + 1]; j++)
      if (!(mesh.wingFlags.data[j] & WING_WAS_TRIANGLE)) quadBy.set(mesh.wingFace.data[j], i);
    nav.refine(i + 1);
    for (let f = created; f < nav.faceCount; f++) createdBy.set(f, i);
    out.push([...deps].sort((x, y) => x - y));
  }
  return out;
}

// The fan rule (docs/viewer.md "Selective refinement"), the slow way: v1's fan found by
// scanning every face before each split, per-face writer and reader lists in plain arrays.
function bruteForceFan(mesh) {
  const nav = new Navigator(mesh);
  const b = mesh.head.baseVertexCount;
  const lastWriter = new Map(), readers = new Map();
  const out = [];
  for (let i = 0; i < mesh.splitsLoaded; i++) {
    const v1 = mesh.parent[i];
    const written = [];
    for (let j = mesh.movedStart[i]; j < mesh.movedStart[i + 1]; j++) written.push(mesh.movedFaces.data[j]);
    for (let j = mesh.wingStart[i]; j < mesh.wingStart[i + 1]; j++) written.push(mesh.wingFace.data[j]);
    const read = new Set([...written, ...fanOf(nav, v1)]);
    const deps = new Set();
    if (v1 >= b) deps.add(v1 - b);
    for (const f of read) if (lastWriter.has(f)) deps.add(lastWriter.get(f));
    for (const f of written) for (const r of readers.get(f) ?? []) deps.add(r);
    for (const f of read) if (!written.includes(f)) readers.set(f, [...(readers.get(f) ?? []), i]);
    for (const f of written) lastWriter.set(f, i), readers.set(f, []);
    out.push([...deps].sort((x, y) => x - y));
    nav.refine(i + 1);
  }
  return out;
}

const BRUTE_FORCE = { faceCreators: bruteForceFaceCreators, fan: bruteForceFan };

test('the face creators are the default rule; an unknown rule is an error', () => {
  assert.equal(SPLIT_RULES[0], 'faceCreators');
  const mesh = crashbox(CRASHBOXES[0]);
  assert.equal(new SplitDependencies(mesh).rule, 'faceCreators');
  assert.throws(() => new SplitDependencies(mesh, { rule: 'wing' }), /unknown split dependency rule 'wing'/);
});

for (const name of CRASHBOXES) for (const rule of SPLIT_RULES) {
  test(`${name}, ${rule}: every dependency is an earlier split, and they are the brute-force ones`, () => {
    const mesh = crashbox(name);
    assert.ok(mesh.complete && mesh.splitsLoaded > 1000, `${name}: ${mesh.splitsLoaded} splits`);
    const deps = new SplitDependencies(mesh, { rule }).update();
    const b = mesh.head.baseVertexCount;
    const expected = BRUTE_FORCE[rule](mesh);
    let moved = 0;
    for (let i = 0; i < mesh.splitsLoaded; i++) {
      const d = Array.from(deps.of(i));
      for (let k = 0; k < d.length; k++) {
        assert.ok(d[k] < i, `${name}: split ${i} depends on ${d[k]}`);
        if (k) assert.ok(d[k] > d[k - 1], `${name}: split ${i}: ascending, each once`);
      }
      if (mesh.parent[i] >= b) assert.ok(d.includes(mesh.parent[i] - b), `${name}: split ${i} needs its parent's split`);
      assert.deepEqual(d, expected[i], `${name}: split ${i}`);
      moved += mesh.movedStart[i + 1] - mesh.movedStart[i];
    }
    const s = deps.stats();
    assert.ok(s.mean > 1 && s.max >= s.mean, JSON.stringify(s));
    console.log(`${name}, ${rule}: ${JSON.stringify(s)}`);
    assert.ok(moved > 0, 'the crash box has moved faces');
    // Fully derived, the replay's faces are the fully refined mesh's.
    const nav = new Navigator(mesh);
    nav.setLevel(mesh.splitsLoaded);
    for (let f = 0; f < mesh.head.faceCount; f++)
      assert.deepEqual(Array.from(deps.corners.subarray(4 * f, 4 * f + nav.degree(f))), nav.face(f), `face ${f}`);
  });

  test(`${name}, ${rule}: derived while the file arrives, the same as derived at once`, () => {
    const path = crashboxDpm(name);
    const bytes = new Uint8Array(readFileSync(path));
    let deps = null, updates = 0;
    const decoder = new DpmDecoder({
      name: path,
      onBase: (mesh) => (deps = new SplitDependencies(mesh, { rule })),
      onSplits: () => (deps.update(), updates++),
    });
    for (let at = 0; at < bytes.length; at += 4096) decoder.push(bytes.subarray(at, at + 4096));
    assert.ok(decoder.complete && updates > 1, `${updates} updates`);
    const once = new SplitDependencies(crashbox(name), { rule }).update();
    assert.equal(deps.derived, once.derived);
    assert.deepEqual(deps.depStart, once.depStart);
    assert.deepEqual(deps.deps.data.subarray(0, deps.count), once.deps.data.subarray(0, once.count));
  });
}
