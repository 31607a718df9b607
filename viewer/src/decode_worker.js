// The page's decoder, off its main thread (docs/viewer.md "Decoding in a worker"): fetches the
// .dpm (by ranges, range_fetch.js), feeds DpmDecoder as bytes arrive, and posts what each chunk
// made loadable — the base mesh, then splits. With `shared` the mesh's arrays are shared with
// the page and only the growing lists (and the arrays of every step, when made anew) travel;
// else runs of at most `sliceSplits` splits go as copies of the ranges the page's mesh needs,
// their buffers transferred (mesh_pieces.js). The page (worker_decoder.js) starts it with
// { url, name, shared, sliceSplits, vertices, memory, positionsWorker } and may later send
// { type: 'want', vertices } (fetch until that many vertices are loaded; Infinity: the whole
// file, or with `memory` as many as budgetedVertices() allows, model_file.js); it hears: start,
// first-bytes, progress, head, base, navigator, splits, dependencies, paused, end, done or error.
// It ends itself once the stream has: what the page does not share goes with it. The split
// dependencies are derived here whenever the stream stops (paused, end, done: the splits are
// shown first) and sent, so that no refinement derives them on the page (moved_dependencies.js).
import { DpmDecoder } from './dpm/file.js';
import { Navigator } from './dpm/navigator.js';
import { navigatorParts } from './moved_navigator.js';
import { dependencyParts } from './moved_dependencies.js';
import { budgetedVertices, remeasuredBudget } from './model_file.js';
import { positionsInWorker } from './positions_executor.js';
import { fetchByRanges } from './range_fetch.js';
import { SplitDependencies } from './dpm/split_dependencies.js';
import { fieldDefs, growableTails, levelPieces, regrownSteps, shareFields, shareMesh } from './mesh_pieces.js';

const post = (message, transfer = []) => self.postMessage(message, transfer);

// The page's wish: vertices it wants loaded (`budgeted`: the memory budget's, not asked for); a
// promise's resolve while waiting for more.
const want = { vertices: Infinity, budgeted: false, wake: null };
let decoding = null;  // the DpmDecoder

