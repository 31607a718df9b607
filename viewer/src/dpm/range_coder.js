// The .dpm's entropy decoder (docs/FORMAT.md "Range coding"), bit for bit as the C++ one in
// src/progressive/range_coder.h: a binary range decoder with adaptive bit probabilities and an
// adaptive Exp-Golomb code for integers. Numbers, not 32-bit operators, wherever a value can
// reach 2^32 (code and range are unsigned 32-bit quantities).

const PROB_BITS = 12;
const PROB_ONE = 1 << PROB_BITS;
const ADAPT_SHIFT = 5;
const TOP = 1 << 24;
export const MAX_MAGNITUDE_BITS = 53;
const SLOTS = 25;

// Adaptive probabilities that a bit is 0, in units of 1/4096, several in one typed array.
export function bitModels(count) {
  return new Uint16Array(count).fill(PROB_ONE >> 1);
}

export class RangeDecoder {
  // bytes: a Uint8Array holding exactly one coded section.
  constructor(bytes) {
    this.bytes = bytes;
    this.pos = 0;
    this.overrun = 0;
    this.tooLarge = false;
    this.badStart = this.next() !== 0;  // the encoder's first byte is always 0
    this.code = 0;
    for (let k = 0; k < 4; k++) this.code = this.code * 256 + this.next();
    this.range = 0xffffffff;
  }
  next() {
    if (this.pos < this.bytes.length) return this.bytes[this.pos++];
    this.overrun++;
    return 0;
  }
  // One bit with the model at models[i].
  bit(models, i) {
    const p = models[i];
    const bound = (this.range >>> PROB_BITS) * p;
    let b;
    if (this.code < bound) {
      this.range = bound;
      models[i] = p + ((PROB_ONE - p) >> ADAPT_SHIFT);
      b = 0;
    } else {
      this.code -= bound;
      this.range -= bound;
      models[i] = p - (p >> ADAPT_SHIFT);
      b = 1;
    }
    while (this.range < TOP) {
      this.range *= 256;
      this.code = this.code * 256 + this.next();
    }
    return b;
  }
  // count bits of equal probability, the highest first (count ≤ 52: the value stays exact).
  direct(count) {
    let v = 0;
    for (let k = 0; k < count; k++) {
      this.range = Math.floor(this.range / 2);
      let b = 0;
      if (this.code >= this.range) {
        this.code -= this.range;
        b = 1;
      }
      v = v * 2 + b;
      while (this.range < TOP) {
        this.range *= 256;
        this.code = this.code * 256 + this.next();
      }
    }
    return v;
  }
  ok() {
    return !this.badStart && this.overrun === 0 && !this.tooLarge;
  }
  exhausted() {
    return this.pos === this.bytes.length;
  }
}

// An unsigned integer u < 2^53 − 1 (C++ UnsignedModel): n = u + 1, the position k of n's
// leading 1 in unary, the two bits below it with models per k, the rest direct.
export class UnsignedModel {
  constructor() {
    this.length = bitModels(SLOTS);
    this.high = bitModels(SLOTS * 3);
  }
  decode(d) {
    let k = 0;
    while (k < MAX_MAGNITUDE_BITS && d.bit(this.length, Math.min(k, SLOTS - 1)) === 1) k++;
    if (k >= MAX_MAGNITUDE_BITS) {
      d.tooLarge = true;
      return 0;
    }
    let n = 1;
    let left = k;
    const top = Math.min(k, SLOTS - 1) * 3;
    let node = 0;
    for (let j = 0; j < 2 && left > 0; j++) {
      const b = d.bit(this.high, top + node);
      n = n * 2 + b;
      node = 1 + b;
      left--;
    }
    n = n * 2 ** left + d.direct(left);
    return n - 1;
  }
}

// A signed integer |v| < 2^53 − 1 (C++ SignedModel): zero bit, sign bit, |v| − 1.
export class SignedModel {
  constructor() {
    this.bits = bitModels(2);  // [0]: zero, [1]: sign
    this.magnitude = new UnsignedModel();
  }
  decode(d) {
    if (d.bit(this.bits, 0) === 0) return 0;
    const negative = d.bit(this.bits, 1) === 1;
    const m = this.magnitude.decode(d) + 1;
    return negative ? -m : m;
  }
}
