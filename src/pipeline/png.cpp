// PNG (ISO/IEC 15948) and the zlib/deflate stream it holds (RFC 1950, RFC 1951): png.h.
#include "png.h"

#include <array>
#include <vector>

#include "progressive/dpm_format.h"  // crc32, the one of the .dpm chunks: PNG's is the same

namespace dynpm::pipeline {
namespace {

constexpr std::array<uint16_t, 29> kLengthBase = {3,  4,  5,  6,   7,   8,   9,   10,  11, 13,
                                                  15, 17, 19, 23,  27,  31,  35,  43,  51, 59,
                                                  67, 83, 99, 115, 131, 163, 195, 227, 258};
constexpr std::array<uint8_t, 29> kLengthExtra = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2,
                                                  2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
constexpr std::array<uint16_t, 30> kDistanceBase = {
    1,   2,   3,   4,   5,   7,    9,    13,   17,   25,   33,   49,   65,    97,    129,
    193, 257, 385, 513, 769, 1025, 1537, 2049, 3073, 4097, 6145, 8193, 12289, 16385, 24577};
constexpr std::array<uint8_t, 30> kDistanceExtra = {0, 0, 0,  0,  1,  1,  2,  2,  3,  3,
                                                    4, 4, 5,  5,  6,  6,  7,  7,  8,  8,
                                                    9, 9, 10, 10, 11, 11, 12, 12, 13, 13};
constexpr size_t kWindow = 32768;
constexpr size_t kMinMatch = 3, kMaxMatch = 258;
constexpr int kChainSteps = 32;  // candidates tried per position
constexpr int kHashBits = 15;

// Deflate's bit order: values least significant bit first, Huffman codes most significant first.
class BitWriter {
 public:
  std::string bytes;
  void bits(uint32_t value, int count) {
    for (int i = 0; i < count; ++i) bit((value >> i) & 1);
  }
  void code(uint32_t code, int length) {
    for (int i = length - 1; i >= 0; --i) bit((code >> i) & 1);
  }
  void flush() {
    if (used_) bytes.push_back(static_cast<char>(acc_)), acc_ = 0, used_ = 0;
  }

 private:
  void bit(uint32_t b) {
    acc_ |= b << used_;
    if (++used_ == 8) flush();
  }
  uint32_t acc_ = 0;
  int used_ = 0;
};

// The fixed literal/length code (RFC 1951, 3.2.6).
void literal_length(BitWriter& w, uint32_t symbol) {
  if (symbol < 144)
    w.code(0x30 + symbol, 8);
  else if (symbol < 256)
    w.code(0x190 + symbol - 144, 9);
  else if (symbol < 280)
    w.code(symbol - 256, 7);
  else
    w.code(0xc0 + symbol - 280, 8);
}

void match(BitWriter& w, size_t length, size_t distance) {
  size_t l = kLengthBase.size() - 1;
  while (kLengthBase[l] > length) --l;
  literal_length(w, static_cast<uint32_t>(257 + l));
  w.bits(static_cast<uint32_t>(length - kLengthBase[l]), kLengthExtra[l]);
  size_t d = kDistanceBase.size() - 1;
  while (kDistanceBase[d] > distance) --d;
  w.code(static_cast<uint32_t>(d), 5);
  w.bits(static_cast<uint32_t>(distance - kDistanceBase[d]), kDistanceExtra[d]);
}

uint32_t adler32(std::span<const uint8_t> bytes) {
  uint32_t a = 1, b = 0;
  for (uint8_t c : bytes) a = (a + c) % 65521, b = (b + a) % 65521;
  return (b << 16) | a;
}

void put_be32(std::string& out, uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<char>(v >> shift));
}

void put_png_chunk(std::string& out, std::string_view type, std::string_view data) {
  put_be32(out, static_cast<uint32_t>(data.size()));
  const size_t typed = out.size();
  out.append(type);
  out.append(data);
  put_be32(out, progressive::crc32(std::string_view(out).substr(typed)));
}

}  // namespace

std::string zlib_compress(std::span<const uint8_t> in) {
  BitWriter w;
  w.bytes = "\x78\x01";  // deflate, 32 KiB window, no dictionary; a multiple of 31
  w.bits(1, 1);          // the last block
  w.bits(1, 2);          // fixed Huffman codes
  std::vector<int64_t> head(size_t{1} << kHashBits, -1), previous(in.size(), -1);
  auto hash = [&](size_t i) {
    return ((uint32_t{in[i]} << 10) ^ (uint32_t{in[i + 1]} << 5) ^ in[i + 2]) &
           ((1u << kHashBits) - 1);
  };
  auto insert = [&](size_t i) {
    if (i + kMinMatch > in.size()) return;
    const uint32_t h = hash(i);
    previous[i] = head[h];
    head[h] = static_cast<int64_t>(i);
  };
  for (size_t i = 0; i < in.size();) {
    size_t best = 0, best_distance = 0;
    if (i + kMinMatch <= in.size()) {
      int64_t candidate = head[hash(i)];
      const size_t limit = std::min(kMaxMatch, in.size() - i);
      for (int step = 0;
           step < kChainSteps && candidate >= 0 && i - static_cast<size_t>(candidate) <= kWindow;
           ++step, candidate = previous[static_cast<size_t>(candidate)]) {
        const size_t c = static_cast<size_t>(candidate);
        size_t n = 0;
        while (n < limit && in[c + n] == in[i + n]) ++n;
        if (n > best) best = n, best_distance = i - c;
        if (n == limit) break;
      }
    }
    if (best >= kMinMatch) {
      match(w, best, best_distance);
      for (size_t k = 0; k < best; ++k) insert(i + k);
      i += best;
    } else {
      literal_length(w, in[i]);
      insert(i);
      ++i;
    }
  }
  literal_length(w, 256);  // end of block
  w.flush();
  put_be32(w.bytes, adler32(in));
  return std::move(w.bytes);
}

std::string encode_png(std::span<const uint8_t> rgb, uint32_t width, uint32_t height) {
  // Each row after a filter byte: 1 (Sub, the difference to the pixel on the left), which turns
  // a flat colour into zeros whatever the colour.
  const size_t stride = size_t{width} * 3;
  std::vector<uint8_t> rows;
  rows.reserve((stride + 1) * height);
  for (uint32_t y = 0; y < height; ++y) {
    rows.push_back(1);
    const uint8_t* row = rgb.data() + y * stride;
    for (size_t x = 0; x < stride; ++x)
      rows.push_back(static_cast<uint8_t>(row[x] - (x >= 3 ? row[x - 3] : 0)));
  }
  std::string header;
  put_be32(header, width);
  put_be32(header, height);
  header +=
      std::string("\x08\x02\x00\x00\x00", 5);  // 8 bits, RGB, deflate, filters 0, no interlace
  std::string png("\x89PNG\r\n\x1a\n", 8);
  put_png_chunk(png, "IHDR", header);
  put_png_chunk(png, "IDAT", zlib_compress(rows));
  put_png_chunk(png, "IEND", {});
  return png;
}

}  // namespace dynpm::pipeline
