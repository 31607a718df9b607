// Issue 23's "Done when" for the catalogue and compare, in headless Chromium: `dynpm serve` on a
// folder of 20 variants of the hat rail, made here from the shipped sample — 16 separate builds
// on 16 position grids (one hierarchy: compare_fixture.mjs says why) and a family file of 4
// members whose motion is the sample's scaled by 0.5, 1, 1.5 and 2 (docs/family.md) — lists the
// 20; two selected in the page open side by side with the difference fringe, whose largest
// value and its vertex are the ones `dynpm extract` of both gives at a level and a step: two
// separate files, then two members of the family (`extract --variant`), exact per vertex, the
// family file fetched and decoded once for both, and the same overlaid (B's edges on A's canvas).
// Screenshots: DYNPM_TEST_OUT/catalogue-compare/*.png.
//
// Environment (CTest): DYNPM_CLI, DYNPM_TEST_OUT, DYNPM_SAMPLE_DIR (the sample's frame_*.obj).
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdirSync, readdirSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before, test } from 'node:test';

import { chromium } from 'playwright-core';

import { readDpm } from '../src/dpm.js';
import { allShown, CHROMIUM_ARGS, startServer } from './chromium.mjs';
import { bothShown, checkLargest, extracted } from './compare_checks.mjs';

const { DYNPM_CLI: cli, DYNPM_TEST_OUT: out, DYNPM_SAMPLE_DIR: sample } = process.env;
if (!cli || !out || !sample) throw new Error('catalogue_compare_browser.test.mjs needs DYNPM_CLI, DYNPM_TEST_OUT, DYNPM_SAMPLE_DIR');
const base = join(out, 'catalogue-compare');
const dir = join(base, 'doe');

// 16 grids, in diagonals (null: the default grid), and the family's motion scales.
const GRIDS = [null, 1e-5, 2e-5, 3e-5, 5e-5, 7e-5, 1e-4, 1.5e-4, 2e-4, 3e-4, 5e-4, 7e-4, 1e-3, 1.5e-3, 2e-3, 3e-3];
const gridName = (k) => `grid${String(k + 1).padStart(2, '0')}`;
const SCALES = { scale050: 0.5, scale100: 1, scale150: 1.5, scale200: 2 };
const FAMILY_FRAMES = ['000', '010', '020', '030'];

// One family member's OBJ sequence: the sample's frames with p0 + s · (p(t) − p0).
function writeScaled(folder, s) {
  mkdirSync(folder, { recursive: true });
  const lines = (frame) => readFileSync(join(sample, `frame_${frame}.obj`), 'utf8').split('\n');
  const first = lines(FAMILY_FRAMES[0]);
  for (const frame of FAMILY_FRAMES) {
    let v = 0;
    const scaled = lines(frame).map((line, i) => {
      if (!line.startsWith('v ')) return line;
      assert.ok(first[i].startsWith('v '), 'the frames list their vertices on the same lines');
      const p = line.split(/\s+/).slice(1, 4).map(Number), p0 = first[i].split(/\s+/).slice(1, 4).map(Number);
      v++;
      return `v ${p.map((x, c) => p0[c] + s * (x - p0[c])).join(' ')}`;
    });
    assert.ok(v > 0);
    writeFileSync(join(folder, `frame_${frame}.obj`), scaled.join('\n'));
  }
}

const build = (args) => execFileSync(cli, ['build', ...args, '--quiet'], { stdio: 'pipe' });
let server, url, browser;
const errors = [];
before(async () => {
  rmSync(base, { recursive: true, force: true });
  mkdirSync(join(dir, 'grids'), { recursive: true });
  GRIDS.forEach((e, k) => build([join(sample, 'frame_*.obj'), '-o', join(dir, 'grids', `${gridName(k)}.dpm`), ...(e === null ? [] : ['--position-error', String(e)])]));
  const inputs = Object.entries(SCALES).map(([name, s]) => (writeScaled(join(base, 'runs', name), s), join(base, 'runs', name, 'frame_*.obj')));
  build(['--family', ...inputs, '-o', join(dir, 'family.dpm')]);
  ({ server, url } = await startServer(cli, dir, [], 'serve'));
  browser = await chromium.launch({ executablePath: process.env.DYNPM_CHROMIUM ?? '/usr/bin/chromium', headless: true, args: CHROMIUM_ARGS });
});
after(async () => {
  await browser?.close();
  server?.kill('SIGTERM');
});

