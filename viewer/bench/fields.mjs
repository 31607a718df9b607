// Speed of dpm.js's result fields in Node (V8, as in Chromium): decoding a .dpm with and without
// its FDEF/FLDS chunks, the pass per step change (ShownValues.set) and a change of level in place
// (ShownValues.setLevel) against the direct pass to the level (jumpTo).
//   node bench/fields.mjs MODEL.dpm        a .dpm with fields
//   node bench/fields.mjs MODEL.dpm --add  one without: a node and an element field are added
//                                          (test/fields_fixture.mjs) and both files are timed
import { readFileSync } from 'node:fs';

import { readDpm, ShownValues } from '../src/dpm.js';
import { rawChunks, withFields } from '../test/fields_fixture.mjs';

const file = process.argv[2];
if (!file) {
  console.error('usage: node bench/fields.mjs MODEL.dpm [--add]');
  process.exit(2);
}
const ms = (start) => Number(process.hrtime.bigint() - start) / 1e6;
const median = (xs) => [...xs].sort((a, b) => a - b)[xs.length >> 1];
const timed = (runs, f) => median(Array.from({ length: runs }, () => {
  const s = process.hrtime.bigint();
  f();
  return ms(s);
}));

let bytes = new Uint8Array(readFileSync(file));
let plain = null;
if (process.argv.includes('--add')) {
  plain = bytes;
  bytes = withFields(plain, [
    { name: 'node', unit: 'MPa', perFace: false, value: (v, t, m) => m.position(v, t)[2] * 7 },
    { name: 'element', perFace: true, value: (f, t) => Math.max(0, Math.sin(f * 0.001 + t)) },
  ]);
} else {
  // The same file without its optional chunks: what a reader that skips them decodes.
  const kept = rawChunks(bytes).filter((c) => c.tag !== 'FDEF' && c.tag !== 'FLDS').map((c) => c.bytes);
  plain = new Uint8Array(12 + kept.reduce((a, c) => a + c.length, 0));
  plain.set(bytes.subarray(0, 12));
  kept.reduce((at, c) => (plain.set(c, at), at + c.length), 12);
}
const withTime = timed(5, () => readDpm(bytes, file));
const withoutTime = timed(5, () => readDpm(plain, file));
const { mesh } = readDpm(bytes, file);
const h = mesh.head;
console.log(`${file}: ${h.vertexCount} vertices, ${h.faceCount} faces, ${h.stepCount} steps, ` +
  `${mesh.fields.length} fields (${mesh.fields.map((f) => `${f.name}: ${f.perFace ? 'element' : 'node'}`).join(', ')})`);
console.log(`decode: ${withoutTime.toFixed(0)} ms without fields (${(plain.length / 2 ** 20).toFixed(1)} MiB), ` +
  `${withTime.toFixed(0)} ms with (${(bytes.length / 2 ** 20).toFixed(1)} MiB), median of 5`);

const S = mesh.splitsLoaded;
for (const field of mesh.fields)
  for (const aggregate of ['max', 'mean']) {
    const s = new ShownValues(mesh, field, aggregate);
    const k = Math.round(S * 0.25);
    let t = 0;
    const step = timed(9, () => s.set((t = (t + 1) % h.stepCount), k));
    // A change of level as the slider makes one: 1 % of the splits, refine then coarsen.
    const d = Math.max(1, Math.round(S * 0.01));
    const level = timed(9, () => {
      s.setLevel(k + d);
      s.setLevel(k);
    }) / 2;
    const sweep = timed(3, () => {
      s.setLevel(S);
      s.setLevel(0);
    }) / 2;
    const jump = timed(9, () => s.jumpTo(k));
    console.log(`${field.name} (${field.perFace ? 'element' : 'node'}), ${aggregate}: step change ` +
      `${step.toFixed(1)} ms; level change of ${d} splits ${level.toFixed(2)} ms in place, ` +
      `all ${S} splits ${sweep.toFixed(1)} ms; direct pass to a level ${jump.toFixed(1)} ms`);
  }
