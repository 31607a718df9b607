// Speed of dpm.js in Node (V8, as in Chromium): decoding a .dpm, full refine and full coarsen
// with the index buffers the page keeps, and the per-frame work of time scrubbing.
//   node bench/refine.mjs MODEL.dpm [--visible N]
import { readFileSync } from 'node:fs';

import { Navigator, readDpm, updateIndices } from '../src/dpm.js';

const file = process.argv[2];
if (!file) {
  console.error('usage: node bench/refine.mjs MODEL.dpm [--visible N]');
  process.exit(2);
}
const visibleArg = process.argv.indexOf('--visible');
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
const refine = best(3, () => {
  nav.setLevel(0);
  updateIndices(nav, tri, edges);
  const s = process.hrtime.bigint();
  nav.setLevel(h.splitCount);
  updateIndices(nav, tri, edges);
  return ms(s);
});
const coarsen = best(3, () => {
  nav.setLevel(h.splitCount);
  updateIndices(nav, tri, edges);
  const s = process.hrtime.bigint();
  nav.setLevel(0);
  updateIndices(nav, tri, edges);
  return ms(s);
});
console.log(`full refine ${h.splitCount} splits + index update: ${refine.toFixed(0)} ms; ` +
  `full coarsen: ${coarsen.toFixed(0)} ms`);

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