// The decode workers the pages start and the requests of each file ({range} per request).
const workers = [];
const requests = new Map();
async function catalogue() {
  const page = await browser.newPage({ viewport: { width: 1280, height: 860 } });
  page.on('worker', (w) => workers.push(w.url()));
  page.on('request', (r) => {
    const path = new URL(r.url()).pathname;
    requests.set(path, [...(requests.get(path) ?? []), r.headers().range ?? null]);
  });
  page.on('console', (m) => m.type() === 'error' && !/404/.test(m.text()) && errors.push(m.text()));
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto(url);
  await page.waitForFunction(() => window.dynpmCatalogue?.entries().length === 17);
  return page;
}

// Ticks two check boxes of the catalogue, follows its compare link and waits for both models.
async function compareTwo(page, boxes) {
  for (const box of boxes) await page.check(box);
  const href = await page.getAttribute('#compare', 'href');
  await Promise.all([page.waitForURL(/\/view\?.*compare=/), page.click('#compare')]);
  await page.waitForFunction(bothShown, null, { timeout: 60000 });
  await page.evaluate(() => window.dpmViewer.compare().done);
  await page.waitForFunction(allShown, null, { timeout: 60000 });
  return new URL(href, url).searchParams;
}

// The fringe at each level and step against `extract` of both (with its arguments per model).
async function checkFringe(page, { a, b, vertexOriginal, levels, what }) {
  await page.selectOption('#colour', 'difference');
  const largest = [];
  for (const [vertices, step] of levels) {
    await page.evaluate(([n, t]) => (window.dynpm.setLevel({ vertices: n }), window.dynpm.setStep(t)), [vertices, step]);
    const c = await page.evaluate(() => window.dpmViewer.compare());
    assert.equal(c.vertices, vertices);
    const pa = extracted(cli, a.file, vertices, step, join(base, 'a.obj'), a.extra);
    const pb = extracted(cli, b.file, vertices, step, join(base, 'b.obj'), b.extra);
    const max = checkLargest(c.largest, pa, pb, vertices, vertexOriginal, `${what}: ${vertices} vertices, step ${step}`);
    const legend = await page.locator('#legend').textContent();
    assert.match(legend, new RegExp(`max \\|value\\| [0-9.e+-]+ at node ${c.largest.node} \\(vertex ${c.largest.vertex}\\)`));
    largest.push(max);
  }
  return largest;
}

test('dynpm serve lists 20 variants; two selected open side by side with the difference fringe of extract', async () => {
  const page = await catalogue();
  assert.equal(await page.textContent('#count'), '17 files · 20 variants');
  // The 20 variants the page lists: 16 files to select, and the family's 4 members.
  const files = await page.locator('article:not(:has(ul.variants)) .select').count();
  const members = await page.$$eval('article[data-path="family.dpm"] ul.variants li', (ls) => ls.map((l) => `${l.dataset.variant}: ${l.textContent.trim()}`));
  assert.equal(files, 16);
  assert.deepEqual(members, Object.keys(SCALES).map((name) => `${name}: ${name} 4 steps (t 0 … 30)`));
  assert.equal(files + members.length, 20);
  await page.fill('#filter', 'scale15');  // a member's name finds its family
  assert.deepEqual(await page.evaluate(() => window.dynpmCatalogue.shown()), ['family.dpm']);
  await page.fill('#filter', '');
  await page.screenshot({ path: join(base, 'catalogue.png') });

  const [a, b] = [3, 14].map((k) => `grids/${gridName(k - 1)}.dpm`);
  const query = await compareTwo(page, [a, b].map((p) => `article[data-path="${p}"] .select`));
  assert.equal(query.get('model'), `/files/${a}`);
  assert.equal(query.get('compare'), `/files/${b}`);
  assert.equal(query.get('variant'), null);
  const c = await page.evaluate(() => window.dpmViewer.compare());
  assert.ok(c.sameHierarchy, c.why);
  const { mesh } = readDpm(new Uint8Array(readFileSync(join(dir, a))), a);
  const { mesh: meshB } = readDpm(new Uint8Array(readFileSync(join(dir, b))), b);
  const largest = await checkFringe(page, {
    a: { file: join(dir, a) }, b: { file: join(dir, b) }, vertexOriginal: mesh.vertexOriginal, what: 'grids',
    levels: [[800, 20], [2608, 30], [mesh.head.baseVertexCount, 5]],
  });
  // Two grids of one input: the difference is their quantization, within both bounds.
  for (const max of largest) assert.ok(max > 0 && max <= mesh.head.maxError + meshB.head.maxError, `${max}`);
  await page.close();
  assert.deepEqual(errors, []);
});

