// mesh_pieces.js, the way the decode worker's mesh reaches the page (docs/viewer.md "Decoding in
// a worker"), on the sample with a node and an element field added (fields_fixture.mjs), fed in
// pieces as from a network: the page's mesh — copied run by run, or shared — must equal the
// decoder's in every array the page reads, and navigate to the same faces.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { test } from 'node:test';

import { DpmDecoder, Navigator, ProgressiveMesh } from '../src/dpm.js';
import { withRoom } from '../src/dpm/bytes.js';
import { addFields, applyPieces, fieldDefs, growableTails, levelPieces, regrownSteps, shareFields, shareMesh, sharedMesh } from '../src/mesh_pieces.js';
import { DEMO_FIELDS, withFields } from './fields_fixture.mjs';

const { DYNPM_DPM: dpm } = process.env;
if (!dpm) throw new Error('mesh_pieces.test.mjs needs DYNPM_DPM');
const file = withFields(new Uint8Array(readFileSync(dpm)), DEMO_FIELDS);

// Decodes `file` in pieces of 5,000 bytes; `mirror` gets the messages the worker would post
// (structuredClone stands for postMessage: shared buffers stay shared, others are copied).
function decodeMirrored(shared, slice) {
  const page = {};
  const sent = {}, sentSteps = {};
  const post = (m) => {
    m = structuredClone(m);
    if (m.type === 'head') page.mesh = m.shared ? sharedMesh(m.shared) : new ProgressiveMesh(m.head);
    if (m.type === 'base') addFields(page.mesh, m.fields, m.faceHeir), applyPieces(page.mesh, m.pieces), (page.mesh.hasBase = true);
    if (m.type === 'splits') applyPieces(page.mesh, m.pieces), (page.mesh.splitsLoaded = m.first + m.count);
    page.messages = (page.messages ?? 0) + 1;
    page.regrown = (page.regrown ?? 0) + (m.pieces ?? []).filter(([path, first]) => path === 'positions.steps' && first === null).length;
  };
  // Room for the base only at first, as for ?vertices=1: the arrays of every step grow.
  const decoder = new DpmDecoder({
    vertices: 1,
    onHead: (mesh) => post({ type: 'head', head: mesh.head, shared: shared ? shareMesh(mesh) : null }),
    onBase: (mesh) => {
      if (shared) {
        const fields = shareFields(mesh);
        post({ type: 'base', fields, faceHeir: mesh.faceHeir, pieces: [['baseDegree', 0, mesh.baseDegree], ['baseCorners', 0, mesh.baseCorners], ...growableTails(mesh, sent), ...regrownSteps(mesh, sentSteps)] });
      } else {
        post({ type: 'base', fields: fieldDefs(mesh), pieces: levelPieces(mesh, 0, 0).pieces });
      }
    },
    onSplits: (mesh, s, n) => {
      if (shared) return post({ type: 'splits', first: s, count: n, pieces: [...growableTails(mesh, sent), ...regrownSteps(mesh, sentSteps)] });
      for (let first = s; first < s + n; first += slice)
        post({ type: 'splits', first, count: Math.min(slice, s + n - first), pieces: levelPieces(mesh, first, Math.min(slice, s + n - first)).pieces });
    },
  });
  for (let at = 0; at < file.length; at += 5000) decoder.push(file.subarray(at, at + 5000));
  assert.ok(decoder.complete);
  return { mesh: decoder.mesh, page: page.mesh, messages: page.messages, regrown: page.regrown };
}

// Every array the page reads, by name, as plain arrays (a Growable up to its length).
function arrays(mesh) {
  const out = {};
  const add = (name, a) => (out[name] = Array.from(a));
  for (const [key, value] of Object.entries(mesh)) {
    if (ArrayBuffer.isView(value)) add(key, value);
    else if (value?.data && 'length' in value) add(key, value.data.subarray(0, value.length));
  }
  // Positions as the page reads them: every step of the loaded vertices, and what is stored.
  const n = mesh.vertexCountLoaded;
  for (let t = 0; t < mesh.head.stepCount; t++) add(`positions${t}`, mesh.positionsAt(t, n, new Float32Array(3 * n)));
  // Packed steps as their second differences: a copied page packs them in runs of its own.
  mesh.positions.steps.forEach((a, t) => add(`steps${t}`, mesh.positions.dir[t] ? mesh.positions.differences(t, 0, 3 * n) : a.subarray(0, 3 * n)));
  // (A packed step's escapes depend on its blocks, which a copied page cuts where its pieces do.)
  mesh.positions.wide.forEach((a, t) => mesh.positions.dir[t] || add(`wide${t}`, a.subarray(0, 1 + 2 * a[0])));
  mesh.fields.forEach((f, k) => {
    f.q.forEach((a, t) => add(`field${k}.q${t}`, a));
    add(`field${k}.error`, f.error);
  });
  return out;
}

