// Cross-language golden test: dpm.js against the C++ navigator. For several (resolution, step)
// pairs, `dynpm extract MODEL --vertices N --step T -o out.obj` and dpm.js's Navigator must give
// the same faces (corners, order, part ids) and the same positions.
//
// Environment (set by CTest, tests/CMakeLists.txt): DYNPM_CLI (the dynpm binary), DYNPM_DPM (a
// .dpm, the shipped sample's), DYNPM_TEST_OUT (a scratch folder).
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { test } from 'node:test';

import { findVariant, Navigator, readDpm, ShownValues, variantView } from '../src/dpm.js';
import { readVtkLegacy } from './vtk_legacy.mjs';

const { DYNPM_CLI: cli, DYNPM_DPM: dpm, DYNPM_TEST_OUT: out } = process.env;
if (!cli || !dpm || !out) throw new Error('golden.test.mjs needs DYNPM_CLI, DYNPM_DPM, DYNPM_TEST_OUT');
mkdirSync(out, { recursive: true });

// OBJ as dynpm writes it: `v x y z`, `f a b c [d]` with 1-based indices, `g part_N` groups.
function readObj(path) {
  const positions = [];
  const faces = [];
  const parts = [];
  let part = 0;
  for (const line of readFileSync(path, 'utf8').split('\n')) {
    const w = line.trim().split(/\s+/);
    if (w[0] === 'v') positions.push(w.slice(1, 4).map(Number));
    else if (w[0] === 'f') faces.push(w.slice(1).map((c) => Number(c.split('/')[0]) - 1)), parts.push(part);
    else if (w[0] === 'g') part = Number(w[1].replace(/^part_/, ''));
  }
  return { positions, faces, parts };
}

function extract(args, name) {
  const path = join(out, name);
  execFileSync(cli, ['extract', dpm, ...args, '-o', path, '--ascii'], { stdio: 'pipe' });
  return readObj(path);
}

const { mesh, complete } = readDpm(readFileSync(dpm), dpm);
const h = mesh.head;

test('the sample .dpm decodes completely', () => {
  assert.equal(complete, true);
  assert.equal(mesh.vertexCountLoaded, h.vertexCount);
  assert.ok(h.splitCount > 0 && h.stepCount > 1, 'a progressive animation');
});

const m = h.stepCount;
const cases = [];
for (const n of [h.baseVertexCount, Math.round(h.baseVertexCount + h.splitCount * 0.37), h.vertexCount - 1])
  for (const t of [0, Math.floor(m / 2), m - 1, 1.25]) cases.push([n, t]);

for (const [n, t] of cases) {
  test(`${n} vertices at step ${t}: same faces and positions as dynpm extract`, () => {
    const obj = extract(['--vertices', String(n), '--step', String(t)], `golden_${n}_${t}.obj`);
    const nav = new Navigator(mesh);
    nav.setVertexCount(n);
    assert.equal(obj.positions.length, nav.vertexCount, 'vertex count');
    assert.equal(obj.faces.length, nav.faceCount, 'face count');
    for (let f = 0; f < nav.faceCount; f++) {
      assert.deepEqual(obj.faces[f], nav.face(f), `face ${f}`);
      assert.equal(obj.parts[f], mesh.partId[f], `part of face ${f}`);
    }
    const p = mesh.positionsAt(t, nav.vertexCount, new Float32Array(3 * nav.vertexCount));
    // Whole steps: the same float32 (OBJ holds %.9g, which round-trips float32). Between steps
    // the two interpolate in different orders of operations: a few float32 ulps.
    const exact = Number.isInteger(t);
    const tol = exact ? 0 : 4 * h.quantStep + 1e-6 * Math.hypot(...h.bboxMax);
    for (let v = 0; v < nav.vertexCount; v++)
      for (let c = 0; c < 3; c++) {
        const a = Math.fround(obj.positions[v][c]);
        const b = p[3 * v + c];
        if (exact) assert.equal(a, b, `vertex ${v} coordinate ${c}`);
        else assert.ok(Math.abs(a - b) <= tol, `vertex ${v} coordinate ${c}: ${a} vs ${b}`);
      }
  });
}

// Fully refined, extract writes the input's order: vertex and face original indices map dpm.js's
// progressive numbering back to it.
test('fully refined: the input, in the input order', () => {
  const t = m - 1;
  const obj = extract(['--full', '--step', String(t)], 'golden_full.obj');
  const nav = new Navigator(mesh);
  nav.setLevel(h.splitCount);
  assert.equal(obj.faces.length, h.faceCount);
  assert.equal(obj.positions.length, h.vertexCount);
  const order = new Int32Array(h.faceCount);
  for (let f = 0; f < h.faceCount; f++) order[mesh.faceOriginal[f]] = f;
  const p = mesh.positionsAt(t, h.vertexCount, new Float32Array(3 * h.vertexCount));
  for (let i = 0; i < h.faceCount; i++) {
    const f = order[i];
    assert.deepEqual(obj.faces[i], nav.face(f).map((v) => mesh.vertexOriginal[v]), `input face ${i}`);
  }
  for (let v = 0; v < h.vertexCount; v++) {
    const o = mesh.vertexOriginal[v];
    for (let c = 0; c < 3; c++) assert.equal(Math.fround(obj.positions[o][c]), p[3 * v + c]);
  }
});

