// The screenshot of docs/batch.md "dynpm serve" (docs/images/catalogue.png), made reproducibly:
// `dynpm serve DIR` on a free port, headless Chromium (as the browser tests start it) on its page
// once every thumbnail is in, saved as PNG.
//   node scripts/catalogue_screenshot.mjs DYNPM DIR OUT.png [--filter TEXT] [--select A,B]
// --select ticks two files (paths below DIR) for the compare link.
import { chromium } from 'playwright-core';

import { CHROMIUM_ARGS, startServer } from '../test/chromium.mjs';

const [cli, dir, out] = process.argv.slice(2);
if (!cli || !dir || !out) {
  console.error('usage: node scripts/catalogue_screenshot.mjs DYNPM DIR OUT.png [--filter TEXT] [--select A,B]');
  process.exit(2);
}
const flag = (name) => {
  const i = process.argv.indexOf(name);
  return i > 0 ? process.argv[i + 1] : null;
};

const { server, url } = await startServer(cli, dir, [], 'serve');
const browser = await chromium.launch({ executablePath: process.env.DYNPM_CHROMIUM ?? '/usr/bin/chromium', headless: true, args: CHROMIUM_ARGS });
try {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  await page.goto(url);
  await page.waitForFunction(() => window.dynpmCatalogue?.polls() > 0);
  await page.waitForFunction(() => [...document.querySelectorAll('img.thumb')].every((i) => i.complete && i.naturalWidth > 0));
  if (flag('--filter')) await page.fill('#filter', flag('--filter'));
  for (const path of flag('--select')?.split(',') ?? []) await page.check(`article[data-path="${path}"] .select`);
  await page.evaluate(() => window.scrollTo(0, 0));  // checking scrolled to the boxes
  await page.screenshot({ path: out });
  console.log(`wrote ${out}`);
} finally {
  await browser.close();
  server.kill('SIGTERM');
}
