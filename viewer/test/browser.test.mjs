// The page in Debian's headless Chromium, driven by playwright-core: `dynpm view` serves the
// sample's .dpm (throttled, so that loading is seen to be progressive); the test waits for the
// base mesh, checks the canvas shows something, moves the resolution and time sliders with the
// mouse and checks the stats line and the picture change; the max error box gives the levels
// dpm.js gives. Screenshots go to DYNPM_TEST_OUT.
//
// If Chromium cannot start, this fails: it never skips.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdirSync, readFileSync } from 'node:fs';
import { createServer } from 'node:http';
import { extname, join, normalize } from 'node:path';
import { after, before, test } from 'node:test';

import { chromium } from 'playwright-core';

import { Navigator, readDpm } from '../src/dpm.js';
import { allShown, CHROMIUM_ARGS, startServer } from './chromium.mjs';

const { DYNPM_CLI: cli, DYNPM_DPM: dpm, DYNPM_TEST_OUT: out } = process.env;
if (!cli || !dpm || !out) throw new Error('browser.test.mjs needs DYNPM_CLI, DYNPM_DPM, DYNPM_TEST_OUT');
mkdirSync(out, { recursive: true });
const CHROMIUM = process.env.DYNPM_CHROMIUM ?? '/usr/bin/chromium';

function variance(xs) {
  const mean = xs.reduce((a, x) => a + x, 0) / xs.length;
  return xs.reduce((a, x) => a + (x - mean) ** 2, 0) / xs.length;
}
const difference = (a, b) => a.reduce((s, x, i) => s + Math.abs(x - b[i]), 0) / a.length;

function statsNumbers(text) {
  const get = (word) => Number(text.match(new RegExp(`${word} ([\\d,]+)`))[1].replace(/,/g, ''));
  return { vertices: get('vertices'), triangles: get('triangles'), quads: get('quads') };
}

let server, url, browser, page;
const consoleErrors = [];

before(async () => {
  // About 4.5 s for the sample's file (187 KB since version 2): BASE arrives long before the
  // last split.
  ({ server, url } = await startServer(cli, dpm, ['--throttle', '40']));
  browser = await chromium.launch({ executablePath: CHROMIUM, headless: true, args: CHROMIUM_ARGS });
  page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  page.on('console', (m) => m.type() === 'error' && consoleErrors.push(m.text()));
  page.on('pageerror', (e) => consoleErrors.push(String(e)));
});

after(async () => {
  await browser?.close();
});

async function click(selector, fraction) {
  const box = await page.locator(selector).boundingBox();
  await page.mouse.click(box.x + 8 + (box.width - 16) * fraction, box.y + box.height / 2);
}

test('shows the base mesh before the file has arrived, then refines to the full mesh', async () => {
  await page.goto(url);
  await page.waitForFunction(() => window.dpmViewer?.state().hasBase, null, { timeout: 20000 });
  const first = await page.evaluate(() => window.dpmViewer.state());
  assert.equal(first.error, null);
  assert.equal(first.complete, false, 'the base mesh shows while splits are still coming');
  const picture = await page.evaluate(() => window.dpmViewer.snapshot());
  assert.ok(variance(picture) > 20, `canvas is not blank (variance ${variance(picture)})`);
  await page.screenshot({ path: join(out, 'viewer-base.png') });

  await page.waitForFunction(allShown, null, { timeout: 30000 });
  const full = await page.evaluate(() => window.dpmViewer.state());
  assert.ok(full.vertices > first.vertices, `refined from ${first.vertices} to ${full.vertices}`);
  assert.equal(full.vertices, full.loadedVertices);
  const stats = statsNumbers(await page.locator('#stats').textContent());
  assert.equal(stats.vertices, full.vertices);
  assert.equal(stats.triangles + stats.quads, full.faces);
  await page.screenshot({ path: join(out, 'viewer-full.png') });
  assert.deepEqual(consoleErrors, []);
});

test('the resolution slider changes the faces and the picture', async () => {
  const before = statsNumbers(await page.locator('#stats').textContent());
  const picture = await page.evaluate(() => window.dpmViewer.snapshot());
  await click('#resolution', 0.02);
  const coarse = statsNumbers(await page.locator('#stats').textContent());
  assert.ok(coarse.vertices < before.vertices / 2, `${coarse.vertices} vertices after the move`);
  assert.ok(coarse.triangles + coarse.quads < before.triangles + before.quads);
  const label = await page.locator('#resolution-label').textContent();
  assert.match(label, /vertices \([\d.]+%\), error [\d.e+-]+/);
  const coarsePicture = await page.evaluate(() => window.dpmViewer.snapshot());
  assert.ok(difference(picture, coarsePicture) > 0.2, 'the picture changed');
  await page.screenshot({ path: join(out, 'viewer-coarse.png') });
  await click('#resolution', 1);
  const back = statsNumbers(await page.locator('#stats').textContent());
  assert.deepEqual(back, before, 'back at full resolution: the same counts');
});

