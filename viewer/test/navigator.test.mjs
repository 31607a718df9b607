// The level navigator's own loops (navigator.js: faces written from what it learned the first
// time a split was applied) against applySplit()/undoSplit() split by split, on real crash boxes
// built by the CLI (C++: Navigator.EveryLevelIsWhatApplySplitMakes): the whole face array at
// every level on the way up, on the way down and up again, then at random levels reached in
// jumps both ways, with the touched-face list holding every face that changed.
import assert from 'node:assert/strict';
import { test } from 'node:test';

import { Navigator } from '../src/dpm.js';
import { applySplit, undoSplit } from '../src/dpm/progressive_mesh.js';
import { random } from './mesh_checks.mjs';
import { crashbox, CRASHBOXES } from './selective_fixture.mjs';

// The faces applySplit()/undoSplit() make, one split at a time.
class Reference {
  constructor(mesh) {
    this.mesh = mesh;
    this.corners = new Int32Array(4 * mesh.head.faceCount).fill(-1);
    this.corners.set(mesh.baseCorners);
    this.level = 0;
    this.quads = mesh.baseDegree.reduce((n, d) => n + (d === 4 ? 1 : 0), 0);
  }
  setLevel(k) {
    for (; this.level < k; this.level++) this.quads += applySplit(this.mesh, this.level, this.corners, () => {});
    for (; this.level > k; this.level--) this.quads -= undoSplit(this.mesh, this.level - 1, this.corners, () => {});
  }
}

// The faces below the level's face count (an undone triangle wing lies beyond it, where the
// navigator's stores may leave anything), the counts, and, when `before` is given (the faces
// before the change), every face that changed is in the touched-face list.
function assertSame(nav, ref, what, before = null) {
  assert.equal(nav.level, ref.level, what);
  assert.equal(nav.quadCount, ref.quads, what);
  const a = nav.corners, b = ref.corners;
  assert.equal(nav.faceCount, ref.mesh.faceCountAt[ref.level], what);
  for (let x = 0; x < 4 * nav.faceCount; x++) if (a[x] !== b[x]) assert.fail(`${what}: face ${x >> 2}: ${nav.face(x >> 2)}, applySplit makes ${Array.from(b.subarray(x & ~3, (x & ~3) + 4))}`);
  const touched = new Set(nav.takeDirty());
  if (!before) return 0;
  let changed = 0;
  for (let f = 0; f < a.length >> 2; f++) {
    const c = 4 * f;
    // Room the navigator made since (it grows with the finest level reached) read −1 before.
    if (c >= before.length && a[c] === -1 && a[c + 1] === -1 && a[c + 2] === -1 && a[c + 3] === -1) continue;
    if (a[c] === before[c] && a[c + 1] === before[c + 1] && a[c + 2] === before[c + 2] && a[c + 3] === before[c + 3]) continue;
    assert.ok(touched.has(f), `${what}: face ${f} changed and is not in the touched faces`);
    changed++;
  }
  return changed;
}

for (const name of CRASHBOXES) {
  const mesh = crashbox(name);
  const S = mesh.splitsLoaded;

  test(`${name}: every level up, down and up again is what applySplit and undoSplit make`, () => {
    assert.ok(S > 4000, `${S} splits`);
    const nav = new Navigator(mesh), ref = new Reference(mesh);
    nav.takeDirty();
    const step = (k, what) => {
      const before = nav.corners.slice();
      nav.setLevel(k), ref.setLevel(k);
      return assertSame(nav, ref, `${what}, level ${k}`, before);
    };
    let changed = 0;
    for (let k = 1; k <= S; k++) changed += step(k, 'up');
    assert.equal(nav.learned, S);
    for (let k = S - 1; k >= 0; k--) changed += step(k, 'down');
    for (let k = 1; k <= S; k++) changed += step(k, 'up again');
    assert.ok(changed > 3 * 3 * S, `${changed} faces changed`);
    assert.ok(ref.quads > 0 && ref.quads < mesh.faceCountAt[S], `${ref.quads} quads`);
  });

  test(`${name}: levels reached in jumps, learned and known splits in one move`, () => {
    const rand = random(19);
    const nav = new Navigator(mesh), ref = new Reference(mesh);
    nav.takeDirty();
    let changed = 0, learnedPart = 0;
    for (let round = 0; round < 60; round++) {
      // Early rounds go down below what was learned, then up beyond it (a move that applies
      // known splits and learns the rest); later ones anywhere, whole refines and coarsens too.
      let k = Math.floor(S * rand());
      if (round < 12) k = round % 2 ? Math.floor(nav.learned * rand()) : Math.min(S, nav.learned + 1 + Math.floor(S / 8 * rand()));
      else if (round % 5 < 2) k = round % 5 ? S : 0;
      if (k > nav.learned && nav.level < nav.learned) learnedPart++;
      const before = nav.corners.slice();
      nav.setLevel(k), ref.setLevel(k);
      changed += assertSame(nav, ref, `round ${round}, level ${k}`, before);
    }
    assert.ok(learnedPart >= 3, `${learnedPart} moves both known and learned`);
    assert.ok(changed > 10 * S, `${changed} faces changed`);
  });
}
