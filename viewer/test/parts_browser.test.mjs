// Parts in the page, in Debian's headless Chromium (docs/viewer.md "Parts"), on a multi-part
// model with named parts: the hat rail as six Exodus blocks with names, written by
// scripts/sample/make_parts.py (netCDF4) and built by `dynpm build` (the CTest fixture
// viewer_parts_dpm). Through the scripting API (window.dynpm.parts(), setPartsVisible()) and the
// visible controls (the list's check boxes, "isolate", "show all", the search box): the names
// are the file's, each face is its part's one colour on slots of its own (no vertex shared with
// another part), and a hidden part is neither in the part slots nor in the picture.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { after, before, test } from 'node:test';

import { chromium } from 'playwright-core';

import { Navigator, readDpm } from '../src/dpm.js';
import { openViewer } from './chromium.mjs';

const { DYNPM_CLI: cli, DYNPM_PARTS_DPM: file } = process.env;
if (!cli || !file) throw new Error('parts_browser.test.mjs needs DYNPM_CLI and DYNPM_PARTS_DPM');

// What make_parts.py writes.
const NAMES = new Map([[101, 'Hat top'], [102, 'Hat top — hole patch'], [201, 'Wall left'],
  [202, 'Wall right'], [301, 'Flange left'], [302, 'Flange right']]);

let server, browser, page, mesh;
const consoleErrors = [];

before(async () => {
  ({ mesh } = readDpm(new Uint8Array(readFileSync(file)), file));
  ({ server, browser, page } = await openViewer(chromium, cli, file, { viewport: { width: 1100, height: 700 }, errors: consoleErrors }));
});

after(async () => {
  await browser?.close();
  server?.kill('SIGTERM');
});

const parts = () => page.evaluate(() => window.dynpm.parts());
const setVisible = (ids, visible) => page.evaluate(([i, v]) => window.dynpm.setPartsVisible(i, v), [ids, visible]);
const slots = () => page.evaluate(() => window.dpmViewer.partSlots());
const level = (n) => page.evaluate((v) => window.dpmViewer.setVertexCount(v), n);
// Cells of the grey picture that are not the background (0xeef0f3).
const covered = async () => (await page.evaluate(() => window.dpmViewer.snapshot(48))).filter((g) => Math.abs(g - 239.6) > 2).length;

// The faces present at the page's level, from dpm.js run here.
function present(faceCount) {
  const nav = new Navigator(mesh);
  nav.setLevel(mesh.splitsLoaded);
  while (nav.faceCount > faceCount) nav.coarsen();
  return nav;
}

// Every drawn face is a present face of a shown part, each once, all of them; its four slots
// hold one colour, the same for every face of its part and different between parts.
async function checkSlots(hidden = new Set()) {
  const s = await slots();
  const nav = present(s.faces);
  assert.equal(nav.faceCount, s.faces);
  const expected = [];
  for (let f = 0; f < s.faces; f++) if (!hidden.has(mesh.partId[f])) expected.push(f);
  assert.deepEqual(s.drawn, expected);
  const colourOf = new Map();
  for (const f of s.drawn) {
    const c = s.slotColours.slice(12 * f, 12 * f + 12);
    for (let k = 3; k < 12; k++) assert.equal(c[k], c[k % 3], `face ${f}: one colour on its four slots`);
    const key = c.slice(0, 3).join();
    const id = mesh.partId[f];
    if (!colourOf.has(id)) colourOf.set(id, key);
    assert.equal(colourOf.get(id), key, `part ${id}: one colour`);
  }
  assert.equal(new Set(colourOf.values()).size, colourOf.size, 'a colour per part');
  return s;
}

test('the part list holds the file\'s names, and the API says the same', async () => {
  assert.deepEqual([...mesh.partNames], [...NAMES]);
  assert.deepEqual(await parts(), [...NAMES].map(([id, name]) => ({ id, name, visible: true })));
  const rows = page.locator('#part-list li');
  assert.equal(await rows.count(), 6);
  assert.match(await rows.nth(1).textContent(), /Hat top — hole patch\s*102/);
  assert.match(await page.locator('#part-count').textContent(), /^6 parts$/);
  assert.deepEqual(consoleErrors, []);
});

