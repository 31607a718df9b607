// The .dpm file (docs/FORMAT.md): its header, its chunks and their payloads, as a plain ES module
// that runs in the browser and in Node (tests, benchmarks). The C++ reader is
// src/progressive/dpm_read.cpp: both make the same checks at the same moment, and reject a file
// at the same byte (viewer/test/conformance.test.mjs holds them to it).
//
// DpmDecoder takes the file's bytes in pieces as they arrive and parses every chunk as soon as it
// is complete, into a ProgressiveMesh whose arrays are sized from HEAD once. Each chunk's header
// is checked as soon as its 24 bytes are in, before the payload has arrived; the split records
// are replayed on a face array as they are decoded, so that the navigator applies them unchecked.
import { decompress } from 'fzstd';

import { crc32, DpmError, Reader } from './bytes.js';
import { fieldModels, maxFieldValueBytes, parseFieldDefs, parseFieldValues } from './fields.js';
import { parsePartNames } from './parts.js';
import { parseVariants } from './variants.js';
import { parseBase, parseHead } from './head_base.js';
import { ChunkStencils, decodeSplitPositions, positionJob, positionModels, storePositions } from './positions.js';
import { ProgressiveMesh } from './progressive_mesh.js';
import { decodeSplitRecords, RecordModels } from './split_records.js';

export const MAGIC = Uint8Array.of(0x89, 0x44, 0x50, 0x4d, 0x0d, 0x0a, 0x1a, 0x0a);
const VERSION = 7;
const CHUNK_HEADER_BYTES = 24;
const FLAG_ZSTD = 1;
const TAGS = ['HEAD', 'FDEF', 'PART', 'VARI', 'BASE', 'FLDS', 'SPLT', 'END '];
// What may come next in each state (FORMAT.md "Layout"); known chunks keep this order.
const NEXT = {
  HEAD: ['HEAD'],
  FDEF: ['FDEF', 'PART', 'VARI', 'BASE'],  // right after HEAD
  PART: ['PART', 'VARI', 'BASE'],  // after FDEF
  VARI: ['VARI', 'BASE'],  // after PART
  BASE: ['BASE'],
  FLDS: ['FLDS'],
  SPLT: ['SPLT', 'END '],
};
// The tag of an optional chunk a reader may skip: four characters from A–Z, 0–9 and space.
const OPTIONAL_TAG = /^[A-Z0-9 ]{4}$/;
// A chunk's bounds (FORMAT.md "Chunk"): stored and raw at most 2^31 bytes; zstd's densest block,
// RLE, holds 128 KiB in 4 bytes, so no frame decompresses to more than 32768 times its size.
const MAX_CHUNK_BYTES = 2 ** 31;
const MAX_ZSTD_RATIO = 32768;
// The longest varint the reader takes (Reader.varint: 64 bits, 7 per byte).
const MAX_VARINT = 10;
// Room for this many vertices past the ones a reader means to load (takeRoom()): dynpm's
// largest SPLT (kMaxChunkSplits in dpm_write.cpp).
const ROOM_MARGIN_SPLITS = 16384;
// The vertices a reader that means to load n holds once the chunk that crosses n is in, as far
// as dynpm's chunks go: n and a margin (a quarter of n, at most ROOM_MARGIN_SPLITS; small: cheap).
export const withChunkMargin = (n) => n + Math.min(ROOM_MARGIN_SPLITS, Math.ceil(n / 4));
// A bound on the bytes of one range-coded integer (C++ kMaxCodedInteger).
const MAX_CODED_INTEGER = 64;

