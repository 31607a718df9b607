// The values a level shows of a result field (docs/FORMAT.md "Shown values: peaks are never
// hidden"): each present vertex (face) shows the aggregate of the original values it stands for
// — itself and the vertices collapsed into it (the faces whose chain of heirs leads to it).
// C++: Navigator::field_values() in src/lod/navigator.cpp, which runs the pass down to one level.
//
// Kept cheap while refining and coarsening, as FORMAT.md says: per step one backward pass over
// the loaded splits gives sub() (each item's whole subtree) and after() (what the parent shows
// right after the merge is undone); then a change of level costs O(items the splits name).
// A merge is (into, from): split i merges vertex b + i into its parent; the faces it creates
// merge into their heirs, in creation order — which is the items' numbering. after() is indexed
// by `from`.

export const AGGREGATES = ['max', 'mean'];

// max |value| with its sign; of two with equal magnitude the larger: the max of a total order,
// so the order of merging never changes the result (as the C++ larger_magnitude()).
export function largerMagnitude(a, b) {
  const ma = Math.abs(a), mb = Math.abs(b);
  return ma > mb || (ma === mb && a >= b) ? a : b;
}

export class ShownValues {
  // field: a DpmField of mesh (fields.js); aggregate: 'max' (max |value|, default) or 'mean'.
  constructor(mesh, field, aggregate = 'max') {
    this.mesh = mesh;
    this.field = field;
    this.mean = aggregate === 'mean';
    const h = mesh.head;
    const n = field.perFace ? h.faceCount : h.vertexCount;
    this.values = new Float32Array(n);  // per present item: what it shows (the output)
    this.raw = new Float32Array(n);  // per loaded item: its own value at this step
    this.sub = new Float64Array(n);  // per loaded item: the aggregate (sum, mean) of its subtree
    this.after = new Float64Array(n);  // per merged item `from`: its parent's, right after
    this.shown = new Float64Array(n);  // per present item: the aggregate (sum, mean) it shows
    if (this.mean) {
      this.subCount = new Float64Array(n);
      this.afterCount = new Float64Array(n);
      this.shownCount = new Float64Array(n);
    }
    this.step = -1;
    this.splits = 0;  // splits the pass covered (loaded when it ran)
    this.level = 0;
    this.stepMin = 0;  // smallest and largest original value at this step (loaded items)
    this.stepMax = 0;
  }

  // Items present with k splits applied.
  itemCount(k) {
    const { mesh } = this;
    return this.field.perFace ? mesh.faceCountAt[k] : mesh.head.baseVertexCount + k;
  }

  // The merges in creation order are the items from the base mesh's count on, each into its
  // parent (its heir): split i creates the items [itemCount(i), itemCount(i + 1)).
  // Returns [first merged item, into array, offset]: item x merges into into[x − offset].
  mergeList() {
    const { mesh } = this;
    const b = mesh.head.baseVertexCount;
    return this.field.perFace ? [mesh.head.baseFaceCount, mesh.faceHeir, 0] : [b, mesh.parent, b];
  }

  // Step t and level k (splits applied, ≤ the loaded ones): the backward pass, then the level.
  set(t, k) {
    const { mesh, field, sub, after, mean, subCount, afterCount, raw } = this;
    const L = mesh.splitsLoaded;
    const n = this.itemCount(L);
    field.valuesAt(t, n, raw);
    let lo = Infinity, hi = -Infinity;
    for (let x = 0; x < n; x++) {
      const v = raw[x];
      sub[x] = v;
      if (v < lo) lo = v;
      if (v > hi) hi = v;
    }
    this.stepMin = n ? lo : 0;
    this.stepMax = n ? hi : 0;
    const [first, into, offset] = this.mergeList();
    // Reverse creation order: what x merges into holds, then x's subtree merged in.
    if (mean) {
      subCount.fill(1, 0, n);
      for (let x = n - 1; x >= first; x--) {
        const p = into[x - offset];
        after[x] = sub[p];
        afterCount[x] = subCount[p];
        sub[p] += sub[x];
        subCount[p] += subCount[x];
      }
    } else {
      for (let x = n - 1; x >= first; x--) {
        const p = into[x - offset];
        const a = sub[p], c = sub[x];
        after[x] = a;
        // largerMagnitude(a, c), inline: this loop is the step change's cost.
        const ma = a < 0 ? -a : a, mc = c < 0 ? -c : c;
        if (mc > ma || (mc === ma && c > a)) sub[p] = c;
      }
    }
    this.step = t;
    this.splits = L;
    this.jumpTo(k);
  }

  // The level directly: every present item its subtree, then each applied merge in order (the
  // last merge into an item before the level wins).
  jumpTo(k) {
    const n = this.itemCount(k);
    const { shown, after, mean } = this;
    shown.set(this.sub.subarray(0, n));
    if (mean) this.shownCount.set(this.subCount.subarray(0, n));
    const [first, into, offset] = this.mergeList();
    for (let x = first; x < n; x++) {
      const p = into[x - offset];
      shown[p] = after[x];
      if (mean) this.shownCount[p] = this.afterCount[x];
    }
    this.level = k;
    const values = this.values;
    if (mean) for (let x = 0; x < n; x++) values[x] = shown[x] / this.shownCount[x];
    else values.set(shown.subarray(0, n));
  }

  // A change of level, O(items the splits name); returns false when the pass must run again
  // (splits loaded since).
  setLevel(k) {
    if (k > this.splits) return false;
    const { shown, sub, after, mean, shownCount, subCount } = this;
    const [, into, offset] = this.mergeList();
    const now = this.itemCount(this.level), then = this.itemCount(k);
    // Refining: each created item its subtree; its parent what it holds right after the split.
    for (let x = now; x < then; x++) {
      const p = into[x - offset];
      shown[p] = after[x];
      shown[x] = sub[x];
      if (mean) (shownCount[p] = this.afterCount[x]), (shownCount[x] = subCount[x]);
      this.output(p), this.output(x);
    }
    // Coarsening: each removed item's subtree merged back into its parent.
    for (let x = now - 1; x >= then; x--) {
      const p = into[x - offset];
      if (mean) (shown[p] += sub[x]), (shownCount[p] += subCount[x]);
      else shown[p] = largerMagnitude(shown[p], sub[x]);
      this.output(p);
    }
    this.level = k;
    return true;
  }

  output(x) {
    this.values[x] = this.mean ? this.shown[x] / this.shownCount[x] : this.shown[x];
  }

  // The present item of largest |shown value| (the first of equals), or −1 when none.
  peak() {
    const n = this.itemCount(this.level);
    let best = -1, m = -1;
    for (let x = 0; x < n; x++) {
      const a = Math.abs(this.values[x]);
      if (a > m) (m = a), (best = x);
    }
    return best;
  }
}
