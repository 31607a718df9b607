// What the page's arrays for a model take, in bytes, by what they are for (bench/load.mjs,
// docs/viewer.md "Memory"): a typed array counts once however many objects hold it.
const GROUPS = {
  positions: (m) => m.q,
  ids: (m) => [m.vertexOriginal, m.nodeId, m.faceOriginal, m.partId, m.elementId],
  splits: (m) => [m.parent, m.error, m.wingStart, m.movedStart, m.faceCountAt, m.baseCorners, m.baseDegree,
    m.wingFace?.data, m.wingVertex?.data, m.wingFlags?.data, m.movedFaces?.data],
  fields: (m) => [m.faceHeir, ...m.fields.flatMap((f) => [...f.q, f.error])],
};

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
  const sum = (arrays) => arrays.filter((a) => a && !counted.has(a.buffer) && counted.add(a.buffer))
    .reduce((n, a) => n + a.buffer.byteLength, 0);
  const use = {};
  for (const [name, pick] of Object.entries(GROUPS)) use[name] = sum(pick(mesh));
  use.navigator = sum(typedArrays(nav));
  use.draw = sum(Object.values(draw));
  for (const [name, array] of Object.entries(extra)) use[name] = sum([array]);
  return use;
}
