// The page's decoder, off its main thread (docs/viewer.md "Decoding in a worker"): fetches the
// .dpm, feeds DpmDecoder as bytes arrive, and posts what each chunk made loadable — the base
// mesh, then splits. With `shared` the mesh's arrays are shared with the page and only the
// growing lists travel; else runs of at most `sliceSplits` splits go as copies of the ranges
// the page's mesh needs, their buffers transferred (mesh_pieces.js). The page
// (worker_decoder.js) starts it with { url, name, shared, sliceSplits } and hears: start,
// first-bytes, progress, head, base, splits, end, done or error. It ends itself once the
// stream has: what the page does not share goes with it.
import { DpmDecoder } from './dpm/file.js';
import { fieldDefs, growableTails, levelPieces, shareFields, shareMesh } from './mesh_pieces.js';

const post = (message, transfer = []) => self.postMessage(message, transfer);

async function decode({ url, name, shared, sliceSplits }) {
  const response = await fetch(url);
  if (!response.ok) throw new Error(`${name}: HTTP ${response.status}`);
  const reader = response.body.getReader();
  const sent = {};  // shared: the length of each growing list the page has
  const decoder = new DpmDecoder({
    name,
    onHead: (mesh) => post({ type: 'head', head: mesh.head, shared: shared ? shareMesh(mesh) : null }),
    onBase: (mesh) => {
      if (shared) {
        const fields = shareFields(mesh);
        const pieces = [['baseDegree', 0, mesh.baseDegree], ['baseCorners', 0, mesh.baseCorners]];
        post({ type: 'base', fields, faceHeir: mesh.faceHeir, pieces: [...pieces, ...growableTails(mesh, sent)] });
        return;
      }
      const { pieces, transfer } = levelPieces(mesh, 0, 0);
      post({ type: 'base', fields: fieldDefs(mesh), pieces }, transfer);
    },
    onSplits: (mesh, s, n) => {
      if (shared) return post({ type: 'splits', first: s, count: n, pieces: growableTails(mesh, sent) });
      for (let first = s; first < s + n; first += sliceSplits) {
        const count = Math.min(sliceSplits, s + n - first);
        const { pieces, transfer } = levelPieces(mesh, first, count);
        post({ type: 'splits', first, count, pieces }, transfer);
      }
    },
    onEnd: () => post({ type: 'end' }),
  });
  post({ type: 'start', total: Number(response.headers.get('Content-Length')) || 0, shared });
  for (;;) {
    const { done, value } = await reader.read();
    if (done) break;
    // When the first bytes arrived, in the page's clock (the worker's has another origin).
    if (decoder.bytesReceived === 0) post({ type: 'first-bytes', at: performance.timeOrigin + performance.now() });
    decoder.push(value);
    post({ type: 'progress', bytes: decoder.bytesReceived });
  }
  post({ type: 'done', complete: decoder.complete, chunkStart: decoder.chunkStart, state: decoder.state });
}

self.onmessage = (e) => {
  decode(e.data)
    .catch((error) => post({ type: 'error', message: String(error.message ?? error) }))
    .finally(() => self.close());
};