test('every prefix that ends on a chunk boundary is a coarser, valid mesh', () => {
  const bytes = readFileSync(dpm);
  const { decoder } = readDpm(bytes, dpm);
  assert.equal(decoder.bytesReceived, bytes.length);
  // Feed in uneven pieces and stop at several places: the loaded levels only ever grow, and the
  // navigator can reach each of them.
  let last = 0;
  for (const cut of [0.2, 0.5, 0.8, 1].map((x) => Math.floor(bytes.length * x))) {
    const { mesh: part } = readDpm(bytes.subarray(0, cut), dpm);
    if (!part.hasBase) continue;
    assert.ok(part.vertexCountLoaded >= last);
    last = part.vertexCountLoaded;
    const nav = new Navigator(part);
    assert.equal(nav.setLevel(part.splitsLoaded), part.splitsLoaded);
  }
  assert.equal(last, h.vertexCount);
});

// ---------------------------------------------------------------------------------------------
// Fields: a plate with a point field and a cell field in VTU (as meshio writes them), built by
// `dynpm build`; `dynpm extract … -o x.vtk` writes the values the level shows (FORMAT.md "Shown
// values", max |value| by default) as POINT_DATA and CELL_DATA SCALARS named as the fields,
// float32. dpm.js's ShownValues must give the same, value for value.

function plateVtu(step, n = 12) {
  const points = [], nodal = [], cells = [], cellValues = [];
  for (let j = 0; j < n; j++)
    for (let i = 0; i < n; i++) {
      points.push(i, j, 0.3 * step * Math.sin(i / 3) * Math.cos(j / 4));
      nodal.push(Math.fround(step * (i - 4) * (j - 7) * 0.1));
    }
  for (let j = 0; j + 1 < n; j++)
    for (let i = 0; i + 1 < n; i++) {
      const a = j * n + i;
      cells.push(a, a + 1, a + n + 1, a + n);
      cellValues.push(Math.fround(Math.max(0, step - Math.hypot(i - 6, j - 3)) * 0.01));
    }
  const c = cells.length / 4;
  return `<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">
<UnstructuredGrid><Piece NumberOfPoints="${n * n}" NumberOfCells="${c}">
<PointData><DataArray type="Float32" Name="stress" format="ascii">${nodal.join(' ')}</DataArray></PointData>
<CellData><DataArray type="Float32" Name="peeq" format="ascii">${cellValues.join(' ')}</DataArray></CellData>
<Points><DataArray type="Float32" NumberOfComponents="3" format="ascii">${points.join(' ')}</DataArray></Points>
<Cells>
<DataArray type="Int32" Name="connectivity" format="ascii">${cells.join(' ')}</DataArray>
<DataArray type="Int32" Name="offsets" format="ascii">${Array.from({ length: c }, (_, k) => 4 * (k + 1)).join(' ')}</DataArray>
<DataArray type="UInt8" Name="types" format="ascii">${Array(c).fill(9).join(' ')}</DataArray>
</Cells>
</Piece></UnstructuredGrid></VTKFile>
`;
}

// The VTK reader the field comparison uses, on what extract writes today: faces, part and node ids.
for (const ascii of [true, false])
  test(`extract's VTK (${ascii ? 'ASCII' : 'binary'}) as vtk_legacy.mjs reads it: faces, part and node ids`, () => {
    const n = Math.round(h.baseVertexCount + h.splitCount * 0.37);
    const path = join(out, `golden_${ascii}.vtk`);
    execFileSync(cli, ['extract', dpm, '--vertices', String(n), '--step', '2', '-o', path, ...(ascii ? ['--ascii'] : [])]);
    const vtk = readVtkLegacy(readFileSync(path));
    const nav = new Navigator(mesh);
    nav.setVertexCount(n);
    assert.deepEqual(vtk.polygons, Array.from({ length: nav.faceCount }, (_, f) => nav.face(f)));
    assert.deepEqual(Array.from(vtk.cellData.part_id.values), Array.from(mesh.partId.subarray(0, nav.faceCount)));
    assert.deepEqual(Array.from(vtk.pointData.node_id.values), Array.from(mesh.nodeId.subarray(0, nav.vertexCount)));
    const p = mesh.positionsAt(2, nav.vertexCount, new Float32Array(3 * nav.vertexCount));
    assert.deepEqual(Array.from(vtk.points, Math.fround), Array.from(p));
  });

