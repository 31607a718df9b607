// Loading a model in headless Chromium: time from the first bytes to the first picture of the
// base mesh and to the fully loaded model (or to where the page pauses: ?vertices=N, or the
// levels its memory budget holds, QUERY='?memory=MiB'), the longest main-thread task meanwhile,
// and the renderer's memory (RSS of Chromium's renderer processes, which hold the page and its
// worker) against the file's size.
//   [THROTTLE=KiB/s] [QUERY=?worker=0] [TASKS=1] [FIRST_ONLY=1] [PROFILE=1] [COMPARE=B.dpm] node bench/load.mjs DYNPM_BINARY MODEL.dpm
// (?worker=0: the decoder on the page's main thread, as before the worker; TASKS: every long
// task and the page's timings; FIRST_ONLY: stop 2 s after the first picture; PROFILE: the main
// thread's functions by self time until the end, from Chromium's sampling profiler; COMPARE: a
// second model beside the first, `dynpm view MODEL B`, waited for as well: both share the budget.)
import { readFileSync, readdirSync, statSync } from 'node:fs';

import { chromium } from 'playwright-core';

import { CHROMIUM_ARGS, startServer } from '../test/chromium.mjs';

const [cli, file] = process.argv.slice(2);
if (!cli || !file) {
  console.error('usage: [THROTTLE=KiB/s] node bench/load.mjs DYNPM_BINARY MODEL.dpm');
  process.exit(2);
}
const extra = [...(process.env.COMPARE ? [process.env.COMPARE] : []), ...(process.env.THROTTLE ? ['--throttle', process.env.THROTTLE] : [])];
const { server, url } = await startServer(cli, file, extra);
const browser = await chromium.launch({ executablePath: '/usr/bin/chromium', args: CHROMIUM_ARGS });

// Before the page's own scripts: long tasks, and the first animation frame after the base mesh
// is there (the frame that draws it: the page renders from requestAnimationFrame).
const probe = () => {
  window.loadProbe = { longTasks: [], firstPicture: 0, complete: 0 };
  new PerformanceObserver((list) => {
    for (const e of list.getEntries()) window.loadProbe.longTasks.push([e.startTime, e.duration]);
  }).observe({ type: 'longtask', buffered: true });
  const tick = () => {
    const s = window.dpmViewer?.state();
    // The frame after the one that drew the base: that one has ended (and was presented).
    if (window.loadProbe.baseFrame && !window.loadProbe.firstPicture) window.loadProbe.firstPicture = performance.now();
    if (s?.hasBase && !window.loadProbe.baseFrame) window.loadProbe.baseFrame = performance.now();
    const b = window.dpmViewer?.compare?.();  // the second model's, if any, as well
    // Loaded (or paused) and shown: the level catches up with what arrived a step a frame (but
    // stays where ?vertices=N puts it).
    const shown = /[?&]vertices=/.test(location.search) || (s && s.vertices === s.loadedVertices);
    if ((s?.complete || s?.paused) && shown && (!b || b.complete || b.paused) && !window.loadProbe.complete) window.loadProbe.complete = performance.now();
    if (!window.loadProbe.complete) requestAnimationFrame(tick);
  };
  requestAnimationFrame(tick);
};

// RSS in MiB of this browser's renderer processes (the page, its worker, their array buffers).
function rendererMiB() {
  let kib = 0;
  const parent = (pid) => Number(readFileSync(`/proc/${pid}/stat`, 'utf8').replace(/^.*\) /, '').split(' ')[1]);
  const ours = (pid) => {
    for (let p = Number(pid); p > 1; p = parent(p)) if (p === process.pid) return true;
    return false;
  };
  for (const pid of readdirSync('/proc').filter((d) => /^\d+$/.test(d))) {
    try {
      const cmd = readFileSync(`/proc/${pid}/cmdline`, 'utf8');
      if (!cmd.includes('--type=renderer') || !ours(pid)) continue;
      kib += Number(readFileSync(`/proc/${pid}/status`, 'utf8').match(/VmRSS:\s+(\d+)/)[1]);
    } catch {
      // The process ended meanwhile.
    }
  }
  return kib / 1024;
}

// The page's main thread's functions by self time (Chromium's sampling profiler), the top 25.
async function printProfile(cdp) {
  const { profile } = await cdp.send('Profiler.stop');
  const self = new Map();
  const dt = (profile.endTime - profile.startTime) / profile.samples.length / 1000;
  const byId = new Map(profile.nodes.map((n) => [n.id, n]));
  for (const id of profile.samples) {
    const { functionName, url, lineNumber } = byId.get(id).callFrame;
    const key = `${functionName || '(anonymous)'} ${url.split('/').pop()}:${lineNumber + 1}`;
    self.set(key, (self.get(key) ?? 0) + dt);
  }
  const top = [...self].sort((a, b) => b[1] - a[1]).slice(0, 25);
  console.log(top.map(([k, v]) => `${v.toFixed(0)} ms ${k}`).join('\n'));
}

