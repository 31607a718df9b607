// Fetching by HTTP ranges (docs/viewer.md "Fetching by ranges"), in headless Chromium on
// `dynpm view` (throttled, so that the order of what arrives is seen): the base mesh is drawn
// before the whole file is in; a page that asks for a coarse level (?vertices=N), or whose memory
// budget for the steps' values (?memory=MiB) holds only part of the model, stops after the chunks
// that hold it, having fetched only part of the file; the slider asks for the rest,
// which then arrives whole, as does a max error no loaded level reaches. The plain GET (a
// server without ranges) is browser.test.mjs's --export case.
import assert from 'node:assert/strict';
import { readFileSync, statSync } from 'node:fs';
import { after, before, test } from 'node:test';

import { chromium } from 'playwright-core';

import { readDpm, withChunkMargin } from '../src/dpm.js';
import { positionBytes } from '../src/dpm/step_positions.js';
import { CHROMIUM_ARGS, startServer } from './chromium.mjs';

const { DYNPM_CLI: cli, DYNPM_DPM: dpm } = process.env;
if (!cli || !dpm) throw new Error('range_browser.test.mjs needs DYNPM_CLI, DYNPM_DPM');
const CHROMIUM = process.env.DYNPM_CHROMIUM ?? '/usr/bin/chromium';
const size = statSync(dpm).size;

let server, url, browser;
before(async () => {
  ({ server, url } = await startServer(cli, dpm, ['--throttle', '60']));
  browser = await chromium.launch({ executablePath: CHROMIUM, headless: true, args: CHROMIUM_ARGS });
});
after(async () => {
  await browser?.close();
  server?.kill('SIGINT');
});

async function open(query) {
  const page = await browser.newPage({ viewport: { width: 640, height: 400 } });
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  const ranges = [];
  page.on('request', (r) => r.url().endsWith('.dpm') && ranges.push(r.headers().range ?? 'none'));
  await page.goto(url + query);
  return { page, errors, ranges };
}

const state = (page) => page.evaluate(() => window.dpmViewer.state());

test('the base mesh is drawn before the file is in, from range requests', async () => {
  const { page, errors, ranges } = await open('');
  await page.waitForFunction(() => window.dpmViewer?.state().hasBase, null, { timeout: 20000 });
  const first = await state(page);
  assert.ok(first.rangeRequests, 'the server answered 206');
  // As counted when the base was drawn: the rest may have come in since (a loaded machine).
  const atBase = await page.evaluate(() => window.dpmViewer.timing.baseBytes);
  assert.ok(atBase > 0 && atBase < size, `base shown after ${atBase} of ${size} bytes`);
  const grey = await page.evaluate(() => window.dpmViewer.snapshot(32));
  assert.ok(new Set(grey).size > 1, 'the base mesh is on the canvas');
  // Complete, and the level has followed the file to its end.
  const followed = () => ((s) => s.complete && s.vertices === s.loadedVertices)(window.dpmViewer.state());
  await page.waitForFunction(followed, null, { timeout: 60000 });
  const last = await state(page);
  assert.equal(last.bytesLoaded, size);
  assert.equal(last.loadedVertices, last.vertices);
  // The first request takes 64 KiB: a larger file needs more than one.
  assert.ok(size > 65536, `the sample is ${size} bytes`);
  assert.ok(ranges.length >= 2 && ranges.every((r) => /^bytes=\d+-\d+$/.test(r)), ranges.join(' '));
  assert.equal(ranges[0], 'bytes=0-65535');
  assert.deepEqual(errors, []);
  await page.close();
});

// The page's state once nothing more arrives (the decoder paused at ?vertices=N).
async function paused(page) {
  await page.waitForFunction(() => window.dpmViewer?.state().navigator, null, { timeout: 20000 });
  let s = await state(page);
  for (let before = -1; before !== s.bytesLoaded; ) {
    before = s.bytesLoaded;
    await new Promise((resolve) => setTimeout(resolve, 1500));
    s = await state(page);
  }
  return s;
}
// The bytes a vertex's positions take on the page, at least (the stored arrays: step 0, the first
// motion in 16 bits, and the packed steps after, which on the sample need more than a byte a
// vertex a step; 32 bits a coordinate when lossless) and at most (the budget's estimate, escaped
// values and a cursor in it, and a second cursor).
function positionBounds({ stepCount: T, flags }) {
  const lossless = (flags & 1) !== 0;
  return [lossless ? 12 * T : 12 + 6 + (T - 2), positionBytes(T, lossless) + 24];
}

const followed = () => ((s) => s.complete && s.vertices === s.loadedVertices)(window.dpmViewer.state());