// What is wrong with a chunk's zstd payload before fzstd sees it, or null. fzstd allocates
// what the frame header declares (up to 2 GB, or the window when no size is declared), not the
// chunk's raw size, so a small chunk could make the page take gigabytes before the size check
// after decompression. As FORMAT.md says and the C++ reader checks: one frame, declaring
// exactly `raw` bytes, and nothing after it. Blocks are walked by their headers only.
export function zstdFrameProblem(bytes, raw) {
  const n = bytes.length;
  if (n < 6 || bytes[0] !== 0x28 || bytes[1] !== 0xb5 || bytes[2] !== 0x2f || bytes[3] !== 0xfd)
    return 'the payload is not a zstd frame';
  const descriptor = bytes[4];
  if (descriptor & 8) return 'zstd frame header has its reserved bit set';
  const sizeFlag = descriptor >> 6;
  const singleSegment = (descriptor >> 5) & 1;
  const checksum = (descriptor >> 2) & 1;
  const sizeBytes = sizeFlag ? 1 << sizeFlag : singleSegment;
  if (!sizeBytes) return 'the zstd frame does not declare its size';
  let at = 5 + (singleSegment ? 0 : 1) + [0, 1, 2, 4][descriptor & 3];
  if (at + sizeBytes > n) return 'the zstd frame header is cut short';
  let size = 0;
  for (let i = sizeBytes - 1; i >= 0; i--) size = size * 256 + bytes[at + i];
  if (sizeFlag === 1) size += 256;
  if (size !== raw) return `the zstd frame declares ${size} bytes, the chunk header ${raw}`;
  at += sizeBytes;
  for (let last = 0; !last; ) {
    if (at + 3 > n) return 'the zstd frame is cut short';
    const block = bytes[at] | (bytes[at + 1] << 8) | (bytes[at + 2] << 16);
    const type = (block >> 1) & 3;
    if (type === 3) return 'the zstd frame has a reserved block type';
    last = block & 1;
    at += 3 + (type === 1 ? 1 : block >>> 3);  // an RLE block stores one byte
  }
  if (at + 4 * checksum !== n) return 'bytes after the zstd frame';
  return null;
}

// The mesh HEAD describes. Its arrays are made for HEAD's counts, untouched until splits arrive;
// a browser that cannot reserve them says so as a file error, not as a crash.
function meshFor(head) {
  try {
    return new ProgressiveMesh(head);
  } catch (e) {
    if (!(e instanceof RangeError)) throw e;
    throw new DpmError(`HEAD: ${head.vertexCount} vertices, ${head.faceCount} faces, ` +
      `${head.stepCount} steps: more than this browser can hold (${e.message})`);
  }
}

// Feed it the file's bytes with push() as they arrive; it parses each chunk once complete and
// calls the callbacks: onHead(mesh), onBase(mesh), onSplits(mesh, first, count), onEnd(mesh).
// With a `positions` executor, call flush() before taking mesh.splitsLoaded as final.
export class DpmDecoder {
  // vertices: how many the reader means to load (the page's ?vertices=N or budget; raise it when
  // it wants more): the arrays of every step take room for them and a margin at once
  // (takeRoom()), and grow past them by doubling.
  // positions: null (each SPLT's positions are decoded as it is parsed), or an executor that
  // decodes them elsewhere while the next chunk is parsed — start(job), then wait() → null or
  // what is wrong (positions_executor.js: a second worker; deferredPositions() in the tests). A SPLT
  // is committed once its positions are in, and a file is refused at the same byte, with the
  // same message, either way.
  constructor({ name = 'file', onHead, onBase, onSplits, onEnd, vertices = Infinity, positions = null } = {}) {
    this.name = name;
    this.vertices = vertices;
    this.callbacks = { onHead, onBase, onSplits, onEnd };
    this.positions = positions;
    // The SPLT whose positions the executor is decoding: { chunk, at, parsed, job } (its FLDS
    // too; job: positionJob()'s).
    this.inFlight = null;
    // The arrays a SPLT's positions are decoded into (positions.js positionJob()), kept for the next.
    this.staging = null;
    // Splits whose records are parsed: committed (mesh.splitsLoaded) or in flight.
    this.splitsDecoded = 0;
    this.buffer = new Uint8Array(1 << 16);
    this.start = 0;   // first unparsed byte in buffer
    this.end = 0;     // end of the received bytes in buffer
    this.offset = 0;  // file offset of buffer[0]
    this.bytesReceived = 0;
    // magic → HEAD → FDEF? → PART? → VARI? → BASE → FLDS? → (SPLT → FLDS?)… → END → done
    this.state = 'magic';
    this.mesh = null;
    // The records' models and the faces at the last decoded split (4 slots each), for the checks.
    this.records = null;
    // The splits of a SPLT whose FLDS has not arrived: not applied yet (FORMAT.md "Prefixes").
    this.pending = null;
  }

  // The split records' models and the faces as the splits so far left them, made at the first
  // SPLT, not at BASE: the replay holds 16 bytes a face of the whole mesh, which would delay the
  // base mesh's picture. The test encoder starts from them too.
  recordModels() {
    if (!this.records) {
      const mesh = this.mesh;
      // Not filled with −1: a split writes all 4 slots of a face it creates, and no face is read
      // before it exists, so the pages of faces HEAD claims but no split makes are never written.
      const replay = new Int32Array(4 * mesh.head.faceCount);
      replay.set(mesh.baseCorners);
      this.records = new RecordModels(mesh, replay);
    }
    return this.records;
  }

