// Bytes of a .dpm (docs/FORMAT.md "Conventions"): CRC-32, a bounds-checked reader of one chunk's
// payload with LEB128 varints and zigzag svarints, and a typed array that grows. The C++ side:
// src/progressive/bytes.h.

export class DpmError extends Error {}

// Slicing by 8 (8 tables: table k advances a byte's CRC by k more zero bytes), 8 bytes a step.
let crcTables = null;
export function crc32(bytes) {
  if (!crcTables) {
    crcTables = new Int32Array(8 * 256);
    for (let n = 0; n < 256; n++) {
      let c = n;
      for (let k = 0; k < 8; k++) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
      crcTables[n] = c;
    }
    for (let n = 0; n < 7 * 256; n++)
      crcTables[n + 256] = crcTables[crcTables[n] & 0xff] ^ (crcTables[n] >>> 8);
  }
  const t = crcTables;
  let c = -1;
  let i = 0;
  for (const end = bytes.length - 7; i < end; i += 8) {
    const a = c ^ (bytes[i] | (bytes[i + 1] << 8) | (bytes[i + 2] << 16) | (bytes[i + 3] << 24));
    c = t[1792 + (a & 0xff)] ^ t[1536 + ((a >>> 8) & 0xff)] ^ t[1280 + ((a >>> 16) & 0xff)] ^
      t[1024 + (a >>> 24)] ^ t[768 + bytes[i + 4]] ^ t[512 + bytes[i + 5]] ^ t[256 + bytes[i + 6]] ^
      t[bytes[i + 7]];
  }
  for (; i < bytes.length; i++) c = t[(c ^ bytes[i]) & 0xff] ^ (c >>> 8);
  return (c ^ -1) >>> 0;
}

// Reads one chunk payload; every read checks the end, so a short payload is an error with the
// byte where it happened, never a read past the end.
export class Reader {
  constructor(bytes, at, where) {
    this.bytes = bytes;
    this.view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    this.pos = 0;
    this.end = bytes.length;
    this.at = at;  // "file: byte N", N where the payload starts in the file
    this.where = where;  // (payload offset) → "TAG payload byte K" text
  }
  // An error at the payload's byte K.
  fail(cause) {
    throw new DpmError(`${this.at}: ${this.where(this.pos)}: ${cause}`);
  }
  // An error of the payload as a whole (a record that does not fit the faces).
  failChunk(cause) {
    throw new DpmError(`${this.at}: ${cause}`);
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
  i32() {
    this.need(4);
    const v = this.view.getInt32(this.pos, true);
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

// `array` when it holds `length` elements, else a copy of it with room for them (twice its length,
// so that growing level by level copies each element a few times at most, but never more than
// `max`; just `length` when not `doubling`), its new elements `fill`, on a SharedArrayBuffer when
// `array` is on one. Arrays that multiply by the steps grow so as the levels arrive: a page that
// fetches 100 k of 5 M vertices holds every step's positions of the 100 k, not of the 5 M. They
// stay plain fixed-length arrays: V8 reads arrays on resizable or growable buffers 1.2×
// (resizable) to 3.3× (growable, shared) slower in the decoder's loops (measured in Chromium 156,
// 2026-12-06).
export function withRoom(array, length, max, fill = 0, doubling = true) {
  if (array.length >= length) return array;
  const n = Math.min(max, doubling ? Math.max(length, 2 * array.length) : length);
  const bytes = n * array.BYTES_PER_ELEMENT;
  const shared = typeof SharedArrayBuffer !== 'undefined' && array.buffer instanceof SharedArrayBuffer;
  const out = new array.constructor(shared ? new SharedArrayBuffer(bytes) : n);
  out.set(array);
  if (fill) out.fill(fill, array.length);
  return out;
}

// A typed array that grows by doubling (split records whose total is only known at the end).
export class Growable {
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
