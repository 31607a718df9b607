// Speed of dpm.js in Node (V8, as in Chromium): decoding a .dpm, full refine and full coarsen
// with the index buffers the page keeps (timed apart), and the per-frame work of time scrubbing.
//   node bench/refine.mjs MODEL.dpm [--visible N] [--repeat N]
import { readFileSync } from 'node:fs';

import { Navigator, readDpm, updateIndices } from '../src/dpm.js';

const file = process.argv[2];
if (!file) {
  console.error('usage: node bench/refine.mjs MODEL.dpm [--visible N] [--repeat N]');
  process.exit(2);
}
const visibleArg = process.argv.indexOf('--visible');
const repeatArg = process.argv.indexOf('--repeat');
const repeat = repeatArg > 0 ? Number(process.argv[repeatArg + 1]) : 1;
const ms = (start) => Number(process.hrtime.bigint() - start) / 1e6;
const best = (runs, f) => Math.min(...Array.from({ length: runs }, f));

const bytes = readFileSync(file);
let start = process.hrtime.bigint();
const { mesh } = readDpm(bytes, file);
const decode = ms(start);
const h = mesh.head;
console.log(`${file}: ${(bytes.length / 2 ** 20).toFixed(1)} MiB, ${h.vertexCount} vertices ` +
  `(base ${h.baseVertexCount}), ${h.faceCount} faces, ${h.stepCount} steps`);
console.log(`decode (crc, zstd, records, positions): ${decode.toFixed(0)} ms`);

const nav = new Navigator(mesh);
const tri = new Uint32Array(6 * h.faceCount);
const edges = new Uint32Array(8 * h.faceCount);
updateIndices(nav, tri, edges);
// The first full refine, then the median of 7 full refines and coarsens: the navigator alone,
// then the index update after it; in wall time and in this process's CPU time (cpu), which time
// spent waiting for a core (a loaded machine) does not count.
const median = (v) => v.sort((a, b) => a - b)[v.length >> 1];
const timed = (f) => {
  const c = process.cpuUsage();
  const s = process.hrtime.bigint();
  f();
  const wall = ms(s);
  const cpu = process.cpuUsage(c);
  return [wall, (cpu.user + cpu.system) / 1e3];
};
const perS = (t) => (h.splitCount / t / 1e3).toFixed(2);
// The first is apart: on it the navigator learns where its later writes go (navigator.js).
const [firstWall, firstCpu] = timed(() => nav.setLevel(h.splitCount));
updateIndices(nav, tri, edges);
nav.setLevel(0);
updateIndices(nav, tri, edges);
console.log(`first full refine: ${firstWall.toFixed(0)} ms, ${perS(firstWall)} M splits/s (cpu ${perS(firstCpu)})`);
// With --repeat N each run is N refines and coarsens (a small model's take well under a
// millisecond), after N untimed ones (the compiler's background threads count as CPU time).
const add = (sum, [wall, cpu]) => [sum[0] + wall, sum[1] + cpu];
for (let r = 0; r < repeat; r++) nav.setLevel(h.splitCount), updateIndices(nav, tri, edges), nav.setLevel(0), updateIndices(nav, tri, edges);
const runs = { refine: [], refineIdx: [], coarsen: [], coarsenIdx: [] };
for (let r = 0; r < 7; r++) {
  const sums = Object.fromEntries(Object.keys(runs).map((key) => [key, [0, 0]]));
  for (let k = 0; k < repeat; k++) {
    sums.refine = add(sums.refine, timed(() => nav.setLevel(h.splitCount)));
    sums.refineIdx = add(sums.refineIdx, timed(() => updateIndices(nav, tri, edges)));
    sums.coarsen = add(sums.coarsen, timed(() => nav.setLevel(0)));
    sums.coarsenIdx = add(sums.coarsenIdx, timed(() => updateIndices(nav, tri, edges)));
  }
  for (const key of Object.keys(runs)) runs[key].push(sums[key].map((t) => t / repeat));
}
const report = (what, unit, nav, idx) => {
  const [w, c] = [0, 1].map((k) => median(nav.map((x) => x[k])));
  const [wi, ci] = [0, 1].map((k) => median(idx.map((x) => x[k])));
  console.log(`full ${what}: ${w.toFixed(0)} ms, ${perS(w)} M ${unit}/s (cpu ${perS(c)}); ` +
    `with the index update ${perS(w + wi)} M/s (cpu ${perS(c + ci)})`);
};
console.log(`${h.splitCount} splits, median of 7${repeat > 1 ? ` runs of ${repeat}` : ''}:`);
report('refine', 'splits', runs.refine, runs.refineIdx);
report('coarsen', 'collapses', runs.coarsen, runs.coarsenIdx);

// The page's moves: steps of 65,536 splits (viewer.js SPLITS_PER_STEP), up to the full level and
// down again, the index update after each step; medians of 5 in CPU time.
const PAGE_STEP = 65536;
const page = [];
for (let r = 0; r < 5; r++) {
  let moving = 0, indexing = 0;
  for (const up of [true, false]) {
    while (up ? nav.level < h.splitCount : nav.level > 0) {
      const k = up ? Math.min(h.splitCount, nav.level + PAGE_STEP) : Math.max(0, nav.level - PAGE_STEP);
      moving += timed(() => nav.setLevel(k))[1];
      indexing += timed(() => updateIndices(nav, tri, edges))[1];
    }
  }
  page.push([moving, indexing]);
}
const [pageMove, pageIndex] = [0, 1].map((k) => median(page.map((x) => x[k])));
console.log(`the page's steps of ${PAGE_STEP} splits, up and down (cpu): navigator ${pageMove.toFixed(0)} ms, ` +
  `index update ${pageIndex.toFixed(0)} ms, ${(2 * h.splitCount / (pageMove + pageIndex) / 1e3).toFixed(2)} M moves/s with it`);

const visible = visibleArg > 0 ? Number(process.argv[visibleArg + 1]) : Math.min(100000, h.vertexCount);
nav.setVertexCount(visible);
const out = new Float32Array(3 * h.vertexCount);
const frames = 200;
const scrub = best(3, () => {
  const s = process.hrtime.bigint();
  for (let i = 0; i < frames; i++) mesh.positionsAt((i * 0.37) % (h.stepCount - 1), nav.vertexCount, out);
  return ms(s) / frames;
});
console.log(`positions at a fractional step, ${nav.vertexCount} vertices: ${scrub.toFixed(2)} ms/frame`);
