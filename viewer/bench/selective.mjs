// Speed of selective refinement in dpm.js (Node, V8 as in Chromium; docs/viewer.md "Selective
// refinement"): deriving the split dependencies from the records (what a page pays at load), and
// moving the active front between two box requests (the splits applied and undone, the
// wanted set with its closure, and the index entries the page rewrites), medians of 7 in wall
// and CPU time with the load average.
// Then a view re-targeted (docs/viewer.md "Spheres from a worker"): the split spheres and per
// camera the screen errors (both made in the page's spheres worker), and per camera what the
// page's main thread does — the closure (wantedSet()), the front moved, the index entries — for
// the camera of bench/selective_bench.cpp (1920 × 1080, 45°, low over one corner) moved by a
// twentieth; beside it the page's work before the screen errors moved to the worker (screen
// errors and closure, the wanted set closed again, the front, the index entries).
//   node bench/selective.mjs MODEL.dpm [--box-fraction F] [--px P] [--derive RUNS (default 7)]
import { readFileSync } from 'node:fs';
import { loadavg } from 'node:os';

import { readDpm, updateIndices } from '../src/dpm.js';
import { elsewhereLevel, parseElsewhere, parseRequest, requestedSplits, wantedSet } from '../src/dpm/refine_targets.js';
import { SelectiveNavigator } from '../src/dpm/selective_navigator.js';
import { SplitDependencies } from '../src/dpm/split_dependencies.js';
import { splitSpheres, viewOrder } from '../src/dpm/view_target.js';

const file = process.argv[2];
if (!file) {
  console.error('usage: node bench/selective.mjs MODEL.dpm [--box-fraction F]');
  process.exit(2);
}
const at = process.argv.indexOf('--box-fraction');
const fraction = at > 0 ? Number(process.argv[at + 1]) : 0.1;
const pxAt = process.argv.indexOf('--px');
const px = pxAt > 0 ? Number(process.argv[pxAt + 1]) : 0.005;
const deriveAt = process.argv.indexOf('--derive');
const deriveRuns = deriveAt > 0 ? Math.max(1, Number(process.argv[deriveAt + 1])) : 7;
const ms = (start) => Number(process.hrtime.bigint() - start) / 1e6;
const median = (v) => v.slice().sort((a, b) => a - b)[v.length >> 1];
const timed = (f) => {
  const c = process.cpuUsage();
  const s = process.hrtime.bigint();
  const result = f();
  const wall = ms(s);
  const cpu = process.cpuUsage(c);
  return { wall, cpu: (cpu.user + cpu.system) / 1e3, result };
};
const summary = (runs) => `${median(runs.map((r) => r.wall)).toFixed(1)} ms wall, ${median(runs.map((r) => r.cpu)).toFixed(1)} ms CPU`;

const { mesh } = readDpm(readFileSync(file), file);
const h = mesh.head;
console.log(`${file}: ${h.vertexCount} vertices (base ${h.baseVertexCount}), ${h.faceCount} faces, ${h.splitCount} splits; load average ${loadavg().map((x) => x.toFixed(2)).join(' ')}`);

// 1. The dependencies, derived from scratch (7 times by default).
// Only the last is kept (the others' arrays would make the collector's work grow run by run).
const derive = Array.from({ length: deriveRuns }, () => timed(() => new SplitDependencies(mesh).update()));
const deps = derive[deriveRuns - 1].result;
for (const r of derive) r.result = null;
const s = deps.stats();
console.log(`dependencies: ${summary(derive)} (${(median(derive.map((r) => r.wall)) / (h.splitCount / 1e6)).toFixed(0)} ms per M splits); ` +
  `${s.dependencies} in all, ${s.mean.toFixed(2)} per split (max ${s.max}); as CSR in memory ${((4 * s.dependencies + 4 * (h.splitCount + 1)) / h.vertexCount).toFixed(1)} B per vertex, none in the file`);

// 2. Two boxes of `fraction` of the box's extent along its longest axis, at its two ends, and
// the level elsewhere at 5 %: the front moves from one to the other and back.
const axis = [0, 1, 2].reduce((a, c) => (h.bboxMax[c] - h.bboxMin[c] > h.bboxMax[a] - h.bboxMin[a] ? c : a), 0);
const box = (end) => {
  const lo = h.bboxMin.slice(), hi = h.bboxMax.slice();
  const len = hi[axis] - lo[axis];
  if (end) lo[axis] = hi[axis] - fraction * len;
  else hi[axis] = lo[axis] + fraction * len;
  return `box:${[...lo, ...hi].join(',')}`;
};
const level = elsewhereLevel(mesh, parseElsewhere('5%'));
const nav = new SelectiveNavigator(mesh, deps);
const tri = new Uint32Array(6 * h.faceCount), edges = new Uint32Array(8 * h.faceCount);
const targets = [box(0), box(1)].map((b) => timed(() => nav.wanted(level, requestedSplits(mesh, deps, [b], 0))));
nav.setTarget(targets[0].result, level);
updateIndices(nav, tri, edges);
const moves = [], indices = [];
for (let r = 0; r < 7; r++)
  for (const wanted of [targets[1].result, targets[0].result]) {
    moves.push(timed(() => nav.setTarget(wanted, level)));
    indices.push(timed(() => updateIndices(nav, tri, edges)));
  }
