// The page decodes in a Web Worker (docs/viewer.md "Decoding in a worker"): in Debian's headless
// Chromium, `dynpm view` serves the sample; the page must start src/decode_worker.js (which hands
// each SPLT's positions to src/positions_worker.js), share the mesh's memory with it (the server makes the page cross-origin isolated), end it once loaded,
// and show exactly what the decoder on the page's own thread (?worker=0) shows: the same counts
// and the same picture at the full level, at a coarse level and between two steps.
//
// If Chromium cannot start, this fails: it never skips.
import assert from 'node:assert/strict';
import { after, before, test } from 'node:test';

import { chromium } from 'playwright-core';

import { CHROMIUM_ARGS, startServer } from './chromium.mjs';

const { DYNPM_CLI: cli, DYNPM_DPM: dpm } = process.env;
if (!cli || !dpm) throw new Error('worker_browser.test.mjs needs DYNPM_CLI and DYNPM_DPM');
const CHROMIUM = process.env.DYNPM_CHROMIUM ?? '/usr/bin/chromium';

let server, url, browser;
before(async () => {
  ({ server, url } = await startServer(cli, dpm));
  browser = await chromium.launch({ executablePath: CHROMIUM, headless: true, args: CHROMIUM_ARGS });
});
after(async () => {
  await browser?.close();
  server?.kill('SIGINT');
});

// Loads the page, waits for the whole model; returns the page, the workers it started (URL and
// whether closed) and the errors it logged.
async function load(query) {
  const page = await browser.newPage({ viewport: { width: 640, height: 480 } });
  const workers = [];
  const errors = [];
  page.on('worker', (w) => {
    const record = { url: w.url(), closed: false };
    workers.push(record);
    w.on('close', () => (record.closed = true));
  });
  page.on('console', (m) => m.type() === 'error' && errors.push(m.text()));
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto(url + query);
  await page.waitForFunction(() => window.dpmViewer?.state().complete, null, { timeout: 60000 });
  await page.evaluate(() => window.dpmViewer.done);
  return { page, workers, errors };
}

const difference = (a, b) => a.reduce((s, x, i) => s + Math.abs(x - b[i]), 0) / a.length;

// The picture at a level and a (fractional) step, after the same camera and size.
async function views(page) {
  return page.evaluate(() => {
    const v = window.dpmViewer;
    const full = v.state().vertices;
    const out = { full: v.snapshot(), state: v.state() };
    v.setVertexCount(Math.ceil(full / 10));
    out.coarse = v.snapshot();
    out.coarseState = v.state();
    v.setVertexCount(full);
    return out;
  });
}

test('the decoder runs in a worker that shares the mesh and ends once the file is in', async () => {
  const { page, workers, errors } = await load('');
  const s = await page.evaluate(() => window.dpmViewer.state());
  assert.deepEqual(errors, []);
  assert.equal(s.error, null);
  assert.ok(s.worker, 'the page says it used the worker');
  assert.ok(await page.evaluate(() => crossOriginIsolated), 'dynpm view makes the page cross-origin isolated');
  assert.ok(s.sharedMemory, 'the worker and the page share the mesh');
  const decoders = workers.filter((w) => new URL(w.url).pathname.endsWith('/src/decode_worker.js'));
  assert.equal(decoders.length, 1, `workers started: ${JSON.stringify(workers)}`);
  // The positions on a second worker (docs/viewer.md "Decoding in a worker"), started by the first.
  const positions = workers.filter((w) => new URL(w.url).pathname.endsWith('/src/positions_worker.js'));
  assert.equal(positions.length, 1, `workers started: ${JSON.stringify(workers)}`);
  assert.ok(s.positionsWorker, 'and it answered: the decode worker handed it the positions');
  // The close event arrives a little after the last message: within 200 ms on an idle machine,
  // later when the tests run two browsers on two cores.
  for (let waited = 0; waited < 5000 && !decoders[0].closed; waited += 100) await new Promise((resolve) => setTimeout(resolve, 100));
  assert.ok(decoders[0].closed, 'the worker has ended: its copy of the file is gone');
  assert.ok(s.vertices > 1000 && s.vertices === s.loadedVertices, `${s.vertices} of ${s.loadedVertices} vertices`);
  await page.close();
});

test('the worker shows what the decoder on the page thread shows', async () => {
  const inWorker = await load('');
  const onPage = await load('?worker=0');
  assert.equal(onPage.workers.length, 0, '?worker=0 starts no worker');
  const a = await views(inWorker.page);
  const b = await views(onPage.page);
  for (const key of ['vertices', 'faces', 'triangles', 'quads', 'loadedVertices'])
    assert.equal(a.state[key], b.state[key], key);
  assert.equal(a.coarseState.faces, b.coarseState.faces, 'faces at the coarse level');
  assert.ok(difference(a.full, b.full) < 0.5, `full level: pictures differ by ${difference(a.full, b.full)}`);
  assert.ok(difference(a.coarse, b.coarse) < 0.5, `coarse level: pictures differ by ${difference(a.coarse, b.coarse)}`);
  assert.ok(difference(a.full, a.coarse) > 0.05, 'the coarse level looks different (the comparison can fail)');
  // Between two steps: positions read from the shared memory.
  const at = (page) => page.evaluate(() => {
    const t = document.getElementById('time');
    t.value = String(Number(t.max) * 0.6 + 0.3);
    t.dispatchEvent(new Event('input'));
    return window.dpmViewer.snapshot();
  });
  const ta = await at(inWorker.page), tb = await at(onPage.page);
  assert.ok(difference(ta, tb) < 0.5, `at a fractional step: pictures differ by ${difference(ta, tb)}`);
  assert.deepEqual([...inWorker.errors, ...onPage.errors], []);
  await inWorker.page.close();
  await onPage.page.close();
});
