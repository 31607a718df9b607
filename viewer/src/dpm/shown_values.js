// The values a level shows of a result field (docs/FORMAT.md "Shown values: peaks are never
// hidden"): each present vertex (face) shows the aggregate of the original values it stands for
// — itself and the vertices collapsed into it (the faces whose chain of heirs leads to it).
// C++: Navigator::field_values() in src/lod/navigator.cpp, which runs the pass down to one level.
//
// Kept cheap while refining and coarsening, as FORMAT.md says: per step one backward pass over
// the loaded splits gives sub() (each item's whole subtree) and after() (what the parent shows
// right after the merge is undone); then a change of level costs O(items the splits name).
// A merge is (into, from): split i merges vertex b + i into its parent; the faces it creates
// merge into their heirs, in creation order. after() is indexed by `from`.

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

  // Calls visit(into, from) for each merge of split i, in creation order.
  merges(i, visit) {
    const { mesh } = this;
    if (!this.field.perFace) return visit(mesh.parent[i], mesh.head.baseVertexCount + i);
    const heir = mesh.faceHeir;
    for (let g = mesh.faceCountAt[i], end = mesh.faceCountAt[i + 1]; g < end; g++) visit(heir[g], g);
  }

  // Step t and level k (splits applied, ≤ the loaded ones): the backward pass, then the level.
  set(t, k) {
    const { mesh, field, sub, after, mean, subCount, afterCount } = this;
    const L = mesh.splitsLoaded;
    const n = this.itemCount(L);
    field.valuesAt(t, n, this.raw);
    let lo = Infinity, hi = -Infinity;
    for (let x = 0; x < n; x++) {
      const v = this.raw[x];
      sub[x] = v;
      if (v < lo) lo = v;
      if (v > hi) hi = v;
    }
    this.stepMin = n ? lo : 0;
    this.stepMax = n ? hi : 0;
    if (mean) subCount.fill(1, 0, n);
    // Reverse creation order: a split's faces last-first, splits last-first.
    const reversed = [];
    for (let i = L - 1; i >= 0; i--) {
      reversed.length = 0;
      this.merges(i, (into, from) => reversed.push(into, from));
      for (let j = reversed.length - 2; j >= 0; j -= 2) {
        const into = reversed[j], from = reversed[j + 1];
        after[from] = sub[into];
        if (mean) {
          afterCount[from] = subCount[into];
          sub[into] += sub[from];
          subCount[into] += subCount[from];
        } else {
          sub[into] = largerMagnitude(sub[into], sub[from]);
        }
      }
    }
    this.step = t;
    this.splits = L;
    this.jumpTo(k);
  }

  // The level directly: every present item its subtree, then each applied merge in order.
  jumpTo(k) {
    const n = this.itemCount(k);
    this.shown.set(this.sub.subarray(0, n));
    if (this.mean) this.shownCount.set(this.subCount.subarray(0, n));
    for (let i = 0; i < k; i++) this.merges(i, (into, from) => this.takeAfter(into, from));
    this.level = k;
    for (let x = 0; x < n; x++) this.output(x);
  }

  // A change of level, O(items the splits name); returns false when the pass must run again
  // (splits loaded since).
  setLevel(k) {
    if (k > this.splits) return false;
    for (let i = this.level; i < k; i++)
      this.merges(i, (into, from) => {
        this.takeAfter(into, from);
        this.shown[from] = this.sub[from];
        if (this.mean) this.shownCount[from] = this.subCount[from];
        this.output(into), this.output(from);
      });
    for (let i = this.level - 1; i >= k; i--)
      this.merges(i, (into, from) => {
        if (this.mean) {
          this.shown[into] += this.sub[from];
          this.shownCount[into] += this.subCount[from];
        } else {
          this.shown[into] = largerMagnitude(this.shown[into], this.sub[from]);
        }
        this.output(into);
      });
    this.level = k;
    return true;
  }

  takeAfter(into, from) {
    this.shown[into] = this.after[from];
    if (this.mean) this.shownCount[into] = this.afterCount[from];
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
