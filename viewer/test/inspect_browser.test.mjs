// Picking, time histories, measuring and the section cut in the page (inspect.js; docs/viewer.md
// "Picking, history, section, measure"), in Debian's headless Chromium, on the multi-part model
// with named parts (the hat rail as six named Exodus blocks, scripts/sample/make_parts.py, the
// CTest fixture viewer_parts_dpm) with test/fields_fixture.mjs's fields added (a node field
// 'stress' and an element field 'plastic strain', which the C++ reader reads too), and on the
// CalculiX hat rail (data/hat-rail/rail.frd.gz: von Mises stress and plastic strain per node, as
// CalculiX wrote them) built by `dynpm build`. What the page says is compared with the C++ side:
// `dynpm extract --full` writes the input again in its order, with node and element numbers,
// parts and the fields, at every step (legacy VTK). Each feature is driven through window.dynpm
// and through its visible control.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { existsSync, mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { after, before, test } from 'node:test';
import { gunzipSync } from 'node:zlib';

import { chromium } from 'playwright-core';

import { allShown, openViewer, startServer } from './chromium.mjs';
import { DEMO_FIELDS, withFields } from './fields_fixture.mjs';
import { readVtkLegacy } from './vtk_legacy.mjs';

const { DYNPM_CLI: cli, DYNPM_PARTS_DPM: parts, DYNPM_TEST_OUT: out } = process.env;
if (!cli || !parts || !out) throw new Error('inspect_browser.test.mjs needs DYNPM_CLI, DYNPM_PARTS_DPM and DYNPM_TEST_OUT');
const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
const dir = join(out, 'inspect-browser');
mkdirSync(dir, { recursive: true });
const STEPS = 31;
const LAST = STEPS - 1;
// What make_parts.py writes.
const NAMES = new Map([[101, 'Hat top'], [102, 'Hat top — hole patch'], [201, 'Wall left'],
  [202, 'Wall right'], [301, 'Flange left'], [302, 'Flange right']]);

let server, browser, page;
const full = [];  // per step: the full-resolution mesh as `dynpm extract --full` writes it
const consoleErrors = [];

before(async () => {
  const dpm = join(dir, 'rail-parts-fields.dpm');
  writeFileSync(dpm, withFields(new Uint8Array(readFileSync(parts)), DEMO_FIELDS));
  // Every step (with --step T, --full writes the progressive order, not the input's).
  execFileSync(cli, ['extract', dpm, '--full', '--ascii', '-o', join(dir, 'full_{:03d}.vtk')], { stdio: 'ignore' });
  for (let t = 0; t < STEPS; t++) full.push(readVtkLegacy(readFileSync(join(dir, `full_${String(t).padStart(3, '0')}.vtk`))));
  ({ server, browser, page } = await openViewer(chromium, cli, dpm, { viewport: { width: 1100, height: 760 }, errors: consoleErrors,
    timeout: 60000 }));
  await setStep(LAST);
});

after(async () => {
  await browser?.close();
  server?.kill('SIGTERM');
});

// The panel follows at the next render: wait for that frame.
const nextFrame = () => page.evaluate(() => new Promise(requestAnimationFrame));
async function setStep(t) {
  await page.evaluate((t) => {
    const e = document.getElementById('time');
    e.value = String(t);
    e.dispatchEvent(new Event('input'));
  }, t);
  await nextFrame();
}
const setVertices = async (n) => (await page.evaluate((n) => window.dpmViewer.setVertexCount(n), n), await nextFrame());
const canvasBox = () => page.locator('#view').boundingBox();
const api = (name, ...args) => page.evaluate(([name, args]) => window.dynpm[name](...args), [name, args]);
const close = (a, b, tol, what) => assert.ok(Math.abs(a - b) <= tol, `${what}: ${a} vs ${b}`);

// Pixels of a grid over the canvas where the model is, and not under the panel.
async function pixelsOnModel(count = 12) {
  const { width, height } = await canvasBox();
  const found = [];
  for (let i = 1; i < 12 && found.length < count; i++)
    for (let j = 1; j < 12 && found.length < count; j++) {
      const [x, y] = [(width * i) / 12, (height * j) / 12];
      const free = await page.evaluate(([x, y]) => document.elementFromPoint(x, y)?.id === 'view', [x, y]);
      if (free && (await api('pick', x, y))) found.push([x, y]);
    }
  return found;
}

