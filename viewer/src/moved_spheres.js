// The view-dependent request's split spheres (dpm/view_target.js splitSpheres()), made in a
// worker and moved to the page (docs/viewer.md "Spheres from a worker"): one bottom-up pass over
// every split at each step, which at a million vertices held the page's main thread for
// hundreds of milliseconds at the first view of a step. The page sends what the pass reads —
// the HEAD numbers, the positions of the two steps around t and the splits' parents, shared
// (cross-origin isolated page: the decode worker's shared arrays, nothing copied) or as copies
// of the prefixes it needs, transferred —, the worker answers with the spheres, transferred.
import { splitSpheres } from './dpm/view_target.js';
import { ProgressiveMesh } from './dpm/progressive_mesh.js';

const isShared = (a) => typeof SharedArrayBuffer !== 'undefined' && a.buffer instanceof SharedArrayBuffer;

// Page: the message asking for the spheres of the first L splits at fractional step t, and the
// buffers to transfer.
export function spheresRequest(mesh, L, t, id = 0) {
  const { t0, t1 } = mesh.stepsAround(t);
  const n = mesh.head.baseVertexCount + L;
  const transfer = [];
  // Shared arrays go as they are; others as copies of what is read.
  const part = (a, count) => {
    if (isShared(a)) return a;
    const copy = a.slice(0, count);
    transfer.push(copy.buffer);
    return copy;
  };
  const q0 = part(mesh.q[t0], 3 * n);
  const q1 = t1 === t0 ? null : part(mesh.q[t1], 3 * n);
  const message = { id, L, t, head: mesh.head, q0, q1, parent: part(mesh.parent, L) };
  return { message, transfer };
}

// Worker: the answer to spheresRequest()'s message, and the buffers to transfer.
export function spheresAnswer({ id, L, t, head, q0, q1, parent }) {
  const mesh = Object.create(ProgressiveMesh.prototype);
  const { t0, t1 } = ProgressiveMesh.prototype.stepsAround.call({ head }, t);
  const q = [];
  q[t0] = q0;
  q[t1] = q1 ?? q0;
  Object.assign(mesh, { head, q, parent });
  const spheres = splitSpheres(mesh, L, t);
  return { answer: { id, L, t, spheres }, transfer: [spheres.buffer] };
}

// Page: a worker making spheres, one request at a time. `get(mesh, L, t)` gives the spheres if
// they are the last ones made, else null and asks for them (after the one in flight);
// `onSpheres(L, t)` hears when new ones have come.
export class SpheresFromWorker {
  constructor(onSpheres) {
    this.onSpheres = onSpheres;
    this.worker = null;
    this.last = null;  // {L, t, spheres}
    this.inFlight = null;  // {L, t}
    this.next = null;  // {mesh, L, t}: asked for while one was in flight
    this.failed = null;  // why the worker could not be used
  }

  get(mesh, L, t) {
    if (this.last && this.last.L === L && this.last.t === t) return this.last.spheres;
    if (this.inFlight?.L === L && this.inFlight.t === t) return null;
    if (this.inFlight) this.next = { mesh, L, t };
    else this.ask(mesh, L, t);
    return null;
  }

  ask(mesh, L, t) {
    this.worker ??= this.start();
    this.inFlight = { L, t };
    const { message, transfer } = spheresRequest(mesh, L, t);
    this.worker.postMessage(message, transfer);
  }

  start() {
    const worker = new Worker(new URL('./spheres_worker.js', import.meta.url), { type: 'module' });
    worker.onmessage = ({ data: { L, t, spheres } }) => {
      this.last = { L, t, spheres };
      this.inFlight = null;
      const next = this.next;
      this.next = null;
      if (next && !(next.L === L && next.t === t)) this.ask(next.mesh, next.L, next.t);
      this.onSpheres(L, t);
    };
    worker.onerror = (e) => {
      this.failed = `the spheres worker failed: ${e.message ?? 'could not start'}`;
      this.inFlight = this.next = null;
      this.onSpheres(null, null);
    };
    return worker;
  }
}
