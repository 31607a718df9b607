// The screenshots of docs/viewer.md "Picking, history, section, measure", made reproducibly:
// `dynpm view` serves the model, headless Chromium (as in the browser tests) shows its last step,
// clicks three nodes (the plot of a field over all steps, the last two measured), then a section
// cut at a coarse level; saved as PNG.
//   node scripts/inspect_screenshots.mjs DYNPM MODEL.dpm OUT_DIR [--field NAME]
import { mkdirSync } from 'node:fs';
import { join } from 'node:path';

import { chromium } from 'playwright-core';

import { CHROMIUM_ARGS, startServer } from '../test/chromium.mjs';

const [cli, model, out] = process.argv.slice(2);
if (!cli || !model || !out) {
  console.error('usage: node scripts/inspect_screenshots.mjs DYNPM MODEL.dpm OUT_DIR [--field NAME]');
  process.exit(2);
}
const at = process.argv.indexOf('--field');
const field = at > 0 ? process.argv[at + 1] : 'displacement';
mkdirSync(out, { recursive: true });
const { server, url } = await startServer(cli, model);
server.removeAllListeners('exit');
const browser = await chromium.launch({ executablePath: process.env.DYNPM_CHROMIUM ?? '/usr/bin/chromium', headless: true, args: CHROMIUM_ARGS });
try {
  const page = await browser.newPage({ viewport: { width: 1280, height: 860 } });
  await page.goto(url);
  await page.waitForFunction(() => window.dpmViewer?.state().complete && window.dynpm?.pick, null, { timeout: 60000 });
  const frame = () => page.evaluate(() => new Promise(requestAnimationFrame));
  await page.evaluate(() => {
    const t = document.getElementById('time');
    t.value = t.max;
    t.dispatchEvent(new Event('input'));
  });
  // Three picks on a grid over the right of the canvas (the panel covers the left).
  const { width, height } = await page.locator('#view').boundingBox();
  let picked = 0;
  for (let i = 5; i < 12 && picked < 3; i += 2)
    for (let j = 4; j < 9 && picked < 3; j += 2) {
      const [x, y] = [(width * i) / 12, (height * j) / 12];
      if (!(await page.evaluate(([x, y]) => window.dynpm.pick(x, y), [x, y]))) continue;
      await page.mouse.click(x, y);
      picked++;
    }
  await page.locator('#history-quantity').selectOption(field);
  await frame();
  await page.screenshot({ path: join(out, 'viewer-pick-history.png') });
  await page.locator('#history-quantity').selectOption('distance');
  await frame();
  await page.screenshot({ path: join(out, 'viewer-measure.png') });
  await page.locator('#pick-clear').click();
  await page.evaluate(() => window.dpmViewer.setVertexCount(Math.round(window.dpmViewer.state().vertices * 0.25)));
  await page.evaluate(() => window.dynpm.setSection({ enabled: true, axis: 'z', position: 0.55, tilt: 15, turn: 0 }));
  // Turned to look into the cut (a drag orbits the view).
  await page.mouse.move(width * 0.75, height * 0.7), await page.mouse.down();
  await page.mouse.move(width * 0.62, height * 0.6, { steps: 8 }), await page.mouse.up();
  await frame();
  await page.screenshot({ path: join(out, 'viewer-section.png') });
  console.log(`wrote viewer-pick-history.png, viewer-measure.png, viewer-section.png to ${out}`);
} finally {
  await browser.close();
  server.kill('SIGTERM');
}
