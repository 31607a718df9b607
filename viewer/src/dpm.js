// Decoder and navigator for .dpm files (docs/FORMAT.md), as a plain ES module that runs in the
// browser (through the page's import map) and in Node (tests, benchmarks).
//
// DpmDecoder takes the file's bytes in pieces as they arrive and parses every chunk as soon as it
// is complete, into a ProgressiveMesh whose arrays are sized from HEAD once. Navigator holds the
// mesh at one level (b + k vertices) and moves between levels by applying or undoing the split
// records, touching only the faces they name. Positions are kept as the file's quantized integers,
// one Int32Array of 3·V per step, so that any level at any (fractional) step is a prefix of them.
import { decompress } from 'fzstd';

export const MAGIC = Uint8Array.of(0x89, 0x44, 0x50, 0x4d, 0x0d, 0x0a, 0x1a, 0x0a);
const CHUNK_HEADER_BYTES = 24;
const FLAG_ZSTD = 1;
const HEAD_FLAG_LOSSLESS = 1;
// A browser tab cannot hold more; a HEAD asking for it is refused before anything is allocated.
const MAX_ARRAY_ELEMENTS = 2 ** 31 - 1;

export class DpmError extends Error {}

// ---------------------------------------------------------------------------------------------
// Bytes

let crcTable = null;
function crc32(bytes) {
  if (!crcTable) {
    crcTable = new Int32Array(256);
    for (let n = 0; n < 256; n++) {
      let c = n;
      for (let k = 0; k < 8; k++) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
      crcTable[n] = c;
    }
  }
  let c = -1;
  for (let i = 0; i < bytes.length; i++) c = crcTable[(c ^ bytes[i]) & 0xff] ^ (c >>> 8);
  return (c ^ -1) >>> 0;
}

// Reads one chunk payload; every read checks the end, so a short payload is an error with the
// byte where it happened, never a read past the end.
class Reader {
  constructor(bytes, where) {
    this.bytes = bytes;
    this.view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    this.pos = 0;
    this.end = bytes.length;
    this.where = where;  // (payload offset) → "file: byte N" text
  }
  fail(cause) {
    throw new DpmError(`${this.where(this.pos)}: ${cause}`);
  }
  need(n) {
    if (this.end - this.pos < n) this.fail(`needs ${n} more bytes, the chunk ends`);
  }
  remaining() {
    return this.end - this.pos;
  }
  u8() {
    this.need(1);
    return this.bytes[this.pos++];
  }
  u16() {
    this.need(2);
    const v = this.view.getUint16(this.pos, true);
    this.pos += 2;
    return v;
  }
  u32() {
    this.need(4);
    const v = this.view.getUint32(this.pos, true);
    this.pos += 4;
    return v;
  }
  f32() {
    this.need(4);
    const v = this.view.getFloat32(this.pos, true);
    this.pos += 4;
    return v;
  }
  f64() {
    this.need(8);
    const v = this.view.getFloat64(this.pos, true);
    this.pos += 8;
    return v;
  }
  varint() {
    const b = this.bytes;
    let p = this.pos;
    if (p < this.end && b[p] < 0x80) {
      this.pos = p + 1;
      return b[p];
    }
    // Multiplication, not shifts: JS bit operators are 32-bit and a varint may hold 64 bits.
    let result = 0;
    let scale = 1;
    for (let i = 0; i < 10; i++) {
      if (p >= this.end) this.fail('varint runs past the end of the chunk');
      const x = b[p++];
      result += (x & 0x7f) * scale;
      scale *= 128;
      if (x < 0x80) {
        this.pos = p;
        return result;
      }
    }
    this.fail('varint longer than 10 bytes');
  }
  svarint() {
    const u = this.varint();
    // zigzag: 0, 1, 2, 3 → 0, −1, 1, −2; the bit form is exact below 2^32.
    if (u < 4294967296) return (u >>> 1) ^ -(u & 1);
    return u % 2 ? -(u + 1) / 2 : u / 2;
  }
  string() {
    const n = this.u16();
    this.need(n);
    const s = new TextDecoder().decode(this.bytes.subarray(this.pos, this.pos + n));
    this.pos += n;
    return s;
  }
}

// A typed array that grows by doubling (split records whose total is only known at the end).
class Growable {
  constructor(Type, capacity) {
    this.Type = Type;
    this.data = new Type(Math.max(16, capacity));
    this.length = 0;
  }
  push(v) {
    if (this.length === this.data.length) {
      const bigger = new this.Type(this.data.length * 2);
      bigger.set(this.data);
      this.data = bigger;
    }
    this.data[this.length++] = v;
  }
}

// ---------------------------------------------------------------------------------------------
// The mesh as far as it has arrived

