// A large synthetic shell animation for the benchmarks: an N × N quad plate (a triangle strip
// along one edge, so both kinds occur) with a travelling bump, as OBJ frames.
//   node bench/make_grid.mjs N STEPS OUT_DIR
import { mkdirSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';

const [n, steps, dir] = [Number(process.argv[2]), Number(process.argv[3]), process.argv[4]];
if (!(n > 1 && steps > 0 && dir)) {
  console.error('usage: node bench/make_grid.mjs N STEPS OUT_DIR');
  process.exit(2);
}
mkdirSync(dir, { recursive: true });
const faces = [];
for (let j = 0; j + 1 < n; j++)
  for (let i = 0; i + 1 < n; i++) {
    const a = j * n + i + 1, b = a + 1, c = a + n + 1, d = a + n;
    if (i === 0) faces.push(`f ${a} ${b} ${c}\nf ${a} ${c} ${d}\n`);
    else faces.push(`f ${a} ${b} ${c} ${d}\n`);
  }
const faceText = faces.join('');
for (let t = 0; t < steps; t++) {
  const s = t / Math.max(1, steps - 1);
  const lines = [`# synthetic plate, time ${s}\n`];
  for (let j = 0; j < n; j++) {
    const row = [];
    for (let i = 0; i < n; i++) {
      const x = i / (n - 1), y = j / (n - 1);
      const r2 = (x - s) ** 2 + (y - 0.5) ** 2;
      const z = 0.15 * s * Math.exp(-r2 * 30) + 0.02 * Math.sin(6 * x) * Math.cos(4 * y);
      row.push(`v ${(100 * x).toFixed(5)} ${(100 * y).toFixed(5)} ${(100 * z).toFixed(5)}\n`);
    }
    lines.push(row.join(''));
  }
  writeFileSync(join(dir, `frame_${String(t).padStart(3, '0')}.obj`), lines.join('') + faceText);
}
console.log(`${n * n} vertices, ${faces.length} face lines, ${steps} steps in ${dir}`);
