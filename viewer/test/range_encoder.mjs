// A range encoder for tests that write .dpm files by hand (docs/FORMAT.md "Range coding"): the
// C++ RangeEncoder (src/progressive/range_coder.h) in JS, coding with the decoder's own model
// objects (src/dpm/range_coder.js), so that a test's models and the decoder's start alike.
const TOP = 2 ** 24;

export class RangeEncoder {
  constructor() {
    this.low = 0;  // up to 33 bits: a Number, not 32-bit operators
    this.range = 0xffffffff;
    this.cache = 0;
    this.pending = 1;
    this.out = [];
  }
  bit(models, i, b) {
    const p = models[i];
    const bound = (this.range >>> 12) * p;
    if (b === 0) {
      this.range = bound;
      models[i] = p + ((4096 - p) >> 5);
    } else {
      this.low += bound;
      this.range -= bound;
      models[i] = p - (p >> 5);
    }
    this.normalize();
  }
  direct(value, count) {
    for (let k = count - 1; k >= 0; k--) {
      this.range = Math.floor(this.range / 2);
      if (Math.floor(value / 2 ** k) % 2) this.low += this.range;
      this.normalize();
    }
  }
  normalize() {
    while (this.range < TOP) {
      this.range *= 256;
      this.shiftLow();
    }
  }
  shiftLow() {
    if (this.low % 2 ** 32 < 0xff000000 || this.low >= 2 ** 32) {
      const carry = this.low >= 2 ** 32 ? 1 : 0;
      let byte = this.cache;
      do {
        this.out.push((byte + carry) & 0xff);
        byte = 0xff;
      } while (--this.pending !== 0);
      this.cache = Math.floor(this.low / TOP) & 0xff;
    }
    this.pending++;
    this.low = (this.low % TOP) * 256;
  }
  finish() {
    for (let k = 0; k < 5; k++) this.shiftLow();
    return Uint8Array.from(this.out);
  }
}

// u with an UnsignedModel (FORMAT.md: n = u + 1, its length in unary, two modelled bits, the rest
// direct).
export function encodeUnsigned(e, model, u) {
  const n = u + 1;
  let k = 0;  // the position of n's leading 1 (not Math.log2: it rounds 2^52 − 1 up to 52)
  while (2 ** (k + 1) <= n) k++;
  for (let i = 0; i < k; i++) e.bit(model.length, Math.min(i, 24), 1);
  e.bit(model.length, Math.min(k, 24), 0);
  let left = k;
  let node = 0;
  for (let j = 0; j < 2 && left > 0; j++) {
    const b = Math.floor(n / 2 ** (left - 1)) % 2;
    e.bit(model.high, Math.min(k, 24) * 3 + node, b);
    node = 1 + b;
    left--;
  }
  e.direct(n % 2 ** left, left);
}

export function encodeSigned(e, model, v) {
  e.bit(model.bits, 0, v === 0 ? 0 : 1);
  if (v === 0) return;
  e.bit(model.bits, 1, v < 0 ? 1 : 0);
  encodeUnsigned(e, model.magnitude, Math.abs(v) - 1);
}