  get complete() {
    return this.state === 'done';
  }
  // The file offset of the first byte not parsed yet: where the next chunk starts.
  get chunkStart() {
    return this.offset + this.start;
  }

  fail(fileByte, cause) {
    throw new DpmError(`${this.name}: byte ${fileByte}: ${cause}`);
  }

  push(bytes) {
    try {
      this.parse(bytes);
    } catch (e) {
      // Decoded in place, the positions in flight were checked before anything that follows.
      if (e instanceof DpmError) this.flush(false);
      throw e;
    }
  }

  // The positions in flight, waited for: an error of theirs is thrown; their SPLT is committed
  // when it is parsed to its end (and `commit`).
  flush(commit = true) {
    const flight = this.inFlight;
    if (!flight) return;
    this.inFlight = null;
    const problem = this.positions.wait();
    if (problem) throw new DpmError(`${flight.at}: ${problem}`);
    storePositions(flight.job);
    if (flight.parsed && commit) this.commit(flight.chunk);
  }

  parse(bytes) {
    this.append(bytes);
    this.bytesReceived += bytes.length;
    for (;;) {
      const available = this.end - this.start;
      const at = this.offset + this.start;
      if (this.state === 'magic') {
        const b = this.buffer.subarray(this.start, this.start + Math.min(available, 12));
        for (let i = 0; i < Math.min(b.length, 8); i++)
          if (b[i] !== MAGIC[i]) this.fail(0, 'not a .dpm file (wrong magic)');
        if (available < 12) return;
        const version = new DataView(b.buffer, b.byteOffset + 8, 4).getUint32(0, true);
        if (version >= 1 && version < VERSION)
          this.fail(8, `written by an older dynpm (version ${version}): build it again`);
        if (version !== VERSION)
          this.fail(8, `version ${version} is not supported (this reader reads version ${VERSION})`);
        this.start += 12;
        this.state = 'HEAD';
        continue;
      }
      if (this.state === 'done') {
        if (available > 0) this.fail(at, 'bytes after the END chunk');
        return;
      }
      if (available < CHUNK_HEADER_BYTES) return;
      const h = new DataView(this.buffer.buffer, this.start, CHUNK_HEADER_BYTES);
      const tag = String.fromCharCode(...this.buffer.subarray(this.start, this.start + 4));
      const flags = h.getUint32(4, true);
      const stored = h.getUint32(8, true);
      const raw = h.getUint32(12, true);
      const crc = h.getUint32(16, true);
      const reserved = h.getUint32(20, true);
      const skipped = this.checkChunkHeader(at, tag, flags, stored, raw, reserved);
      if (available < CHUNK_HEADER_BYTES + stored) return;  // wait for the rest of the chunk
      const payloadStart = this.start + CHUNK_HEADER_BYTES;
      const payloadAt = at + CHUNK_HEADER_BYTES;
      const storedBytes = this.buffer.subarray(payloadStart, payloadStart + stored);
      if (crc32(storedBytes) !== crc) this.fail(at, `${tag} chunk: wrong checksum`);
      if (skipped) {
        this.start = payloadStart + stored;  // an optional chunk this reader does not know
        continue;
      }
      let payload = storedBytes;
      if (flags & FLAG_ZSTD) {
        const frame = zstdFrameProblem(storedBytes, raw);
        if (frame) this.fail(payloadAt, `${tag} chunk: ${frame}`);
        try {
          payload = decompress(storedBytes);
        } catch (e) {
          this.fail(payloadAt, `${tag} chunk: zstd: ${e.message}`);
        }
        if (payload.length !== raw)
          this.fail(payloadAt, `${tag} chunk: ${payload.length} bytes decompressed, not ${raw}`);
      } else {
        payload = storedBytes.slice();  // the buffer is reused for later bytes
      }
      this.start = payloadStart + stored;
      const where = (pos) =>
        `${tag} payload byte ${pos}` + (flags & FLAG_ZSTD ? ' (decompressed)' : '');
      this.parseChunk(at, tag, new Reader(payload, `${this.name}: byte ${payloadAt}`, where));
    }
  }