const fieldsDir = join(out, 'golden-fields');
mkdirSync(fieldsDir, { recursive: true });
for (const step of [0, 1, 2, 3]) writeFileSync(join(fieldsDir, `plate_${step}.vtu`), plateVtu(step));
const fieldsDpm = join(fieldsDir, 'plate.dpm');
execFileSync(cli, ['build', join(fieldsDir, 'plate_*.vtu'), '-o', fieldsDpm], { stdio: 'pipe' });
const fielded = readDpm(readFileSync(fieldsDpm), fieldsDpm).mesh;
const extracted = (args, name) => {
  const path = join(fieldsDir, name);
  execFileSync(cli, ['extract', fieldsDpm, ...args, '-o', path], { stdio: 'pipe' });
  return readVtkLegacy(readFileSync(path));
};
const probe = extracted(['--full', '--step', '1', '--ascii'], 'probe.vtk');
const skipFields =
  fielded.fields.length === 0 ? 'dynpm build writes no FDEF/FLDS yet (branch a18-format)'
  : !fielded.fields.every((f) => (f.perFace ? probe.cellData : probe.pointData)[f.name.replace(/ /g, '_')])
    ? 'dynpm extract does not write the fields as POINT_DATA/CELL_DATA yet (the integrator\'s extract)'
    : false;

for (const ascii of [true, false])
  for (const ratio of [0, 0.3, 1])
    for (const t of [0, 3]) {
      const n = Math.round(fielded.head.baseVertexCount + ratio * fielded.head.splitCount);
      test(`fields at ${n} vertices, step ${t}${ascii ? '' : ', binary'}: the values dynpm extract writes`,
        { skip: skipFields }, () => {
          const vtk = extracted(['--vertices', String(n), '--step', String(t), ...(ascii ? ['--ascii'] : [])],
            `fields_${n}_${t}_${ascii}.vtk`);
          const nav = new Navigator(fielded);
          nav.setVertexCount(n);
          assert.equal(vtk.polygons.length, nav.faceCount);
          for (const field of fielded.fields) {
            const shown = new ShownValues(fielded, field, 'max');
            shown.set(t, nav.level);
            const array = (field.perFace ? vtk.cellData : vtk.pointData)[field.name.replace(/ /g, '_')];
            assert.equal(array.type, 'float', field.name);
            const count = field.perFace ? nav.faceCount : nav.vertexCount;
            assert.equal(array.values.length, count);
            // Fully refined, extract writes the input's order (see the positions above).
            const full = nav.level === fielded.head.splitCount;
            const original = field.perFace ? fielded.faceOriginal : fielded.vertexOriginal;
            for (let x = 0; x < count; x++)
              assert.equal(array.values[full ? original[x] : x], shown.values[x], `${field.name} item ${x}`);
          }
        });
    }

// A family file (FORMAT.md "Variants: VARI"; fuzz/corpus/dpm/small_grid_family.dpm): each variant
// as dpm.js's variantView shows it and as `dynpm extract --variant` writes it, the same mesh at
// every level and step.
test('a family file: each variant the same in dpm.js and dynpm extract --variant', () => {
  const family = join('..', 'fuzz', 'corpus', 'dpm', 'small_grid_family.dpm');
  const { mesh: fm } = readDpm(readFileSync(family), family);
  assert.equal(fm.variants.length, 2);
  for (const [index, which] of [[0, '0'], [1, 'bulge']]) {
    const view = variantView(fm, findVariant(fm, which));
    assert.equal(view.head.stepCount, [3, 4][index]);
    for (const n of [fm.head.baseVertexCount + 5, fm.head.vertexCount - 1])
      for (let t = 0; t < view.head.stepCount; t++) {
        const path = join(out, `family_${index}_${n}_${t}.obj`);
        execFileSync(cli, ['extract', family, '--variant', which, '--vertices', String(n), '--step', String(t), '-o', path, '--ascii'], { stdio: 'pipe' });
        const obj = readObj(path);
        const nav = new Navigator(view);
        nav.setVertexCount(n);
        assert.equal(obj.positions.length, nav.vertexCount);
        for (let f = 0; f < nav.faceCount; f++) assert.deepEqual(obj.faces[f], nav.face(f), `face ${f}`);
        const p = view.positionsAt(t, nav.vertexCount, new Float32Array(3 * nav.vertexCount));
        for (let v = 0; v < nav.vertexCount; v++)
          for (let c = 0; c < 3; c++) assert.equal(Math.fround(obj.positions[v][c]), p[3 * v + c], `variant ${index} step ${t} vertex ${v}`);
      }
  }
  assert.throws(() => findVariant(fm, 'nope'), /the variants: 0 wave, 1 bulge/);
});
