// A split-record encoder for tests that write .dpm files by hand (docs/FORMAT.md "Split records",
// "Split attributes"): src/dpm/split_records.js's decoder turned around, coding with the
// decoder's own models and mesh, so that a test's sections start where a reader's do.
import {
  applyToModels,
  errorCodeAtLeast,
  MovedFan,
  orientationGuess,
  quadWingCandidates,
  slotOf,
  triangleWingCandidates,
} from '../src/dpm/split_records.js';
import { WING_SLOT_SHIFT, WING_V1_FOLLOWS_V0, WING_WAS_TRIANGLE } from '../src/dpm/progressive_mesh.js';
import { encodeSigned, encodeUnsigned, RangeEncoder } from './range_encoder.mjs';

function encodeRecord(e, st, mesh, i, split) {
  const v0 = mesh.head.baseVertexCount + i, v1 = split.parent;
  const c = st.corners;
  const code = errorCodeAtLeast(split.error, st.errorReference);
  if (code > st.errorCode) throw new Error(`split ${i}: the error increases`);
  encodeUnsigned(e, st.errorStep, st.errorCode - code);
  const sameError = code === st.errorCode;
  st.errorCode = code;
  if (sameError && st.lastParent >= 0) encodeSigned(e, st.parentStep, v1 - st.lastParent);
  else encodeUnsigned(e, st.parent, v0 - 1 - v1);
  st.lastParent = v1;
  mesh.parent[i] = v1;
  const fan = st.vertexFaces.of(v1);
  const moved = [];
  const fanMoved = new MovedFan();
  for (const f of fan) {
    let beside = false;
    for (let k = 0; k < 4; k++) {
      const v = c[4 * f + k];
      if (v >= 0 && v !== v1 && fanMoved.hasCorner(v)) beside = true;
    }
    const ctx = (c[4 * f + 3] < 0 ? 6 : 0) + (beside ? 3 : 0) + Math.min(moved.length, 2);
    const isMoved = split.moved.includes(f) ? 1 : 0;
    e.bit(st.moved, ctx, isMoved);
    if (!isMoved) continue;
    moved.push(f);
    fanMoved.add(c, f, v1);
  }
  const movedSet = new Set(moved);
  if (moved.length !== split.moved.length) throw new Error(`split ${i}: a moved face is not v1's`);
  mesh.movedStart[i] = mesh.movedFaces.length;
  moved.forEach((f) => mesh.movedFaces.push(f));
  mesh.movedStart[i + 1] = mesh.movedFaces.length;

  const wings = split.wings;
  encodeUnsigned(e, st.wingCount, wings.length);
  const faces = [];
  let created = 0;
  wings.forEach((w, k) => {
    const triangle = w.flags & WING_WAS_TRIANGLE ? 1 : 0;
    const slot = w.flags >> WING_SLOT_SHIFT;
    const v1Follows = w.flags & WING_V1_FOLLOWS_V0 ? 1 : 0;
    const { triangles, kind } = quadWingCandidates(st, fan, v1, movedSet, fanMoved, faces);
    e.bit(st.wasTriangle, 16 * kind + 4 * (wings.length - 1) + k, triangle);
    if (!triangle) {
      const index = triangles.indexOf(w.face);
      if (index < 0) throw new Error(`split ${i}: a quad wing is not a free triangle of v1`);
      encodeUnsigned(e, st.quadFace, index);
      const a = slotOf(c, w.face, v1);
      const after = c[4 * w.face + ((a + 1) % 3)], before = c[4 * w.face + ((a + 2) % 3)];
      const guessBefore = fanMoved.hasCorner(before) && !fanMoved.hasCorner(after) ? 1 : 0;
      e.bit(st.quad, 0, (w.vertex === before ? 1 : 0) ^ guessBefore);
      const b = slotOf(c, w.face, w.vertex);
      if (Math.min(a, b) === 0 && Math.max(a, b) === 2) e.bit(st.quad, 1, slot === 3 ? 1 : 0);
      e.bit(st.quad, 2, v1Follows ^ ((b + 1) % 3 === a ? 1 : 0));
      faces.push(w.face), fanMoved.used.push(w.vertex);
      return;
    }
    const near = triangleWingCandidates(st, v1, fanMoved);
    const index = near.indexOf(w.vertex);
    encodeUnsigned(e, st.neighbour, index < 0 ? near.length : index);
    if (index < 0) encodeUnsigned(e, st.farVertex, v0 - 1 - w.vertex);
    const guess = orientationGuess(st, v1, w.vertex, movedSet);
    e.bit(st.triFollows, guess !== 0 ? 1 : 0, v1Follows ^ (guess === 2 ? 1 : 0));
    e.bit(st.triSlot, 0, slot !== 0 ? 1 : 0);
    if (slot) e.bit(st.triSlot, 1, slot === 2 ? 1 : 0);
    faces.push(st.faceCount + created++), fanMoved.used.push(w.vertex);
  });
  mesh.wingStart[i] = mesh.wingFlags.length;
  wings.forEach((w, k) => {
    mesh.wingFlags.push(w.flags), mesh.wingVertex.push(w.vertex), mesh.wingFace.push(faces[k]);
  });
  mesh.wingStart[i + 1] = mesh.wingFlags.length;

  mesh.faceCountAt[i + 1] = st.faceCount + created;
}

