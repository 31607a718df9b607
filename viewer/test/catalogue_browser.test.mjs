// `dynpm serve`'s catalogue page in headless Chromium (docs/batch.md "dynpm serve"): a folder of
// 24 variants (copies of the sample's .dpm, made here; two without a thumbnail) is listed with
// thumbnails and metadata, filtered by name, opened in the viewer (/view?model=…), and two are
// opened side by side (/view?model=…&compare=…: the viewer shows the first; the second is the
// compare view's, viewer/src/viewer.js). A variant built while the page is open appears by
// itself. The page's screenshot goes to DYNPM_TEST_OUT/serve-browser/catalogue.png.
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { copyFileSync, mkdirSync, renameSync, rmSync } from 'node:fs';
import { join } from 'node:path';
import { after, before, test } from 'node:test';

import { chromium } from 'playwright-core';

import { CHROMIUM_ARGS, allShown, startServer } from './chromium.mjs';

const { DYNPM_CLI: cli, DYNPM_DPM: dpm, DYNPM_TEST_OUT: out } = process.env;
if (!cli || !dpm || !out) throw new Error('catalogue_browser.test.mjs needs DYNPM_CLI, DYNPM_DPM, DYNPM_TEST_OUT');
const CHROMIUM = process.env.DYNPM_CHROMIUM ?? '/usr/bin/chromium';
const base = join(out, 'serve-browser');
const dir = join(base, 'doe');
const names = Array.from({ length: 22 }, (_, i) => `t${String(i + 1).padStart(2, '0')}`);

let server, url, browser;
const errors = [];
before(async () => {
  rmSync(base, { recursive: true, force: true });
  mkdirSync(join(dir, 'thickness'), { recursive: true });
  for (const name of names) copyFileSync(dpm, join(dir, 'thickness', `${name}.dpm`));
  // Two built without a thumbnail (as files from before dynpm stored one): a placeholder.
  for (const name of ['old-a', 'old-b'])
    assert.equal(spawnSync(cli, ['build', join(out, '..', 'sample', 'hat-rail', 'frame_*.obj'), '-o', join(dir, `${name}.dpm`), '--no-thumbnail', '--quiet']).status, 0);
  ({ server, url } = await startServer(cli, dir, [], 'serve'));
  browser = await chromium.launch({ executablePath: CHROMIUM, headless: true, args: CHROMIUM_ARGS });
});
after(async () => {
  await browser?.close();
  server?.kill('SIGTERM');
});

async function newPage(viewport = { width: 1280, height: 860 }) {
  const page = await browser.newPage({ viewport });
  page.on('console', (m) => m.type() === 'error' && !/404/.test(m.text()) && errors.push(m.text()));
  page.on('pageerror', (e) => errors.push(String(e)));
  return page;
}
const listed = (page) => page.evaluate(() => window.dynpmCatalogue?.entries() ?? []);
const shown = (page) => page.evaluate(() => window.dynpmCatalogue.shown());