// A pick checked against the extracted full mesh at step t: the file's numbers, the part and its
// name, the position, displacement and every field at its vertex (face), and the node is a
// corner of the element.
function checkPick(p, t) {
  const f = full[t], f0 = full[0];
  assert.equal(p.node, f.pointData.node_id.values[p.vertex], 'node number of the vertex');
  assert.equal(p.element, f.cellData.element_id.values[p.face], 'element number of the face');
  assert.equal(p.part, f.cellData.part_id.values[p.face], 'part of the face');
  assert.equal(p.partName, NAMES.get(p.part), 'the part\'s name from the file');
  assert.ok(f.polygons[p.face].includes(p.vertex), 'the node is a corner of the element');
  for (let c = 0; c < 3; c++) close(p.position[c], f.points[3 * p.vertex + c], 1e-4, `position ${c}`);
  const d = Math.hypot(...[0, 1, 2].map((c) => f.points[3 * p.vertex + c] - f0.points[3 * p.vertex + c]));
  close(p.displacement, d, 1e-4, 'displacement');
  assert.deepEqual(Object.keys(p.values).sort(), ['plastic strain', 'stress']);
  close(p.values.stress, f.pointData.stress.values[p.vertex], 1e-6 * Math.max(1, p.values.stress), 'stress (node)');
  close(p.values['plastic strain'], f.cellData.plastic_strain.values[p.face], 1e-6, 'plastic strain (element)');
}

test('pick(x, y): the original node and element under the cursor, with its values, at any level', async () => {
  assert.equal(await api('pick', 2, 2), null, 'a corner of the canvas misses the model');
  const pixels = await pixelsOnModel();
  assert.ok(pixels.length >= 8, `${pixels.length} pixels on the model`);
  const fine = [];
  for (const [x, y] of pixels) {
    const p = await api('pick', x, y);
    checkPick(p, LAST);
    fine.push(p);
  }
  assert.ok(new Set(fine.map((p) => p.part)).size >= 3, `picks on several parts: ${fine.map((p) => p.part)}`);
  // At 10 % of the vertices the same pixels name original elements, most of them the same as at
  // full resolution, and some that the coarse level does not have.
  const { faces } = await page.evaluate(() => window.dpmViewer.state());
  await setVertices(Math.round(0.1 * 2608));
  const coarseFaces = (await page.evaluate(() => window.dpmViewer.state())).faces;
  assert.ok(coarseFaces < faces / 5, `${coarseFaces} faces at 10 %`);
  let same = 0, absent = 0;
  for (let i = 0; i < pixels.length; i++) {
    const p = await api('pick', ...pixels[i]);
    checkPick(p, LAST);
    same += p.element === fine[i].element ? 1 : 0;
    absent += p.dpm.face >= coarseFaces ? 1 : 0;
  }
  assert.ok(same >= 0.6 * pixels.length, `${same} of ${pixels.length} the same element as at full resolution`);
  assert.ok(absent > 0, 'some picked elements are not drawn at the coarse level');
  await setVertices(2608);
  assert.deepEqual(consoleErrors, []);
});

test('a click picks: the panel shows the numbers, the marker follows time and level', async () => {
  await api('clearPicks');
  const [[x, y]] = await pixelsOnModel(1);
  const box = await canvasBox();
  await page.mouse.click(box.x + x, box.y + y);
  await nextFrame();
  const [p] = await api('picks');
  checkPick(p, LAST);
  const text = await page.locator('#pick-info').textContent();
  assert.match(text, new RegExp(`node${p.node} \\(vertex ${p.vertex}\\)`));
  assert.match(text, new RegExp(`element${p.element}`));
  assert.equal(await page.locator('#pick-part-name').textContent(), NAMES.get(p.part));
  assert.match(text, /stress \(step 30\)/);
  assert.match(text, /plastic strain \(step 30\)/);
  // A drag is no pick.
  await page.mouse.move(box.x + x, box.y + y), await page.mouse.down();
  await page.mouse.move(box.x + x + 40, box.y + y + 10, { steps: 4 }), await page.mouse.up();
  assert.equal((await api('picks')).length, 1);
  for (const [t, n] of [[10, 2608], [10, 400], [LAST, 400]]) {
    await setStep(t), await setVertices(n);
    const [now] = await api('picks');
    assert.equal(now.node, p.node, 'the same node');
    checkPick(now, t);
    const [marker] = await api('markers');
    for (let c = 0; c < 3; c++) close(marker[c], full[t].points[3 * p.vertex + c], 1e-4, `marker ${c} at step ${t}`);
    assert.match(await page.locator('#pick-info').textContent(), new RegExp(`stress \\(step ${t}\\)`));
  }
  // A deformation scale moves the drawn model: the marker stays on its node, the values do not
  // change (the panel gives the true position and displacement).
  await api('setDeformationScale', 3);
  await nextFrame();
  const [scaled] = await api('markers');
  for (let c = 0; c < 3; c++) {
    const p0 = full[0].points[3 * p.vertex + c], pt = full[LAST].points[3 * p.vertex + c];
    close(scaled[c], p0 + 3 * (pt - p0), 1e-3, `marker ${c} at ×3`);
  }
  checkPick((await api('picks'))[0], LAST);
  await api('setDeformationScale', 1);
  await nextFrame();
  await setVertices(2608);
  await page.screenshot({ path: join(dir, 'pick.png') });
});