test('two members of one family file open side by side: one file, two variants, the fringe exact per vertex', async () => {
  const page = await catalogue();
  const member = (v) => `article[data-path="family.dpm"] li[data-variant="${v}"] .select`;
  workers.length = 0;
  requests.clear();
  const query = await compareTwo(page, [member('scale050'), member('scale200')]);
  // One file: fetched once (its ranges cover it once, none twice) and decoded by one worker.
  const file = join(dir, 'family.dpm');
  const ranges = (requests.get('/files/family.dpm') ?? []).map((r) => r?.match(/^bytes=(\d+)-(\d+)$/)?.slice(1).map(Number));
  assert.ok(ranges.length > 0 && ranges.every(Boolean), `family.dpm's requests: ${requests.get('/files/family.dpm')}`);
  ranges.sort((x, y) => x[0] - y[0]);
  ranges.forEach(([first], k) => assert.ok(k === 0 ? first === 0 : first === ranges[k - 1][1] + 1, `ranges ${JSON.stringify(ranges)}`));
  // The last range reaches the end (it may ask past it, as the first 64 KiB of a smaller file do).
  const length = readFileSync(file).length;
  assert.ok(ranges.at(-1)[1] + 1 >= length && ranges.at(-1)[0] < length, `ranges ${JSON.stringify(ranges)} of ${length} bytes`);
  assert.equal(workers.filter((u) => u.endsWith('/decode_worker.js')).length, 1, `workers: ${workers}`);
  assert.deepEqual(Object.fromEntries(query), { model: '/files/family.dpm', variant: 'scale050', compare: '/files/family.dpm', compareVariant: 'scale200' });
  const c = await page.evaluate(() => window.dpmViewer.compare());
  assert.ok(c.sameHierarchy, c.why);
  assert.equal(c.variant, 'scale200');
  assert.match(c.labels[0], /^A: family\.dpm \[scale050\] — /);
  assert.match(c.labels[1], /^B: family\.dpm \[scale200\] — /);
  const { mesh } = readDpm(new Uint8Array(readFileSync(file)), file);
  const largest = await checkFringe(page, {
    a: { file, extra: ['--variant', 'scale050'] }, b: { file, extra: ['--variant', 'scale200'] },
    vertexOriginal: mesh.vertexOriginal, what: 'members',
    levels: [[800, 2], [2608, 3], [mesh.head.baseVertexCount, 1], [1300, 2.5]],
  });
  // 0.5 and 2 times one motion: the difference is 1.5 times the motion, far above the grid.
  for (const max of largest) assert.ok(max > 100 * mesh.head.maxError, `${max}`);
  await page.locator('#legend').scrollIntoViewIfNeeded();
  await page.screenshot({ path: join(base, 'compare-members.png') });
  // Overlaid (B's edges in magenta on A's canvas): the same level, step and largest difference,
  // B's marker on A's canvas at B's end of it.
  const side = await page.evaluate(() => window.dpmViewer.compare());
  assert.equal(await page.evaluate(() => window.dynpm.setCompareLayout('edges')), 'edges');
  const over = await page.evaluate(() => window.dpmViewer.compare());
  assert.deepEqual({ ...over, layout: side.layout, labels: side.labels }, side);
  assert.match(over.labels[1], /^B, in magenta over A: family\.dpm \[scale200\] — /);
  await page.screenshot({ path: join(base, 'compare-members-overlay.png') });
  await page.close();
  assert.deepEqual(errors, []);
  assert.ok(readdirSync(base).includes('compare-members.png'));
});