function encodeAttributes(e, st, mesh, i, split) {
  const v0 = mesh.head.baseVertexCount + i, v1 = mesh.parent[i];
  const free = st.freeVertices;
  const indexGuess = mesh.vertexOriginal[v1];
  const index = split.vertexOriginal;
  encodeSigned(e, st.vertexIndex, free.below(index) - free.below(indexGuess));
  free.take(index);
  encodeSigned(e, st.nodeId, split.nodeId - mesh.nodeId[v1] - (index - indexGuess));
  mesh.vertexOriginal[v0] = index;
  mesh.nodeId[v0] = split.nodeId;

  const firstCreated = mesh.faceCountAt[i];
  let like = -1;
  for (let k = mesh.wingStart[i]; k < mesh.wingStart[i + 1] && like < 0; k++)
    if (!(mesh.wingFlags.data[k] & WING_WAS_TRIANGLE)) like = mesh.wingFace.data[k];
  if (like < 0 && mesh.movedStart[i + 1] > mesh.movedStart[i])
    like = mesh.movedFaces.data[mesh.movedStart[i]];
  const fan = st.vertexFaces.of(v1);
  if (like < 0 && fan.length > 0 && fan[0] < firstCreated) like = fan[0];
  const partGuess = like < 0 ? 0 : mesh.partId[like];
  const faceGuess = like < 0 ? 0 : mesh.faceOriginal[like];
  const elementGuess = like < 0 ? 0 : mesh.elementId[like];
  const rankGuess = st.freeFaces.below(faceGuess);
  for (let g = firstCreated; g < st.faceCount; g++) {
    const { part, original, element } = split.faces[g - firstCreated];
    e.bit(st.samePart, 0, part !== partGuess ? 1 : 0);
    if (part !== partGuess) encodeSigned(e, st.part, part - partGuess);
    encodeSigned(e, st.faceIndex, st.freeFaces.below(original) - rankGuess);
    st.freeFaces.take(original);
    encodeSigned(e, st.elementId, element - elementGuess - (original - faceGuess));
    mesh.partId[g] = part, mesh.faceOriginal[g] = original, mesh.elementId[g] = element;
  }
}

// The records and attributes sections of `splits` (from split `first` on), against `mesh` and
// `models` as a reader has them before that split (a DpmDecoder's mesh and records); both are
// advanced past them. A split: {parent, error, wings: [{flags, vertex, face (a quad wing's)}],
// moved: [faces, ascending], vertexOriginal, nodeId, faces: [{part, original, element}] (the
// faces it creates)}.
export function encodeSplitRecords(mesh, models, first, splits) {
  const records = new RangeEncoder(), attributes = new RangeEncoder();
  splits.forEach((split, k) => {
    const i = first + k;
    encodeRecord(records, models, mesh, i, split);
    const problem = applyToModels(models, mesh, i);
    if (problem) throw new Error(problem);
    encodeAttributes(attributes, models, mesh, i, split);
  });
  return { records: records.finish(), attributes: attributes.finish() };
}
