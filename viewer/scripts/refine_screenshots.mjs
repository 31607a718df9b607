// The screenshots of docs/viewer.md "Selective refinement", made reproducibly: `dynpm view`
// serves a crash box (crashbox-mixed-5k of ../shared/data, built lossless), headless Chromium
// (as in the browser tests) refines a box at the crush's last step, then follows the deformation
// (moved more than 20 mm) at a middle step, then the view-dependent mode (1 px, 2 % elsewhere)
// with the camera zoomed toward the tube's crushed end; displacement colours, element edges,
// saved as PNG.
//   node scripts/refine_screenshots.mjs DYNPM MODEL.dpm OUT_DIR
import { mkdirSync } from 'node:fs';
import { join } from 'node:path';

import { chromium } from 'playwright-core';

import { openViewer } from '../test/chromium.mjs';

const [cli, model, out] = process.argv.slice(2);
if (!cli || !model || !out) {
  console.error('usage: node scripts/refine_screenshots.mjs DYNPM MODEL.dpm OUT_DIR');
  process.exit(2);
}
mkdirSync(out, { recursive: true });
const errors = [];
const { server, browser, page } = await openViewer(chromium, cli, model, { viewport: { width: 1200, height: 760 }, errors });
try {
  await page.evaluate(() => window.dynpm.ready);
  await page.locator('#colour').selectOption('displacement');
  const shot = async (name, step, requests, elsewhere) => {
    await page.evaluate(([s, r, e]) => (window.dynpm.setStep(s), window.dynpm.refine(r, e), window.dynpm.setView('iso')), [step, requests, elsewhere]);
    await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
    await page.screenshot({ path: join(out, name) });
    console.log(`${name}: ${(await page.evaluate(() => window.dynpm.refinement())).description}`);
  };
  await shot('viewer-refine-box.png', 40, ['box:-40,-60,150,10,60,260'], '5%');
  await shot('viewer-refine-follow.png', 25, ['moved:>20'], '5%');
  // The view-dependent mode: the camera zooms toward a point, the front follows it once it stops.
  await page.evaluate(() => (window.dynpm.setStep(40), window.dynpm.refine([]), window.dynpm.setView('iso')));
  await page.locator('#refine-elsewhere').fill('2%');
  await page.locator('#refine-mode').selectOption('view');
  const box = await page.locator('#view').boundingBox();
  await page.mouse.move(box.x + box.width * 0.42, box.y + box.height * 0.4);
  for (let k = 0; k < 3; k++) await page.mouse.wheel(0, -300);
  await page.evaluate(() => new Promise((r) => setTimeout(r, 600)));
  await page.waitForFunction(() => ((r) => !r.following && !r.waiting)(window.dynpm.refinement()));
  await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
  await page.screenshot({ path: join(out, 'viewer-refine-view.png') });
  console.log(`viewer-refine-view.png: ${(await page.evaluate(() => window.dynpm.refinement())).description}`);
  if (errors.length) throw new Error(errors.join('\n'));
} finally {
  await browser.close();
  server.kill('SIGTERM');
}