async function decode({ url, name, shared, sliceSplits, vertices = Infinity, memory = Infinity, positionsWorker = true }) {
  want.vertices = vertices;
  const sent = {};  // shared: the length of each growing list the page has
  const sentSteps = {};  // shared: the arrays of every step the page has
  let deps = null;  // the split dependencies (derived when the stream stops)
  let depsSent = -1;  // how many splits the page's dependencies cover
  const sendDependencies = (last = false) => {
    if (!deps?.update() || deps.derived === depsSent) return;
    depsSent = deps.derived;
    const { parts, transfer } = dependencyParts(deps, last);
    post({ type: 'dependencies', parts }, transfer);
    if (last) deps = null;  // its arrays are the page's now
  };
  // Only on shared memory: the second worker writes the positions where the page reads them
  // (?positionsWorker=0: here, for comparison).
  const positions = shared && positionsWorker ? positionsInWorker() : null;
  const decoder = new DpmDecoder({
    name,
    vertices,
    positions,
    onHead: (mesh) => {
      // No count asked for: as many vertices as the memory budget holds, room for them at BASE.
      if (want.vertices === Infinity && memory < Infinity) {
        decoder.vertices = want.vertices = budgetedVertices(mesh.head, memory);
        want.budgeted = true;
      }
      post({ type: 'head', head: mesh.head, shared: shared ? shareMesh(mesh) : null });
    },
    onBase: (mesh) => {
      post({ type: 'progress', bytes: decoder.bytesReceived });  // the bytes the base came in
      if (shared) {
        const fields = shareFields(mesh);
        const pieces = [['baseDegree', 0, mesh.baseDegree], ['baseCorners', 0, mesh.baseCorners]];
        post({ type: 'base', fields, faceHeir: mesh.faceHeir, partNames: mesh.partNames, variants: mesh.variants, pieces: [...pieces, ...growableTails(mesh, sent), ...regrownSteps(mesh, sentSteps)] });
      } else {
        const { pieces, transfer } = levelPieces(mesh, 0, 0);
        post({ type: 'base', fields: fieldDefs(mesh), partNames: mesh.partNames, variants: mesh.variants, pieces }, transfer);
      }
      // After the base mesh has gone: the page draws it meanwhile (moved_navigator.js).
      const { parts, transfer } = navigatorParts(new Navigator(mesh));
      post({ type: 'navigator', parts }, transfer);
      deps = new SplitDependencies(mesh);
    },
    onSplits: (mesh, s, n) => {
      // The budget again with the escaped positions measured (model_file.js).
      if (want.budgeted) decoder.vertices = want.vertices = remeasuredBudget(mesh.head, memory, want.vertices, mesh.positions, mesh.vertexCountLoaded);
      if (shared) return post({ type: 'splits', first: s, count: n, pieces: [...growableTails(mesh, sent), ...regrownSteps(mesh, sentSteps)] });
      for (let first = s; first < s + n; first += sliceSplits) {
        const count = Math.min(sliceSplits, s + n - first);
        const { pieces, transfer } = levelPieces(mesh, first, count);
        post({ type: 'splits', first, count, pieces }, transfer);
      }
    },
    // The whole mesh is shown first; `done` (the page's load resolves) follows the dependencies.
    onEnd: () => {
      post({ type: 'progress', bytes: decoder.bytesReceived });  // all of it, before it says so
      post({ type: 'end', at: performance.timeOrigin + performance.now() });  // decoded: when
      sendDependencies(true);
    },
  });
  // More is wanted until the base mesh, the FLDS of a SPLT, the wanted vertices or END are in
  // (splits counted as their records are parsed: the positions of the last may be in flight).
  decoding = decoder;
  const wanted = () => {
    const mesh = decoder.mesh;
    if (!mesh?.hasBase || decoder.state !== 'SPLT') return true;
    const all = mesh.head.splitCount, decoded = decoder.splitsDecoded;
    return decoded === all || decoded < Math.min(all, want.vertices - mesh.head.baseVertexCount);
  };
  const more = () => {
    decoder.flush();  // the last chunk's positions, then its splits go to the page
    post({ type: 'paused', bytes: decoder.bytesReceived });
    sendDependencies();  // the splits loaded so far, while the page wants no more
    return new Promise((resolve) => (want.wake = resolve));
  };
  const onResponse = ({ total, ranges }) => {
    // When the first bytes arrived, in the page's clock (the worker's has another origin).
    post({ type: 'first-bytes', at: performance.timeOrigin + performance.now() });
    post({ type: 'start', total, shared, ranges, positionsWorker: Boolean(decoder.positions) });
  };
  const onBytes = () => post({ type: 'progress', bytes: decoder.bytesReceived });
  try {
    // A page where the second worker cannot start decodes the positions here, as without shared memory.
    await positions?.ready.catch(() => (decoder.positions = null));
    await fetchByRanges(url, name, decoder, { wanted, more, onResponse, onBytes });
    decoder.flush();  // a file that ends early: the last chunk's positions
  } finally {
    positions?.close();
  }
  sendDependencies(true);  // a file that ends early: those of the splits it holds
  post({ type: 'done', complete: decoder.complete, chunkStart: decoder.chunkStart, state: decoder.state });
}

self.onmessage = (e) => {
  if (e.data.type === 'want') {
    want.vertices = Math.max(want.vertices, e.data.vertices);
    want.budgeted = false;
    if (decoding) decoding.vertices = want.vertices;  // room for them at the next chunk
    want.wake?.();
    return;
  }
  decode(e.data)
    .catch((error) => post({ type: 'error', message: String(error.message ?? error) }))
    .finally(() => self.close());
};