  append(bytes) {
    if (this.end + bytes.length > this.buffer.length) {
      // Drop what has been parsed; grow only if the pending chunk needs it.
      const pending = this.end - this.start;
      if (pending + bytes.length > this.buffer.length) {
        let size = this.buffer.length;
        while (size < pending + bytes.length) size *= 2;
        const bigger = new Uint8Array(size);
        bigger.set(this.buffer.subarray(this.start, this.end));
        this.buffer = bigger;
      } else {
        this.buffer.copyWithin(0, this.start, this.end);
      }
      this.offset += this.start;
      this.end = pending;
      this.start = 0;
    }
    this.buffer.set(bytes, this.end);
    this.end += bytes.length;
  }

  // What the 24 bytes of a chunk's header say, checked before its payload has arrived, in the
  // order the C++ reader checks them (Decoder::check_chunk_header).
  // Returns true for an unknown optional chunk, to be skipped once its checksum is checked.
  checkChunkHeader(at, tag, flags, stored, raw, reserved) {
    const expected = NEXT[this.state];
    const optional = !TAGS.includes(tag) && OPTIONAL_TAG.test(tag) && this.state !== 'HEAD';
    if (!TAGS.includes(tag) && !optional) this.fail(at, `unknown chunk tag '${tag}'`);
    if (!optional && !expected.includes(tag))
      this.fail(at, `${tag} chunk where ${expected.join(' or ')} belongs`);
    if (flags & ~FLAG_ZSTD) this.fail(at + 4, `${tag} chunk: unknown flags ${flags}`);
    if (reserved !== 0) this.fail(at + 20, `${tag} chunk: reserved field is ${reserved}, not 0`);
    if (stored > MAX_CHUNK_BYTES) this.fail(at + 8, `${tag} chunk: stored size ${stored} > 2^31`);
    if (!(flags & FLAG_ZSTD) && raw !== stored)
      this.fail(at + 12, `${tag} chunk: raw size ${raw} differs from stored ${stored}`);
    if ((tag === 'HEAD' || tag === 'END ') && flags & FLAG_ZSTD)
      this.fail(at + 4, `${tag} chunk is compressed`);
    if (tag === 'END ' && raw !== 0) this.fail(at + 12, 'END chunk is not empty');
    if (tag === 'HEAD' || tag === 'END ') return false;
    // Before any allocation: what the chunk says it holds against what it can hold (FDEF and
    // optional chunks: 2^31).
    const limit = this.maxRawBytes(tag);
    if (raw > limit)
      this.fail(at + 12, `${tag} chunk: raw size ${raw}, HEAD allows ${Math.floor(limit)}`);
    if (flags & FLAG_ZSTD && raw > stored * MAX_ZSTD_RATIO)
      this.fail(at + 12, `${tag} chunk: raw size ${raw} from ${stored} compressed bytes`);
    return optional;
  }

  // The most bytes a BASE, SPLT or FLDS payload can take for HEAD's counts, each value at its longest
  // encoding (at most 2^31). Moved faces have no count in HEAD: every remaining split may move
  // every face, a loose bound but a bound. The same arithmetic as the C++ payload_limit().
  maxRawBytes(tag) {
    if (tag !== 'BASE' && tag !== 'SPLT' && tag !== 'FLDS') return MAX_CHUNK_BYTES;
    const h = this.mesh.head;
    const steps = h.stepCount;
    const perVertex = 2 * MAX_VARINT + steps * 3 * MAX_VARINT;
    const perFaceAttributes = 3 * MAX_VARINT;
    let limit;
    if (tag === 'FLDS') {
      const { s, n } = this.pending ?? { s: 0, n: 0 };
      limit = maxFieldValueBytes(this.mesh, s, n);
    } else if (tag === 'BASE') {
      limit = h.baseVertexCount * perVertex +
        h.baseFaceCount * (1 + 4 * MAX_VARINT + perFaceAttributes);
    } else {
      const splits = h.splitCount - this.splitsDecoded;
      const perRecord = MAX_VARINT + 4 + 1 + 4 * (1 + 2 * MAX_VARINT) + MAX_VARINT +
        MAX_VARINT * h.faceCount;
      const perAttributes = 2 * MAX_VARINT + 4 * perFaceAttributes;
      // A range-coded integer takes at most MAX_CODED_INTEGER bytes; a section adds 5 flushed.
      const perPositions = steps * 3 * MAX_CODED_INTEGER;
      limit = 12 + 4 * (2 + steps) + 5 * (2 + steps) +
        splits * (perRecord + perAttributes + perPositions);
    }
    return Math.min(limit, MAX_CHUNK_BYTES);
  }

