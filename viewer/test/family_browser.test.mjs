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
