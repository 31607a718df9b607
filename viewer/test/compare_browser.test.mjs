// Compare (docs/viewer.md "Compare"), in Debian's headless Chromium: `dynpm view A.dpm B.dpm`
// with the sample on two position grids of one hierarchy (compare_fixture.mjs). Two canvases,
// each model decoded by a worker of its own from its own range requests; one camera (a drag on
// either canvas turns both, and both show the same picture); the same step and level; the
// difference fringe's largest |p_A − p_B| equal to the one computed from `dynpm extract` of both
// at that level and step, within the two grids' bounds; another hierarchy offers no difference
// and says why; ?compare= of this origin, and of another refused. Screenshot:
// <DYNPM_TEST_OUT>/compare-browser/compare.png (docs/images/compare.png).
//
// If Chromium cannot start, this fails: it never skips.
import assert from 'node:assert/strict';
import { mkdirSync } from 'node:fs';
import { join } from 'node:path';
import { after, before, test } from 'node:test';

import { chromium } from 'playwright-core';

import { positionBytes } from '../src/dpm/step_positions.js';
import { allShown, CHROMIUM_ARGS, startServer } from './chromium.mjs';
import { bothShown, checkLargest, extracted } from './compare_checks.mjs';
import { cli, compareDpm, compareMesh, outDir } from './compare_fixture.mjs';

const shots = join(outDir, '..', 'compare-browser');
mkdirSync(shots, { recursive: true });
const fine = compareDpm('fine'), coarse = compareDpm('coarse'), keys3 = compareDpm('keys3');
const servers = [];
let browser;
before(async () => {
  browser = await chromium.launch({ executablePath: process.env.DYNPM_CHROMIUM ?? '/usr/bin/chromium', headless: true, args: CHROMIUM_ARGS });
});
after(async () => {
  await browser?.close();
  for (const s of servers) s.kill('SIGINT');
});

// `dynpm view A B` (or one model) and a page on it, once both models are in; the page's
// workers, requests and errors are recorded.
async function open(models, query = '') {
  const { server, url } = await startServer(cli, models[0], models.slice(1));
  servers.push(server);
  const page = await browser.newPage({ viewport: { width: 1200, height: 600 } });
  const seen = { workers: [], requests: [], errors: [] };
  page.on('worker', (w) => seen.workers.push(w.url()));
  page.on('request', (r) => seen.requests.push({ url: r.url(), range: r.headers().range ?? null }));
  page.on('console', (m) => m.type() === 'error' && seen.errors.push(m.text()));
  page.on('pageerror', (e) => seen.errors.push(String(e)));
  await page.goto(url + query);
  return { page, url, seen };
}

// Both models shown whole; on a timeout, what each page says.
async function waitBothShown({ page, seen }) {
  await page.waitForFunction(bothShown, null, { timeout: 60000 }).catch(async (e) => {
    throw new Error(`${e.message}: ${JSON.stringify(await page.evaluate(() => [window.dpmViewer?.state(), window.dpmViewer?.compare()]))} ${seen.errors}`);
  });
}

async function openBoth(models, query = '') {
  const o = await open(models, query);
  await waitBothShown(o);
  await o.page.evaluate(() => window.dpmViewer.compare().done);
  await o.page.waitForFunction(allShown);
  return o;
}

const compare = (page) => page.evaluate(() => window.dpmViewer.compare());
// The error setCompareLink('pixels') throws, as "Name: message".
const thrownLink = (page) => page.evaluate(() => {
  try {
    window.dynpm.setCompareLink('pixels');
    return null;
  } catch (e) {
    return `${e.name}: ${e.message}`;
  }
});
const meanDifference = (a, b) => a.reduce((s, x, i) => s + Math.abs(x - b[i]), 0) / a.length;
const pictures = (page) => page.evaluate(() => ({ a: window.dpmViewer.snapshot(), b: window.dpmViewer.compareSnapshot() }));

