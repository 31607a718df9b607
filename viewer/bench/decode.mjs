// Speed of the browser's decoder in Node (V8, as in Chromium): readDpm of whole files, repeated
// in one process, so that the figure is the optimised code's and not the first run's compile.
// Several files are alternated run by run (old and new side by side see the same machine load).
//   node bench/decode.mjs [--runs N] A.dpm [B.dpm …]
import { readFileSync } from 'node:fs';

import { readDpm } from '../src/dpm.js';

const args = process.argv.slice(2);
const at = args.indexOf('--runs');
const runs = at >= 0 ? Number(args.splice(at, 2)[1]) : 7;
if (args.length === 0 || !(runs >= 1)) {
  console.error('usage: node bench/decode.mjs [--runs N] A.dpm [B.dpm …]');
  process.exit(2);
}
const files = args.map((name) => ({ name, bytes: readFileSync(name), wall: [], cpu: [] }));
for (let r = 0; r < runs; r++) {
  for (const f of files) {
    const c = process.cpuUsage();
    const s = process.hrtime.bigint();
    readDpm(f.bytes, f.name);
    f.wall.push(Number(process.hrtime.bigint() - s) / 1e6);
    const u = process.cpuUsage(c);
    f.cpu.push((u.user + u.system) / 1e3);
  }
}
const median = (v) => [...v].sort((a, b) => a - b)[v.length >> 1];
for (const f of files) {
  console.log(`${f.name}: decode median ${median(f.wall).toFixed(0)} ms (fastest ` +
    `${Math.min(...f.wall).toFixed(0)}, first ${f.wall[0].toFixed(0)}; cpu median ` +
    `${median(f.cpu).toFixed(0)} ms) over ${runs} runs`);
}