try {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  await page.addInitScript(probe);
  const cdp = await page.context().newCDPSession(page);
  let peak = 0;
  const sampler = setInterval(() => (peak = Math.max(peak, rendererMiB())), 100);
  if (process.env.PROFILE) {
    await cdp.send('Profiler.enable');
    await cdp.send('Profiler.setSamplingInterval', { interval: 500 });
    await cdp.send('Profiler.start');
  }
  await page.goto(url + (process.env.QUERY ?? ''));
  if (process.env.FIRST_ONLY) {
    await page.waitForFunction(() => window.loadProbe?.firstPicture, null, { timeout: 900000, polling: 100 });
    await new Promise((resolve) => setTimeout(resolve, 2000));
    clearInterval(sampler);
    if (process.env.PROFILE) await printProfile(cdp);
    console.log(await page.evaluate(() => {
      const t = window.dpmViewer.timing;
      const since = (x) => (x - t.firstByte).toFixed(0);
      return `base frame ${since(window.loadProbe.baseFrame)}, first picture ${since(window.loadProbe.firstPicture)}; ` + Object.entries(t).map(([k, v]) => `${k} ${since(v)}`).join(', ') +
        '; tasks ' + window.loadProbe.longTasks.map(([s, d]) => `${since(s)}+${d.toFixed(0)}`).join(' ');
    }));
  } else {
    await page.waitForFunction(() => window.loadProbe?.complete, null, { timeout: 900000, polling: 500 });
    clearInterval(sampler);
    const r = await page.evaluate(() => {
      // The first bytes: the fetch's response start, in the page's or (worker) the page's record.
      const entry = performance.getEntriesByType('resource').find((e) => e.name.endsWith('.dpm'));
      const firstByte = window.dpmViewer.timing?.firstByte ?? entry?.responseStart;
      const b = window.dpmViewer.compare?.();
      return { ...window.loadProbe, firstByte, timing: window.dpmViewer.timing, worker: window.dpmViewer.state().worker ?? false, state: window.dpmViewer.state(),
        compare: b && { name: b.name, vertices: b.vertices, loaded: b.loadedVertices, complete: b.complete } };
    });
    if (process.env.PROFILE) await printProfile(cdp);
    const use = await page.evaluate(() => window.dpmViewer.memory());
    await cdp.send('HeapProfiler.collectGarbage');
    await new Promise((resolve) => setTimeout(resolve, 1000));
    const heap = await cdp.send('Runtime.getHeapUsage');
    const after = rendererMiB();
    const size = statSync(file).size / 2 ** 20;
    const during = r.longTasks.filter(([s]) => s >= r.firstByte && s <= r.complete);
    const longest = during.reduce((a, [, d]) => Math.max(a, d), 0);
    console.log(`${file}: ${r.state.vertices} vertices${r.state.complete ? '' : ` (paused: ${r.state.loadedVertices} loaded, ${(r.state.bytesLoaded / 2 ** 20).toFixed(1)} MiB fetched)`}, ${size.toFixed(1)} MiB, decoder in a worker: ${r.worker}`);
    if (r.compare) console.log(`B, ${r.compare.name}: ${r.compare.vertices} vertices${r.compare.complete ? '' : ` (paused: ${r.compare.loaded} loaded)`}`);
    console.log(`base mesh drawn in the frame of ${(r.baseFrame - r.firstByte).toFixed(0)} ms, first picture (the next frame) ${(r.firstPicture - r.firstByte).toFixed(0)} ms after the first bytes; ` +
      `${r.state.complete ? 'fully loaded' : 'paused'} after ${(r.complete - r.firstByte).toFixed(0)} ms`);
    const t = r.timing ?? {};  // the page before the worker had no timing
    const since = (x) => (x === undefined ? '?' : (x - r.firstByte).toFixed(0));
    console.log(`after the first bytes: HEAD on the page ${since(t.head)} ms, BASE ${since(t.base)} ms, ` +
      `base mesh made ${since(t.baseDone)} ms, the worker through END ${since(t.decoded)} ms`);
    if (process.env.TASKS) console.log(JSON.stringify(Object.fromEntries(Object.entries(t).map(([k, v]) => [k, since(v)]))));
    if (process.env.TASKS) console.log(r.longTasks.map(([s, d]) => `${(s - r.firstByte).toFixed(0)}+${d.toFixed(0)}`).join(" "));
    console.log(`main-thread tasks > 50 ms while loading: ${during.length}, longest ${longest.toFixed(0)} ms ` +
      `(sum ${during.reduce((a, [, d]) => a + d, 0).toFixed(0)} ms)`);
    console.log(`renderer RSS: peak ${peak.toFixed(0)} MiB while loading, ${after.toFixed(0)} MiB loaded ` +
      `(${(after / size).toFixed(2)}× the file); page JS heap ${(heap.usedSize / 2 ** 20).toFixed(0)} MiB`);
    const total = Object.values(use).reduce((a, x) => a + x, 0);
    console.log(`the page's arrays: ${(total / 2 ** 20).toFixed(0)} MiB (${(total / 2 ** 20 / size).toFixed(2)}× the file): ` +
      Object.entries(use).map(([k, v]) => `${k} ${(v / 2 ** 20).toFixed(1)}`).join(', '));
  }
} finally {
  await browser.close();
  server.kill('SIGINT');
}
