// The decode worker's side of the positions worker (docs/viewer.md "Decoding in a worker").
// DpmDecoder's `positions` executor on a second worker (positions_worker.js): while it decodes a
// SPLT's positions into the shared arrays of every step, the decode worker parses the next chunk's
// records, so a long file decodes on two cores (about 40 % of the decoding is the positions).
// wait() blocks the decode worker (Atomics.wait) until the last job started is done; `ready` resolves
// once a message from here has reached the second worker and its answer came back. Chromium
// starts a nested worker through its parent's event loop and holds the messages posted to it
// until its parent has heard that its script ran — news that may come after a message the
// script posted while running: blocked in wait() before that, the decode worker waited for a job that
// was never delivered (a CI run saw it). A round trip is past that point.
export function positionsInWorker() {
  const worker = new Worker(new URL('./positions_worker.js', import.meta.url), { type: 'module' });
  const answered = new Promise((resolve, reject) => {
    worker.onmessage = resolve;
    worker.onerror = (e) => reject(new Error(`the positions' worker did not start: ${e.message ?? e}`));
    // A worker that neither starts nor fails (a starved browser) must not hold up the file.
    setTimeout(() => reject(new Error("the positions' worker gave no answer in 10 s")), 10000);
  });
  worker.postMessage('ping');
  const signal = new Int32Array(new SharedArrayBuffer(12));  // done, problem length, started
  const text = new Uint8Array(new SharedArrayBuffer(4096));
  let started = 0;
  const wait = (seconds) => {
    for (let done; (done = Atomics.load(signal, 0)) < started;)
      if (Atomics.wait(signal, 0, done, 1000 * seconds) === 'timed-out' && Atomics.load(signal, 0) === done)
        return `the positions' worker gave no answer in ${seconds} s`;
    const length = Atomics.load(signal, 1);
    return length ? new TextDecoder().decode(text.slice(0, length)) : null;
  };
  // Then a job that decodes nothing, posted and waited for at once, blocked, as every job is: a
  // way of starting the worker that let a job wait undelivered fails here, every time, and the
  // file is decoded in place (the worker test sees which).
  const ready = answered.then(() => {
    Atomics.store(signal, 2, ++started);
    worker.postMessage({ signal, probe: true });
    const problem = wait(5);
    if (problem) throw new Error(problem);
  });
  return {
    ready,
    start({ head, lossless, positions, s, n, stencils, sections, staging }) {
      // Copies of exactly what the job reads (a view would send its whole buffer); the compact
      // positions and the staging arrays are shared.
      const bytes = sections.map((b) => b.slice());
      const { split, ringStart, ring, old, first } = stencils;
      const { vertexCount, steps, wide, dir, runs } = positions;
      Atomics.store(signal, 2, ++started);
      worker.postMessage({ signal, text, head, lossless, positions: { vertexCount, steps, wide, dir, runs }, s, n,
        stencils: { split, ringStart, ring: ring.data, old, first }, sections: bytes, staging },
      [split.buffer, ring.data.buffer, old.buffer, ...bytes.map((b) => b.buffer)]);
    },
    // A chunk's positions take a second or two at most: a worker silent for a minute is gone.
    wait: () => wait(60),
    close() {
      worker.terminate();
    },
  };
}
