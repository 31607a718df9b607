// Compare's field A − field B (docs/viewer.md "Compare"), in headless Chromium on a real variant
// pair: the CalculiX crash box of ../shared/data/crashbox-fields (a three-point bend, its strip
// on the y = +30 face pushed 100 mm per time unit) and a second CalculiX run of the very same
// mesh under another load (bench/family/crashbox-side.frd.gz: the strip of the x = +30 face
// pushed 2 mm, made by bench/family/make_crashbox_variant.py … side), built here into one family
// file and shown as its two members side by side. For each field both hold (S_MISES, PEEQ,
// ERROR per node) the page offers "NAME A − B"; its largest |difference|, the item it names and
// the legend's symmetric range equal those computed from `dynpm extract --variant … -o x.vtk` of
// both members (the values each fringe shows, written by the C++ side) at several levels and
// steps, also past B's last step (B clamped there, as compare's linked time does).
//
// Environment (CTest): DYNPM_CLI, DYNPM_TEST_OUT.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { existsSync, mkdirSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { gunzipSync } from 'node:zlib';
import { after, before, test } from 'node:test';

import { chromium } from 'playwright-core';

import { readDpm } from '../src/dpm.js';
import { allShown, CHROMIUM_ARGS, startServer } from './chromium.mjs';
import { bothShown } from './compare_checks.mjs';
import { readVtkLegacy } from './vtk_legacy.mjs';

const { DYNPM_CLI: cli, DYNPM_TEST_OUT: out } = process.env;
if (!cli || !out) throw new Error('field_difference_browser.test.mjs needs DYNPM_CLI and DYNPM_TEST_OUT');
const here = (path) => fileURLToPath(new URL(path, import.meta.url));
const inputs = { 'crashbox-fields': here('../../../shared/data/crashbox-fields/crashbox-fields.frd.gz'), 'crashbox-side': here('../../bench/family/crashbox-side.frd.gz') };
const dir = join(out, 'field-difference');
const family = join(dir, 'family.dpm');

let server, url, browser;
const errors = [];
before(async () => {
  rmSync(dir, { recursive: true, force: true });
  mkdirSync(dir, { recursive: true });
  const frds = Object.entries(inputs).map(([name, gz]) => {
    assert.ok(existsSync(gz), `${gz} is missing`);
    writeFileSync(join(dir, `${name}.frd`), gunzipSync(readFileSync(gz)));
    return join(dir, `${name}.frd`);
  });
  execFileSync(cli, ['build', '--family', ...frds, '-o', family, '--quiet'], { stdio: 'pipe' });
  ({ server, url } = await startServer(cli, family));
  browser = await chromium.launch({ executablePath: process.env.DYNPM_CHROMIUM ?? '/usr/bin/chromium', headless: true, args: CHROMIUM_ARGS });
});
after(async () => {
  await browser?.close();
  server?.kill('SIGINT');
});

// A member's field `name` as `dynpm extract --vertices N --step T` writes it (VTK, ASCII).
function extractedField(variant, vertices, step, name) {
  const path = join(dir, `${variant}.vtk`);
  execFileSync(cli, ['extract', family, '--variant', variant, '--vertices', String(vertices), '--step', String(step), '--ascii', '-o', path], { stdio: 'pipe' });
  const vtk = readVtkLegacy(readFileSync(path));
  const field = vtk.pointData[name] ?? vtk.cellData[name];
  assert.ok(field, `${path}: no field ${name}`);
  return field.values;
}

test('field A − B of two members of a family: the largest difference and its node as extract gives them', async () => {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  page.on('console', (m) => m.type() === 'error' && errors.push(m.text()));
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto(`${url}?variant=crashbox-fields&compare=model.dpm&compareVariant=crashbox-side`);
  await page.waitForFunction(bothShown, null, { timeout: 120000 });
  await page.evaluate(() => window.dpmViewer.compare().done);
  await page.waitForFunction(allShown, null, { timeout: 60000 });
  const c = await page.evaluate(() => window.dpmViewer.compare());
  assert.ok(c.sameHierarchy, c.why);
  const { mesh } = readDpm(new Uint8Array(readFileSync(family)), family);
  const names = mesh.fields.map((f) => f.name);
  assert.deepEqual(names, ['S_MISES', 'PEEQ', 'ERROR']);
  assert.deepEqual(c.fieldDifferences, ['fielddiff:0', 'fielddiff:1', 'fielddiff:2']);
  const options = await page.$$eval('#colour option', (os) => os.map((o) => o.textContent));
  for (const name of names) assert.ok(options.includes(`${name} A − B`), `${options}`);
  const original = mesh.vertexOriginal;
  const V = mesh.head.vertexCount;
  // B (the side push) has 3 steps: A's steps 5 and 14 show B's last.
  for (const [k, name] of names.entries()) {
    await page.selectOption('#colour', `fielddiff:${k}`);
    for (const [vertices, step] of [[V, 1], [1500, 2], [300, 5], [V, 14]]) {
      const what = `${name}, ${vertices} vertices, step ${step}`;
      await page.evaluate(([n, t]) => (window.dynpm.setLevel({ vertices: n }), window.dynpm.setStep(t)), [vertices, step]);
      const shown = await page.evaluate(() => ({ a: window.dpmViewer.fringe(), b: window.dpmViewer.compare() }));
      const a = extractedField('crashbox-fields', vertices, step, name);
      const b = extractedField('crashbox-side', vertices, Math.min(step, 2), name);
      assert.equal(a.length, vertices, what);
      let max = 0;
      for (let i = 0; i < a.length; i++) max = Math.max(max, Math.abs(a[i] - b[i]));
      assert.ok(max > 0, `${what}: the two loads differ`);
      const peak = shown.a.peak;
      assert.equal(Math.abs(peak.value), max, `${what}: page ${peak.value}, extract ${max}`);
      const at = vertices === V ? original[peak.item] : peak.item;  // full: extract's input order
      assert.equal(Math.abs(a[at] - b[at]), max, `${what}: the item the page names`);
      assert.equal(peak.where, `node ${mesh.nodeId[peak.item]}`);
      // The legend: symmetric about 0, the largest at its ends, the peak line, B the same.
      assert.deepEqual([shown.a.lo, shown.a.hi], [-max, max], what);
      assert.equal(shown.a.step, step, what);
      assert.deepEqual(shown.b.fieldPeak.where, peak.where, what);
      assert.equal(shown.b.fieldPeak.value, peak.value, what);
      const legend = await page.locator('#legend').textContent();
      assert.ok(legend.startsWith(`${name} A − B (node, step ${step})`), legend);
      assert.match(legend, new RegExp(`▲ max \\|value\\| [0-9.e+-]+ at ${peak.where}$`), legend);
    }
  }
  await page.selectOption('#colour', 'fielddiff:0');
  await page.evaluate(() => (window.dynpm.setLevel({ ratio: 1 }), window.dynpm.setStep(2)));
  await page.screenshot({ path: join(dir, 'field-difference.png') });
  await page.close();
  assert.deepEqual(errors, []);
});
