// A view-dependent request's splits made in a worker (docs/viewer.md "Spheres from a worker"):
// the split spheres (dpm/view_target.js splitSpheres(), one bottom-up pass over every split at
// each step) and, per camera, the screen errors against them (viewOrder(): 21–31 ms of the
// page's thread per camera move at a million vertices). The page sends what the spheres are made
// from once per step — the HEAD numbers, the positions of the two steps around t, the splits'
// parents and errors, shared (cross-origin isolated page: the decode worker's shared arrays,
// nothing copied) or as copies of the prefixes read, transferred —; the worker keeps the spheres
// and answers each camera with the splits it wants, transferred. The page closes them.
import { splitSpheres, viewOrder } from './dpm/view_target.js';
import { ProgressiveMesh, positionsBetween } from './dpm/progressive_mesh.js';

const isShared = (a) => typeof SharedArrayBuffer !== 'undefined' && a.buffer instanceof SharedArrayBuffer;

// Page: the message asking for the splits of `views` (parsed view requests) among the first L at
// fractional step t, and the buffers to transfer. withSpheres: the worker does not hold the
// spheres of (L, t) yet, so what they are made from goes along.
export function viewRequest(mesh, L, t, views, withSpheres, key = '') {
  const transfer = [];
  const message = { key, L, t, views, spheres: null };
  if (!withSpheres) return { message, transfer };
  const { t0, t1, a } = mesh.stepsAround(t);
  const n = mesh.head.baseVertexCount + L;
  // Shared arrays go as they are; others as copies of what is read.
  const part = (a, count) => {
    if (isShared(a)) return a;
    const copy = a.slice(0, count);
    transfer.push(copy.buffer);
    return copy;
  };
  // The steps around t as the page's positions hold them (step 0 stored and shared; others made
  // on the page, in arrays that move with time: copied), the later only between two steps.
  const [p0, p1] = mesh.positions.around(mesh.storedStep(t0), mesh.storedStep(a === 0 ? t0 : t1), n);
  const q0 = part(p0, 3 * n);
  const q1 = a === 0 ? null : part(p1, 3 * n);
  message.spheres = { head: mesh.head, q0, q1, parent: part(mesh.parent, L), error: part(mesh.error, L) };
  return { message, transfer };
}

// Worker: holds the spheres of the last (L, t) it was sent what they are made from, and answers
// viewRequest()'s messages.
export class ViewWorker {
  constructor() {
    this.held = null;  // {L, t, spheres, mesh: {head, error}}
  }

  answer({ key, L, t, views, spheres: from }) {
    if (from) this.held = { L, t, spheres: spheresOf(from, L, t), mesh: { head: from.head, error: from.error } };
    const { held } = this;
    if (!held || held.L !== L || held.t !== t) throw new Error(`the spheres worker holds no spheres of ${L} splits at step ${t}`);
    const splits = views.map((view) => viewOrder(held.mesh, held.spheres, L, view));
    return { answer: { key, splits }, transfer: splits.map((s) => s.buffer) };
  }
}

// The spheres of the first L splits at step t from what viewRequest() sent.
function spheresOf({ head, q0, q1, parent }, L, t) {
  const { a } = ProgressiveMesh.prototype.stepsAround.call({ head }, t);
  const positionsAt = (_, n, out) => positionsBetween(head, q0, q1 ?? q0, a, n, out);
  return splitSpheres({ head, parent, positionsAt }, L, t);
}

// Page: a worker making a view's splits, one request at a time. `get(mesh, L, t, views)` gives
// {splits} (one Int32Array per view, for requestedSplits()/wantedSet()) if they are the last
// answer, else null and asks for them (after the one in flight); `onAnswer()` hears when an
// answer has come (or the worker failed: then `failed` says why).
export class ViewSplitsFromWorker {
  constructor(onAnswer) {
    this.onAnswer = onAnswer;
    this.worker = null;
    this.last = null;  // {key, splits}
    this.inFlight = null;  // key
    this.next = null;  // {mesh, L, t, views, key}: asked for while one was in flight
    this.sent = null;  // {L, t}: the spheres the worker holds once it has read what was posted
    this.failed = null;  // why the worker could not be used
  }

  get(mesh, L, t, views) {
    const key = `${L} ${t} ${JSON.stringify(views)}`;
    if (this.last?.key === key) return { splits: this.last.splits };
    if (this.inFlight === key) return null;
    if (this.inFlight) this.next = { mesh, L, t, views, key };
    else this.ask({ mesh, L, t, views, key });
    return null;
  }

  ask({ mesh, L, t, views, key }) {
    this.worker ??= this.start();
    this.inFlight = key;
    const withSpheres = !(this.sent?.L === L && this.sent.t === t);
    this.sent = { L, t };
    const { message, transfer } = viewRequest(mesh, L, t, views, withSpheres, key);
    this.worker.postMessage(message, transfer);
  }

  start() {
    const worker = new Worker(new URL('./spheres_worker.js', import.meta.url), { type: 'module' });
    worker.onmessage = ({ data: { key, splits } }) => {
      this.last = { key, splits };
      this.inFlight = null;
      const next = this.next;
      this.next = null;
      if (next && next.key !== key) this.ask(next);
      this.onAnswer();
    };
    worker.onerror = (e) => {
      this.failed = `the spheres worker failed: ${e.message ?? 'could not start'}`;
      this.inFlight = this.next = null;
      this.onAnswer();
    };
    return worker;
  }
}
