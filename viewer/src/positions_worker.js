// The positions of each SPLT, decoded beside the decode worker (its side there: positions_executor.js):
// it parses the next chunk's records while this decodes the last one's positions (docs/viewer.md
// "Decoding in a worker"). Jobs come in the file's order (the models run on from SPLT to SPLT);
// the positions are written into the job's shared staging arrays, from which the decode worker
// stores them compact. `signal` (shared): [jobs done, length of the last problem's text in
// `text`, jobs started].
import { decodeSplitPositions, positionModels } from './dpm/positions.js';
import { StepPositions } from './dpm/step_positions.js';

let models = null;
let failed = false;
self.onmessage = ({ data }) => {
  // The decode worker's first message: answered, it may block on us from now on.
  if (data === 'ping') return self.postMessage('pong');
  const { signal, text, head, lossless, positions, s, n, stencils, sections, staging, probe } = data;
  Atomics.load(signal, 2);  // the decode worker's writes before the job (the stored positions) seen
  if (probe) return void (Atomics.add(signal, 0, 1), Atomics.notify(signal, 0));  // nothing to decode
  let problem = null;
  if (!failed) {  // after a problem the decoder stops: the models would be out of step
    try {  // whatever goes wrong is answered: the decode worker is blocked until it hears
      models ??= positionModels(head.stepCount);
      const job = { head, lossless, positions: StepPositions.from(positions), s, n,
        stencils: { ...stencils, ring: { data: stencils.ring } }, models, sections, staging };
      problem = decodeSplitPositions(job);
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
