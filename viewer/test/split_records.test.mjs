// The browser's split-record decoder (src/dpm/split_records.js) on the sections the C++ encoder
// wrote for the sample (tests/split_records_dump.cpp, run by ctest before this): every array
// comes back exactly as the C++ side has it, and damaged sections get the C++ decoder's messages.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { test } from 'node:test';

import { ProgressiveMesh } from '../src/dpm/progressive_mesh.js';
import {
  decodeSplitRecords,
  errorCodeAtLeast,
  errorOfCode,
  errorReference,
  FreeIndices,
  RecordModels,
} from '../src/dpm/split_records.js';

const path = process.env.DYNPM_SPLIT_RECORDS;
const dump = path ? JSON.parse(readFileSync(path, 'utf8')) : null;

function bytesOf(base64) {
  return new Uint8Array(Buffer.from(base64, 'base64'));
}

// The mesh as a reader has it after BASE: HEAD's counts, the base faces and attributes.
function baseMesh(d) {
  const head = {
    vertexCount: d.vertexCount, faceCount: d.faceCount, baseVertexCount: d.baseVertexCount,
    baseFaceCount: d.baseFaceCount, splitCount: d.splitCount, stepCount: 1, baseError: d.baseError,
  };
  const mesh = new ProgressiveMesh(head);
  for (let v = 0; v < d.baseVertexCount; v++) {
    mesh.vertexOriginal[v] = d.vertexOriginal[v];
    mesh.nodeId[v] = d.nodeId[v];
  }
  for (let f = 0; f < d.baseFaceCount; f++) {
    mesh.faceOriginal[f] = d.faceOriginal[f];
    mesh.partId[f] = d.partId[f];
    mesh.elementId[f] = d.elementId[f];
  }
  mesh.faceCountAt[0] = d.baseFaceCount;
  const corners = new Int32Array(4 * d.faceCount).fill(-1);
  corners.set(d.baseCorners);
  return { mesh, models: new RecordModels(mesh, corners) };
}

function decodeAll(d, chunks) {
  const { mesh, models } = baseMesh(d);
  for (const c of chunks) {
    const problem = decodeSplitRecords(c.records, c.attributes, c.first, c.count, mesh, models);
    if (problem) return { problem };
  }
  return { mesh };
}

const sections = dump?.chunks.map((c) => ({
  first: c.first, count: c.count, records: bytesOf(c.records), attributes: bytesOf(c.attributes),
}));

// The free original indices against a list of flags (C++: SplitRecords.FreeIndices…): ranks both
// ways after takes spread over the set, on sizes that end inside a word and on its edge.
test('free indices answer as a list of flags', () => {
  let seed = 7;
  const random = (n) => (seed = (seed * 1103515245 + 12345) % 2147483648) % n;
  for (const n of [1, 31, 32, 33, 64, 1000, 4097, 70001]) {
    const set = new FreeIndices(n), free = new Uint8Array(n).fill(1);
    const check = () => {
      let below = 0;
      for (let v = 0; v <= n; v++) {
        assert.equal(set.below(v), below, `n ${n}: below(${v})`);
        if (v === n) break;
        assert.equal(set.isFree(v), free[v] === 1, `n ${n}: isFree(${v})`);
        if (free[v]) assert.equal(set.nth(below++), v, `n ${n}: nth`);
      }
      assert.equal(set.count, below);
      assert.equal(set.isFree(n), false);
    };
    check();
    for (let k = 0; k < Math.min(n, 2000); k++) {
      const v = set.nth(random(set.count));
      set.take(v);
      free[v] = 0;
      if (k % 300 === 0) check();
    }
    check();
  }
});

test('the error grid: powers of two and 16 steps per octave, exact', () => {
  assert.equal(errorReference(3), 4);
  assert.equal(errorReference(4), 4);
  assert.equal(errorReference(0), 1);
  assert.equal(errorOfCode(0, 4), 0);
  assert.equal(errorOfCode(641, 4), 4);
  assert.equal(errorOfCode(641 - 16, 4), 2);
  assert.equal(errorOfCode(641 - 8, 4), 3);
  assert.equal(errorCodeAtLeast(3, 4), 633);
  assert.equal(errorCodeAtLeast(2.9, 4), 633);
  assert.equal(errorCodeAtLeast(1e-30, 4), 1);
});

test('every array decodes as the C++ decoder has it', { skip: !dump && 'DYNPM_SPLIT_RECORDS is not set (ctest sets it)' }, () => {
  const { mesh, problem } = decodeAll(dump, sections);
  assert.equal(problem, undefined);
  const S = dump.splitCount;
  assert.deepEqual(Array.from(mesh.parent.subarray(0, S)), dump.parent);
  assert.deepEqual(Array.from(mesh.error.subarray(0, S)), dump.error);
  assert.deepEqual(Array.from(mesh.wingStart), dump.wingStart);
  assert.deepEqual(Array.from(mesh.wingFace.data.subarray(0, mesh.wingFace.length)), dump.wingFace);
  assert.deepEqual(Array.from(mesh.wingVertex.data.subarray(0, mesh.wingVertex.length)), dump.wingVertex);
  assert.deepEqual(Array.from(mesh.wingFlags.data.subarray(0, mesh.wingFlags.length)), dump.wingFlags);
  assert.deepEqual(Array.from(mesh.movedStart), dump.movedStart);
  assert.deepEqual(Array.from(mesh.movedFaces.data.subarray(0, mesh.movedFaces.length)), dump.movedFaces);
  assert.deepEqual(Array.from(mesh.vertexOriginal), dump.vertexOriginal);
  assert.deepEqual(Array.from(mesh.nodeId), dump.nodeId);
  assert.deepEqual(Array.from(mesh.faceOriginal), dump.faceOriginal);
  assert.deepEqual(Array.from(mesh.partId), dump.partId);
  assert.deepEqual(Array.from(mesh.elementId), dump.elementId);
  assert.equal(mesh.faceCountAt[S], dump.faceCount);
});

test('damaged sections get the C++ decoder\'s messages', { skip: !dump && 'DYNPM_SPLIT_RECORDS is not set' }, () => {
  const damaged = (change) => {
    const copy = sections.map((s) => ({ ...s }));
    change(copy);
    return decodeAll(dump, copy).problem;
  };
  assert.equal(damaged((s) => (s[0].records = s[0].records.subarray(0, s[0].records.length - 1))),
    'the split records section is cut short or damaged');
  assert.equal(damaged((s) => (s[1].attributes = s[1].attributes.subarray(0, s[1].attributes.length >> 1))),
    'the split attributes section is cut short or damaged');
  assert.equal(damaged((s) => (s[0].records = Uint8Array.of(...s[0].records, 0))),
    'bytes left over after the split records');
  assert.equal(damaged((s) => (s[0].attributes = Uint8Array.of(...s[0].attributes, 0))),
    'bytes left over after the split attributes');
  assert.equal(damaged((s) => s.pop()), undefined);
  let refused = 0;
  for (let k = 0; k < sections[0].records.length; k++) {
    const problem = damaged((s) => {
      s[0].records = s[0].records.slice();
      s[0].records[k] ^= 0x5a;
    });
    if (problem) refused++;
  }
  assert.ok(refused > sections[0].records.length * 0.9, `${refused} of ${sections[0].records.length}`);
});
