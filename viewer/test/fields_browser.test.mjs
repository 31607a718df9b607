// Result fields in the page, in Debian's headless Chromium (docs/viewer.md "Fields"): an element
// field as a flat per-face fringe with its banded legend (N bands, min and max, the unit), a
// marker at the face of the largest |value|, the peak kept at a coarse level (max |value|
// aggregate), and a nodal field as a smooth fringe. The model: the sample's .dpm with a node and
// an element field added from FORMAT.md (test/fields_fixture.mjs), until `dynpm build` writes
// fields from inputs with cell data. The page's state is compared with dpm.js run here.
import assert from 'node:assert/strict';
import { mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before, test } from 'node:test';

import { chromium } from 'playwright-core';

import { Navigator, readDpm, ShownValues } from '../src/dpm.js';
import { Fringe } from '../src/fringe.js';
import { openViewer } from './chromium.mjs';
import { DEMO_FIELDS, withFields } from './fields_fixture.mjs';

const { DYNPM_CLI: cli, DYNPM_DPM: dpm, DYNPM_TEST_OUT: out } = process.env;
if (!cli || !dpm || !out) throw new Error('fields_browser.test.mjs needs DYNPM_CLI, DYNPM_DPM, DYNPM_TEST_OUT');
const dir = join(out, 'fields-browser');
mkdirSync(dir, { recursive: true });
const file = join(dir, 'fields.dpm');

let server, browser, page, mesh;
const consoleErrors = [];

before(async () => {
  const bytes = withFields(new Uint8Array(readFileSync(dpm)), DEMO_FIELDS);
  writeFileSync(file, bytes);
  ({ mesh } = readDpm(bytes, file));
  ({ server, browser, page } = await openViewer(chromium, cli, file, { viewport: { width: 1100, height: 700 }, errors: consoleErrors }));
});

after(async () => {
  await browser?.close();
  server?.kill('SIGTERM');
});

const fringe = () => page.evaluate(() => window.dpmViewer.fringe());
const setInput = (selector, value) => page.locator(selector).fill(String(value));
async function lastStep() {
  await page.evaluate(() => {
    const t = document.getElementById('time');
    t.value = t.max;
    t.dispatchEvent(new Event('input'));
  });
}

// What dpm.js shows here for the page's field, level and step.
function expected(f) {
  const field = mesh.fields[f.field];
  const nav = new Navigator(mesh);
  nav.setLevel(f.level);
  const shown = new ShownValues(mesh, field, f.aggregate);
  shown.set(f.step, f.level);
  return { field, nav, shown };
}

test('an element field: flat per-face fringe, banded legend, the marker at the peak face', async () => {
  await lastStep();
  await page.locator('#colour').selectOption({ label: 'plastic strain' });
  const f = await fringe();
  assert.equal(f.perFace, true);
  assert.equal(f.bands, 10);
  const { field, nav, shown } = expected(f);
  // The legend: 10 bands, the range of all steps at its ends, the unit.
  assert.equal(await page.locator('#legend .band .swatch:not(.blank)').count(), 10);
  const edges = await page.locator('#legend .band .edge').allTextContents();
  assert.equal(edges.length, 11);
  assert.ok(Math.abs(Number(edges[0]) - field.max) <= 1e-3 * (field.max - field.min), `top ${edges[0]}`);
  assert.ok(Math.abs(Number(edges[10]) - field.min) <= 1e-3 * (field.max - field.min), `bottom ${edges[10]}`);
  assert.equal(await page.isVisible('#variant-section'), false, 'no Variant row for a file that is not a family');
  // In one format: the same decimals on every label, the step between neighbours to 3 digits.
  const decimals = new Set(edges.map((e) => (e.split('.')[1] ?? '').length));
  assert.equal(decimals.size, 1, `one format: ${edges.join(' ')}`);
  const step = (field.max - field.min) / 10;
  assert.ok(Math.abs(Number(edges[0]) - Number(edges[1]) - step) <= 0.01 * step, `${edges[0]} − ${edges[1]}`);
  assert.match(await page.locator('#legend .title').textContent(), /plastic strain .*\[mm\/mm\]/);
  // Every face one colour, the colour of its band; faces that share a vertex differ somewhere.
  assert.deepEqual(f.values, Array.from(shown.values.subarray(0, nav.faceCount)));
  const bands = new Fringe({ lo: field.min, hi: field.max, bands: 10 });
  const rgb = [0, 0, 0];
  let sharedDiffer = 0;
  const colourOfVertex = new Map();
  for (let g = 0; g < nav.faceCount; g++) {
    const c = f.slotColours.slice(12 * g, 12 * g + 12);
    for (let k = 3; k < 12; k++) assert.equal(c[k], c[k % 3], `face ${g}: one colour`);
    bands.colour(f.values[g], rgb, 0);
    for (let k = 0; k < 3; k++) assert.ok(Math.abs(c[k] - rgb[k]) < 1e-6, `face ${g}: its band's colour`);
    for (const v of nav.face(g)) {
      const seen = colourOfVertex.get(v);
      if (seen !== undefined && seen !== c.join()) sharedDiffer++;
      colourOfVertex.set(v, c.join());
    }
  }
  assert.ok(sharedDiffer > 0, 'neighbouring faces keep their own colours (no blending)');
  // The marker: at the centroid of the face of largest |value|, its value in the legend.
  const peak = shown.peak();
  assert.equal(f.peak.item, peak);
  const p = mesh.positionsAt(await page.evaluate(() => window.dpmViewer.state().t), nav.vertexCount,
    new Float32Array(3 * nav.vertexCount));
  const corners = nav.face(peak);
  for (let c = 0; c < 3; c++) {
    const centroid = corners.reduce((a, v) => a + p[3 * v + c], 0) / corners.length;
    assert.ok(Math.abs(f.peak.position[c] - centroid) < 1e-3, `marker coordinate ${c}`);
  }
  assert.match(await page.locator('#legend .peak').textContent(), new RegExp(`element ${mesh.elementId[peak]}`));
  await page.screenshot({ path: join(dir, 'element-fringe.png') });
  assert.deepEqual(consoleErrors, []);
});