export class ProgressiveMesh {
  constructor(head) {
    this.head = head;
    const { vertexCount: V, faceCount: F, stepCount: m, fieldCount } = head;
    if (3 * V * 1 > MAX_ARRAY_ELEMENTS || 4 * F > MAX_ARRAY_ELEMENTS || m * fieldCount > 65536)
      throw new DpmError(`HEAD: ${V} vertices, ${F} faces, ${m} steps is more than a browser holds`);
    this.q = [];  // per step: Int32Array(3V), quantized (or f32 bit patterns when lossless)
    for (let t = 0; t < m; t++) this.q.push(new Int32Array(3 * V));
    this.fields = [];  // per field, per step: Float32Array(V)
    for (let f = 0; f < fieldCount; f++) {
      const steps = [];
      for (let t = 0; t < m; t++) steps.push(new Float32Array(V));
      this.fields.push(steps);
    }
    this.vertexOriginal = new Float64Array(V);
    this.nodeId = new Float64Array(V);
    // Faces as the base mesh has them; splits re-create the others (Navigator).
    this.baseDegree = null;
    this.baseCorners = null;
    this.faceOriginal = new Float64Array(F);
    this.partId = new Float64Array(F);
    this.elementId = new Float64Array(F);
    // Split records, flat: split i has wings [wingStart[i], wingStart[i+1]) and moved faces
    // [movedStart[i], movedStart[i+1]); faceCountAt[k] = faces after k splits.
    const S = head.splitCount;
    this.parent = new Int32Array(S);
    this.error = new Float32Array(S);
    this.wingStart = new Uint32Array(S + 1);
    this.movedStart = new Uint32Array(S + 1);
    this.faceCountAt = new Uint32Array(S + 1);
    this.wingFlags = new Growable(Uint8Array, S * 2);
    this.wingVertex = new Growable(Int32Array, S * 2);
    this.wingFace = new Growable(Int32Array, S * 2);  // quad wing: the face; triangle wing: new face
    this.moved = new Growable(Int32Array, S * 2);
    this.hasBase = false;
    this.splitsLoaded = 0;
    this.complete = false;
    // Delta chains that continue across chunks.
    this.lastVertexOriginal = 0;
    this.lastNodeId = 0;
    this.lastElementId = 0;
    this.lastFaceOriginal = 0;
  }

  get lossless() {
    return (this.head.flags & HEAD_FLAG_LOSSLESS) !== 0;
  }
  // Vertices available: the base plus the splits that have arrived.
  get vertexCountLoaded() {
    return this.hasBase ? this.head.baseVertexCount + this.splitsLoaded : 0;
  }
  // The error of the level with k splits applied.
  levelError(k) {
    return k === 0 ? this.head.baseError : this.error[k - 1];
  }
  // Position of vertex v at integer step t, as the f32 the file means.
  position(v, t, out = [0, 0, 0]) {
    const q = this.q[t];
    if (this.lossless) {
      const f = new Float32Array(q.buffer, q.byteOffset + 12 * v, 3);
      out[0] = f[0], out[1] = f[1], out[2] = f[2];
    } else {
      const { bboxMin, quantStep } = this.head;
      for (let c = 0; c < 3; c++) out[c] = Math.fround(bboxMin[c] + q[3 * v + c] * quantStep);
    }
    return out;
  }

  // Positions of vertices [0, n) at fractional step t (linear between the two steps around it),
  // into out (Float32Array, ≥ 3n). This is the per-frame work while time changes: one pass over
  // a prefix of two arrays.
  positionsAt(t, n, out) {
    const m = this.head.stepCount;
    t = Math.min(Math.max(t, 0), m - 1);
    const t0 = Math.floor(t);
    const t1 = Math.min(t0 + 1, m - 1);
    const a = t - t0;
    const count = 3 * n;
    if (this.lossless) {
      const p0 = new Float32Array(this.q[t0].buffer, 0, count);
      const p1 = new Float32Array(this.q[t1].buffer, 0, count);
      if (a === 0) out.set(p0);
      else for (let i = 0; i < count; i++) out[i] = p0[i] + (p1[i] - p0[i]) * a;
      return out;
    }
    const q0 = this.q[t0];
    const q1 = this.q[t1];
    const s = this.head.quantStep;
    const [x0, y0, z0] = this.head.bboxMin;
    if (a === 0) {
      for (let i = 0; i < count; i += 3) {
        out[i] = x0 + q0[i] * s;
        out[i + 1] = y0 + q0[i + 1] * s;
        out[i + 2] = z0 + q0[i + 2] * s;
      }
    } else {
      const b0 = (1 - a) * s;
      const b1 = a * s;
      for (let i = 0; i < count; i += 3) {
        out[i] = x0 + q0[i] * b0 + q1[i] * b1;
        out[i + 1] = y0 + q0[i + 1] * b0 + q1[i + 1] * b1;
        out[i + 2] = z0 + q0[i + 2] * b0 + q1[i + 2] * b1;
      }
    }
    return out;
  }

