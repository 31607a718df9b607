// What comparing two models needs that is pure arithmetic (compare_view.js draws it; the node
// test checks it alone): whether the two files hold one hierarchy, so that vertex v is the same
// node in both at every level, and the per-vertex distance between their positions.

// The first difference between the hierarchies of meshes a and b as far as `splits` splits
// (a string naming it), or null when they are the same: counts, base faces, and each split's
// record — parent, wings (face, vertex, flags) and moved faces — and the node ids of the
// vertices. Positions, errors and fields may differ: those are what is compared.
export function hierarchyDifference(a, b, splits) {
  const ha = a.head, hb = b.head;
  for (const key of ['vertexCount', 'faceCount', 'splitCount', 'baseVertexCount', 'baseFaceCount']) {
    if (ha[key] !== hb[key]) return `${key} ${ha[key]} ≠ ${hb[key]}`;
  }
  if (splits > Math.min(a.splitsLoaded, b.splitsLoaded)) return `only ${Math.min(a.splitsLoaded, b.splitsLoaded)} splits of both loaded`;
  const differs = (x, y, from, to) => {
    for (let i = from; i < to; i++) if (x[i] !== y[i]) return i;
    return -1;
  };
  let i = differs(a.baseCorners, b.baseCorners, 0, 4 * ha.baseFaceCount);
  if (i >= 0) return `base face ${i >> 2} has other corners`;
  i = differs(a.nodeId, b.nodeId, 0, ha.baseVertexCount + splits);
  if (i >= 0) return `vertex ${i} is node ${a.nodeId[i]} in one and node ${b.nodeId[i]} in the other`;
  i = differs(a.parent, b.parent, 0, splits);
  if (i >= 0) return `split ${i} has another parent`;
  for (const [name, list, start] of [
    ['wings', ['wingFace', 'wingVertex', 'wingFlags'], 'wingStart'],
    ['moved faces', ['movedFaces'], 'movedStart'],
  ]) {
    i = differs(a[start], b[start], 0, splits + 1);
    if (i >= 0) return `split ${Math.max(0, i - 1)} has other ${name}`;
    for (const key of list) {
      const k = differs(a[key].data, b[key].data, 0, a[start][splits]);
      if (k >= 0) return `split ${upperBound(a[start], splits, k)} has other ${name}`;
    }
  }
  return null;
}

// The split whose run [start[s], start[s + 1]) holds entry k.
function upperBound(start, splits, k) {
  let lo = 0, hi = splits;
  while (lo < hi) {
    const mid = (lo + hi) >> 1;
    if (start[mid + 1] <= k) lo = mid + 1;
    else hi = mid;
  }
  return lo;
}

// |p_a − p_b| of vertices [0, n) into out (per vertex), and the largest: {value, vertex}
// (vertex −1 when n is 0). The largest is computed in doubles from the float positions, as a
// script that reads both models' extracted positions computes it.
export function positionDifference(pa, pb, n, out) {
  let value = 0, vertex = n > 0 ? 0 : -1;
  for (let v = 0, i = 0; v < n; v++, i += 3) {
    const dx = pa[i] - pb[i], dy = pa[i + 1] - pb[i + 1], dz = pa[i + 2] - pb[i + 2];
    const d = Math.sqrt(dx * dx + dy * dy + dz * dz);
    out[v] = d;
    if (d > value) (value = d), (vertex = v);
  }
  return { value, vertex };
}

// The level of the second model for the first's n of V vertices: the same fraction of its own
// vertices (the same count when both hold one hierarchy), within what it has.
export function linkedVertexCount(n, V, head, loaded) {
  const wanted = V === head.vertexCount ? n : Math.round((n / V) * head.vertexCount);
  return Math.max(head.baseVertexCount, Math.min(wanted, loaded));
}