test('each face its part\'s flat colour on its own slots, at the full and a coarse level', async () => {
  await checkSlots();
  await level(mesh.head.baseVertexCount + 40);
  const coarse = await checkSlots();
  assert.ok(coarse.faces < mesh.head.faceCount / 4, `${coarse.faces} faces at the coarse level`);
  await level(mesh.head.vertexCount);
});

test('a hidden part cannot be picked (inspect.js): the ray passes through it', async () => {
  await setVisible([...NAMES.keys()], true);
  const pickAt = (x, y) => page.evaluate(([x, y]) => window.dynpm.pick(x, y), [x, y]);
  const { w, h } = await page.evaluate(() => {
    const r = document.querySelector('canvas').getBoundingClientRect();
    return { w: r.width, h: r.height };
  });
  let hit = null;
  for (let i = 1; i < 16 && !hit; i++) for (let j = 1; j < 10 && !hit; j++) {
    const p = await pickAt((w * i) / 16, (h * j) / 10);
    if (p) hit = { x: (w * i) / 16, y: (h * j) / 10, part: p.part };
  }
  assert.ok(hit, 'some pixel picks a part');
  // The pick names the part as the file does, in the panel too.
  assert.equal((await pickAt(hit.x, hit.y)).partName, NAMES.get(hit.part));
  await page.evaluate(([x, y]) => window.dynpm.select(x, y), [hit.x, hit.y]);
  assert.equal(await page.locator('#pick-part-name').textContent(), NAMES.get(hit.part));
  await page.evaluate(() => window.dynpm.clearPicks());
  await setVisible([hit.part], false);
  const after = await pickAt(hit.x, hit.y);
  assert.ok(after === null || after.part !== hit.part, `part ${hit.part} hidden, picked ${after?.part}`);
  await setVisible([hit.part], true);
  assert.equal((await pickAt(hit.x, hit.y))?.part, hit.part);
});

test('hidden through the API: not in the part slots, not in the picture', async () => {
  const all = await covered();
  await setVisible([201, 202], false);
  assert.deepEqual((await parts()).filter((p) => !p.visible).map((p) => p.id), [201, 202]);
  assert.equal(await page.locator('#part-list li[data-part="201"] input').isChecked(), false);
  await checkSlots(new Set([201, 202]));
  await setVisible([...NAMES.keys()], false);
  assert.equal(await covered(), 0, 'nothing drawn with every part hidden');
  // In the displacement colours too (the shared surface and the edges).
  await page.locator('#colour').selectOption('displacement');
  assert.equal(await covered(), 0);
  await setVisible([101], true);
  const top = await covered();
  assert.ok(top > 0 && top < all, `the hat top alone covers ${top} of ${all} cells`);
  await page.locator('#colour').selectOption('part');
  await assert.rejects(setVisible([999], true), /no part 999/);
});

test('the visible controls: check box, isolate, search, show all', async () => {
  await page.locator('#parts-show-all').click();
  assert.ok((await parts()).every((p) => p.visible));
  await page.locator('#part-list li[data-part="301"] input').uncheck();
  assert.deepEqual((await parts()).filter((p) => !p.visible).map((p) => p.id), [301]);
  await checkSlots(new Set([301]));
  await page.locator('#part-list li[data-part="202"] button').click();  // isolate
  assert.deepEqual((await parts()).filter((p) => p.visible).map((p) => p.id), [202]);
  await checkSlots(new Set([101, 102, 201, 301, 302]));
  assert.match(await page.locator('#part-count').textContent(), /6 parts, 5 hidden/);
  await page.locator('#part-search').fill('flange');
  const shownRows = await page.locator('#part-list li:visible').evaluateAll((rows) => rows.map((r) => r.dataset.part));
  assert.deepEqual(shownRows, ['301', '302']);
  await page.locator('#part-search').fill('20');  // ids too
  assert.deepEqual(await page.locator('#part-list li:visible').evaluateAll((rows) => rows.map((r) => r.dataset.part)), ['201', '202']);
  await page.locator('#part-search').fill('');
  await page.locator('#parts-show-all').click();
  await checkSlots();
  assert.deepEqual(consoleErrors, []);
});
