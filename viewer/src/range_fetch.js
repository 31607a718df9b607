// How the decode worker fetches a .dpm (docs/viewer.md "Fetching by ranges"): with HTTP range
// requests, chunk by chunk, so that a page that wants only coarse levels stops after the
// chunks that hold them; or, from a server that answers a range with the whole file (200), as
// one plain stream. The chunk framing is FORMAT.md's: a 12-byte signature, then chunks of a
// 24-byte header (tag, flags, stored size at byte 8, …) and `stored` payload bytes.
const SIGNATURE_BYTES = 12;
const CHUNK_HEADER_BYTES = 24;
// The first request: the signature, HEAD, FDEF and BASE of most models; small chunks that
// follow are fetched together up to this many bytes a request.
export const FIRST_REQUEST_BYTES = 1 << 16;

// The end (exclusive) of the chunk the decoder waits for, and of the header after it, so that
// the next request knows that chunk's size: from the decoder's unparsed bytes.
export function nextRequestEnd(decoder) {
  const at = decoder.chunkStart;
  if (at === 0) return SIGNATURE_BYTES + CHUNK_HEADER_BYTES;
  const have = decoder.end - decoder.start;
  if (have < CHUNK_HEADER_BYTES) return at + CHUNK_HEADER_BYTES;
  const header = new DataView(decoder.buffer.buffer, decoder.buffer.byteOffset + decoder.start, CHUNK_HEADER_BYTES);
  return at + 2 * CHUNK_HEADER_BYTES + header.getUint32(8, true);
}

// The file's size from a 206's Content-Range ("bytes a-b/size"), or NaN.
export function rangeTotal(response) {
  const m = /\/(\d+)\s*$/.exec(response.headers.get('Content-Range') ?? '');
  return m ? Number(m[1]) : NaN;
}

// Feeds `decoder` the file at `url`: first FIRST_REQUEST_BYTES by range, then one request per
// chunk while `wanted()` says more is needed (else awaits `more()`, which resolves when the
// page asks for more). onResponse({ total, ranges }) once; onBytes() after every piece. Returns
// when the file is in, the decoder is done, or a response ends short.
export async function fetchByRanges(url, name, decoder, { wanted, more, onResponse, onBytes }) {
  let response = await fetch(url, { headers: { Range: `bytes=0-${FIRST_REQUEST_BYTES - 1}` } });
  if (response.status === 416) throw new Error(`${name}: the file is empty`);
  if (!response.ok) throw new Error(`${name}: HTTP ${response.status}`);
  const ranges = response.status === 206;
  const total = ranges ? rangeTotal(response) : Number(response.headers.get('Content-Length')) || 0;
  if (ranges && !(total >= 0)) throw new Error(`${name}: a 206 without the file's size`);
  onResponse?.({ total, ranges });
  for (;;) {
    const expected = ranges ? Number(response.headers.get('Content-Length')) : Infinity;
    let got = 0;
    const reader = response.body.getReader();
    for (;;) {
      const { done, value } = await reader.read();
      if (done) break;
      got += value.length;
      decoder.push(value);
      onBytes?.();
    }
    // A plain GET, the whole file, the end, or a response cut short (file changed meanwhile).
    if (!ranges || decoder.bytesReceived >= total || decoder.complete || got < expected) return;
    while (!wanted()) await more();
    const from = decoder.bytesReceived;
    const to = Math.min(total, Math.max(nextRequestEnd(decoder), from + FIRST_REQUEST_BYTES));
    response = await fetch(url, { headers: { Range: `bytes=${from}-${to - 1}` } });
    if (response.status !== 206) throw new Error(`${name}: HTTP ${response.status} for bytes ${from}-${to - 1}`);
  }
}