test('lists the 24 variants with their metadata and thumbnails, and filters them', async () => {
  const page = await newPage();
  await page.goto(url + '?poll=300');
  await page.waitForFunction(() => window.dynpmCatalogue?.entries().length === 24);
  assert.equal((await listed(page)).length, 24);
  assert.equal(await page.textContent('#count'), '24 files');
  const card = page.locator('article[data-path="thickness/t07.dpm"]');
  assert.equal(await card.locator('h2').textContent(), 't07');
  const facts = await card.locator('.facts').allTextContents();
  assert.ok(facts.some((t) => /2,608 nodes · 2,558 faces · 31 steps/.test(t)), facts.join(' | '));
  // Thumbnails: decoded PNGs of 256 × 192; the two old files a placeholder.
  await page.waitForFunction(() => [...document.querySelectorAll('img.thumb')].every((i) => i.complete && i.naturalWidth > 0));
  const sizes = await page.$$eval('img.thumb', (imgs) => imgs.map((i) => `${i.naturalWidth}x${i.naturalHeight}`));
  assert.equal(sizes.length, 22);
  assert.ok(sizes.every((s) => s === '256x192'), sizes.join());
  assert.equal(await page.locator('.placeholder').count(), 2);
  mkdirSync(base, { recursive: true });
  await page.screenshot({ path: join(base, 'catalogue.png') });

  await page.fill('#filter', 't1');
  assert.deepEqual(await shown(page), names.filter((n) => n.startsWith('t1')).map((n) => `thickness/${n}.dpm`));
  assert.equal(await page.textContent('#count'), '10 of 24 files');
  await page.fill('#filter', 'OLD');
  assert.deepEqual(await shown(page), ['old-a.dpm', 'old-b.dpm']);
  await page.fill('#filter', 'nothing-like-this');
  assert.deepEqual(await shown(page), []);
  assert.equal(await page.isVisible('#empty'), true);
  await page.fill('#filter', '');
  assert.equal((await shown(page)).length, 24);

  // A variant that a batch finishes while the page is open: listed by the next poll.
  copyFileSync(dpm, join(dir, 'thickness', 'late.dpm.tmp-777-0'));
  renameSync(join(dir, 'thickness', 'late.dpm.tmp-777-0'), join(dir, 'thickness', 'late.dpm'));
  await page.waitForFunction(() => window.dynpmCatalogue.entries().includes('thickness/late.dpm'), null, { timeout: 10000 });
  assert.equal(await page.textContent('#count'), '25 files');
  rmSync(join(dir, 'thickness', 'late.dpm'));
  await page.waitForFunction(() => window.dynpmCatalogue.entries().length === 24, null, { timeout: 10000 });
  await page.close();
  assert.deepEqual(errors, []);
});

test('opens one variant in the viewer', async () => {
  const page = await newPage({ width: 800, height: 600 });
  await page.goto(url);
  await page.waitForFunction(() => window.dynpmCatalogue?.entries().length === 24);
  await Promise.all([page.waitForURL(/\/view\?/), page.click('article[data-path="thickness/t03.dpm"] h2 a')]);
  assert.equal(new URL(page.url()).searchParams.get('model'), '/files/thickness/t03.dpm');
  await page.waitForFunction(allShown, null, { timeout: 60000 });
  const state = await page.evaluate(() => window.dpmViewer.state());
  assert.equal(state.vertices, 2608);
  assert.equal(await page.textContent('#title'), 't03.dpm');
  await page.close();
  assert.deepEqual(errors, []);
});

test('two selected open side by side: the compare link (and the overlay link), and the viewer on the first', async () => {
  const page = await newPage({ width: 900, height: 600 });
  await page.goto(url);
  await page.waitForFunction(() => window.dynpmCatalogue?.entries().length === 24);
  assert.equal(await page.getAttribute('#compare', 'aria-disabled'), 'true');
  assert.equal(await page.getAttribute('#compare-overlay', 'aria-disabled'), 'true');
  for (const name of ['t02', 't05', 't09']) await page.check(`article[data-path="thickness/${name}.dpm"] .select`);
  // A third choice lets the oldest go: t05 and t09 stay.
  assert.deepEqual(await page.evaluate(() => window.dynpmCatalogue.selected()), ['thickness/t05.dpm', 'thickness/t09.dpm']);
  assert.equal(await page.isChecked('article[data-path="thickness/t02.dpm"] .select'), false);
  const href = await page.getAttribute('#compare', 'href');
  const query = new URL(href, url).searchParams;
  assert.equal(new URL(href, url).pathname, '/view');
  assert.equal(query.get('model'), '/files/thickness/t05.dpm');
  assert.equal(query.get('compare'), '/files/thickness/t09.dpm');
  // The overlay link: the same two, the second's edges over the first.
  const overlay = new URL(await page.getAttribute('#compare-overlay', 'href'), url).searchParams;
  assert.deepEqual(Object.fromEntries(overlay), { ...Object.fromEntries(query), compareLayout: 'edges' });
  await Promise.all([page.waitForURL(/compare=/), page.click('#compare')]);
  await page.waitForFunction(allShown, null, { timeout: 60000 });
  assert.equal(await page.textContent('#title'), 't05.dpm');
  await page.close();
  assert.deepEqual(errors, []);
});
