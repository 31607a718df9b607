// The HEAD and BASE payloads (docs/FORMAT.md "HEAD payload", "BASE payload"): the header's
// counts, box, grid and step times, and the base mesh with its ids and the positions of its
// vertices at every step. The C++ side is src/progressive/dpm_read.cpp; DpmDecoder (file.js)
// calls these as the chunks arrive.
import { LOSSLESS_RESIDUAL, residualFits } from './positions.js';
import { HEAD_FLAG_LOSSLESS } from './progressive_mesh.js';
import { baseDeltaFits, idFits, MAX_BASE_ERROR } from './split_records.js';

export function parseHead(r) {
  const h = {};
  h.vertexCount = r.u32();
  h.faceCount = r.u32();
  h.baseVertexCount = r.u32();
  h.baseFaceCount = r.u32();
  h.splitCount = r.u32();
  h.stepCount = r.u32();
  h.fieldCount = r.u32();
  h.flags = r.u32();
  h.bboxMin = [r.f64(), r.f64(), r.f64()];
  h.bboxMax = [r.f64(), r.f64(), r.f64()];
  h.quantStep = r.f64();
  h.maxError = r.f64();
  h.baseError = r.f64();
  // Each split brings back at most 4 faces (its triangle wings).
  if (h.splitCount !== h.vertexCount - h.baseVertexCount)
    r.fail(`split_count ${h.splitCount} is not V − b = ${h.vertexCount - h.baseVertexCount}`);
  if (h.baseFaceCount > h.faceCount) r.fail('more base faces than faces');
  if (h.faceCount - h.baseFaceCount > 4 * h.splitCount)
    r.fail(`${h.faceCount - h.baseFaceCount} faces from ${h.splitCount} splits (4 each at most)`);
  if (h.stepCount < 1) r.fail('no time steps');
  if (r.remaining() < 8 * h.stepCount) r.fail(`${h.stepCount} step times do not fit in HEAD`);
  if (h.flags & ~HEAD_FLAG_LOSSLESS) r.fail(`unknown HEAD flags ${h.flags}`);
  if (![...h.bboxMin, ...h.bboxMax].every(Number.isFinite)) r.fail('the box is not finite');
  if (!(h.flags & HEAD_FLAG_LOSSLESS) && !(h.quantStep > 0 && Number.isFinite(h.quantStep)))
    r.fail(`quant_step ${h.quantStep} is not valid`);
  // The writer keeps the grid at least 4 float32 ulps at the box's largest coordinate
  // (FORMAT.md "Positions"); the C++ reader predicts from float32 positions, so a finer grid
  // would decode differently there: refused by both.
  const largest = Math.max(...h.bboxMin.map(Math.abs), ...h.bboxMax.map(Math.abs));
  if (!(h.flags & HEAD_FLAG_LOSSLESS) && h.quantStep < 4 * largest * 2 ** -23)
    r.fail(`quant_step ${h.quantStep} is finer than float32 holds in the bounding box`);
  if (!(h.maxError >= 0 && h.maxError < Infinity && h.baseError >= 0 && h.baseError <= MAX_BASE_ERROR))
    r.fail('the error bounds are not finite numbers ≥ 0 (base error ≤ 2^1000)');
  h.times = new Float64Array(h.stepCount);
  for (let t = 0; t < h.stepCount; t++) h.times[t] = r.f64();
  if (!h.times.every(Number.isFinite)) r.fail('a step time is not finite');
  const keyCount = r.u32();
  if (r.remaining() < 4 * keyCount) r.fail(`${keyCount} key steps do not fit in HEAD`);
  h.keySteps = [];
  for (let i = 0; i < keyCount; i++) h.keySteps.push(r.u32());
  // Fields have chunks of their own (FORMAT.md "HEAD payload").
  if (h.fieldCount !== 0)
    r.fail(`the header lists ${h.fieldCount} fields (written by an older dynpm: build it again)`);
  h.note = r.string();
  if (r.remaining() !== 0) r.fail(`${r.remaining()} bytes left over at the end of HEAD`);
  return h;
}