test('history(node, field): one value per state, as the extracted steps hold', async () => {
  const [p] = await api('picks');
  const stress = await api('history', p.node, 'stress');
  assert.equal(stress.length, STEPS);
  stress.forEach((v, t) => close(v, full[t].pointData.stress.values[p.vertex], 1e-6 * Math.max(1, Math.abs(v)), `stress at step ${t}`));
  // An element field: by the element's number.
  const strain = await api('history', p.element, 'plastic strain');
  assert.equal(strain.length, STEPS);
  strain.forEach((v, t) => close(v, full[t].cellData.plastic_strain.values[p.face], 1e-6, `plastic strain at step ${t}`));
  const d = await api('history', p.node, 'displacement');
  d.forEach((v, t) => close(v, Math.hypot(...[0, 1, 2].map((c) => full[t].points[3 * p.vertex + c] - full[0].points[3 * p.vertex + c])), 1e-4, `displacement at step ${t}`));
  assert.equal(d[0], 0);
  assert.ok(Math.max(...d) > 0);
  await assert.rejects(api('history', p.node, 'no such field'), /no field named/);
  await assert.rejects(api('history', -12345, 'stress'), /no node -12345/);
  await assert.rejects(api('history', p.node, 'distance'), /two nodes/);
});

test('the history plot: a line per pick, the current step marked, CSV as history() says', async () => {
  const pixels = await pixelsOnModel(3);
  const box = await canvasBox();
  for (const [x, y] of pixels.slice(1)) await page.mouse.click(box.x + x, box.y + y);
  const picks = await api('picks');
  assert.equal(picks.length, 3);
  await page.locator('#history-quantity').selectOption('stress');
  assert.equal(await page.locator('#history-plot polyline').count(), 3);
  await setStep(15);
  close(Number(await page.locator('#history-plot .cursor').getAttribute('data-step')), 15, 0, 'cursor step');
  const x15 = Number(await page.locator('#history-plot .cursor').getAttribute('x1'));
  await setStep(LAST);
  assert.ok(Number(await page.locator('#history-plot .cursor').getAttribute('x1')) > x15, 'the cursor moves right with time');
  const [download] = await Promise.all([page.waitForEvent('download'), page.locator('#history-csv').click()]);
  const csv = readFileSync(await download.path(), 'utf8').trim().split('\n').map((l) => l.split(','));
  assert.deepEqual(csv[0], ['step', 'time', ...picks.map((q) => `"node ${q.node}"`)]);
  assert.equal(csv.length, 1 + STEPS);
  for (let i = 0; i < picks.length; i++) {
    const h = await api('history', picks[i].node, 'stress');
    for (let t = 0; t < STEPS; t++) assert.equal(Number(csv[1 + t][2 + i]), h[t], `CSV row ${t}, pick ${i}`);
  }
  await page.locator('#history-plot').screenshot({ path: join(dir, 'history.png') });
  // An element field plots the picked elements, and the CSV names them.
  await page.locator('#history-quantity').selectOption('plastic strain');
  assert.deepEqual(await page.locator('#history-plot polyline title').allTextContents(), picks.map((q) => `element ${q.element}`));
  const [elements] = await Promise.all([page.waitForEvent('download'), page.locator('#history-csv').click()]);
  const rows = readFileSync(await elements.path(), 'utf8').trim().split('\n');
  assert.equal(rows[0], `step,time,${picks.map((q) => `"element ${q.element}"`).join(',')}`);
  const h = await api('history', picks[0].element, 'plastic strain');
  rows.slice(1).forEach((row, t) => assert.equal(Number(row.split(',')[2]), h[t], `CSV row ${t}`));
});

