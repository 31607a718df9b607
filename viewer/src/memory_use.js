// What the page's arrays for a model take, in bytes, by what they are for (bench/load.mjs,
// docs/viewer.md "Memory"): a typed array counts once however many objects hold it. The ids, the
// split records and the fields' split errors are made at the whole model's size (HEAD's counts)
// and filled as splits arrive: they count as far as they are filled (a paused model's rest is
// never written, so never resident); positions and field values count their room (`makeRoom()`),
// which is what they hold.
const GROUPS = {
  positions: (m) => m.positions.arrays(),
  ids: (m) => {
    const [vertices, faces] = loaded(m);
    return [[m.vertexOriginal, vertices], [m.nodeId, vertices], [m.faceOriginal, faces], [m.partId, faces], [m.elementId, faces]];
  },
  splits: (m) => {
    const s = m.splitsLoaded;
    return [[m.parent, s], [m.error, s], [m.wingStart, s + 1], [m.movedStart, s + 1], [m.faceCountAt, s + 1],
      m.baseCorners, m.baseDegree, ...[m.wingFace, m.wingVertex, m.wingFlags, m.movedFaces].map((g) => g && [g.data, g.length])];
  },
  fields: (m) => [[m.faceHeir, loaded(m)[1]], ...m.fields.flatMap((f) => [...f.q, [f.error, m.splitsLoaded]])],
};

// The vertices and faces that have arrived (none before the base).
function loaded(m) {
  return m.hasBase ? [m.vertexCountLoaded, m.faceCountAt[m.splitsLoaded]] : [0, 0];
}

function typedArrays(object, seen = new Set(), depth = 0) {
  const out = [];
  if (!object || typeof object !== 'object' || depth > 2) return out;
  for (const value of Object.values(object)) {
    if (ArrayBuffer.isView(value)) out.push(value);
    else if (value && typeof value === 'object' && !seen.has(value) && value.constructor !== undefined) {
      seen.add(value);
      if (!('head' in value)) out.push(...typedArrays(value, seen, depth + 1));  // not the mesh
    }
  }
  return out;
}

// { group: bytes } for the mesh, the navigator, the draw buffers and anything else `extra` holds.
export function memoryUse(mesh, nav, draw, extra = {}) {
  const counted = new Set();
  // An entry is an array (all of its buffer) or [array, elements filled].
  const bytesOf = (entry) => Array.isArray(entry)
    ? Math.min(entry[0].buffer.byteLength, entry[1] * entry[0].BYTES_PER_ELEMENT) : entry.buffer.byteLength;
  const sum = (entries) => entries.filter((e) => {
    const a = Array.isArray(e) ? e[0] : e;
    return a && !counted.has(a.buffer) && counted.add(a.buffer);
  }).reduce((n, e) => n + bytesOf(e), 0);
  const use = {};
  for (const [name, pick] of Object.entries(GROUPS)) use[name] = sum(pick(mesh));
  use.navigator = sum(typedArrays(nav));
  use.draw = sum(Object.values(draw));
  for (const [name, array] of Object.entries(extra)) use[name] = sum([array]);
  return use;
}
