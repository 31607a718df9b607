// The view-dependent mode's cost on the page's main thread, in headless Chromium (docs/viewer.md
// "View-dependent"): the first re-target at a step (the split spheres, the request, the front
// moved, the index entries rewritten), camera moves at that step (the spheres reused), and a
// time step (new spheres). Per re-target: the page's own `retargetMs` and the longest main-thread
// task (PerformanceObserver 'longtask', ≥ 50 ms) from the call until the front has settled.
//   node bench/view_retarget.mjs DYNPM_BINARY MODEL.dpm [PX] [elsewhere] [repeats]
import { loadavg } from 'node:os';

import { chromium } from 'playwright-core';

import { allShown, openViewer } from '../test/chromium.mjs';

const [cli, file, px = '1', elsewhere = '1%', repeatsText = '3'] = process.argv.slice(2);
if (!cli || !file) {
  console.error('usage: node bench/view_retarget.mjs DYNPM_BINARY MODEL.dpm [PX] [elsewhere] [repeats]');
  process.exit(2);
}
const repeats = Number(repeatsText);
const load = () => loadavg().map((x) => x.toFixed(1)).join(' ');
const median = (v) => v.slice().sort((a, b) => a - b)[v.length >> 1];
console.log(`${file}: PX ${px}, ${elsewhere} elsewhere; load average ${load()}`);

const rows = {};
for (let run = 0; run < repeats; run++) {
  const errors = [];
  const { server, browser, page } = await openViewer(chromium, cli, file, { viewport: { width: 1280, height: 800 }, errors, timeout: 600000, ready: allShown });
  try {
    await page.evaluate(() => window.dynpm.ready);
    await page.evaluate(() => {
      window.longTasks = [];
      new PerformanceObserver((list) => {
        for (const e of list.getEntries()) window.longTasks.push([e.startTime, e.duration]);
      }).observe({ type: 'longtask' });
    });
    await page.evaluate(() => (window.dynpm.setStep(12), window.dynpm.setView('iso')));
    // Runs `action` (in Node: page calls, the mouse), waits until the front has settled,
    // returns its costs.
    const measure = async (what, action) => {
      const start = await page.evaluate(() => new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(() => done(performance.now())))));
      const before = await page.evaluate(() => ((r) => `${r.requests?.[0]} ${r.step}`)(window.dynpm.refinement()));
      await action();
      const r = await page.evaluate(async ([from, previous]) => {
        const settled = () => ((r) => r.active && !r.following && !r.waiting && `${r.requests[0]} ${r.step}` !== previous)(window.dynpm.refinement());
        while (!settled()) await new Promise((done) => setTimeout(done, 10));
        await new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done)));
        const longest = Math.max(0, ...window.longTasks.filter(([at]) => at >= from).map(([, d]) => d));
        const r = window.dynpm.refinement();
        return { retargetMs: r.retargetMs, longest, vertices: r.vertices, spheresFrom: r.spheresFrom };
      }, [start, before]);
      (rows[what] ??= []).push(r);
    };
    await measure('first view at a step', () => page.evaluate(([p, e]) => window.dynpm.refine([`view:PX=${p}`], e), [px, elsewhere]));
    const canvas = await page.locator('#view').boundingBox();
    await page.mouse.move(canvas.x + canvas.width / 2, canvas.y + canvas.height / 2);
    for (let k = 0; k < 2; k++) await measure('camera move (wheel)', () => page.mouse.wheel(0, -300));
    await measure('time step (new spheres)', () => page.evaluate(() => window.dynpm.setStep(13)));
    if (errors.length) console.log(`page errors: ${errors.join('; ')}`);
  } finally {
    await browser.close();
    server.kill('SIGTERM');
  }
}
for (const [what, runs] of Object.entries(rows)) {
  const v = runs.map((r) => r.vertices);
  console.log(`${what}: retargetMs median ${median(runs.map((r) => r.retargetMs)).toFixed(1)} ms, longest task median ${median(runs.map((r) => r.longest)).toFixed(0)} ms ` +
    `(runs: ${runs.map((r) => `${r.retargetMs.toFixed(1)}/${r.longest.toFixed(0)}`).join(', ')}); vertices ${Math.min(...v)}–${Math.max(...v)}; spheres from ${runs[0].spheresFrom ?? 'the page'}`);
}
console.log(`load average after: ${load()}`);