test('the max error box: E and E% give the coarsest level within them, as dpm.js does; bad values refused; the slider clears it', async () => {
  const { mesh } = readDpm(new Uint8Array(readFileSync(dpm)), dpm);
  const h = mesh.head;
  const diagonal = Math.hypot(...h.bboxMax.map((x, c) => x - h.bboxMin[c]));
  const box = page.locator('#resolution-error');
  const vertices = async () => (await page.evaluate(() => window.dpmViewer.state())).vertices;
  const nav = new Navigator(mesh);
  for (const [text, e] of [[800, null], [3000, null], ['0.05%', 0.0005 * diagonal], ['1e9', 1e9]]) {
    // A number from a level's own error (the boundary case), or as given.
    if (e === null) nav.setVertexCount(text);
    const error = e ?? nav.error;
    await box.fill(e === null ? String(error) : text);
    await box.press('Enter');
    const n = h.baseVertexCount + mesh.levelForError(error);
    assert.equal(await vertices(), n, `max error ${text}`);
    nav.setVertexCount(n);
    assert.ok(nav.error <= error, `${nav.error} ≤ ${error}`);
    if (n > h.baseVertexCount) (nav.setVertexCount(n - 1), assert.ok(nav.error > error, `one split coarser than ${n} is above ${error}`));
    assert.equal(await box.evaluate((b) => b.validationMessage), '');
  }
  assert.equal(await vertices(), h.baseVertexCount, '1e9: the base mesh');
  for (const bad of ['abc', '-1', '101%', '1,5']) {
    await box.fill(bad);
    await box.press('Enter');
    assert.match(await box.evaluate((b) => b.validationMessage), /a number ≥ 0 in model units, or a percentage of the box diagonal/, bad);
    assert.equal(await vertices(), h.baseVertexCount, `${bad}: the level stays`);
  }
  await page.locator('#resolution').fill('1000');
  assert.equal(await vertices(), 1000);
  assert.deepEqual(await box.evaluate((b) => [b.value, b.validationMessage]), ['', ''], 'the slider clears the box');
  await page.evaluate(() => window.dynpm.setLevel({ ratio: 1 }));
});

test('the time slider and play move the animation', async () => {
  const picture = await page.evaluate(() => window.dpmViewer.snapshot());
  await click('#time', 1);
  const t = await page.evaluate(() => window.dpmViewer.state().t);
  assert.ok(t > 0, `time moved to ${t}`);
  assert.match(await page.locator('#stats').textContent(), /step [1-9][\d.]*/);
  const later = await page.evaluate(() => window.dpmViewer.snapshot());
  assert.ok(difference(picture, later) > 0.2, 'the picture changed with time');
  await page.screenshot({ path: join(out, 'viewer-last-step.png') });
  // Play a while: time advances by itself.
  await click('#time', 0);
  await page.locator('#play').click();
  await page.waitForTimeout(600);
  await page.locator('#play').click();
  assert.ok((await page.evaluate(() => window.dpmViewer.state().t)) > 0, 'playing advances time');
});

test('displacement colours, legend and element edges', async () => {
  await click('#time', 1);
  const plain = await page.evaluate(() => window.dpmViewer.snapshot());
  await page.locator('#colour').selectOption('displacement');
  assert.match(await page.locator('#legend').textContent(), /displacement/);
  const coloured = await page.evaluate(() => window.dpmViewer.snapshot());
  assert.ok(difference(plain, coloured) > 0.2, 'colours changed');
  await page.screenshot({ path: join(out, 'viewer-displacement.png') });
  await page.locator('#edges').uncheck();
  const noEdges = await page.evaluate(() => window.dpmViewer.snapshot());
  assert.ok(difference(coloured, noEdges) > 0.05, 'edges toggled');
  await page.locator('#edges').check();
  await page.locator('#reset').click();
  assert.deepEqual(consoleErrors, []);
});

test('time scrubbing frame times (reported, not asserted)', async () => {
  const r = await page.evaluate(() => window.dpmViewer.scrub(90));
  const sorted = [...r.frameMs].sort((a, b) => a - b);
  const median = sorted[sorted.length >> 1];
  const state = await page.evaluate(() => window.dpmViewer.state());
  console.log(
    `scrub: ${state.vertices} vertices, median frame ${median.toFixed(1)} ms ` +
      `(${(1000 / median).toFixed(0)} fps), JS update ${r.updateMs.toFixed(2)} ms/frame`,
  );
});

test('--export writes a folder that a plain static server can host', async () => {
  const dir = join(out, 'export');
  execFileSync(cli, ['view', dpm, '--export', dir], { stdio: 'pipe' });
  const types = { '.html': 'text/html', '.js': 'text/javascript', '.css': 'text/css' };
  const files = createServer((req, res) => {
    const path = normalize(new URL(req.url, 'http://x').pathname).replace(/^\/+/, '') || 'index.html';
    try {
      const body = readFileSync(join(dir, path));
      res.writeHead(200, { 'Content-Type': types[extname(path)] ?? 'application/octet-stream' });
      res.end(body);
    } catch {
      res.writeHead(404).end();
    }
  });
  await new Promise((resolve) => files.listen(0, '127.0.0.1', resolve));
  try {
    const exported = await browser.newPage({ viewport: { width: 800, height: 600 } });
    await exported.goto(`http://127.0.0.1:${files.address().port}/`);
    await exported.waitForFunction(allShown, null, { timeout: 30000 });
    const s = await exported.evaluate(() => window.dpmViewer.state());
    assert.equal(s.error, null);
    assert.equal(s.vertices, s.loadedVertices);
    // A plain server does not make the page cross-origin isolated: the worker copies the mesh.
    assert.ok(s.worker && !s.sharedMemory, `decoded in a worker, copied: ${JSON.stringify(s)}`);
    const picture = await exported.evaluate(() => window.dpmViewer.snapshot());
    assert.ok(variance(picture) > 20, 'the exported page draws');
    await exported.close();
  } finally {
    files.close();
  }
});

test('Ctrl-C stops dynpm view cleanly', async () => {
  const code = await new Promise((resolve) => {
    server.removeAllListeners('exit');
    server.on('exit', (c) => resolve(c));
    server.kill('SIGINT');
  });
  assert.equal(code, 0);
});