test('measure: the distance of the last two picked nodes, and its history', async () => {
  const picks = await api('picks');
  const [a, b] = picks.slice(-2).map((p) => p.vertex);
  const dist = (t) => Math.hypot(...[0, 1, 2].map((c) => full[t].points[3 * a + c] - full[t].points[3 * b + c]));
  const m = await api('measure');
  assert.deepEqual(m.nodes, picks.slice(-2).map((p) => p.node));
  close(m.distance, dist(LAST), 1e-4, 'distance now');
  m.history.forEach((v, t) => close(v, dist(t), 1e-4, `distance at step ${t}`));
  close(Number(await page.locator('#measure-info').getAttribute('data-distance')), dist(LAST), 1e-4, 'the panel');
  await page.locator('#history-quantity').selectOption('distance');
  assert.equal(await page.locator('#history-plot polyline').count(), 1);
  assert.deepEqual((await api('historyCsv')).trim().split('\n').slice(1).map((row) => Number(row.split(',')[2])), m.history);
  await setStep(0);
  close(Number(await page.locator('#measure-info').getAttribute('data-distance')), dist(0), 1e-4, 'the panel at step 0');
  await setStep(LAST);
});

// Faces of the extracted mesh at step t with corners on both sides of the plane (of the parts
// not in `hidden`).
function facesCut(t, normal, constant, hidden = new Set()) {
  const f = full[t];
  return f.polygons.filter((poly, i) => !hidden.has(f.cellData.part_id.values[i])).filter((poly) => {
    const s = poly.map((v) => normal.reduce((a, n, c) => a + n * f.points[3 * v + c], constant));
    return s.some((x) => x < 0) && s.some((x) => x >= 0);
  }).length;
}

test('section cut: the plane clips the model, the outline lies on it and crosses every cut face', async () => {
  const before = await page.evaluate(() => window.dpmViewer.snapshot(64));
  // The visible control: the checkbox, then the position slider.
  await page.locator('#section').check();
  await page.locator('#section-axis').selectOption('x');
  await page.locator('#section-position').fill('40');
  let s = await api('section');
  assert.equal(s.enabled, true);
  assert.equal(s.position, 0.4);
  assert.ok(s.segments > 0, 'an outline');
  assert.equal(s.segments, facesCut(LAST, s.normal, s.constant), 'one segment per face the plane crosses (full resolution)');
  const [lo, hi] = [0, 1].map((e) => [0, 1, 2].map((c) => (e ? Math.max : Math.min)(...full[LAST].points.filter((_, i) => i % 3 === c))));
  const diagonal = Math.hypot(...hi.map((x, c) => x - lo[c]));
  for (let i = 0; i < s.outline.length; i += 3)
    close(s.normal.reduce((a, n, c) => a + n * s.outline[i + c], s.constant), 0, 1e-4 * diagonal, 'outline point on the plane');
  const cut = await page.evaluate(() => window.dpmViewer.snapshot(64));
  assert.notDeepEqual(cut, before, 'the picture changed');
  // Picks land on the kept side only.
  for (const [x, y] of await pixelsOnModel(6)) {
    const p = await api('pick', x, y);
    const poly = full[LAST].polygons[p.face];
    const side = poly.map((v) => s.normal.reduce((a, n, c) => a + n * full[LAST].points[3 * v + c], s.constant));
    assert.ok(Math.max(...side) >= 0, 'the picked element reaches the kept side');
  }
  // The API: turned and flipped; a coarse level and another step follow.
  s = await api('setSection', { axis: 'z', position: 0.5, tilt: 20, turn: -10, flip: true });
  assert.ok(Math.abs(Math.hypot(...s.normal) - 1) < 1e-9);
  assert.ok(s.normal[2] < -0.8, `flipped z normal ${s.normal}`);
  assert.equal(Number(await page.locator('#section-tilt').inputValue()), 20);
  // The flip box and the tilt and turn sliders: the normal turns back, then square to z again.
  await page.locator('#section-flip').uncheck();
  assert.ok((await api('section')).normal[2] > 0.8, 'unflipped');
  await page.locator('#section-tilt').fill('0');
  await page.locator('#section-turn').fill('0');
  assert.deepEqual((await api('section')).normal.map((x) => Math.round(x * 1e9) / 1e9 + 0), [0, 0, 1]);
  s = await api('setSection', { tilt: 20, turn: -10, flip: true });
  await setStep(12);
  s = await api('section');
  assert.equal(s.segments, facesCut(12, s.normal, s.constant));
  await setVertices(600);
  s = await api('section');
  assert.ok(s.segments > 0 && s.segments < facesCut(12, s.normal, s.constant), 'fewer faces cut at a coarse level');
  await page.screenshot({ path: join(dir, 'section.png') });
  await setVertices(2608), await setStep(LAST);
  // A hidden part leaves the outline too (it is not drawn): the walls, through the API and
  // through their check boxes.
  s = await api('setSection', { axis: 'y', position: 0.5, tilt: 0, turn: 0, flip: false });
  const walls = new Set([201, 202]);
  assert.ok(facesCut(LAST, s.normal, s.constant, walls) < s.segments, 'the plane cuts the walls');
  await api('setPartsVisible', [...walls], false);
  await nextFrame();
  assert.equal((await api('section')).segments, facesCut(LAST, s.normal, s.constant, walls), 'hidden walls: not in the outline');
  await page.locator('#part-list li[data-part="201"] input').check();
  await nextFrame();
  assert.equal((await api('section')).segments, facesCut(LAST, s.normal, s.constant, new Set([202])), 'the left wall back');
  await page.locator('#parts-show-all').click();
  await nextFrame();
  assert.equal((await api('section')).segments, facesCut(LAST, s.normal, s.constant));
  await page.locator('#section').uncheck();
  assert.equal((await api('section')).enabled, false);
  assert.deepEqual(consoleErrors, []);
});

