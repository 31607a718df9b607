// The page's side of decode_worker.js: starts the worker on a file's URL and keeps a
// ProgressiveMesh that the worker fills (shared memory) or that its messages fill
// (mesh_pieces.js), so that the page's main thread never runs the decode; the callbacks are those of DpmDecoder. Copying a run of splits
// in is quick; what the page redraws for new splits (onSplits) is paced to at most one call per
// `pauseMs`, since its cost grows with the mesh, not with the run.
import { DpmError } from './dpm/bytes.js';
import { DpmDecoder, streamDpm } from './dpm/file.js';
import { ProgressiveMesh } from './dpm/progressive_mesh.js';
import { addFields, applyPieces, sharedMesh } from './mesh_pieces.js';
import { movedDependencies } from './moved_dependencies.js';
import { movedNavigator } from './moved_navigator.js';

// Splits per message: a run of this many costs the page a few milliseconds to copy in.
const SLICE_SPLITS = 32768;

// Resolves with { mesh, complete } when the stream has ended (mesh null if HEAD never came);
// rejects with the decoder's error. onStart(totalBytes, shared, ranges, positionsWorker), onFirstBytes(pageTime),
// onDecoded(pageTime): the worker has decoded the whole file (END),
// onProgress(bytes), onPaused(bytes): the worker stopped fetching at `vertices` (by ranges;
// Infinity: the whole file, or what `memory` bytes of the steps' values hold) until
// `control.want(vertices)` asks for more. onNavigator(nav): the worker's Navigator at the base
// mesh, moved here (moved_navigator.js). onDependencies(deps): the split dependencies the
// worker derived, as far as the splits loaded (moved_dependencies.js).
export function decodeInWorker({ url, name, onHead, onBase, onNavigator, onDependencies, onSplits, onStart, onFirstBytes, onDecoded, onProgress, onPaused, vertices = Infinity, memory = Infinity, positionsWorker = true, control = {}, pauseMs = 100 }) {
  const worker = new Worker(new URL('./decode_worker.js', import.meta.url), { type: 'module' });
  control.want = (n) => worker.postMessage({ type: 'want', vertices: n });
  let mesh = null;
  let complete = false;
  let timer = 0;
  let lastSplits = 0;
  let splitsShown = 0;
  const showSplits = () => {
    clearTimeout(timer);
    timer = 0;
    lastSplits = performance.now();
    if (!mesh || mesh.splitsLoaded === splitsShown) return;
    const first = splitsShown;
    splitsShown = mesh.splitsLoaded;
    onSplits?.(mesh, first, splitsShown - first);
  };
  return new Promise((resolve, reject) => {
    const finish = (error) => {
      worker.terminate();
      if (error) {
        // The levels before the damage are shown, as the decoder on the page shows them.
        try {
          showSplits();
        } finally {
          reject(error);
        }
      } else {
        showSplits();
        resolve({ mesh, complete });
      }
    };
    worker.onerror = (e) => finish(new Error(`${name}: the decode worker failed: ${e.message ?? 'could not start'}`));
    worker.onmessage = ({ data: m }) => {
      try {
        if (m.type === 'start') onStart?.(m.total, m.shared, m.ranges, m.positionsWorker);
        else if (m.type === 'first-bytes') onFirstBytes?.(m.at - performance.timeOrigin);
        else if (m.type === 'progress') onProgress?.(m.bytes);
        else if (m.type === 'head') {
          mesh = m.shared ? sharedMesh(m.shared) : new ProgressiveMesh(m.head);
          onHead?.(mesh);
        } else if (m.type === 'base') {
          addFields(mesh, m.fields, m.faceHeir);
          mesh.partNames = m.partNames;  // PART (parts.js): a Map, cloned
          mesh.variants = m.variants;  // VARI (variants.js), cloned
          applyPieces(mesh, m.pieces);
          mesh.hasBase = true;
          onBase?.(mesh);
        } else if (m.type === 'navigator') {
          onNavigator?.(movedNavigator(m.parts, mesh));
        } else if (m.type === 'dependencies') {
          onDependencies?.(movedDependencies(m.parts, mesh));
        } else if (m.type === 'splits') {
          applyPieces(mesh, m.pieces);
          mesh.splitsLoaded = m.first + m.count;
          if (!timer) timer = setTimeout(showSplits, Math.max(0, lastSplits + pauseMs - performance.now()));
        } else if (m.type === 'paused') {
          showSplits();
          onPaused?.(m.bytes);
        } else if (m.type === 'end') {
          onDecoded?.(m.at - performance.timeOrigin);
          showSplits();  // the last splits are shown before the mesh says it is complete
          mesh.complete = complete = true;
        } else if (m.type === 'done') {
          finish();
        } else if (m.type === 'error') {
          finish(new DpmError(m.message));
        }
      } catch (error) {
        finish(error);
      }
    };
    // Shared memory needs a cross-origin isolated page (`dynpm view` serves it so).
    worker.postMessage({ url, name, shared: Boolean(globalThis.crossOriginIsolated), sliceSplits: SLICE_SPLITS, vertices, memory, positionsWorker });
  });
}

// The decoder on the page's own thread (?worker=0, for comparison): the page is busy while a
// chunk decodes. The same callbacks; resolves with the decoder ({ mesh, complete }).
export async function decodeOnPage({ url, name, onHead, onBase, onSplits, onStart, onProgress }) {
  const response = await fetch(url);
  if (!response.ok) throw new Error(`${url}: HTTP ${response.status}`);
  onStart?.(Number(response.headers.get('Content-Length')) || 0);
  const decoder = new DpmDecoder({ name, onHead, onBase, onSplits });
  await streamDpm(response.body, decoder, onProgress);
  return decoder;
}