  // |p − p(0)| of vertices [0, n), given their positions now and at step 0.
  static displacement(positions, base, n, out) {
    for (let v = 0, i = 0; v < n; v++, i += 3) {
      const dx = positions[i] - base[i];
      const dy = positions[i + 1] - base[i + 1];
      const dz = positions[i + 2] - base[i + 2];
      out[v] = Math.sqrt(dx * dx + dy * dy + dz * dz);
    }
    return out;
  }

  // Field f's values of vertices [0, n) at fractional step t.
  fieldAt(f, t, n, out) {
    const m = this.head.stepCount;
    t = Math.min(Math.max(t, 0), m - 1);
    const t0 = Math.floor(t);
    const t1 = Math.min(t0 + 1, m - 1);
    const a = t - t0;
    const v0 = this.fields[f][t0];
    const v1 = this.fields[f][t1];
    for (let v = 0; v < n; v++) out[v] = v0[v] + (v1[v] - v0[v]) * a;
    return out;
  }
}

// ---------------------------------------------------------------------------------------------
// Streaming decoder

// Feed it the file's bytes with push() as they arrive; it parses each chunk once complete and
// calls the callbacks: onHead(mesh), onBase(mesh), onSplits(mesh, first, count), onEnd(mesh).
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

export class DpmDecoder {
  constructor({ name = 'file', onHead, onBase, onSplits, onEnd } = {}) {
    this.name = name;
    this.callbacks = { onHead, onBase, onSplits, onEnd };
    this.buffer = new Uint8Array(1 << 16);
    this.start = 0;   // first unparsed byte in buffer
    this.end = 0;     // end of the received bytes in buffer
    this.offset = 0;  // file offset of buffer[0]
    this.bytesReceived = 0;
    this.state = 'magic';  // magic → HEAD → BASE → SPLT… → END → done
    this.mesh = null;
  }

  get complete() {
    return this.state === 'done';
  }

  fail(fileByte, cause) {
    throw new DpmError(`${this.name}: byte ${fileByte}: ${cause}`);
  }

