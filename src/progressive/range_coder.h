// The .dpm's entropy coder (docs/FORMAT.md "Range coding"): a binary range coder with adaptive
// bit probabilities (the LZMA kind) and an adaptive Exp-Golomb code for integers on top. The
// browser's decoder is viewer/src/dpm/range_coder.js; both follow the spec bit for bit.
//
// Why not zstd alone: residuals and split records are small integers whose distribution is
// skewed but not repetitive; an adaptive binary code prices each bit by its learned probability,
// where zstd over varints pays whole bytes for sign and length.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <string>
#include <string_view>

namespace dynpm::progressive {

inline constexpr int kProbBits = 12;          // a probability is p / 4096 that the bit is 0
inline constexpr int kAdaptShift = 5;         // each bit moves p by 1/32 of the way
inline constexpr int kMaxMagnitudeBits = 53;  // integers below 2^53 − 1 (exact in JS numbers)

// An adaptive probability that the next bit is 0.
struct BitModel {
  uint16_t p = 1 << (kProbBits - 1);
};

// p after a bit: moved 1/32 of the way toward certainty of that bit (`one`: all ones for a 1, 0
// for a 0; both moves are made and one is selected).
inline uint32_t adapted(uint32_t p, uint32_t one) {
  const uint32_t up = p + (((1u << kProbBits) - p) >> kAdaptShift), down = p - (p >> kAdaptShift);
  return up ^ ((up ^ down) & one);
}

class RangeEncoder {
 public:
  // Without a branch on the bit: whether a residual is zero is as good as random to the branch
  // predictor; both moves made and one selected coded 30 M residuals 15–20 % faster.
  void bit(BitModel& m, int b) {
    const uint32_t p = m.p, bound = (range_ >> kProbBits) * p;
    const uint32_t one = 0u - static_cast<uint32_t>(b);  // all ones for a 1
    low_ += bound & one;
    range_ = bound ^ ((bound ^ (range_ - bound)) & one);
    m.p = static_cast<uint16_t>(adapted(p, one));
    normalize();
  }
  // Bits of equal probability, the highest first (no model: they do not repeat).
  void direct(uint64_t value, int count) {
    for (int k = count - 1; k >= 0; --k) {
      range_ >>= 1;
      if ((value >> k) & 1) low_ += range_;
      normalize();
    }
  }
  // The coded bytes; the encoder is done after this.
  std::string finish() {
    for (int k = 0; k < 5; ++k) shift_low();
    return std::move(out_);
  }

 private:
  void normalize() {
    while (range_ < (1u << 24)) {
      range_ <<= 8;
      shift_low();
    }
  }
  // Emits the top byte of low_, holding back 0xFF bytes until a carry is known.
  void shift_low() {
    if (static_cast<uint32_t>(low_) < 0xFF000000u || (low_ >> 32) != 0) {
      const auto carry = static_cast<uint8_t>(low_ >> 32);
      uint8_t byte = cache_;
      do {
        out_.push_back(static_cast<char>(static_cast<uint8_t>(byte + carry)));
        byte = 0xFF;
      } while (--pending_ != 0);
      cache_ = static_cast<uint8_t>(low_ >> 24);
    }
    ++pending_;
    low_ = (low_ & 0x00FFFFFFu) << 8;
  }

  uint64_t low_ = 0;
  uint32_t range_ = 0xFFFFFFFFu;
  uint8_t cache_ = 0;
  uint64_t pending_ = 1;
  std::string out_;
};

// Decodes one section. Reading past its end yields zero bytes and marks the section as cut
// short; the caller checks ok() (and exhausted()) once at the end, as with ByteReader.
class RangeDecoder {
 public:
  explicit RangeDecoder(std::string_view bytes) : bytes_(bytes) {
    if (next() != 0) bad_start_ = true;  // the encoder's first byte is always 0
    for (int k = 0; k < 4; ++k) code_ = (code_ << 8) | next();
  }
  // With a branch, unlike RangeEncoder::bit(): the next bit's model depends on this one, and a
  // predicted branch lets the decoder run ahead where selects would wait (measured no faster).
  int bit(BitModel& m) {
    const uint32_t bound = (range_ >> kProbBits) * m.p;
    int b;
    if (code_ < bound) {
      range_ = bound;
      m.p = static_cast<uint16_t>(m.p + (((1u << kProbBits) - m.p) >> kAdaptShift));
      b = 0;
    } else {
      code_ -= bound;
      range_ -= bound;
      m.p = static_cast<uint16_t>(m.p - (m.p >> kAdaptShift));
      b = 1;
    }
    normalize();
    return b;
  }
  uint64_t direct(int count) {
    uint64_t v = 0;
    for (int k = 0; k < count; ++k) {
      range_ >>= 1;
      const int b = code_ >= range_ ? 1 : 0;
      if (b) code_ -= range_;
      v = (v << 1) | static_cast<uint64_t>(b);
      normalize();
    }
    return v;
  }
  // False once a read went past the section's end or the section does not start as coded ones
  // do, or a number was too large.
  bool ok() const { return !bad_start_ && overrun_ == 0 && !too_large_; }
  // The coder read exactly the section's bytes (a section with bytes left over is refused).
  bool exhausted() const { return pos_ == bytes_.size(); }
  bool too_large() const { return too_large_; }
  void set_too_large() { too_large_ = true; }

