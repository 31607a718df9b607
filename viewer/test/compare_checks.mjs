// What the compare tests (compare_browser, catalogue_compare_browser) check of a page showing two
// models: both whole and shown, and the difference fringe's largest |p_A − p_B| against the
// positions `dynpm extract` writes of both at the same level and step.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { readFileSync } from 'node:fs';

// Run in the page: both models decoded, their Navigators made, the first at its finest level.
export const bothShown = () => {
  const c = window.dpmViewer?.compare();
  const s = window.dpmViewer?.state();
  return Boolean(c?.complete && c.navigator && s.complete && s.navigator && s.vertices === s.loadedVertices);
};

// The OBJ's vertex positions, as `dynpm extract DPM --vertices N --step T [extra]` writes them.
export function extracted(cli, dpm, vertices, step, objPath, extra = []) {
  execFileSync(cli, ['extract', dpm, '--vertices', String(vertices), '--step', String(step), ...extra, '-o', objPath], { stdio: 'pipe' });
  const p = [];
  for (const line of readFileSync(objPath, 'utf8').split('\n'))
    if (line.startsWith('v ')) p.push(...line.split(/\s+/).slice(1, 4).map(Number));
  return Float32Array.from(p);
}

// The page's largest difference (dpmViewer.compare().largest) against the extracted positions a
// and b of n vertices: the same value (relative 1e-9), a vertex that has it, the two markers on
// that vertex's extracted positions. `original` is the file's vertexOriginal: fully refined,
// extract writes the input's order, else the level's. Returns the extracted largest.
export function checkLargest(largest, a, b, n, original, what) {
  assert.equal(a.length, 3 * n, `${what}: A's extracted vertices`);
  assert.equal(b.length, 3 * n, `${what}: B's extracted vertices`);
  const distance = (v) => Math.hypot(a[3 * v] - b[3 * v], a[3 * v + 1] - b[3 * v + 1], a[3 * v + 2] - b[3 * v + 2]);
  let max = 0;
  for (let v = 0; v < n; v++) max = Math.max(max, distance(v));
  assert.ok(Math.abs(largest.value - max) <= 1e-9 * max, `${what}: page ${largest.value}, extract ${max}`);
  const at = n === original.length ? original[largest.vertex] : largest.vertex;  // several may tie
  assert.ok(Math.abs(distance(at) - max) <= 1e-9 * max, `${what}: vertex ${at}: ${distance(at)} of ${max}`);
  assert.deepEqual(largest.positionA, Array.from(a.subarray(3 * at, 3 * at + 3)), `${what}: A's marker at the vertex`);
  assert.deepEqual(largest.positionB, Array.from(b.subarray(3 * at, 3 * at + 3)), `${what}: B's marker at the vertex`);
  return max;
}
