// The values a selectively refined mesh shows of a result field (selective_navigator.js), kept
// conservative as the level's are (docs/FORMAT.md "Shown values: peaks are never hidden"): a
// missing vertex merges into its nearest existing ancestor (its parent chain), a missing face into
// its heir, so the largest |value| shown is the largest of the loaded items. One backward pass per
// update (O(loaded items)); the level's incremental bookkeeping does not apply to a set.
import { largerMagnitude, ShownValues } from './shown_values.js';

export class SelectiveShownValues extends ShownValues {
  constructor(mesh, field, aggregate, nav) {
    super(mesh, field, aggregate);
    this.nav = nav;
  }
  // Items [0, itemCount) hold every present one (the navigator's prefix; k is not used).
  itemCount() {
    return this.field.perFace ? this.nav.faceCount : this.nav.vertexCount;
  }
  present(x) {
    return this.field.perFace ? this.nav.faceActive(x) : this.nav.exists(x);
  }
  setLevel() {
    return false;  // a set, not a level: set() runs again
  }

  set(t, k) {
    const { mesh, field, shown, mean, shownCount, raw, values } = this;
    const L = mesh.splitsLoaded;
    const n = this.field.perFace ? mesh.faceCountAt[L] : mesh.head.baseVertexCount + L;
    field.valuesAt(t, n, raw);
    let lo = Infinity, hi = -Infinity;
    for (let x = 0; x < n; x++) {
      const v = (shown[x] = raw[x]);
      if (v < lo) lo = v;
      if (v > hi) hi = v;
    }
    this.stepMin = n ? lo : 0;
    this.stepMax = n ? hi : 0;
    if (mean) shownCount.fill(1, 0, n);
    // From the last item: what a missing item merges into is an earlier one (its parent or heir),
    // which its own missing descendants have already merged into.
    const [first, into, offset] = this.mergeList();
    for (let x = n - 1; x >= first; x--) {
      if (this.present(x)) continue;
      const p = into[x - offset];
      if (mean) (shown[p] += shown[x]), (shownCount[p] += shownCount[x]);
      else shown[p] = largerMagnitude(shown[p], shown[x]);
    }
    for (let x = 0; x < n; x++) values[x] = mean ? shown[x] / shownCount[x] : shown[x];
    Object.assign(this, { step: t, splits: L, level: k });
  }

  // The present item of largest |shown value| (the first of equals), or −1 when none.
  peak() {
    const n = this.itemCount();
    let best = -1, m = -1;
    for (let x = 0; x < n; x++) {
      const a = Math.abs(this.values[x]);
      if (a > m && this.present(x)) (m = a), (best = x);
    }
    return best;
  }
}