  parseChunk(at, tag, r) {
    const { mesh } = this;
    const withFields = mesh?.fields.length > 0;
    if (tag === 'HEAD') {
      this.mesh = meshFor(parseHead(r));
      this.state = 'FDEF';
      this.callbacks.onHead?.(this.mesh);
    } else if (tag === 'FDEF') {
      parseFieldDefs(r, mesh);
      this.state = 'PART';
    } else if (tag === 'PART') {
      parsePartNames(r, mesh);
      this.state = 'VARI';
    } else if (tag === 'VARI') {
      parseVariants(r, mesh);
      this.state = 'BASE';
    } else if (tag === 'BASE') {
      this.takeRoom();
      parseBase(r, mesh);
      this.pending = { s: 0, n: 0 };
      if (withFields) this.state = 'FLDS';
      else this.parsed();
    } else if (tag === 'SPLT') {
      const at = r.pos;
      r.u32();
      const n = r.u32();  // the chunk's split count (parseSplits() reads and checks it again)
      r.pos = at;
      const s = this.splitsDecoded, b = mesh.head.baseVertexCount;
      this.takeRoom(b + s + Math.min(n, mesh.head.splitCount - s));
      this.models ??= positionModels(mesh.head.stepCount);
      const records = this.recordModels();
      const chunk = { s, ...parseSplits(r, mesh, records, s) };
      this.room(b + s + chunk.n, mesh.faceCountAt[s + chunk.n]);  // for positions, then FLDS
      this.splitsDecoded = s + chunk.n;
      this.pending = chunk;
      this.decodePositions(r, chunk);
      if (withFields) this.state = 'FLDS';
      else this.parsed();
    } else if (tag === 'FLDS') {
      this.fieldModels ??= fieldModels(mesh);
      const { s, n, stencils } = this.pending;
      parseFieldValues(r, mesh, s, n, stencils, this.fieldModels);
      this.parsed();
    } else {
      this.flush();
      const { splitsLoaded, head } = this.mesh;
      if (splitsLoaded !== head.splitCount)
        this.fail(at, `END after ${splitsLoaded} of ${head.splitCount} splits`);
      this.mesh.complete = true;
      this.state = 'done';
      this.callbacks.onEnd?.(this.mesh);
    }
  }

  // Room in the arrays of every step for the vertices the reader means to load, and their share
  // of the faces, with a margin for the chunk that goes past them (the last before a pause):
  // dynpm writes at most 16,384 splits a chunk, so past 65,536 vertices that chunk fits without
  // the arrays being made anew, which held the old and the new arrays of every step at once (a
  // page with a 1 GiB budget peaked 1.1 GiB above what it kept). Room no split writes is never
  // touched: it costs address space, not memory. A crossing chunk beyond the margin gets room
  // for all of it, not doubled.
  takeRoom(chunkEnd = 0) {
    const { vertexCount: V, faceCount: F, baseVertexCount: b } = this.mesh.head;
    const decoded = this.mesh.hasBase ? b + this.splitsDecoded : 0;
    const crossing = decoded < this.vertices && chunkEnd > this.vertices;
    const n = Math.min(V, Math.max(crossing ? chunkEnd : 0, withChunkMargin(this.vertices)));
    this.room(n, n === V ? F : Math.ceil((F * n) / V), !crossing);
  }

  // mesh.makeRoom(): the positions in flight read the arrays they were given, which keep what
  // they held, and are stored into the mesh's arrays once in (flush()).
  room(vertices, faces, doubling = true) {
    this.mesh.makeRoom(vertices, faces, doubling);
  }

  // The positions of the SPLT just parsed: decoded here (a problem is the chunk's), or started
  // on the executor once the ones in flight are in.
  decodePositions(r, chunk) {
    const { mesh } = this;
    const { s, n, stencils, sections } = chunk;
    this.flush();  // the staging arrays are the job in flight's until then
    // The staging arrays go to the executor's thread (which exists only where memory is shared).
    this.staging ??= new Int32Array(this.positions ? new SharedArrayBuffer(0) : 0);
    const job = positionJob(mesh, s, n, stencils, sections, this.models, this.staging);
    this.staging = job.staging;
    if (!this.positions) {
      const problem = decodeSplitPositions(job);
      if (problem) r.failChunk(problem);
      storePositions(job);
      return;
    }
    this.positions.start(job);
    this.inFlight = { chunk, at: r.at, parsed: false, job };
  }