test('?vertices=N fetches only the chunks up to N vertices; the slider fetches the rest', async () => {
  const { page, errors } = await open('?vertices=1');
  let s = await paused(page);
  const total = await page.evaluate(() => Number(document.getElementById('resolution').max));
  assert.ok(s.bytesLoaded < size, `${s.bytesLoaded} of ${size} bytes fetched for the base level`);
  assert.ok(s.loadedVertices < total, `${s.loadedVertices} of ${total} vertices`);
  assert.equal(s.complete, false);
  assert.doesNotMatch(await page.locator('#stats').textContent(), /…/, 'paused: the status line says no more is coming');
  // Memory in proportion to what is loaded: every step's positions of the loaded vertices (with
  // room for as many again, as arrays grow), not of the whole file (docs/viewer.md "Memory").
  const steps = await page.evaluate(() => window.dynpm.view().stepCount);
  const positionsHeld = () => page.evaluate(() => window.dpmViewer.memory().positions);
  const held = await positionsHeld();
  const { head } = readDpm(new Uint8Array(readFileSync(dpm)), dpm).mesh;
  const [least, most] = positionBounds(head);
  assert.ok(held >= least * s.loadedVertices && held <= 2 * most * s.loadedVertices && held < 12 * total * steps / 3,
    `${held} bytes of positions for ${s.loadedVertices} of ${total} vertices × ${steps} steps`);
  // The ids and split records count as far as they are filled: 12 B a loaded vertex (original
  // index, node id) and 16 a loaded face (original index, part, element id), not the whole
  // model's arrays.
  const { ids } = await page.evaluate(() => window.dpmViewer.memory());
  // (faces: at most two a vertex on these meshes).
  const allIds = 12 * head.vertexCount + 16 * head.faceCount;
  assert.ok(ids >= 12 * s.loadedVertices && ids <= 44 * s.loadedVertices && ids < allIds,
    `${ids} bytes of ids for ${s.loadedVertices} of ${total} vertices (all: ${allIds})`);
  // The slider's far end asks for every vertex (the panel starts collapsed in this small window).
  await page.locator('#panel-toggle').click();
  const box = await page.locator('#resolution').boundingBox();
  await page.mouse.click(box.x + box.width - 2, box.y + box.height / 2);
  await page.waitForFunction(followed, null, { timeout: 60000 });
  s = await state(page);
  assert.equal(s.bytesLoaded, size);
  assert.equal(s.loadedVertices, total);
  assert.equal(s.vertices, total, 'following the file to the full mesh');
  const all = await positionsHeld();
  assert.ok(all >= least * total && all <= most * total, `${all} bytes of positions for all ${total} vertices`);
  assert.deepEqual(errors, []);
  await page.close();
});

test('without ?vertices=N the page loads at first the levels whose values fit ?memory=MiB; the slider the rest', async () => {
  const { page, errors } = await open('?memory=0.25');
  const s = await paused(page);
  const steps = await page.evaluate(() => window.dynpm.view().stepCount);
  const total = await page.evaluate(() => Number(document.getElementById('resolution').max));
  // 0.25 MiB: a vertex's positions (about 3 B a step, compact), 2 B a step for each field's value
  // (4 when lossless) and 200 B for what does not depend on the steps.
  const { head } = readDpm(new Uint8Array(readFileSync(dpm)), dpm).mesh;
  const { fieldCount, flags } = head;
  const budgeted = Math.floor(2 ** 18 / (positionBytes(steps, (flags & 1) !== 0) + (flags & 1 ? 4 : 2) * fieldCount * steps + 200));
  assert.ok(budgeted < total, `the sample's ${total} vertices × ${steps} steps fit 0.25 MiB`);
  assert.equal(s.paused, true);
  assert.ok(s.loadedVertices >= budgeted && s.loadedVertices < total && s.bytesLoaded < size,
    `${s.loadedVertices} of ${total} vertices (${budgeted} budgeted), ${s.bytesLoaded} of ${size} bytes`);
  assert.match(await page.locator('#resolution-label').textContent(), /loaded \(the levels whose arrays fit 256\.0 KiB/);
  const held = await page.evaluate(() => window.dpmViewer.memory().positions);
  const [least, most] = positionBounds(head);
  assert.ok(held >= least * s.loadedVertices && held <= 2 * most * s.loadedVertices, `${held} bytes of positions`);
  // The draw buffers grow to what the worker loads before it pauses (the budget's vertices and a
  // margin, or the chunk that crossed them when it was longer), not 4× past it: 28 bytes a
  // vertex (positions, colours, a scalar) and 56 a face (triangle and edge index entries), the
  // faces in proportion with a quarter more.
  const expected = Math.max(withChunkMargin(budgeted), s.loadedVertices);
  const drawn = await page.evaluate(() => window.dpmViewer.memory().draw);
  const drawRoom = 28 * expected + 56 * Math.ceil((1.25 * expected * head.faceCount) / head.vertexCount);
  assert.ok(drawn <= drawRoom, `${drawn} bytes of draw buffers for ${s.loadedVertices} vertices (room for ${expected}: ${drawRoom})`);
  await page.locator('#panel-toggle').click();
  const box = await page.locator('#resolution').boundingBox();
  await page.mouse.click(box.x + box.width - 2, box.y + box.height / 2);
  await page.waitForFunction(followed, null, { timeout: 60000 });
  const full = await state(page);
  assert.equal(full.bytesLoaded, size);
  assert.equal(full.loadedVertices, total);
  assert.equal(full.paused, false);
  assert.doesNotMatch(await page.locator('#resolution-label').textContent(), /fit 256/);
  assert.deepEqual(errors, []);
  await page.close();
});

test('the max error box asks for the rest of the file when no level loaded reaches the error', async () => {
  const { page, errors } = await open('?vertices=1');
  const s = await paused(page);
  assert.equal(s.complete, false);
  await page.locator('#panel-toggle').click();
  await page.locator('#resolution-error').fill('0');  // only the full mesh is exact
  await page.locator('#resolution-error').press('Enter');
  await page.waitForFunction(followed, null, { timeout: 60000 });
  const full = await state(page);
  assert.equal(full.bytesLoaded, size);
  assert.equal(full.vertices, await page.evaluate(() => Number(document.getElementById('resolution').max)));
  assert.deepEqual(errors, []);
  await page.close();
});