const changed = moves[0].result.applied + moves[0].result.undone;
const per100k = (runs) => (median(runs.map((r) => r.wall)) * 1e5 / changed).toFixed(1);
console.log(`targets (box → wanted splits, closure): ${targets.map((t) => `${t.wall.toFixed(1)} ms`).join(', ')}; ` +
  `${nav.activeVertexCount} vertices active (level elsewhere ${h.baseVertexCount + level})`);
console.log(`front move: ${changed} splits (${moves[0].result.applied} applied, ${moves[0].result.undone} undone): ${summary(moves)} = ${per100k(moves)} ms per 100 k splits`);
console.log(`index entries after it: ${summary(indices)} = ${per100k(indices)} ms per 100 k splits`);

// 3. A view re-targeted: the spheres once per step, then two cameras in turn, 1 % elsewhere.
const spheresRuns = Array.from({ length: 7 }, () => timed(() => splitSpheres(mesh, deps.derived, 0)));
const spheres = spheresRuns[6].result;
for (const r of spheresRuns) r.result = null;
console.log(`view: spheres (in the page's worker, once per step): ${summary(spheresRuns)}`);
const c = [0, 1, 2].map((k) => (h.bboxMin[k] + h.bboxMax[k]) / 2);
const across = Math.max(h.bboxMax[0] - h.bboxMin[0], h.bboxMax[1] - h.bboxMin[1]);
const camera = (shift) => parseRequest(`view:EYE=${h.bboxMin[0] + (0.1 + shift) * across},${h.bboxMin[1] + 0.1 * across},${c[2] + 0.06 * across};` +
  `AT=${c[0] + shift * across},${c[1]},${c[2]};FOV=45;W=1920;H=1080;PX=${px}`);
const one = elsewhereLevel(mesh, parseElsewhere('1%'));
// The page before (request with the screen errors, its set closed again) and now (the screen
// errors from the worker, closed once), each on a navigator of its own moved between the same
// cameras; both must reach the same vertices.
const before = { nav: new SelectiveNavigator(mesh, deps), request: [], wanted: [], setTarget: [], indices: [], page: [] };
const now = { nav: new SelectiveNavigator(mesh, deps), worker: [], wantedSet: [], setTarget: [], indices: [], page: [] };
const pageCost = (start) => {
  const cpu = process.cpuUsage(start.cpu);
  return { wall: ms(start.wall), cpu: (cpu.user + cpu.system) / 1e3 };
};
const begin = () => ({ wall: process.hrtime.bigint(), cpu: process.cpuUsage() });
const counts = [];
for (const side of [before, now]) updateIndices(side.nav, tri, edges);
for (let r = 0; r < 8; r++) {
  const view = camera(r % 2 ? 0.05 : 0);
  let start = begin();
  const request = timed(() => requestedSplits(mesh, deps, [view], 0, one, { spheres }));
  const wanted = timed(() => before.nav.wanted(one, request.result));
  const moved = timed(() => before.nav.setTarget(wanted.result, one));
  const indices = timed(() => updateIndices(before.nav, tri, edges));
  const pageBefore = pageCost(start);
  const worker = timed(() => [viewOrder(mesh, spheres, deps.derived, view)]);
  start = begin();
  const set = timed(() => wantedSet(mesh, deps, [view], 0, one, { splits: worker.result }));
  const movedNow = timed(() => now.nav.setTarget(set.result, one));
  const indicesNow = timed(() => updateIndices(now.nav, tri, edges));
  const pageNow = pageCost(start);
  if (before.nav.activeVertexCount !== now.nav.activeVertexCount) throw new Error(`camera ${r}: ${before.nav.activeVertexCount} vertices before, ${now.nav.activeVertexCount} now`);
  if (r === 0) continue;  // the first fills the front from the level
  Object.entries({ request, wanted, setTarget: moved, indices, page: pageBefore }).forEach(([k, v]) => before[k].push(v));
  Object.entries({ worker, wantedSet: set, setTarget: movedNow, indices: indicesNow, page: pageNow }).forEach(([k, v]) => now[k].push(v));
  counts.push(`${now.nav.activeVertexCount} (${movedNow.result.applied + movedNow.result.undone} changed)`);
}
console.log(`view: PX ${px}, camera moved by 1/20; vertices ${[...new Set(counts)].join(', ')}`);
for (const [name, side] of [['before (screen errors on the page, closed twice)', before], ['now (screen errors in the worker, closed once)', now]]) {
  console.log(`  ${name}:`);
  for (const [what, runs] of Object.entries(side)) if (what !== 'nav') console.log(`    ${what}: ${summary(runs)}`);
}
console.log(`load average after: ${loadavg().map((x) => x.toFixed(2)).join(' ')}`);
