// Field A − field B in compare (docs/viewer.md "Compare"): for two files of one hierarchy, a
// result field both hold (the same name, location and unit) shown as its signed difference per
// vertex (node field) or face (element field) of the current level. Each side's values are the
// ones its own fringe shows there (ShownValues: max |value| or mean of what the item stands for,
// at the nearest whole step), so the difference is that of the two pictures, and of what
// `dynpm extract` writes of each at that level and step. B's step is A's clamped to B's last
// (compare's linked time). FieldView draws it (its `shown` option) in a diverging scheme over
// ±the largest |difference|, on both canvases from one object.
import { ShownValues } from './dpm.js';

export const FIELD_DIFFERENCE = 'fielddiff:';

// The fields of A that B holds too, as [k in A, k in B]: the same name, location and unit (an
// element field's merges also need the same heirs, which one hierarchy built by dynpm has).
export function commonFields(a, b) {
  const pairs = [];
  a.fields.forEach((f, k) => {
    const j = b.fields.findIndex((g) => g.name === f.name && g.perFace === f.perFace && g.unit === f.unit);
    if (j < 0) return;
    if (f.perFace && !sameValues(a.faceHeir, b.faceHeir, a.head.faceCount)) return;
    pairs.push([k, j]);
  });
  return pairs;
}

function sameValues(x, y, n) {
  if (!x || !y) return x === y;
  for (let i = 0; i < n; i++) if (x[i] !== y[i]) return false;
  return true;
}

// What FieldView reads of a ShownValues (step, splits, level, mean, values, itemCount, set,
// setLevel, peak), for A's field k − B's field j.
export class FieldDifference {
  constructor(a, k, b, j, aggregate) {
    this.a = new ShownValues(a, a.fields[k], aggregate);
    this.b = new ShownValues(b, b.fields[j], aggregate);
    this.field = a.fields[k];
    this.mean = this.a.mean;
    this.stepCount = a.head.stepCount;  // steps are A's
    this.lastB = b.head.stepCount - 1;
    this.values = new Float64Array(this.a.values.length);  // exact: of two float32 values
    this.step = -1;
    this.splits = 0;
    this.level = 0;
    this.largest = 0;  // the largest |difference| at this level and step
    this.item = -1;  // where it is (peak())
  }

  itemCount(level) {
    return this.a.itemCount(level);
  }

  // Step t (A's) at level k: both sides' passes, then the difference.
  set(t, k) {
    this.a.set(t, k);
    this.b.set(Math.min(t, this.lastB), k);
    this.step = t;
    this.splits = Math.min(this.a.splits, this.b.splits);
    this.subtract(k);
  }

  setLevel(k) {
    if (!this.a.setLevel(k) || !this.b.setLevel(k)) return false;
    this.subtract(k);
    return true;
  }

  subtract(k) {
    const n = this.itemCount(k);
    const { values } = this, va = this.a.values, vb = this.b.values;
    let largest = 0, item = -1;
    for (let x = 0; x < n; x++) {
      const d = Math.abs((values[x] = va[x] - vb[x]));
      if (d > largest || item < 0) (largest = d), (item = x);
    }
    this.level = k;
    this.largest = largest;
    this.item = item;
  }

  // The fringe's range: symmetric, so that zero is the scheme's middle.
  get range() {
    return [-this.largest, this.largest];
  }

  // The present item of largest |difference| (the first of equals), or −1: found by subtract().
  peak() {
    return this.item;
  }
}