test('two models side by side: two canvases, a worker and range requests each, each named with its level', async () => {
  const { page, seen } = await openBoth([fine, coarse]);
  assert.deepEqual(seen.errors, []);
  assert.equal(await page.locator('canvas').count(), 2, 'the two models\' canvases');
  const decoders = seen.workers.filter((u) => u.endsWith('/src/decode_worker.js'));
  assert.equal(decoders.length, 2, `workers: ${seen.workers}`);
  for (const file of ['/model.dpm', '/compare.dpm']) {
    const requests = seen.requests.filter((r) => new URL(r.url).pathname === file);
    assert.ok(requests.length > 0 && requests.every((r) => /^bytes=\d+-\d+$/.test(r.range)), `${file}: ${JSON.stringify(requests)}`);
  }
  const c = await compare(page);
  assert.equal(c.name, 'coarse.dpm');
  assert.equal(c.vertices, 2608);
  assert.ok(c.sameHierarchy, c.why);
  assert.match(c.labels[0], /^A: fine\.dpm — 2,608 of 2,608 vertices \(100\.0%\)/);
  assert.match(c.labels[1], /^B: coarse\.dpm — 2,608 of 2,608 vertices \(100\.0%\)/);
  // Each half of what the open panel leaves (it covers neither model), each half of the window
  // once it is collapsed.
  // [x, CSS width] of each canvas; its drawing buffer follows (resized with the panel).
  const boxes = async () => {
    const all = await page.locator('canvas').evaluateAll((cs) => cs.map((e) => [e.getBoundingClientRect().x, e.getBoundingClientRect().width, e.width]));
    for (const [, width, buffer] of all) assert.equal(buffer, width, 'the drawing buffer is the canvas\'s size');
    return all.map(([x, width]) => [x, width]);
  };
  const panelRight = await page.locator('#panel').evaluate((p) => p.getBoundingClientRect().right);
  assert.equal(panelRight, 320);
  assert.deepEqual(await boxes(), [[330, 435], [765, 435]], 'beside the panel');
  await page.click('#panel-toggle');
  assert.deepEqual(await boxes(), [[0, 600], [600, 600]], 'each half of the window');
  await page.click('#panel-toggle');
  assert.deepEqual(await boxes(), [[330, 435], [765, 435]], 'beside the panel again');
  await page.close();
});

test('one camera: a drag on either canvas turns both, and both show the same picture', async () => {
  const { page } = await openBoth([fine, coarse]);
  const start = await pictures(page);
  assert.ok(meanDifference(start.a, start.b) < 3, `A and B differ by ${meanDifference(start.a, start.b)}`);
  const look0 = (await page.evaluate(() => window.dynpm.view())).look;
  for (const [x, y] of [[900, 300], [470, 320]]) {
    const before = await pictures(page);
    await page.mouse.move(x, y);
    await page.mouse.down();
    await page.mouse.move(x + 90, y + 40, { steps: 6 });
    await page.mouse.up();
    const now = await pictures(page);
    assert.ok(meanDifference(before.a, now.a) > 5 && meanDifference(before.b, now.b) > 5, `a drag at ${x} turned both`);
    assert.ok(meanDifference(now.a, now.b) < 3, `after the drag at ${x}, A and B differ by ${meanDifference(now.a, now.b)}`);
  }
  const look1 = (await page.evaluate(() => window.dynpm.view())).look;
  assert.ok(Math.hypot(...look1.map((x, i) => x - look0[i])) > 0.1, 'the camera turned');
  await page.close();
});

test('linked time and resolution: the slider, the API and the state buttons move both', async () => {
  const { page } = await openBoth([fine, coarse]);
  await page.evaluate(() => window.dynpm.setStep(12.5));
  assert.equal((await compare(page)).step, 12.5);
  await page.locator('#time').fill('20');
  assert.equal((await compare(page)).step, 20);
  await page.click('#state-first');
  assert.equal((await compare(page)).step, 0);
  for (const vertices of [13, 500, 1300]) {
    await page.evaluate((n) => window.dynpm.setLevel({ vertices: n }), vertices);
    const c = await compare(page);
    assert.equal(c.vertices, vertices);
    assert.match(c.labels[1], new RegExp(`${vertices.toLocaleString('en')} of 2,608 vertices`));
  }
  await page.locator('#resolution').fill('800');
  await page.waitForFunction(() => window.dpmViewer.compare().vertices === 800);
  // One hierarchy stays linked vertex for vertex when the panel says "error".
  await page.selectOption('#compare-link', 'error');
  await page.evaluate(() => window.dynpm.setLevel({ vertices: 500 }));
  const c = await compare(page);
  assert.equal(c.vertices, 500);
  assert.doesNotMatch(c.labels[1], /linked by error/);
  await page.close();
});

