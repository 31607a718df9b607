// Frame times in headless Chromium (SwiftShader: software rendering): full refine from the base
// mesh, then time scrubbing at a given number of visible vertices.
//   [VIEWPORT=WxH] [QUERY=?antialias=0] node bench/scrub.mjs DYNPM_BINARY MODEL.dpm [VISIBLE_VERTICES]
import { chromium } from 'playwright-core';

import { CHROMIUM_ARGS, startServer } from '../test/chromium.mjs';

const [cli, file, visibleArg] = process.argv.slice(2);
if (!cli || !file) {
  console.error('usage: node bench/scrub.mjs DYNPM_BINARY MODEL.dpm [VISIBLE_VERTICES]');
  process.exit(2);
}
const { server, url } = await startServer(cli, file);
const browser = await chromium.launch({ executablePath: '/usr/bin/chromium', args: CHROMIUM_ARGS });
try {
  // VIEWPORT=WxH: a software renderer's frame time follows the pixels; QUERY=?antialias=0.
  const [width, height] = (process.env.VIEWPORT ?? '1280x800').split('x').map(Number);
  const page = await browser.newPage({ viewport: { width, height } });
  const loadStart = Date.now();
  await page.goto(url + (process.env.QUERY ?? ''));
  await page.waitForFunction(() => window.dpmViewer?.state().complete || window.dpmViewer?.state().paused, null, { timeout: 600000 });  // or the memory budget's levels
  const state = await page.evaluate(() => window.dpmViewer.state());
  console.log(`loaded ${state.vertices} vertices, ${state.faces} faces in ${Date.now() - loadStart} ms (fetch + decode + refine + first frames)`);
  const base = await page.evaluate(() => window.dpmViewer.setVertexCount(0));
  const refine = await page.evaluate((n) => window.dpmViewer.setVertexCount(n), state.vertices);
  console.log(`browser: coarsen to base ${base.js.toFixed(0)} ms JS (${base.total.toFixed(0)} ms with one frame), ` +
    `full refine ${refine.js.toFixed(0)} ms JS (${refine.total.toFixed(0)} ms with upload and one frame)`);
  const visible = Number(visibleArg ?? 100000);
  await page.evaluate((n) => window.dpmViewer.setVertexCount(n), visible);
  const r = await page.evaluate(() => window.dpmViewer.scrub(120));
  const sorted = [...r.frameMs].sort((a, b) => a - b);
  const median = sorted[sorted.length >> 1];
  const shown = await page.evaluate(() => window.dpmViewer.state());
  console.log(`scrub at ${shown.vertices} vertices (${shown.faces} faces): median frame ${median.toFixed(1)} ms ` +
    `(${(1000 / median).toFixed(1)} fps), 90th percentile ${sorted[Math.floor(sorted.length * 0.9)].toFixed(1)} ms, ` +
    `JS update ${r.updateMs.toFixed(2)} ms/frame`);
} finally {
  await browser.close();
  server.kill('SIGINT');
}
