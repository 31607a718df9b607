// The .dpm's entropy decoder (docs/FORMAT.md "Range coding"), bit for bit as the C++ one in
// src/progressive/range_coder.h: a binary range decoder with adaptive bit probabilities and an
// adaptive Exp-Golomb code for integers.
//
// Speed: code and range are unsigned 32-bit quantities kept as int32 bit patterns (`| 0`) and
// compared as unsigned (`>>> 0`), so that V8 keeps them in machine words (a Number field above
// 2^31 would be a boxed double); bounds come from Math.imul. Integers are decoded in int32
// arithmetic up to 2^30 and in Numbers beyond (values up to 2^53 − 2).

const PROB_BITS = 12;
const PROB_ONE = 1 << PROB_BITS;
const ADAPT_SHIFT = 5;
export const MAX_MAGNITUDE_BITS = 53;
const SLOTS = 25;
// An UnsignedModel's probabilities in one array: the unary length's SLOTS, then 3 per slot for
// the two bits below the leading 1. A SignedModel's: zero, sign, then its magnitude's.
const UNSIGNED_LENGTH = 0;
const UNSIGNED_HIGH = SLOTS;
export const UNSIGNED_MODEL_SIZE = SLOTS + 3 * SLOTS;
export const SIGNED_MODEL_SIZE = 2 + UNSIGNED_MODEL_SIZE;

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
    this.code = 0;  // int32 bit pattern of the unsigned code
    this.range = -1;  // int32 bit pattern of 0xffffffff
    this.badStart = this.next() !== 0;  // the encoder's first byte is always 0
    for (let k = 0; k < 4; k++) this.code = (this.code << 8) | this.next();
  }
  next() {
    if (this.pos < this.bytes.length) return this.bytes[this.pos++];
    this.overrun++;
    return 0;
  }
  // One bit with the model at models[i]. Without a branch on the bit (it is as often
  // unpredictable as not): b is 0 or 1 and mask is −b.
  bit(models, i) {
    const p = models[i];
    const range = this.range;
    const bound = Math.imul(range >>> PROB_BITS, p);
    const b = (this.code >>> 0 >= bound >>> 0) | 0;
    const mask = -b;
    this.code = (this.code - (bound & mask)) | 0;
    let r = (bound + ((range - bound - bound) & mask)) | 0;  // 0: bound, 1: range − bound
    models[i] = p + (((PROB_ONE - p) >> ADAPT_SHIFT) & ~mask) - ((p >> ADAPT_SHIFT) & mask);
    // range < 2^24: shift a byte in (at most twice: a bound is ≥ 2^12 · 31).
    while (r >>> 24 === 0) {
      r <<= 8;
      this.code = (this.code << 8) | this.next();
    }
    this.range = r;
    return b;
  }
  // count bits of equal probability, the highest first (count ≤ 52: the value stays exact).
  direct(count) {
    if (count > 30) {
      const high = this.directInt(count - 30);
      return high * 2 ** 30 + this.directInt(30);
    }
    return this.directInt(count);
  }
  // count ≤ 30 bits: an int32.
  directInt(count) {
    let v = 0;
    for (let k = 0; k < count; k++) {
      const r = this.range >>> 1;  // ≥ 2^23: one byte shifts it back above 2^24
      const b = (this.code >>> 0 >= r) | 0;
      this.code = (this.code - (r & -b)) | 0;
      v = (v << 1) | b;
      if (r >>> 24 === 0) {
        this.range = r << 8;
        this.code = (this.code << 8) | this.next();
      } else {
        this.range = r;
      }
    }
    return v;
  }
  // decodeUnsigned(): the integers' hot path, the coder's state in locals (fields written back
  // once), each bit as bit() decodes it.
  unsigned(models, at) {
    const bytes = this.bytes;
    const end = bytes.length;
    let code = this.code, range = this.range, pos = this.pos;
    // n = u + 1; k, the position of its leading 1, in unary (bit j with the model of slot
    // min(j, SLOTS − 1)), then the two bits below the leading 1 with the slot's models: the
    // first's, then the one the first bit picks. One loop, one modelled bit a turn.
    let k = 0;
    let n = 1;
    let highs = -1;  // modelled bits still to read below the leading 1; −1 while in unary
    let top = 0;
    let model = at + UNSIGNED_LENGTH;
    for (;;) {
      const p = models[model];
      const bound = Math.imul(range >>> PROB_BITS, p);
      const b = (code >>> 0 >= bound >>> 0) | 0;
      const mask = -b;
      code = (code - (bound & mask)) | 0;
      range = (bound + ((range - bound - bound) & mask)) | 0;
      models[model] = p + (((PROB_ONE - p) >> ADAPT_SHIFT) & ~mask) - ((p >> ADAPT_SHIFT) & mask);
      while (range >>> 24 === 0) {
        range <<= 8;
        code = (code << 8) | (pos < end ? bytes[pos] : 0);
        pos++;
      }
      if (highs < 0) {
        if (b === 1) {
          if (++k === MAX_MAGNITUDE_BITS) break;
          model += (k < SLOTS) | 0;
          continue;
        }
        highs = k < 2 ? k : 2;
        top = at + UNSIGNED_HIGH + 3 * (k < SLOTS - 1 ? k : SLOTS - 1);
        model = top;
      } else {
        n = (n << 1) | b;
        model = top + 1 + b;
        highs--;
      }
      if (highs === 0) break;
    }
    const tooLarge = k === MAX_MAGNITUDE_BITS;  // 2^53 − 1 and beyond: JS numbers cannot hold it
    let left = tooLarge ? 0 : k - (k < 2 ? k : 2);
    // The rest as direct bits (up to 28 in int32 here; longer ones through direct()).
    for (; left > 0 && k <= 30; left--) {
      const r = range >>> 1;  // ≥ 2^23: one byte shifts it back above 2^24
      const b = (code >>> 0 >= r) | 0;
      code = (code - (r & -b)) | 0;
      n = (n << 1) | b;
      range = r;
      if (r >>> 24 === 0) {
        range = r << 8;
        code = (code << 8) | (pos < end ? bytes[pos] : 0);
        pos++;
      }
    }
    if (pos > end) {
      this.overrun += pos - end;
      pos = end;
    }
    this.code = code, this.range = range, this.pos = pos;
    if (tooLarge) {
      this.tooLarge = true;
      return 0;
    }
    if (left > 0) return n * 2 ** left + this.direct(left) - 1;
    return n - 1;
  }
  ok() {
    return !this.badStart && this.overrun === 0 && !this.tooLarge;
  }
  exhausted() {
    return this.pos === this.bytes.length;
  }
}