 private:
  uint8_t next() {
    if (pos_ < bytes_.size()) return static_cast<uint8_t>(bytes_[pos_++]);
    ++overrun_;
    return 0;
  }
  void normalize() {
    while (range_ < (1u << 24)) {
      range_ <<= 8;
      code_ = (code_ << 8) | next();
    }
  }

  std::string_view bytes_;
  size_t pos_ = 0;
  uint32_t code_ = 0;
  uint32_t range_ = 0xFFFFFFFFu;
  uint32_t overrun_ = 0;
  bool bad_start_ = false;
  bool too_large_ = false;
};

// An adaptive Exp-Golomb code for an unsigned integer u < 2^53 − 1: with n = u + 1 and k = the
// position of n's leading 1, k in unary (bit i of the unary code has its own model, the last
// shared from 24 on), then the two bits below the leading 1 with models per k and the rest of
// n's bits as direct bits. Small values cost a bit or two once their models have learned.
class UnsignedModel {
 public:
  void encode(RangeEncoder& e, uint64_t u) {
    const uint64_t n = u + 1;
    const int k = std::bit_width(n) - 1;
    for (int i = 0; i < k; ++i) e.bit(length_[slot(i)], 1);
    e.bit(length_[slot(k)], 0);  // k < 53: the caller's values are below 2^53 − 1
    int left = k;
    BitModel* top = high_[slot(k)].data();
    int node = 0;
    for (int j = 0; j < 2 && left > 0; ++j) {
      const int b = static_cast<int>((n >> (left - 1)) & 1);
      e.bit(top[node], b);
      node = 1 + b;
      --left;
    }
    e.direct(n & ((uint64_t{1} << left) - 1), left);
  }
  uint64_t decode(RangeDecoder& d) {
    int k = 0;
    while (k < kMaxMagnitudeBits && d.bit(length_[slot(k)]) == 1) ++k;
    if (k >= kMaxMagnitudeBits) {  // 2^53 − 1 and beyond: refused, as JS numbers cannot hold it
      d.set_too_large();
      return 0;
    }
    uint64_t n = 1;
    int left = k;
    BitModel* top = high_[slot(k)].data();
    int node = 0;
    for (int j = 0; j < 2 && left > 0; ++j) {
      const int b = d.bit(top[node]);
      n = (n << 1) | static_cast<uint64_t>(b);
      node = 1 + b;
      --left;
    }
    n = (n << left) | d.direct(left);
    return n - 1;
  }

 private:
  static int slot(int i) { return std::min(i, kSlots - 1); }
  static constexpr int kSlots = 25;
  std::array<BitModel, kSlots> length_{};
  std::array<std::array<BitModel, 3>, kSlots> high_{};
};

// A signed integer |v| < 2^53 − 1: a zero bit, a sign bit, then |v| − 1 as an UnsignedModel.
class SignedModel {
 public:
  void encode(RangeEncoder& e, int64_t v) {
    e.bit(zero_, v == 0 ? 0 : 1);
    if (v == 0) return;
    e.bit(sign_, v < 0 ? 1 : 0);
    magnitude_.encode(e, (v < 0 ? -static_cast<uint64_t>(v) : static_cast<uint64_t>(v)) - 1);
  }
  int64_t decode(RangeDecoder& d) {
    if (d.bit(zero_) == 0) return 0;
    const bool negative = d.bit(sign_) == 1;
    const auto m = static_cast<int64_t>(magnitude_.decode(d) + 1);
    return negative ? -m : m;
  }

 private:
  BitModel zero_, sign_;
  UnsignedModel magnitude_;
};

}  // namespace dynpm::progressive