  // The base mesh, or a SPLT with its FLDS, parsed to its end: committed, or, while its
  // positions are in flight, once they are in (flush()).
  parsed() {
    const chunk = this.pending;
    this.pending = null;
    this.state = 'SPLT';
    if (this.inFlight?.chunk === chunk) this.inFlight.parsed = true;
    else this.commit(chunk);
  }

  // The base mesh, or the splits of a SPLT, with their field values when the file has fields:
  // now they are levels a navigator may reach.
  commit({ s, n }) {
    const { mesh } = this;
    if (!mesh.hasBase) {
      mesh.hasBase = true;
      this.callbacks.onBase?.(mesh);
      return;
    }
    mesh.splitsLoaded = s + n;
    this.callbacks.onSplits?.(mesh, s, n);
  }
}

// ---------------------------------------------------------------------------------------------
// Payloads

// A SPLT's header and records (its stencils made as they are applied), and its position sections;
// `expected`: its first split.
function parseSplits(r, mesh, records, expected) {
  const h = mesh.head;
  const s = r.u32();
  const n = r.u32();
  if (s !== expected) r.fail(`first_split ${s}, expected ${expected}`);
  if (n === 0 || n > h.splitCount - s) r.fail(`${n} splits from ${s} (${h.splitCount} in all)`);
  // The sections: records, attributes, then the positions of each step (FORMAT.md).
  const count = r.u32();
  if (count !== 2 + h.stepCount) r.fail(`${count} sections, not 2 + ${h.stepCount}`);
  const sizes = [];
  for (let k = 0; k < count; k++) sizes.push(r.u32());
  if (sizes.reduce((a, x) => a + x, 0) !== r.remaining())
    r.fail('the section sizes do not add up to the payload');
  const starts = [];
  sizes.reduce((at, size) => (starts.push(at), at + size), r.pos);
  // The records, applied to the faces as they are decoded (checked: the navigator can apply
  // them unchecked); the faces right after each split give its stencil. A problem is the
  // records section's, at its start (C++: decode_split_records()).
  const stencils = new ChunkStencils(n);
  const bytes = (k) => r.bytes.subarray(starts[k], starts[k] + sizes[k]);
  const problem = decodeSplitRecords(bytes(0), bytes(1), s, n, mesh, records,
    (i) => stencils.add(mesh, i - s, i, records.corners));
  if (problem) {
    r.pos = starts[0];
    r.fail(problem);
  }
  const sections = starts.slice(2).map((at, t) => r.bytes.subarray(at, at + sizes[2 + t]));
  // The loaded levels grow only at commit(): a chunk that fails half-way, or whose FLDS does
  // not arrive, leaves them as they were. The stencils' rings guess the FLDS's node values.
  return { n, stencils, sections };
}

// Reads a whole .dpm held in memory, or a prefix of one (Node tests, tools).
// options: DpmDecoder's (`positions`).
export function readDpm(bytes, name = 'file', options = {}) {
  const decoder = new DpmDecoder({ ...options, name });
  decoder.push(bytes instanceof Uint8Array ? bytes : new Uint8Array(bytes));
  decoder.flush();
  if (!decoder.mesh) throw new DpmError(`${name}: ends before HEAD is complete`);
  return { mesh: decoder.mesh, complete: decoder.complete, decoder };
}

// Reads a whole .dpm, or a prefix that holds at least HEAD and BASE, as the C++ decode_dpm()
// does: a file that ends before is an error at the chunk it ends in.
export function decodeDpm(bytes, name = 'file', options = {}) {
  const decoder = new DpmDecoder({ ...options, name });
  decoder.push(bytes instanceof Uint8Array ? bytes : new Uint8Array(bytes));
  decoder.flush();
  if (decoder.state === 'magic') decoder.fail(0, 'not a .dpm file (shorter than its signature)');
  if (!decoder.mesh?.hasBase)
    decoder.fail(decoder.chunkStart, `the file ends before ${decoder.state} is complete`);
  return { mesh: decoder.mesh, complete: decoder.complete, decoder };
}

// Streams a fetch() Response (or any ReadableStream of Uint8Array) into a decoder;
// onProgress(bytesReceived) after every piece.
export async function streamDpm(stream, decoder, onProgress) {
  const reader = stream.getReader();
  for (;;) {
    const { done, value } = await reader.read();
    if (done) break;
    decoder.push(value);
    onProgress?.(decoder.bytesReceived);
  }
  decoder.flush();
  return decoder.mesh;
}