// An unsigned integer u < 2^53 − 1 (C++ UnsignedModel) whose probabilities are
// models[at, at + UNSIGNED_MODEL_SIZE): n = u + 1, the position k of n's leading 1 in unary, the
// two bits below it with models per k, the rest direct.
export function decodeUnsigned(d, models, at) {
  return d.unsigned(models, at);
}

// A signed integer |v| < 2^53 − 1 (C++ SignedModel) with models[at, at + SIGNED_MODEL_SIZE):
// zero bit, sign bit, |v| − 1.
export function decodeSigned(d, models, at) {
  if (d.bit(models, at) === 0) return 0;
  const negative = -d.bit(models, at + 1);  // −1 or 0
  const m = d.unsigned(models, at + 2) + 1;
  return m <= 0x3fffffff ? (m ^ negative) - negative : negative ? -m : m;
}

// One UnsignedModel, as an object (tests; a decoder with many models keeps them in one array).
export class UnsignedModel {
  constructor(models = bitModels(UNSIGNED_MODEL_SIZE), at = 0) {
    this.models = models;
    this.at = at;
    this.length = models.subarray(at + UNSIGNED_LENGTH, at + UNSIGNED_HIGH);
    this.high = models.subarray(at + UNSIGNED_HIGH, at + UNSIGNED_MODEL_SIZE);
  }
  decode(d) {
    return decodeUnsigned(d, this.models, this.at);
  }
}

// One SignedModel: bits [0] zero, [1] sign, then the magnitude's UnsignedModel.
export class SignedModel {
  constructor(models = bitModels(SIGNED_MODEL_SIZE), at = 0) {
    this.models = models;
    this.at = at;
    this.bits = models.subarray(at, at + 2);
    this.magnitude = new UnsignedModel(models, at + 2);
  }
  decode(d) {
    return decodeSigned(d, this.models, this.at);
  }
}
