// A Navigator made by the decode worker at the base mesh and moved to the page: its arrays (16
// bytes a face of the whole mesh, and the touched-face marks) are first written in the worker,
// which on a large model takes a long time (first writes to fresh memory), and reach the page
// by transfer, without a copy, so that no task of the page's main thread pays for them
// (docs/viewer.md "Loading"). Generic over the Navigator's own properties: typed arrays,
// numbers and the classes listed here.
import { Navigator } from './dpm/navigator.js';
import { DirtyFaces } from './dpm/progressive_mesh.js';

const CLASSES = { DirtyFaces };

function pack(value, transfer) {
  if (ArrayBuffer.isView(value)) {
    if (value.buffer instanceof ArrayBuffer) transfer.add(value.buffer);
    return value;
  }
  if (value === null || typeof value !== 'object') return value;
  const name = Object.keys(CLASSES).find((k) => value instanceof CLASSES[k]);
  if (!name) throw new Error(`navigatorParts: cannot move a ${value.constructor?.name}`);
  const fields = {};
  for (const [key, v] of Object.entries(value)) fields[key] = pack(v, transfer);
  return { movedClass: name, fields };
}

function unpack(value) {
  if (value === null || typeof value !== 'object' || ArrayBuffer.isView(value)) return value;
  const object = Object.create(CLASSES[value.movedClass].prototype);
  for (const [key, v] of Object.entries(value.fields)) object[key] = unpack(v);
  return object;
}

// Worker: the navigator without its mesh, and the buffers to transfer (the worker's navigator
// is unusable after).
export function navigatorParts(nav) {
  const transfer = new Set();
  const parts = {};
  for (const [key, value] of Object.entries(nav)) if (key !== 'mesh') parts[key] = pack(value, transfer);
  return { parts, transfer: [...transfer] };
}

// Page: the navigator over the page's mesh.
export function movedNavigator(parts, mesh) {
  const nav = Object.create(Navigator.prototype);
  nav.mesh = mesh;
  for (const [key, value] of Object.entries(parts)) nav[key] = unpack(value);
  return nav;
}