export function parseBase(r, mesh) {
  const h = mesh.head;
  const b = h.baseVertexCount;
  const nf = h.baseFaceCount;
  if (r.remaining() < 2 * b + 4 * nf) r.fail(`${b} vertices and ${nf} faces do not fit in BASE`);
  mesh.makeRoom(b, nf);
  parseVertexIds(r, mesh, 0, b);
  const degree = new Uint8Array(nf);
  const corners = new Int32Array(4 * nf).fill(-1);
  for (let f = 0; f < nf; f++) {
    const d = r.u8();
    if (d !== 3 && d !== 4) r.fail(`base face ${f} has degree ${d}`);
    degree[f] = d;
    for (let c = 0; c < d; c++) {
      const v = r.varint();
      if (v >= b) r.fail(`base face ${f}: corner ${v} is not a base vertex (b = ${b})`);
      corners[4 * f + c] = v;
    }
    for (let c = 0; c < d; c++)
      for (let e = c + 1; e < d; e++)
        if (corners[4 * f + c] === corners[4 * f + e]) r.fail(`base face ${f}: corner twice`);
  }
  mesh.baseDegree = degree;
  mesh.baseCorners = corners;
  parseFaceIds(r, mesh, 0, nf);
  parsePositions(r, mesh, b);
  if (r.remaining() !== 0) r.fail(`${r.remaining()} bytes left over at the end of BASE`);
  mesh.faceCountAt[0] = nf;
}

// Original indices must name an input vertex (face); part ids are int32; node and element ids
// lie strictly within ±2^51 and a delta within ±2^52 (the C++ reader's read_vertex_attributes()
// and read_face_attributes(); idFits() in split_records.js).
function parseVertexIds(r, mesh, first, count) {
  const V = mesh.head.vertexCount;
  for (let v = first; v < first + count; v++) {
    const indexDelta = r.svarint(), idDelta = r.svarint();
    const original = (mesh.lastVertexOriginal += indexDelta);
    mesh.nodeId[v] = mesh.lastNodeId += idDelta;
    if (!(baseDeltaFits(indexDelta) && original >= 0 && original < V)) r.fail(`vertex ${v}: original index ${original}`);
    if (!(baseDeltaFits(idDelta) && idFits(mesh.lastNodeId))) r.fail(`vertex ${v}: node id ${mesh.lastNodeId} is not within ±2^51`);
    mesh.vertexOriginal[v] = original;
  }
}

function parseFaceIds(r, mesh, first, count) {
  const F = mesh.head.faceCount;
  for (let f = first; f < first + count; f++) {
    // part_id is absolute; element_id and original_index are deltas (FORMAT.md, and the C++
    // writer: the "delta" note binds to the fields after part_id).
    const part = r.svarint(), idDelta = r.svarint(), indexDelta = r.svarint();
    mesh.elementId[f] = mesh.lastElementId += idDelta;
    const original = (mesh.lastFaceOriginal += indexDelta);
    if (!(part >= -2147483648 && part <= 2147483647)) r.fail(`face ${f}: part id ${part}`);
    if (!(baseDeltaFits(indexDelta) && original >= 0 && original < F)) r.fail(`face ${f}: original index ${original}`);
    if (!(baseDeltaFits(idDelta) && idFits(mesh.lastElementId))) r.fail(`face ${f}: element id ${mesh.lastElementId} is not within ±2^51`);
    mesh.partId[f] = part;
    mesh.faceOriginal[f] = original;
  }
}

// The base vertices' positions (FORMAT.md "Positions"), svarint residuals: step 0 against the
// previous vertex, later steps against the vertex's own previous step; each step is kept compact
// as soon as it is read (step_positions.js), three steps at a time. Int32Array stores wrap
// modulo 2^32, as lossless residual arithmetic requires; a quantized position lies in the
// bounding box, give or take two grid steps (dpm_read.cpp checks the same).
function parsePositions(r, mesh, count) {
  const { bboxMin, bboxMax, quantStep, stepCount } = mesh.head;
  const checked = !mesh.lossless;
  const top = [0, 1, 2].map((c) => (bboxMax[c] - bboxMin[c]) / quantStep + 2);
  let [cur, prev, prev2] = [0, 1, 2].map(() => new Int32Array(3 * count));
  for (let t = 0; t < stepCount; t++) {
    for (let i = 0; i < 3 * count; i++) {
      const residual = r.svarint();
      if (!residualFits(residual, mesh.lossless)) r.fail(`vertex ${Math.floor(i / 3)} step ${t}: ${LOSSLESS_RESIDUAL}`);
      const x = residual + (t > 0 ? prev[i] : i >= 3 ? cur[i - 3] : 0);
      if (checked && (x < -2 || x > top[i % 3]))
        r.fail(`vertex ${Math.floor(i / 3)} step ${t}: a position far outside the bounding box`);
      cur[i] = x;
    }
    mesh.positions.store(t, 0, count, cur, prev, t > 1 ? prev2 : prev, 0);
    [prev2, prev, cur] = [prev, cur, prev2];
  }
}