for (const shared of [false, true]) {
  test(`the page's mesh equals the decoder's (${shared ? 'shared' : 'copied in runs of 300 splits'})`, () => {
    const { mesh, page, messages, regrown } = decodeMirrored(shared, 300);
    // Shared: the positions made anew at the base and again as splits came (else copied in).
    assert.ok(shared ? regrown >= 3 : regrown === 0, `positions made anew ${regrown} times`);
    assert.ok(mesh.fields.length === 2 && mesh.head.splitCount > 1000, 'a model with fields and splits');
    assert.ok(messages > 5, `${messages} messages`);
    assert.equal(page.splitsLoaded, mesh.splitsLoaded);
    const a = arrays(mesh), b = arrays(page);
    assert.deepEqual(Object.keys(b).sort(), Object.keys(a).sort());
    for (const name of Object.keys(a)) assert.deepEqual(b[name], a[name], name);
    if (shared) {
      // One memory: what the page's array holds is what the decoder's holds.
      const x = mesh.positions.steps[2][5];
      page.positions.steps[2][5] = x + 1;
      assert.equal(mesh.positions.steps[2][5], x + 1, 'positions are shared');
      page.positions.steps[2][5] = x;
    }
    // The page's mesh navigates: the faces at the full level and half-way are the decoder's.
    for (const level of [mesh.head.splitCount, mesh.head.splitCount >> 1]) {
      const x = new Navigator(mesh), y = new Navigator(page);
      x.setLevel(level), y.setLevel(level);
      assert.deepEqual(Array.from(y.corners), Array.from(x.corners), `faces at level ${level}`);
    }
  });
}

// A reader that means to load n vertices (a page's budget or ?vertices=N) takes room at BASE for
// n and a margin (DpmDecoder.takeRoom(): a quarter of n, at most 16,384), so the chunk that
// crosses n is decoded into the arrays taken then, not into new ones (which held the old and
// the new arrays of every step at once); past the margin that chunk gets room for all of it.
test('the chunk that crosses the vertices a reader means to load fits the room taken at BASE', () => {
  const ends = [];  // the vertices loaded after each SPLT
  const all = new DpmDecoder({ onSplits: (mesh) => ends.push(mesh.vertexCountLoaded) });
  all.push(file);
  assert.ok(all.complete && ends.length >= 3, `${ends.length} SPLTs`);
  const load = (vertices) => {
    const seen = {};
    const decoder = new DpmDecoder({
      vertices,
      onBase: (mesh) => (seen.base = { positions: mesh.positions.steps[0], field: mesh.fields[0].q[0] }),
      onSplits: (mesh) => (seen[mesh.vertexCountLoaded] = { positions: mesh.positions.steps[0], field: mesh.fields[0].q[0] }),
    });
    decoder.push(file);
    return seen;
  };
  const margin = (n) => Math.min(16384, Math.ceil(n / 4));
  // A target whose crossing chunk ends within the margin, and one whose does not.
  const k = ends.findIndex((end, i) => i > 0 && end - ends[i - 1] > 8);
  const [before, end] = [ends[k - 1], ends[k]];
  const fits = Math.max(before + 1, Math.ceil((4 * end) / 5));  // n + n / 4 ≥ end
  const seen = load(fits);
  assert.ok(fits + margin(fits) >= end && fits < end);
  assert.equal(seen[end].positions, seen.base.positions, `room for ${fits} + ${margin(fits)} holds the chunk to ${end}`);
  assert.equal(seen[end].field, seen.base.field, 'and the field values');
  assert.equal(seen.base.positions.length, 3 * (fits + margin(fits)));
  const short = before + 1;  // its margin ends before the chunk does
  assert.ok(short + margin(short) < end, `${short} + ${margin(short)} < ${end}`);
  const other = load(short);
  assert.notEqual(other[end].positions, other.base.positions);
  assert.equal(other[end].positions.length, 3 * end, 'room for all of the crossing chunk, not doubled');
});

// Arrays that grow as levels arrive (dpm/bytes.js withRoom): the same array while it has room,
// else a copy with twice the room (never past the most), new elements filled, shared when the
// array was.
test('withRoom keeps what was written and fills the new room', () => {
  const a = Int32Array.of(7, 8);
  assert.equal(withRoom(a, 2, 100), a);
  const b = withRoom(a, 3, 100, -1);
  assert.deepEqual(Array.from(b), [7, 8, -1, -1]);
  assert.deepEqual(Array.from(withRoom(b, 9, 6)), [7, 8, -1, -1, 0, 0]);
  const c = withRoom(new Float64Array(new SharedArrayBuffer(8)), 2, 4);
  assert.ok(c.buffer instanceof SharedArrayBuffer);
  assert.equal(c.length, 2);
});
