// A family file in the page (docs/family.md): ?variant=NAME shows that variant — its steps, its
// times, its positions — and without it variant 0; the file is fuzz/corpus/dpm/small_grid_family.dpm.
//
// Environment (CTest): DYNPM_CLI (the dynpm binary, which serves the page).
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, test } from 'node:test';

import { chromium } from 'playwright-core';

import { findVariant, readDpm, variantView } from '../src/dpm.js';
import { allShown, CHROMIUM_ARGS, startServer } from './chromium.mjs';

const { DYNPM_CLI: cli } = process.env;
if (!cli) throw new Error('family_browser.test.mjs needs DYNPM_CLI');
const file = join('..', 'fuzz', 'corpus', 'dpm', 'small_grid_family.dpm');
const { mesh } = readDpm(new Uint8Array(readFileSync(file)), file);

const running = [];
after(async () => {
  for (const r of running) await r.close();
});

async function shown(query) {
  const { server, url } = await startServer(cli, file);
  const browser = await chromium.launch({ executablePath: process.env.DYNPM_CHROMIUM ?? '/usr/bin/chromium', headless: true, args: CHROMIUM_ARGS });
  running.push({ close: async () => (await browser.close(), server.kill()) });
  const errors = [];
  const page = await browser.newPage();
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto(url + query);
  await page.waitForFunction(allShown, null, { timeout: 30000 });
  const stepCount = await page.evaluate(() => window.dynpm.view().stepCount);
  const title = await page.evaluate(() => document.getElementById('title').textContent);
  assert.deepEqual(errors, []);
  return { stepCount, title };
}

for (const [query, which] of [['', 0], ['?variant=bulge', 'bulge'], ['?variant=0', 0]]) {
  test(`the page shows variant ${which} for '${query}'`, async () => {
    const view = variantView(mesh, findVariant(mesh, which));
    const { stepCount, title } = await shown(query);
    assert.equal(stepCount, view.head.stepCount);
    assert.match(title, new RegExp(view.variant.name));
  });
}

// The panel's variant list: switching keeps the camera, the level and the step (clamped to the
// member's last), and shows what a page opened on that member shows.
test('the variant list switches members in place', async () => {
  const { server, url } = await startServer(cli, file);
  const browser = await chromium.launch({ executablePath: process.env.DYNPM_CHROMIUM ?? '/usr/bin/chromium', headless: true, args: CHROMIUM_ARGS });
  running.push({ close: async () => (await browser.close(), server.kill()) });
  const errors = [];
  const open = async (query) => {
    const page = await browser.newPage({ viewport: { width: 900, height: 600 } });
    page.on('pageerror', (e) => errors.push(String(e)));
    page.on('console', (m) => m.type() === 'error' && errors.push(m.text()));
    await page.goto(url + query);
    await page.waitForFunction(allShown, null, { timeout: 30000 });
    return page;
  };
  const page = await open('?variant=bulge');
  const options = await page.$$eval('#variant option', (os) => os.map((o) => [o.value, o.textContent]));
  assert.deepEqual(options, mesh.variants.map((v, k) => [String(k), `${k}: ${v.name} (${v.steps.length} steps)`]));
  assert.equal(await page.inputValue('#variant'), '1');
  assert.equal(await page.isVisible('#variant'), true);
  const level = 30;
  await page.evaluate((n) => (window.dynpm.setView('+x'), window.dynpm.setStep(3), window.dynpm.setLevel({ vertices: n })), level);
  const before = await page.evaluate(() => window.dynpm.view());
  await page.selectOption('#variant', '0');
  const wave = variantView(mesh, 0);
  const after = await page.evaluate(() => window.dynpm.view());
  assert.equal(after.stepCount, wave.head.stepCount);
  assert.equal(after.step, wave.head.stepCount - 1, 'the step clamped to wave\'s last');
  assert.equal(after.vertices, level, 'the level kept');
  for (const key of ['up', 'look', 'screenUp', 'target', 'camera']) assert.deepEqual(after[key], before[key], `the camera's ${key}`);
  assert.deepEqual(await page.evaluate(() => window.dynpm.variant()), { index: 0, name: 'wave', count: 2 });
  assert.match(await page.textContent('#title'), /— wave \(variant 0 of 2\)/);
  assert.equal(new URL(page.url()).searchParams.get('variant'), 'wave');
  // What a page opened on wave at that step, level and view shows (the up axis, which the page
  // chooses from the member's motion, set alike).
  const view = () => (window.dynpm.setUp('z'), window.dynpm.setView('+x'));
  await page.evaluate(view);
  const waveSnapshot = await page.evaluate(() => window.dpmViewer.snapshot());
  const fresh = await open('?variant=wave');
  await fresh.evaluate(([n, t]) => (window.dynpm.setStep(t), window.dynpm.setLevel({ vertices: n })), [level, wave.head.stepCount - 1]);
  await fresh.evaluate(view);
  const expected = await fresh.evaluate(() => window.dpmViewer.snapshot());
  const mean = (a, b) => a.reduce((s, x, i) => s + Math.abs(x - b[i]), 0) / a.length;
  assert.ok(mean(waveSnapshot, expected) < 1, `switched and opened on wave differ by ${mean(waveSnapshot, expected)}`);
  // And back, by the API: bulge at wave's last step (2), which looks different.
  assert.equal(await page.evaluate(() => window.dynpm.setVariant('bulge')), 'bulge');
  const back = await page.evaluate(() => window.dynpm.view());
  assert.equal(back.stepCount, variantView(mesh, 1).head.stepCount);
  assert.equal(back.step, 2);
  const bulgeSnapshot = await page.evaluate(() => window.dpmViewer.snapshot());
  assert.ok(mean(bulgeSnapshot, waveSnapshot) > 1, `bulge and wave at step 2 differ by ${mean(bulgeSnapshot, waveSnapshot)}`);
  await assert.rejects(page.evaluate(() => window.dynpm.setVariant('nothing')), /no variant 'nothing'/);
  assert.deepEqual(errors, []);
});