// The page's memory budget (?memory=MiB, docs/viewer.md "A memory budget") is shared: each
// model's worker stops at the levels whose values fit half of it, and A's level asks B's worker
// for B's linked level when B has not loaded it.
test('a memory budget is halved between the two models; A\'s finest level loads the rest of both', async () => {
  // The sample twice (coarse.dpm fits one 64 KiB request, the smallest the page makes).
  const { page, seen } = await open([fine, fine], '?memory=0.25');
  const bothPaused = () => ((s, c) => s?.paused && c?.paused && c.navigator)(window.dpmViewer?.state(), window.dpmViewer?.compare());
  await page.waitForFunction(bothPaused, null, { timeout: 60000 });
  const s = await page.evaluate(() => window.dpmViewer.state()), c = await compare(page);
  // An eighth of a MiB each: a vertex's positions at every step (compact) and 200 B for what
  // does not depend on the steps (the sample has no fields).
  const steps = await page.evaluate(() => window.dynpm.view().stepCount), total = 2608;
  const budgeted = Math.floor(2 ** 17 / (positionBytes(steps, false) + 200));
  for (const [name, loaded] of [['A', s.loadedVertices], ['B', c.loadedVertices]])
    assert.ok(loaded >= budgeted && loaded < total, `${name}: ${loaded} of ${total} vertices loaded (${budgeted} budgeted)`);
  assert.match(await page.locator('#resolution-label').textContent(), /fit 128\.0 KiB, half the page's budget/);
  assert.match(c.labels[1], new RegExp(`, ${c.loadedVertices.toLocaleString('en')} loaded`));
  // A's finest level: A loads the rest, and B follows it to its own finest.
  await page.evaluate(() => window.dynpm.setLevel({ vertices: 2608 }));
  await waitBothShown({ page, seen });
  const whole = await compare(page);
  assert.equal(whole.vertices, total);
  assert.equal(whole.paused, false);
  assert.doesNotMatch(whole.labels[1], /loaded/);
  assert.deepEqual(seen.errors, []);
  await page.close();
});

// A's canvas as counts: the model's pixels (not the background, 0xeef0f3) and the magenta ones
// (B overlaid, compare_overlay.js), each with its box [x0, y0, x1, y1] in pixels; and how many
// pixels turned more magenta (r + b − 2g up by more than 20) since the last call's picture.
const pictureOfA = (page) => page.evaluate(() => {
  const { width, rgba } = window.dpmViewer.pixels();
  const model = { count: 0, box: [Infinity, Infinity, -Infinity, -Infinity] }, magenta = structuredClone(model);
  const add = (set, x, y) => {
    set.count++;
    set.box = [Math.min(set.box[0], x), Math.min(set.box[1], y), Math.max(set.box[2], x), Math.max(set.box[3], y)];
  };
  const magentaness = new Int16Array(rgba.length / 4), last = window.lastMagentaness;
  let tinted = 0;
  for (let i = 0, k = 0; i < rgba.length; i += 4, k++) {
    const [r, g, b] = [rgba[i], rgba[i + 1], rgba[i + 2]];
    const x = k % width, y = Math.floor(k / width);
    if (Math.abs(r - 0xee) + Math.abs(g - 0xf0) + Math.abs(b - 0xf3) > 12) add(model, x, y);
    if (r > 150 && g < 0.5 * Math.min(r, b) && Math.abs(r - b) < 20) add(magenta, x, y);  // (not a lit viridis purple)
    magentaness[k] = r + b - 2 * g;
    if (last?.length === magentaness.length && magentaness[k] > last[k] + 20) tinted++;
  }
  window.lastMagentaness = magentaness;
  return { model, magenta, tinted };
});

test('overlaid: B drawn in magenta on A\'s canvas, at B\'s level and step, following the camera; back side by side', async () => {
  const { page, seen } = await openBoth([fine, coarse, '--layout', 'edges']);  // dpm.json's compareLayout
  await page.selectOption('#colour', 'displacement');  // viridis: no magenta of A's own
  const visible = () => page.locator('canvas').evaluateAll((cs) => cs.map((e) => getComputedStyle(e).display !== 'none' && [e.getBoundingClientRect().x, e.getBoundingClientRect().width, e.width]));
  assert.deepEqual(await visible(), [[330, 870, 870], false], 'A takes what the panel leaves; B\'s canvas is hidden');
  const c = await compare(page);
  assert.equal(c.layout, 'edges');
  assert.equal(await page.locator('#compare-layout').inputValue(), 'edges');
  assert.match(c.labels[1], /^B, in magenta over A: coarse\.dpm — 2,608 of 2,608 vertices/);
  // The two builds differ by their grids only: B's edges cover A's model, box for box (within 2 %
  // of its size: the silhouette's blended pixels are not magenta enough to count).
  const close = (a, b, what) => {
    const slack = 0.02 * Math.max(b[2] - b[0], b[3] - b[1]);
    assert.ok(a.every((x, i) => Math.abs(x - b[i]) <= slack), `${what}: ${a} against ${b}`);
  };
  for (const step of [0, 30]) {
    await page.evaluate((t) => window.dynpm.setStep(t), step);
    const { model, magenta } = await pictureOfA(page);
    assert.ok(magenta.count > 0.1 * model.count, `step ${step}: ${magenta.count} magenta of ${model.count} pixels`);
    close(magenta.box, model.box, `step ${step}, the boxes of B's edges and of the model`);
  }
  // A drag turns B with A; a coarser level draws fewer of B's edges.
  const before = await pictureOfA(page);
  await page.mouse.move(700, 300);
  await page.mouse.down();
  await page.mouse.move(790, 340, { steps: 6 });
  await page.mouse.up();
  const turned = await pictureOfA(page);
  assert.notDeepEqual(turned.model.box, before.model.box, 'the drag turned the camera');
  close(turned.magenta.box, turned.model.box, 'after the drag, the boxes of B\'s edges and of the model');
  await page.evaluate(() => window.dynpm.setLevel({ vertices: 13 }));
  assert.equal((await compare(page)).vertices, 13);
  const coarseEdges = await pictureOfA(page);
  assert.ok(coarseEdges.magenta.count < turned.magenta.count / 3, `13 vertices: ${coarseEdges.magenta.count} magenta pixels, 2,608: ${turned.magenta.count}`);
  // B translucent: its skin tints the model's pixels toward magenta, the background stays.
  await page.evaluate(() => window.dynpm.setLevel({ vertices: 2608 }));
  const edges = await pictureOfA(page);
  await page.selectOption('#compare-layout', 'surface');
  const skin = await pictureOfA(page);
  assert.ok(skin.tinted > 0.6 * edges.model.count, `${skin.tinted} of ${edges.model.count} model pixels tinted`);
  assert.equal(skin.model.count, edges.model.count, 'the background is untouched');
  await page.screenshot({ path: join(shots, 'compare-overlay.png') });
  // Side by side again: two halves, no magenta on A.
  assert.equal(await page.evaluate(() => window.dynpm.setCompareLayout('side')), 'side');
  assert.deepEqual(await visible(), [[330, 435, 435], [765, 435, 435]]);
  const sideBySide = await pictureOfA(page);
  assert.equal(sideBySide.magenta.count, 0, `magenta pixels at ${sideBySide.magenta.box}`);
  assert.match((await compare(page)).labels[1], /^B: coarse\.dpm/);
  await assert.rejects(page.evaluate(() => window.dynpm.setCompareLayout('stacked')), /layout "stacked": one of side, edges, surface/);
  assert.deepEqual(seen.errors, []);
  await page.close();
});

test('the difference fringe: its largest |p_A − p_B| is the one extract gives, within both grids', async () => {
  const { page, seen } = await openBoth([fine, coarse]);
  await page.selectOption('#colour', 'difference');
  const mesh = compareMesh('fine');
  const bound = mesh.head.maxError + compareMesh('coarse').head.maxError;
  for (const [vertices, step] of [[800, 20], [2608, 30], [13, 5]]) {
    await page.evaluate(([n, t]) => (window.dynpm.setLevel({ vertices: n }), window.dynpm.setStep(t)), [vertices, step]);
    const { largest } = await compare(page);
    const a = extracted(cli, fine, vertices, step, join(shots, 'a.obj')), b = extracted(cli, coarse, vertices, step, join(shots, 'b.obj'));
    const max = checkLargest(largest, a, b, vertices, mesh.vertexOriginal, `${vertices} vertices, step ${step}`);
    assert.ok(max > 0 && max <= bound, `${max} within the grids' ${bound}`);
    const legend = await page.locator('#legend').textContent();
    assert.match(legend, /difference \|p_A\(t\) − p_B\(t\)\|/);
    assert.match(legend, new RegExp(`max \\|value\\| [0-9.e+-]+ at node ${largest.node} \\(vertex ${largest.vertex}\\)`));
    assert.equal(Number(await page.locator('#legend').getAttribute('data-max')), largest.value);
  }
  await page.evaluate(() => (window.dynpm.setLevel({ vertices: 800 }), window.dynpm.setStep(20)));
  await page.locator('#legend').scrollIntoViewIfNeeded();  // the panel scrolls to the legend
  await page.screenshot({ path: join(shots, 'compare.png') });
  await page.selectOption('#colour', 'displacement');
  assert.equal((await compare(page)).largest, null, 'the marker goes with the mode');
  assert.deepEqual(seen.errors, []);
  await page.close();
});

test('another hierarchy: levels linked by share or by error, no difference offered, the reason shown', async () => {
  const { page, seen } = await openBoth([fine, keys3]);
  const c = await compare(page);
  assert.equal(c.sameHierarchy, false);
  assert.ok(c.why && !/waiting/.test(c.why), c.why);
  assert.ok(c.labels[1].includes(`no difference fringe: ${c.why}`), c.labels[1]);
  assert.ok(await page.locator('#colour option[value="difference"]').evaluate((o) => o.disabled));
  await page.evaluate(() => window.dynpm.setLevel({ ratio: 0.25 }));
  assert.equal((await compare(page)).vertices, Math.round(0.25 * 2608));
  // Linked by error: B's coarsest level within A's error, as dpm.js gives it; back by share.
  const b = compareMesh('keys3');
  assert.equal(await page.evaluate(() => window.dynpm.setCompareLink('error')), 'error');
  for (const vertices of [200, 800, 2000]) {
    const { error } = await page.evaluate((n) => window.dynpm.setLevel({ vertices: n }), vertices);
    const c = await compare(page);
    assert.equal(c.vertices, b.head.baseVertexCount + b.levelForError(error), `A at ${vertices} vertices, error ${error}`);
    assert.ok(b.levelError(c.vertices - b.head.baseVertexCount) <= error);
    assert.match(c.labels[1], /^B, linked by error: keys3\.dpm/);
  }
  await page.selectOption('#compare-link', 'vertices');
  assert.equal((await compare(page)).vertices, 2000);
  assert.match(await thrownLink(page), /RangeError: link by "pixels": one of vertices, error/);
  assert.deepEqual(seen.errors, []);
  await page.close();
});

test('?compare= names a file of this server; one of another origin is refused, as is an unknown ?compareLayout=', async () => {
  const { page } = await openBoth([keys3, coarse], '?compare=model.dpm');
  const c = await compare(page);
  assert.equal(c.name, 'model.dpm');
  assert.ok(c.sameHierarchy, 'the model beside itself');
  await page.selectOption('#colour', 'difference');
  assert.equal((await compare(page)).largest.value, 0);
  await page.close();
  const { page: refused, seen } = await open([fine], '?compare=http://example.com/x.dpm');
  await refused.waitForFunction(() => !document.getElementById('error').hidden, null, { timeout: 30000 });
  assert.match(await refused.locator('#error').textContent(), /\?compare=http:\/\/example\.com\/x\.dpm: not on this server/);
  assert.ok(seen.requests.every((r) => new URL(r.url).hostname === '127.0.0.1'), 'nothing left the origin');
  await refused.close();
  const { page: surface } = await openBoth([fine], '?compare=model.dpm&compareLayout=surface');
  assert.equal((await compare(surface)).layout, 'surface');
  assert.equal(await surface.locator('#compare-layout').inputValue(), 'surface');
  await surface.close();
  const { page: badLayout } = await open([fine], '?compare=model.dpm&compareLayout=stacked');
  await badLayout.waitForFunction(() => !document.getElementById('error').hidden, null, { timeout: 30000 });
  assert.match(await badLayout.locator('#error').textContent(), /\?compareLayout=stacked: layout "stacked": one of side, edges, surface/);
  await badLayout.close();
});
