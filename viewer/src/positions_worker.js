// The positions of each SPLT, decoded beside the decode worker (decode_worker.js, `positions`):
// it parses the next chunk's records while this decodes the last one's positions (docs/viewer.md
// "Decoding in a worker"). Jobs come in the file's order (the models run on from SPLT to SPLT);
// the positions are written into the mesh's shared arrays of every step. `signal` (shared):
// [jobs done, length of the last problem's text in `text`, jobs started].
import { decodeSplitPositions, positionModels } from './dpm/positions.js';

let models = null;
let failed = false;
self.postMessage('ready');  // the decode worker may block on us from now on

self.onmessage = ({ data }) => {
  const { signal, text, head, lossless, q, s, n, split, ringStart, ring, sections } = data;
  Atomics.load(signal, 2);  // the decode worker's writes before the job (BASE's positions) seen
  models ??= positionModels(q.length);
  let problem = null;
  if (!failed) {  // after a problem the decoder stops: the models would be out of step
    try {
      problem = decodeSplitPositions({ head, lossless, q }, s, n, { split, ringStart, ring: { data: ring } }, models, sections);
    } catch (e) {
      problem = String(e?.message ?? e);
    }
  }
  if (problem) {
    failed = true;
    const bytes = new TextEncoder().encode(problem).subarray(0, text.length);
    text.set(bytes);
    Atomics.store(signal, 1, bytes.length);
  }
  Atomics.add(signal, 0, 1);  // after the positions: whoever sees the count sees them
  Atomics.notify(signal, 0);
};
