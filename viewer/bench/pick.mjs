// What a pick, a history and a section outline cost in the page (docs/viewer.md "Picking, history,
// section, measure"), in headless Chromium: picks at a coarse level (the first makes the finest
// level's Navigator; later ones at the same step reuse its positions; a new step decodes them
// again), at full resolution, a history over every step, and the section outline of the level
// on screen. Medians of REPEAT runs, page JS time (performance.now around window.dynpm calls).
//   [REPEAT=9] node bench/pick.mjs DYNPM_BINARY MODEL.dpm
import { chromium } from 'playwright-core';

import { CHROMIUM_ARGS, startServer } from '../test/chromium.mjs';

const [cli, file] = process.argv.slice(2);
if (!cli || !file) {
  console.error('usage: node bench/pick.mjs DYNPM_BINARY MODEL.dpm');
  process.exit(2);
}
const repeat = Number(process.env.REPEAT ?? 9);
const { server, url } = await startServer(cli, file);
server.removeAllListeners('exit');
const browser = await chromium.launch({ executablePath: process.env.DYNPM_CHROMIUM ?? '/usr/bin/chromium', args: CHROMIUM_ARGS });
try {
  const page = await browser.newPage({ viewport: { width: 1100, height: 760 } });
  await page.goto(`${url}?antialias=0`);
  await page.waitForFunction(() => (window.dpmViewer?.state().complete || window.dpmViewer?.state().paused) && window.dynpm?.pick, null, { timeout: 900000 });  // or the memory budget's levels
  const result = await page.evaluate((repeat) => {
    const { dpmViewer, dynpm } = window;
    const s = dpmViewer.state();
    const median = (xs) => xs.sort((a, b) => a - b)[xs.length >> 1];
    const time = (f) => {
      const start = performance.now();
      const r = f();
      return [performance.now() - start, r];
    };
    const [x, y] = [innerWidth * 0.6, innerHeight * 0.5];
    const vertices = s.vertices;
    const steps = document.getElementById('time').max;
    dpmViewer.setVertexCount(Math.round(vertices * 0.1));
    const [first, p] = time(() => dynpm.pick(x, y));
    if (!p) throw new Error('nothing under the probe pixel');
    const sameStep = median(Array.from({ length: repeat }, () => time(() => dynpm.pick(x, y))[0]));
    const newStep = median(Array.from({ length: repeat }, (_, i) => {
      const t = document.getElementById('time');
      t.value = String(i % 2 ? 0 : steps);
      t.dispatchEvent(new Event('input'));
      return time(() => dynpm.pick(x, y))[0];
    }));
    dpmViewer.setVertexCount(vertices);
    const full = median(Array.from({ length: repeat }, () => time(() => dynpm.pick(x, y))[0]));
    const history = median(Array.from({ length: repeat }, () => time(() => dynpm.history(p.node, 'displacement'))[0]));
    dynpm.setSection({ enabled: true, axis: 'x', position: 0.5 });
    const outline = median(Array.from({ length: repeat }, (_, i) => time(() => (dynpm.setSection({ position: 0.3 + 0.01 * i }), dynpm.section().segments))[0]));
    return { vertices, faces: s.faces, steps: Number(steps) + 1, first, sameStep, newStep, full, history, outline };
  }, repeat);
  const load = await import('node:os').then((os) => os.loadavg().map((l) => l.toFixed(2)).join(' '));
  console.log(JSON.stringify({ ...result, repeat, loadAverage: load }, null, 1));
} finally {
  await browser.close();
  server.kill('SIGTERM');
}