  push(bytes) {
    if (this.state === 'done' && bytes.length) this.fail(this.bytesReceived, 'bytes after END');
    this.append(bytes);
    this.bytesReceived += bytes.length;
    for (;;) {
      const available = this.end - this.start;
      const at = this.offset + this.start;
      if (this.state === 'magic') {
        if (available < 12) return;
        const b = this.buffer.subarray(this.start, this.start + 12);
        for (let i = 0; i < 8; i++)
          if (b[i] !== MAGIC[i]) this.fail(i, 'not a .dpm file (wrong magic)');
        const version = new DataView(b.buffer, b.byteOffset + 8, 4).getUint32(0, true);
        if (version !== 1) this.fail(8, `version ${version}, this reader knows version 1`);
        this.start += 12;
        this.state = 'HEAD';
        continue;
      }
      if (this.state === 'done' || available < CHUNK_HEADER_BYTES) return;
      const h = new DataView(this.buffer.buffer, this.start, CHUNK_HEADER_BYTES);
      const tag = String.fromCharCode(...this.buffer.subarray(this.start, this.start + 4));
      const flags = h.getUint32(4, true);
      const stored = h.getUint32(8, true);
      const raw = h.getUint32(12, true);
      const crc = h.getUint32(16, true);
      const reserved = h.getUint32(20, true);
      this.checkChunkHeader(at, tag, flags, stored, raw, reserved);
      if (available < CHUNK_HEADER_BYTES + stored) return;  // wait for the rest of the chunk
      const payloadStart = this.start + CHUNK_HEADER_BYTES;
      const stored_bytes = this.buffer.subarray(payloadStart, payloadStart + stored);
      if (crc32(stored_bytes) !== crc) this.fail(at, `${tag} chunk: wrong checksum`);
      let payload = stored_bytes;
      if (flags & FLAG_ZSTD) {
        const frame = zstdFrameProblem(stored_bytes, raw);
        if (frame) this.fail(at + CHUNK_HEADER_BYTES, `${tag} chunk: ${frame}`);
        try {
          payload = decompress(stored_bytes);
        } catch (e) {
          this.fail(at, `${tag} chunk: zstd: ${e.message}`);
        }
        if (payload.length !== raw)
          this.fail(at, `${tag} chunk: ${payload.length} bytes after decompression, header says ${raw}`);
      } else {
        payload = stored_bytes.slice();  // the buffer is reused for later bytes
      }
      this.start = payloadStart + stored;
      const payloadAt = at + CHUNK_HEADER_BYTES;
      const where = (pos) =>
        `${this.name}: byte ${payloadAt}: ${tag} payload byte ${pos}` +
        (flags & FLAG_ZSTD ? ' (decompressed)' : '');
      this.parseChunk(tag, new Reader(payload, where));
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

  checkChunkHeader(at, tag, flags, stored, raw, reserved) {
    const expected = this.state === 'SPLT' ? ['SPLT', 'END '] : [this.state];
    if (!['HEAD', 'BASE', 'SPLT', 'END '].includes(tag))
      this.fail(at, `unknown chunk tag '${tag}'`);
    if (!expected.includes(tag))
      this.fail(at, `${tag} chunk where ${expected.join(' or ')} belongs`);
    if (flags & ~FLAG_ZSTD) this.fail(at + 4, `${tag} chunk: unknown flags ${flags}`);
    if (reserved !== 0) this.fail(at + 20, `${tag} chunk: reserved field is ${reserved}, not 0`);
    if (stored > 2 ** 31) this.fail(at + 8, `${tag} chunk: stored size ${stored} > 2^31`);
    if (!(flags & FLAG_ZSTD) && raw !== stored)
      this.fail(at + 12, `${tag} chunk: raw size ${raw} differs from stored ${stored}`);
    if (tag === 'HEAD' && flags & FLAG_ZSTD) this.fail(at + 4, 'HEAD chunk is compressed');
    if (tag === 'END ' && raw !== 0) this.fail(at + 12, 'END chunk is not empty');
    if (this.mesh && raw > this.maxRawBytes(tag))
      this.fail(at + 12, `${tag} chunk: raw size ${raw} is more than HEAD's counts allow`);
  }

  // The most bytes a BASE or SPLT payload can need for HEAD's counts: every varint at its
  // longest. Moved faces have no count in HEAD; a split moves at most every face once.
  maxRawBytes(tag) {
    const h = this.mesh.head;
    const m = h.stepCount;
    const perVertex = 20 + m * 30 + h.fieldCount * m * 4;
    if (tag === 'BASE') return h.baseVertexCount * perVertex + h.baseFaceCount * (1 + 20 + 30);
    const splits = Math.min(16384, h.splitCount);
    return 8 + splits * (5 + 4 + 1 + 4 * 11 + 5 + perVertex + 4 * 30) + splits * 5 * h.faceCount;
  }

  parseChunk(tag, r) {
    if (tag === 'HEAD') {
      this.mesh = new ProgressiveMesh(parseHead(r));
      this.state = 'BASE';
      this.callbacks.onHead?.(this.mesh);
    } else if (tag === 'BASE') {
      parseBase(r, this.mesh);
      this.state = 'SPLT';
      this.callbacks.onBase?.(this.mesh);
    } else if (tag === 'SPLT') {
      const first = this.mesh.splitsLoaded;
      const count = parseSplits(r, this.mesh);
      this.callbacks.onSplits?.(this.mesh, first, count);
    } else {
      if (this.mesh.splitsLoaded !== this.mesh.head.splitCount)
        r.fail(`END after ${this.mesh.splitsLoaded} of ${this.mesh.head.splitCount} splits`);
      this.mesh.complete = true;
      this.state = 'done';
      this.callbacks.onEnd?.(this.mesh);
      return;
    }
    if (r.remaining() !== 0) r.fail(`${r.remaining()} bytes left over at the end of ${tag}`);
  }
}

function parseHead(r) {
  const h = {};
  h.vertexCount = r.u32();
  h.faceCount = r.u32();
  h.baseVertexCount = r.u32();
  h.baseFaceCount = r.u32();
  h.splitCount = r.u32();
  h.stepCount = r.u32();
  h.fieldCount = r.u32();
  h.flags = r.u32();
  if (h.splitCount !== h.vertexCount - h.baseVertexCount)
    r.fail(`split_count ${h.splitCount} is not V − b = ${h.vertexCount - h.baseVertexCount}`);
  if (h.baseFaceCount > h.faceCount) r.fail('more base faces than faces');
  if (h.stepCount < 1) r.fail('no time steps');
  if (h.flags & ~HEAD_FLAG_LOSSLESS) r.fail(`unknown HEAD flags ${h.flags}`);
  h.bboxMin = [r.f64(), r.f64(), r.f64()];
  h.bboxMax = [r.f64(), r.f64(), r.f64()];
  h.quantStep = r.f64();
  h.maxError = r.f64();
  h.baseError = r.f64();
  if (r.remaining() < 8 * h.stepCount) r.fail(`${h.stepCount} step times do not fit in HEAD`);
  h.times = new Float64Array(h.stepCount);
  for (let t = 0; t < h.stepCount; t++) h.times[t] = r.f64();
  const keyCount = r.u32();
  if (r.remaining() < 4 * keyCount) r.fail(`${keyCount} key steps do not fit in HEAD`);
  h.keySteps = [];
  for (let i = 0; i < keyCount; i++) h.keySteps.push(r.u32());
  if (r.remaining() < 2 * h.fieldCount) r.fail(`${h.fieldCount} field names do not fit in HEAD`);
  h.fieldNames = [];
  for (let i = 0; i < h.fieldCount; i++) h.fieldNames.push(r.string());
  h.note = r.string();
  return h;
}

function parseBase(r, mesh) {
  const h = mesh.head;
  const b = h.baseVertexCount;
  const nf = h.baseFaceCount;
  if (r.remaining() < 2 * b + 4 * nf) r.fail(`${b} vertices and ${nf} faces do not fit in BASE`);
  parseVertexIds(r, mesh, 0, b);
  const degree = new Uint8Array(nf);
  const corners = new Int32Array(4 * nf).fill(-1);
  for (let f = 0; f < nf; f++) {
    const d = r.u8();
    if (d !== 3 && d !== 4) r.fail(`base face ${f} has degree ${d}`);
    degree[f] = d;
    for (let c = 0; c < d; c++) {
      const v = r.varint();
      if (v >= b) r.fail(`base face ${f}: corner ${v} is not a base vertex (b = ${b})`);
      corners[4 * f + c] = v;
    }
    for (let c = 0; c < d; c++)
      for (let e = c + 1; e < d; e++)
        if (corners[4 * f + c] === corners[4 * f + e]) r.fail(`base face ${f}: corner twice`);
  }
  mesh.baseDegree = degree;
  mesh.baseCorners = corners;
  parseFaceIds(r, mesh, 0, nf);
  parsePositions(r, mesh, 0, b, true);
  parseFields(r, mesh, 0, b);
  mesh.faceCountAt[0] = nf;
  mesh.hasBase = true;
}

function parseVertexIds(r, mesh, first, count) {
  for (let v = first; v < first + count; v++) {
    mesh.vertexOriginal[v] = mesh.lastVertexOriginal += r.svarint();
    mesh.nodeId[v] = mesh.lastNodeId += r.svarint();
  }
}

function parseFaceIds(r, mesh, first, count) {
  for (let f = first; f < first + count; f++) {
    // part_id is absolute; element_id and original_index are deltas (FORMAT.md, and the C++
    // writer: the "delta" note binds to the fields after part_id).
    mesh.partId[f] = r.svarint();
    mesh.elementId[f] = mesh.lastElementId += r.svarint();
    mesh.faceOriginal[f] = mesh.lastFaceOriginal += r.svarint();
  }
}

// Residuals per FORMAT.md "Positions": base vertices against the previous vertex (step 0) and
// their own previous step; split vertices against their parent, in both step and time.
function parsePositions(r, mesh, first, count, isBase) {
  const q = mesh.q;
  const parent = mesh.parent;
  const b = mesh.head.baseVertexCount;
  const end = first + count;
  for (let t = 0; t < q.length; t++) {
    const cur = q[t];
    const prev = t > 0 ? q[t - 1] : null;
    for (let v = first; v < end; v++) {
      const i = 3 * v;
      if (isBase) {
        if (t === 0) {
          const j = i - 3;
          cur[i] = r.svarint() + (v > 0 ? cur[j] : 0);
          cur[i + 1] = r.svarint() + (v > 0 ? cur[j + 1] : 0);
          cur[i + 2] = r.svarint() + (v > 0 ? cur[j + 2] : 0);
        } else {
          cur[i] = r.svarint() + prev[i];
          cur[i + 1] = r.svarint() + prev[i + 1];
          cur[i + 2] = r.svarint() + prev[i + 2];
        }
      } else {
        const j = 3 * parent[v - b];
        if (t === 0) {
          cur[i] = r.svarint() + cur[j];
          cur[i + 1] = r.svarint() + cur[j + 1];
          cur[i + 2] = r.svarint() + cur[j + 2];
        } else {
          // Int32Array stores wrap modulo 2^32, as lossless residual arithmetic requires.
          cur[i] = r.svarint() + prev[i] + cur[j] - prev[j];
          cur[i + 1] = r.svarint() + prev[i + 1] + cur[j + 1] - prev[j + 1];
          cur[i + 2] = r.svarint() + prev[i + 2] + cur[j + 2] - prev[j + 2];
        }
      }
    }
  }
}

function parseFields(r, mesh, first, count) {
  for (const steps of mesh.fields) {
    for (const values of steps) {
      for (let v = first; v < first + count; v++) values[v] = r.f32();
    }
  }
}

function parseSplits(r, mesh) {
  const h = mesh.head;
  const b = h.baseVertexCount;
  const s = r.u32();
  const n = r.u32();
  if (s !== mesh.splitsLoaded) r.fail(`first_split ${s}, expected ${mesh.splitsLoaded}`);
  if (n > h.splitCount - s) r.fail(`${n} splits from ${s} exceed split_count ${h.splitCount}`);
  if (r.remaining() < n * 6) r.fail(`${n} splits do not fit in the chunk`);
  const { parent, error, wingStart, movedStart, faceCountAt } = mesh;
  const { wingFlags, wingVertex, wingFace, moved } = mesh;
  let newFaces = 0;
  for (let i = s; i < s + n; i++) {
    const v0 = b + i;
    let F = faceCountAt[i];
    const pv = r.varint();
    if (pv > v0 - 1) r.fail(`split ${i}: parent ${v0 - 1 - pv} < 0`);
    parent[i] = v0 - 1 - pv;
    error[i] = r.f32();
    const wings = r.u8();
    if (wings > 4) r.fail(`split ${i}: ${wings} wings (at most 4)`);
    wingStart[i] = wingFlags.length;
    let created = 0;
    for (let w = 0; w < wings; w++) {
      const flags = r.u8();
      if (flags & ~0xf) r.fail(`split ${i}: wing flags ${flags}`);
      const wv = r.varint();
      if (wv > v0 - 1) r.fail(`split ${i}: wing vertex ${v0 - 1 - wv} < 0`);
      wingFlags.push(flags);
      wingVertex.push(v0 - 1 - wv);
      if (flags & 1) {
        if ((flags >> 2) > 2) r.fail(`split ${i}: triangle wing with slot ${flags >> 2}`);
        wingFace.push(F + created++);
      } else {
        const fv = r.varint();
        if (fv > F - 1) r.fail(`split ${i}: wing face ${F - 1 - fv} < 0`);
        wingFace.push(F - 1 - fv);
      }
    }
    const movedCount = r.varint();
    if (movedCount > r.remaining()) r.fail(`split ${i}: ${movedCount} moved faces do not fit`);
    movedStart[i] = moved.length;
    for (let k = 0; k < movedCount; k++) {
      const fv = r.varint();
      if (fv > F - 1) r.fail(`split ${i}: moved face ${F - 1 - fv} < 0`);
      moved.push(F - 1 - fv);
    }
    faceCountAt[i + 1] = F + created;
    wingStart[i + 1] = wingFlags.length;
    movedStart[i + 1] = moved.length;
    newFaces += created;
  }
  if (faceCountAt[s + n] > h.faceCount) r.fail(`splits create more faces than F = ${h.faceCount}`);
  if (s + n === h.splitCount && faceCountAt[s + n] !== h.faceCount)
    r.fail(`all splits give ${faceCountAt[s + n]} faces, HEAD says ${h.faceCount}`);
  parseVertexIds(r, mesh, b + s, n);
  parseFaceIds(r, mesh, faceCountAt[s], newFaces);
  parsePositions(r, mesh, b + s, n, false);
  parseFields(r, mesh, b + s, n);
  // Only now: a chunk that fails half-way leaves the loaded levels as they were.
  mesh.splitsLoaded = s + n;
  return n;
}

// Reads a whole .dpm held in memory (Node tests, tools).
export function readDpm(bytes, name = 'file') {
  const decoder = new DpmDecoder({ name });
  decoder.push(bytes instanceof Uint8Array ? bytes : new Uint8Array(bytes));
  if (!decoder.mesh) throw new DpmError(`${name}: ends before HEAD is complete`);
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
  return decoder.mesh;
}

// ---------------------------------------------------------------------------------------------
// Navigator: the mesh at one level

// Holds the current faces (degree, 4 corner slots, −1 in slot 3 of a triangle) for levels up to
// what has been loaded. Changes are recorded as a list of touched faces, which the renderer
// drains (takeDirty) to rewrite just those faces' index entries.
export class Navigator {
  constructor(mesh) {
    if (!mesh.hasBase) throw new DpmError('Navigator needs the BASE chunk');
    this.mesh = mesh;
    const F = mesh.head.faceCount;
    const nf = mesh.head.baseFaceCount;
    // 4 slots per face, −1 in slot 3 of a triangle: the degree is read from the slots, so that a
    // face is one 16-byte record (one cache miss per face a split touches, not two).
    this.corners = new Int32Array(4 * F).fill(-1);
    this.corners.set(mesh.baseCorners);
    this.level = 0;  // splits applied
    this.quads = 0;
    for (let f = 0; f < nf; f++) this.quads += mesh.baseDegree[f] === 4 ? 1 : 0;
    // The touched faces, each once: a mark per face and a list (grown by hand, so that this hot
    // path sees one array type only).
    this.dirtyMark = new Uint8Array(F);
    this.dirtyList = new Uint32Array(1024);
    this.dirtyCount = 0;
    for (let f = 0; f < nf; f++) this.touch(f);
  }

  get vertexCount() {
    return this.mesh.head.baseVertexCount + this.level;
  }
  get faceCount() {
    return this.mesh.faceCountAt[this.level];
  }
  get quadCount() {
    return this.quads;
  }
  get triangleCount() {
    return this.faceCount - this.quads;
  }
  get error() {
    return this.mesh.levelError(this.level);
  }

  touch(f) {
    if (this.dirtyMark[f]) return;
    this.dirtyMark[f] = 1;
    if (this.dirtyCount === this.dirtyList.length) {
      const bigger = new Uint32Array(2 * this.dirtyList.length);
      bigger.set(this.dirtyList);
      this.dirtyList = bigger;
    }
    this.dirtyList[this.dirtyCount++] = f;
  }

  // The faces changed since the last call (may include faces now beyond faceCount).
  takeDirty() {
    const list = this.dirtyList.subarray(0, this.dirtyCount);
    for (let i = 0; i < list.length; i++) this.dirtyMark[list[i]] = 0;
    this.dirtyCount = 0;
    return list;
  }

  // Any level in [0, splitsLoaded]; returns the level reached.
  setLevel(k) {
    k = Math.max(0, Math.min(k, this.mesh.splitsLoaded));
    if (k > this.level) this.refine(k);
    else if (k < this.level) this.coarsen(k);
    return this.level;
  }
  setVertexCount(n) {
    return this.setLevel(n - this.mesh.head.baseVertexCount);
  }

  // The coarsest loaded level whose error is ≤ e (errors never increase along the stream).
  levelForError(e) {
    const { mesh } = this;
    if (mesh.head.baseError <= e) return 0;
    let lo = 0, hi = mesh.splitsLoaded;  // search the first split i with error[i] ≤ e
    while (lo < hi) {
      const mid = (lo + hi) >> 1;
      if (mesh.error[mid] <= e) hi = mid;
      else lo = mid + 1;
    }
    return Math.min(lo + 1, mesh.splitsLoaded);
  }

  // Applies splits [level, k) (FORMAT.md "Applying a split"): split i re-creates v0 = b + i from
  // its parent v1. One loop with every array in a local: this is the full-refine hot path.
  refine(k = this.level + 1) {
    const { mesh, corners, dirtyMark } = this;
    const b = mesh.head.baseVertexCount;
    const { parent, movedStart, wingStart } = mesh;
    const moved = mesh.moved.data;
    const wingFlags = mesh.wingFlags.data;
    const wingVertex = mesh.wingVertex.data;
    const wingFace = mesh.wingFace.data;
    let quads = this.quads;
    for (let i = this.level; i < k; i++) {
      const v0 = b + i;
      const v1 = parent[i];
      // 1. Moved faces: the corner holding v1 takes v0.
      for (let j = movedStart[i], end = movedStart[i + 1]; j < end; j++) {
        const f = moved[j];
        const c = 4 * f;
        const d = corners[c + 3] < 0 ? 3 : 4;
        let slot = 0;
        while (slot < d && corners[c + slot] !== v1) slot++;
        if (slot === d) this.fail(i, `moved face ${f} does not hold v1 = ${v1}`);
        corners[c + slot] = v0;
        if (!dirtyMark[f]) this.touch(f);
      }
      for (let j = wingStart[i], end = wingStart[i + 1]; j < end; j++) {
        const flags = wingFlags[j];
        const w = wingVertex[j];
        const f = wingFace[j];
        const s = (flags >> 2) & 3;
        const c = 4 * f;
        if (flags & 1) {
          // 2. Triangle wing: a new face with v0 at slot s.
          const v1follows = (flags & 2) !== 0;
          corners[c + s] = v0;
          corners[c + ((s + 1) % 3)] = v1follows ? v1 : w;
          corners[c + ((s + 2) % 3)] = v1follows ? w : v1;
          corners[c + 3] = -1;
        } else {
          // 3. Quad wing: v0 goes in at slot s, the corners from s on move up.
          if (corners[c + 3] >= 0) this.fail(i, `quad wing face ${f} is not a triangle`);
          for (let j2 = 3; j2 > s; j2--) corners[c + j2] = corners[c + j2 - 1];
          corners[c + s] = v0;
          quads++;
        }
        if (!dirtyMark[f]) this.touch(f);
      }
      // The reader's check that records keep every face's corners distinct (FORMAT.md "What a
      // reader checks"), on the faces this split changed.
      for (let j = movedStart[i], end = movedStart[i + 1]; j < end; j++) this.checkDistinct(i, moved[j]);
      for (let j = wingStart[i], end = wingStart[i + 1]; j < end; j++) this.checkDistinct(i, wingFace[j]);
    }
    this.quads = quads;
    this.level = k;
  }

  // Undoes splits [k, level) from the last: each is the collapse v0 → v1.
  coarsen(k = this.level - 1) {
    const { mesh, corners, dirtyMark } = this;
    const b = mesh.head.baseVertexCount;
    const { parent, movedStart, wingStart } = mesh;
    const moved = mesh.moved.data;
    const wingFlags = mesh.wingFlags.data;
    const wingFace = mesh.wingFace.data;
    let quads = this.quads;
    for (let i = this.level - 1; i >= k; i--) {
      const v0 = b + i;
      const v1 = parent[i];
      for (let j = wingStart[i + 1] - 1; j >= wingStart[i]; j--) {
        const f = wingFace[j];
        const flags = wingFlags[j];
        if (flags & 1) {
          corners[4 * f + 3] = -1;  // removed: beyond faceCount now
        } else {
          const s = (flags >> 2) & 3;
          const c = 4 * f;
          if (corners[c + 3] < 0 || corners[c + s] !== v0)
            this.fail(i, `quad wing face ${f} does not hold v0 at slot ${s}`);
          for (let j2 = s; j2 < 3; j2++) corners[c + j2] = corners[c + j2 + 1];
          corners[c + 3] = -1;
          quads--;
        }
        if (!dirtyMark[f]) this.touch(f);
      }
      for (let j = movedStart[i], end = movedStart[i + 1]; j < end; j++) {
        const f = moved[j];
        const c = 4 * f;
        const d = corners[c + 3] < 0 ? 3 : 4;
        let slot = 0;
        while (slot < d && corners[c + slot] !== v0) slot++;
        if (slot === d) this.fail(i, `moved face ${f} does not hold v0 = ${v0}`);
        corners[c + slot] = v1;
        if (!dirtyMark[f]) this.touch(f);
      }
    }
    this.quads = quads;
    this.level = k;
  }

  checkDistinct(i, f) {
    const k = this.corners;
    const c = 4 * f;
    const a = k[c], b = k[c + 1], d = k[c + 2], x = k[c + 3];  // x = −1 for a triangle
    if (a === b || a === d || b === d || a === x || b === x || d === x)
      this.fail(i, `face ${f} has a corner twice`);
  }

  fail(i, cause) {
    throw new DpmError(`split ${i}: ${cause}`);
  }

  // Face f's corners at this level (for tests and exports).
  face(f) {
    return Array.from(this.corners.subarray(4 * f, 4 * f + this.degree(f)));
  }

  degree(f) {
    return this.corners[4 * f + 3] < 0 ? 3 : 4;
  }
}

// Index entries for face f: two triangles (6 entries; a triangle's second one degenerate) and
// four element edges (8 entries; a triangle repeats its last edge). Fixed slots per face mean a
// change of level rewrites only the faces it touched, and drawing `faceCount` faces is a prefix.
export function writeFaceIndices(nav, f, tri, edges) {
  const k = nav.corners;
  const c = 4 * f;
  const a = k[c], b = k[c + 1], d = k[c + 2];
  const t = 6 * f;
  const e = 8 * f;
  tri[t] = a, tri[t + 1] = b, tri[t + 2] = d;
  edges[e] = a, edges[e + 1] = b, edges[e + 2] = b, edges[e + 3] = d;
  const x = k[c + 3];
  if (x >= 0) {
    tri[t + 3] = a, tri[t + 4] = d, tri[t + 5] = x;
    edges[e + 4] = d, edges[e + 5] = x, edges[e + 6] = x, edges[e + 7] = a;
  } else {
    tri[t + 3] = a, tri[t + 4] = a, tri[t + 5] = a;
    edges[e + 4] = d, edges[e + 5] = a, edges[e + 6] = d, edges[e + 7] = a;
  }
}

// Rewrites the index entries of the faces changed since the last call; returns the range of
// faces [lo, hi) that changed, for partial buffer uploads.
export function updateIndices(nav, tri, edges) {
  const dirty = nav.takeDirty();
  const F = nav.faceCount;
  let lo = Infinity, hi = 0;
  for (let i = 0; i < dirty.length; i++) {
    const f = dirty[i];
    if (f >= F) continue;
    writeFaceIndices(nav, f, tri, edges);
    if (f < lo) lo = f;
    if (f + 1 > hi) hi = f + 1;
  }
  return lo < hi ? [lo, hi] : null;
}