test('N bands, continuous, rainbow, this step, user range: legend and colours follow', async () => {
  await setInput('#bands', 6);
  assert.equal(await page.locator('#legend .band .swatch:not(.blank)').count(), 6);
  assert.equal((await fringe()).bands, 6);
  await page.locator('#range').selectOption('step');
  const f = await fringe();
  const { shown } = expected(f);
  assert.equal(f.lo, shown.stepMin);
  assert.equal(f.hi, shown.stepMax);
  await setInput('#range-min', 0.01), await setInput('#range-max', 0.2);
  assert.deepEqual([(await fringe()).lo, (await fringe()).hi], [0.01, 0.2]);
  await page.locator('#scheme').selectOption('rainbow');
  await page.locator('#continuous').check();
  assert.equal((await fringe()).bands, 0);
  assert.equal(await page.locator('#legend .bar').count(), 1);
  await page.locator('#continuous').uncheck();
  await setInput('#range-min', ''), await setInput('#range-max', ''), await setInput('#bands', 10);
  await page.locator('#range').selectOption('all');
  await page.locator('#scheme').selectOption('viridis');
});

test('at a coarse level the peak is still on screen, and the label gives the field error', async () => {
  const box = await page.locator('#resolution').boundingBox();
  await page.mouse.click(box.x + 8 + (box.width - 16) * 0.05, box.y + box.height / 2);
  const f = await fringe();
  assert.ok(f.level < mesh.splitsLoaded / 5, `level ${f.level}`);
  const { shown, nav } = expected(f);
  assert.deepEqual(f.values, Array.from(shown.values.subarray(0, nav.faceCount)));
  const original = shown.raw.reduce((a, x) => Math.max(a, Math.abs(x)), 0);
  assert.equal(Math.abs(f.peak.value), original, 'max |value| on screen = the original peak');
  const label = await page.locator('#resolution-label').textContent();
  assert.match(label, /error [\d.e+-]+ .*field error [\d.e+-]+% of its range/);
  // The stated error is the build's cost, which the fields raise: the label says so.
  assert.match(label, /at any step, raised where the level merges different result values/);
  const error = Number(/field error ([\d.e+-]+)%/.exec(label)[1]);
  assert.ok(Math.abs(error - 100 * nav.fieldError(f.field)) < 0.01 * Math.max(1, error));
  await page.locator('#aggregate').selectOption('mean');
  const mean = await fringe();
  assert.equal(mean.aggregate, 'mean');
  assert.ok(Math.abs(mean.peak.value) <= original, 'a mean is never above the peak');
  await page.locator('#aggregate').selectOption('max');
});

test('a nodal field: smooth fringe with its unit', async () => {
  await page.mouse.click(...(await (async () => {
    const b = await page.locator('#resolution').boundingBox();
    return [b.x + b.width - 4, b.y + b.height / 2];
  })()));
  await page.locator('#colour').selectOption({ label: 'stress' });
  const f = await fringe();
  assert.equal(f.perFace, false);
  assert.equal(f.slotColours, null);
  const { shown, nav } = expected(f);
  assert.deepEqual(f.values, Array.from(shown.values.subarray(0, nav.vertexCount)));
  // Smooth: each vertex its value's place in the range, interpolated across the faces.
  for (let v = 0; v < nav.vertexCount; v++)
    assert.ok(Math.abs(f.uv[2 * v] - Math.min(Math.max((f.values[v] - f.lo) / (f.hi - f.lo), 0), 1)) < 1e-6, `vertex ${v}`);
  assert.match(await page.locator('#legend').textContent(), /stress .*\[MPa\].*node \d+/);
  await page.screenshot({ path: join(dir, 'nodal-fringe.png') });
  await page.locator('#colour').selectOption('part');
  assert.equal(await page.locator('#legend').textContent(), '', 'the part list names the parts');
  assert.match(await page.locator('#part-count').textContent(), /^1 part$/);
  assert.deepEqual(consoleErrors, []);
});
