// The screenshots of docs/viewer.md "Fields", "Parts" and the view's controls ("States" …
// "Scripting API"), made reproducibly: `dynpm view` serves the model, headless Chromium (as in
// the browser tests, openViewer()) shows its last step, saved as PNG.
//   node scripts/screenshots.mjs DYNPM MODEL.dpm OUT_DIR [--element NAME] [--node NAME] [--parts]
// Fields: an element field (fully refined, then at 10 % of the vertices) and a nodal field
// (rainbow); a model without fields gets test/fields_fixture.mjs's DEMO_FIELDS (a nodal 'stress'
// and an element 'plastic strain' from the motion) first. Fields are chosen by name, or the first
// of each location.
// With --parts, on a model with named parts: the part colours and list at the last step, fully
// refined and at 10 % of the vertices, and one part isolated from the list; then the view's
// controls (displacement colours, ×3 over the ghost, the view from above, what Save PNG and
// dynpm.screenshot() save,
// the loading screen, a small window); no fields added.
import { mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';

import { chromium } from 'playwright-core';

import { readDpm } from '../src/dpm.js';
import { openViewer } from '../test/chromium.mjs';
import { DEMO_FIELDS, withFields } from '../test/fields_fixture.mjs';

const [cli, model, out] = process.argv.slice(2);
if (!cli || !model || !out) {
  console.error('usage: node scripts/screenshots.mjs DYNPM MODEL.dpm OUT_DIR [--element NAME] [--node NAME]');
  process.exit(2);
}
const flag = (name) => {
  const i = process.argv.indexOf(name);
  return i > 0 ? process.argv[i + 1] : null;
};
mkdirSync(out, { recursive: true });
let bytes = new Uint8Array(readFileSync(model));
let { mesh } = readDpm(bytes, model);
let served = model;
const partShots = process.argv.includes('--parts');
if (mesh.fields.length === 0 && !partShots) {
  bytes = withFields(bytes, DEMO_FIELDS);
  ({ mesh } = readDpm(bytes, model));
  served = join(out, 'with-fields.dpm');
  writeFileSync(served, bytes);
}
const pick = (perFace, name) => (name ? mesh.fields.find((f) => f.name === name) : mesh.fields.find((f) => f.perFace === perFace));
const shots = partShots ? [] : [
  ['viewer-element-fringe.png', pick(true, flag('--element')), 'viridis', 1],
  ['viewer-element-fringe-10pct.png', pick(true, flag('--element')), 'viridis', 0.1],
  ['viewer-nodal-fringe.png', pick(false, flag('--node')), 'rainbow', 1],
];

const errors = [];
const viewport = { width: 1280, height: 760 };
const { server, browser, page, url } = await openViewer(chromium, cli, served, { viewport, errors, timeout: 60000 });
server.removeAllListeners('exit');
try {
  await page.evaluate(() => {
    const t = document.getElementById('time');
    t.value = t.max;
    t.dispatchEvent(new Event('input'));
  });
  const h = mesh.head;
  if (partShots) {
    for (const [name, ratio] of [['viewer-parts.png', 1], ['viewer-parts-10pct.png', 0.1]]) {
      await page.evaluate((n) => window.dpmViewer.setVertexCount(n), Math.round(h.baseVertexCount + ratio * h.splitCount));
      await page.waitForTimeout(300);
      await page.screenshot({ path: join(out, name) });
      console.log(join(out, name));
    }
    await page.locator('#part-search').fill('wall');
    await page.locator('#part-list li:visible button').last().click();  // isolate
    await page.waitForTimeout(300);
    await page.screenshot({ path: join(out, 'viewer-parts-isolated.png') });
    console.log(join(out, 'viewer-parts-isolated.png'));
  }
  for (const [name, field, scheme, ratio] of shots) {
    if (!field) {
      console.log(`${name}: the model has no such field`);
      continue;
    }
    await page.evaluate((n) => window.dpmViewer.setVertexCount(n), Math.round(h.baseVertexCount + ratio * h.splitCount));
    await page.locator('#colour').selectOption({ label: field.name });
    await page.locator('#scheme').selectOption(scheme);
    // The legend is what these pictures are for: the panel scrolled to its end.
    await page.evaluate(() => document.getElementById('legend').scrollIntoView({ block: 'end' }));
    await page.waitForTimeout(300);
    await page.screenshot({ path: join(out, name) });
    console.log(`${join(out, name)}: ${field.name} (${field.perFace ? 'element' : 'node'})`);
  }
  if (partShots) await viewShots(page, url);
  if (errors.length) throw new Error(`the page's errors: ${errors.join('; ')}`);
} finally {
  await browser.close();
  server.kill('SIGTERM');
}

// The view's controls through window.dynpm: the panel at the last state with displacement
// colours, the deformation scaled ×3 over the undeformed ghost, the view from above with the
// panel's views, Up and image buttons, the PNG that Save PNG and
// dynpm.screenshot() give, the loading screen (the file served slowly) and a small window (panel
// collapsed).
async function viewShots(page, url) {
  await page.locator('#part-search').fill('');
  await page.locator('#parts-show-all').click();
  await page.locator('#colour').selectOption('displacement');
  await page.locator('#scheme').selectOption('viridis');
  await page.evaluate(() => {
    window.dynpm.setLevel({ ratio: 1 });
    window.dynpm.setStep(window.dynpm.view().stepCount - 1);
    window.dynpm.setView('iso');
  });
  await page.waitForTimeout(300);
  await page.screenshot({ path: join(out, 'viewer-view-controls.png') });
  await page.locator('#colour').selectOption('part');
  await page.evaluate(() => {
    window.dynpm.setDeformationScale(3);
    window.dynpm.setGhost(true);
    window.dynpm.setView('+x');
  });
  await page.waitForTimeout(300);
  await page.screenshot({ path: join(out, 'viewer-deformation-ghost.png') });
  await page.evaluate(() => {
    window.dynpm.setDeformationScale(1);
    window.dynpm.setGhost(false);
    window.dynpm.setView('-y');  // from above (y up)
    document.getElementById('orientation').scrollIntoView();
  });
  await page.waitForTimeout(300);
  await page.screenshot({ path: join(out, 'viewer-orientation.png') });
  await page.evaluate(() => {
    document.getElementById('panel').scrollTop = 0;
    window.dynpm.setView('iso');
  });
  const png = await page.evaluate(() => window.dynpm.screenshot());
  writeFileSync(join(out, 'viewer-png.png'), Buffer.from(png.split(',')[1], 'base64'));
  const slow = await openViewer(chromium, cli, served, { viewport, errors, serverArgs: ['--throttle', '1'], ready: false, waitUntil: 'domcontentloaded' });
  slow.server.removeAllListeners('exit');
  try {
    await slow.page.screenshot({ path: join(out, 'viewer-loading.png') });
  } finally {
    await slow.browser.close();
    slow.server.kill('SIGTERM');
  }
  const small = await browser.newPage({ viewport: { width: 560, height: 420 } });
  await small.goto(url);
  await small.evaluate(() => window.dynpm.ready.then(() => window.dynpm.setStep(window.dynpm.view().stepCount - 1)));
  await small.waitForTimeout(300);
  await small.screenshot({ path: join(out, 'viewer-small-window.png') });
  console.log(`${out}: viewer-view-controls.png, viewer-deformation-ghost.png, viewer-orientation.png, viewer-png.png, viewer-loading.png, viewer-small-window.png`);
}