// The fields as CalculiX wrote them (per node: S_MISES, PEEQ, ERROR), on the hat rail built from
// its .frd: a click's values and the history of each field equal the extracted steps'.
test('CalculiX fields: a pick\'s values and histories, as the extracted steps hold', async () => {
  const frd = join(dir, 'rail.frd'), file = join(dir, 'rail.dpm');
  writeFileSync(frd, gunzipSync(readFileSync(join(root, 'data', 'hat-rail', 'rail.frd.gz'))));
  execFileSync(cli, ['build', frd, '-o', file], { stdio: 'ignore' });
  execFileSync(cli, ['extract', file, '--full', '--ascii', '-o', join(dir, 'frd_{:03d}.vtk')], { stdio: 'ignore' });
  const steps = (t) => readVtkLegacy(readFileSync(join(dir, `frd_${String(t).padStart(3, '0')}.vtk`)));
  const { server: second, url } = await startServer(cli, file);
  const other = await browser.newPage({ viewport: { width: 1100, height: 760 } });
  try {
    await other.goto(url);
    // The whole file shown, not only decoded: the Navigator comes a few frames after the last
    // splits, and the API refuses until then.
    await other.waitForFunction(allShown, null, { timeout: 60000 });
    await other.evaluate(() => window.dynpm.setStep(window.dynpm.view().stepCount - 1));
    const box = await other.locator('#view').boundingBox();
    await other.mouse.click(box.x + box.width * 0.6, box.y + 380);
    await other.evaluate(() => new Promise(requestAnimationFrame));
    const [p] = await other.evaluate(() => window.dynpm.picks());
    assert.ok(p, 'a click at the model picks');
    const last = steps(LAST);
    assert.equal(p.node, last.pointData.node_id.values[p.vertex]);
    assert.equal(p.partName, null, 'an FRD names no parts');
    assert.deepEqual(Object.keys(p.values).sort(), ['ERROR', 'PEEQ', 'S_MISES']);
    for (const [name, v] of Object.entries(p.values)) close(v, last.pointData[name].values[p.vertex], 1e-6 * Math.max(1, Math.abs(v)), name);
    const every = Array.from({ length: STEPS }, (_, t) => steps(t));
    for (const name of ['S_MISES', 'PEEQ']) {
      const h = await other.evaluate(([n, f]) => window.dynpm.history(n, f), [p.node, name]);
      assert.equal(h.length, STEPS);
      h.forEach((v, t) => close(v, every[t].pointData[name].values[p.vertex], 1e-6 * Math.max(1, Math.abs(v)), `${name} at step ${t}`));
    }
    await other.locator('#history-quantity').selectOption('S_MISES');
    assert.equal(await other.locator('#history-plot polyline title').textContent(), `node ${p.node}`);
  } finally {
    await other.close();
    second.kill('SIGTERM');
  }
});
