// The screenshots of docs/viewer.md "Picking, history, section, measure", made reproducibly:
// `dynpm view` serves the model, headless Chromium (as in the browser tests) shows its last step,
// clicks three nodes (the plot of a field over all steps, the last two measured; viewer.png, the
// README's picture, with the model coloured by that field), then a section cut at a coarse
// level; saved as PNG.
//   node scripts/inspect_screenshots.mjs DYNPM MODEL.dpm OUT_DIR [--field NAME]
import { mkdirSync } from 'node:fs';
import { join } from 'node:path';

import { chromium } from 'playwright-core';

import { openViewer } from '../test/chromium.mjs';

const [cli, model, out] = process.argv.slice(2);
if (!cli || !model || !out) {
  console.error('usage: node scripts/inspect_screenshots.mjs DYNPM MODEL.dpm OUT_DIR [--field NAME]');
  process.exit(2);
}
const at = process.argv.indexOf('--field');
const field = at > 0 ? process.argv[at + 1] : 'displacement';
mkdirSync(out, { recursive: true });
const errors = [];
const { server, browser, page } = await openViewer(chromium, cli, model, { viewport: { width: 1280, height: 860 }, errors,
  ready: () => window.dpmViewer?.state().complete && window.dynpm?.pick, timeout: 60000 });
server.removeAllListeners('exit');
try {
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
  // The panel is taller than the window: scrolled to what each picture is about.
  const scrollTo = (id) => page.evaluate((id) => document.getElementById(id).scrollIntoView(), id);
  await scrollTo('inspect');
  await frame();
  await page.screenshot({ path: join(out, 'viewer-pick-history.png') });
  if (field !== 'displacement') {
    await page.locator('#colour').selectOption({ label: field });
    await scrollTo('legend');
    await frame();
    await page.screenshot({ path: join(out, 'viewer.png') });
    await page.locator('#colour').selectOption('part');
  }
  await scrollTo('inspect');
  await page.locator('#history-quantity').selectOption('distance');
  await scrollTo('inspect');
  await frame();
  await page.screenshot({ path: join(out, 'viewer-measure.png') });
  await page.locator('#pick-clear').click();
  await scrollTo('section-cut');
  await page.evaluate(() => window.dpmViewer.setVertexCount(Math.round(window.dpmViewer.state().vertices * 0.25)));
  await page.evaluate(() => window.dynpm.setSection({ enabled: true, axis: 'z', position: 0.55, tilt: 15, turn: 0 }));
  // Turned to look into the cut (a drag orbits the view).
  await page.mouse.move(width * 0.75, height * 0.7), await page.mouse.down();
  await page.mouse.move(width * 0.62, height * 0.6, { steps: 8 }), await page.mouse.up();
  // Panned right, clear of the panel (a right-drag), and a little closer (the wheel).
  await page.mouse.move(width * 0.5, height * 0.5), await page.mouse.down({ button: 'right' });
  await page.mouse.move(width * 0.62, height * 0.52, { steps: 8 }), await page.mouse.up({ button: 'right' });
  await page.mouse.move(width * 0.62, height * 0.45);
  for (let i = 0; i < 2; i++) await page.mouse.wheel(0, -120), await page.waitForTimeout(50);
  await frame();
  await page.screenshot({ path: join(out, 'viewer-section.png') });
  if (errors.length) throw new Error(`the page's errors: ${errors.join('; ')}`);
  console.log(`wrote viewer-pick-history.png, viewer.png, viewer-measure.png, viewer-section.png to ${out}`);
} finally {
  await browser.close();
  server.kill('SIGTERM');
}
