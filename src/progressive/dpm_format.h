// The .dpm file's pieces shared by its writer (dpm_write.cpp) and its reader (dpm_read.cpp):
// docs/FORMAT.md is the specification. Internal to dynpm_progressive.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

#include "dynpm/progressive.h"

namespace dynpm::progressive {

inline constexpr std::string_view kMagic{
    "\x89"
    "DPM\r\n\x1a\n",
    8};
inline constexpr uint32_t kVersion = 7;
inline constexpr size_t kChunkHeaderSize = 24;
// Bound on a chunk's stored and decompressed sizes (a corrupt header cannot ask for more).
inline constexpr uint64_t kMaxRawChunk = uint64_t{1} << 31;
// zstd's densest block is an RLE block: 4 bytes (header and the byte) for at most 128 KiB, so no
// frame decompresses to more than 32768 times its size.
inline constexpr uint64_t kMaxZstdRatio = 32768;
// The longest varint the reader takes (ByteReader::varint: 64 bits, 7 per byte).
inline constexpr double kMaxVarint = 10;
// A bound on the bytes of one range-coded integer (FORMAT.md "Range coding": about 110 bits at
// most), loose so that it stays a bound whatever the models learned.
inline constexpr double kMaxCodedInteger = 64;

// CRC-32 (IEEE 802.3, as zlib and PNG): eight bytes a step through eight tables ("slicing by
// 8", as the JavaScript decoder's viewer/src/dpm/bytes.js), 7 ms for 16 MB where a byte a step
// took 38.
inline uint32_t crc32(std::string_view bytes) {
  using Tables = std::array<std::array<uint32_t, 256>, 8>;
  static const Tables tables = [] {
    Tables t{};
    for (uint32_t i = 0; i < 256; ++i) {
      uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xedb88320u ^ (c >> 1) : c >> 1;
      t[0][i] = c;
    }
    for (uint32_t i = 0; i < 256; ++i)  // t[k][i]: byte i followed by k zero bytes
      for (size_t k = 1; k < 8; ++k) t[k][i] = t[0][t[k - 1][i] & 0xff] ^ (t[k - 1][i] >> 8);
    return t;
  }();
  uint32_t c = 0xffffffffu;
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
  size_t n = bytes.size();
  for (; n >= 8; p += 8, n -= 8) {  // the bytes taken in order: no dependence on endianness
    const uint32_t lo =
        c ^ (uint32_t{p[0]} | uint32_t{p[1]} << 8 | uint32_t{p[2]} << 16 | uint32_t{p[3]} << 24);
    c = tables[7][lo & 0xff] ^ tables[6][(lo >> 8) & 0xff] ^ tables[5][(lo >> 16) & 0xff] ^
        tables[4][lo >> 24] ^ tables[3][p[4]] ^ tables[2][p[5]] ^ tables[1][p[6]] ^ tables[0][p[7]];
  }
  for (; n > 0; ++p, --n) c = tables[0][(c ^ *p) & 0xff] ^ (c >> 8);
  return c ^ 0xffffffffu;
}

// Appends a chunk (docs/FORMAT.md "Chunk"): its header and payload, zstd-compressed when
// `compress` is set and the frame is smaller (dpm_write.cpp).
void put_chunk(std::string& out, std::string_view tag, std::string_view raw, bool compress);
// A chunk's header (docs/FORMAT.md "Chunk") into the kChunkHeaderSize bytes at `at`: the tag,
// then flags (1: zstd), stored size, raw size, CRC-32 of the stored bytes and 0, little-endian.
inline void write_chunk_header(char* at, std::string_view tag, bool compressed, size_t stored,
                               size_t raw, uint32_t crc) {
  static_assert(std::endian::native == std::endian::little);
  const uint32_t fields[5] = {compressed ? 1u : 0u, static_cast<uint32_t>(stored),
                              static_cast<uint32_t>(raw), crc, 0};
  std::memcpy(at, tag.data(), 4);
  std::memcpy(at + 4, fields, sizeof fields);
}
// Appends an uncompressed chunk whose payload `write(out)` appends after the header, so that a
// large payload is written once, in place, not assembled apart and copied in.
template <class Write>
void put_chunk_in_place(std::string& out, std::string_view tag, Write&& write) {
  const size_t header = out.size();
  out.append(kChunkHeaderSize, '\0');
  write(out);
  const std::string_view payload = std::string_view(out).substr(header + kChunkHeaderSize);
  write_chunk_header(out.data() + header, tag, false, payload.size(), payload.size(),
                     crc32(payload));
}

// The THMB chunk's tag (docs/FORMAT.md "Thumbnail: THMB"): the last chunk before END.
inline constexpr std::string_view kThumbnailTag = "THMB";

// The chunk tags this version knows.
inline bool is_known_tag(std::string_view tag) {
  return tag == "HEAD" || tag == "FDEF" || tag == "PART" || tag == "VARI" || tag == "BASE" ||
         tag == "FLDS" || tag == "SPLT" || tag == "END ";
}
// An optional chunk a reader may skip has four characters from A–Z, 0–9 and space.
inline bool is_optional_tag(std::string_view tag) {
  for (char c : tag)
    if (!((c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == ' ')) return false;
  return true;
}

// Residual arithmetic: plain integers on a grid, modulo 2^32 on float bits (lossless).
inline int64_t wrap_add(int64_t prediction, int64_t residual, bool lossless) {
  const uint64_t sum = static_cast<uint64_t>(prediction) + static_cast<uint64_t>(residual);
  return lossless ? static_cast<int64_t>(static_cast<uint32_t>(sum)) : static_cast<int64_t>(sum);
}
inline int64_t wrap_residual(int64_t value, int64_t prediction, bool lossless) {
  const uint64_t diff = static_cast<uint64_t>(value) - static_cast<uint64_t>(prediction);
  return lossless ? static_cast<int32_t>(static_cast<uint32_t>(diff)) : static_cast<int64_t>(diff);
}

// A lossless residual is a signed 32-bit value (FORMAT.md "Positions"); a reader refuses one
// outside, so that every reader wraps the same sum (a JavaScript number is exact below 2^53 only,
// and a varint holds 64 bits).
inline constexpr const char* kLosslessResidual = "a lossless residual outside 32 bits";
inline bool residual_fits(int64_t residual, bool lossless) {
  return !lossless || (residual >= INT32_MIN && residual <= INT32_MAX);
}

// ⌊a / b⌋ for b > 0 (C++ division truncates toward zero).
inline int64_t floor_div(int64_t a, int64_t b) { return a / b - ((a % b != 0) && (a < 0)); }

// ⌊(2 · sum + count) / (2 · count)⌋: the mean rounded half up.
inline int64_t rounded_mean(int64_t sum, int64_t count) {
  return floor_div(2 * sum + count, 2 * count);
}

// The context of a range-coded residual of a position or a field value (FORMAT.md "Positions"):
// how large the same item's residual was at the step before, 0 … kResidualBuckets − 1.
inline constexpr int kResidualBuckets = 5;
inline int residual_bucket(int64_t residual) {
  const uint64_t m = residual < 0 ? -static_cast<uint64_t>(residual) : residual;
  return std::min(static_cast<int>(std::bit_width(m)), kResidualBuckets - 1);
}

// Position q-values (docs/FORMAT.md "Positions"): grid integers, or float bits when lossless.
struct Grid {
  std::array<double, 3> origin;
  double step;
  bool lossless;

  int64_t q(float p, int c) const {
    if (lossless) return std::bit_cast<uint32_t>(p);
    return std::llround((p - origin[c]) / step);
  }
  // The grid index nearest p, half to even: the point quantize_step() puts p on (q() of that
  // point gives it back: a float lies within a quarter step of it, the grid being 4 ulps wide).
  int64_t nearest(float p, int c) const {
    return static_cast<int64_t>(std::nearbyint((p - origin[c]) / step));
  }
  float p(int64_t q, int c) const {
    if (lossless) return std::bit_cast<float>(static_cast<uint32_t>(q));
    return static_cast<float>(origin[c] + static_cast<double>(q) * step);
  }
  // Residual → value, wrapping modulo 2^32 when lossless.
  int64_t add(int64_t prediction, int64_t residual) const {
    return wrap_add(prediction, residual, lossless);
  }
  int64_t residual(int64_t value, int64_t prediction) const {
    return wrap_residual(value, prediction, lossless);
  }
};

inline Grid grid_of(const ProgressiveMesh& mesh) {
  return {mesh.bbox_min, mesh.quant_step, mesh.lossless};
}

// The prediction of base vertex v's coordinate at step t from values already known (FORMAT.md
// "Positions", in BASE), q(u, s) giving vertex u's q-value at step s; split vertices are coded
// in position_coding.cpp. A base vertex's (face's) field value follows the same rule ("Fields").
template <class Q>
int64_t predict_base(uint32_t v, size_t t, Q q) {
  if (t > 0) return q(v, t - 1);
  return v > 0 ? q(v - 1, 0) : 0;
}

// A result field's q-values (docs/FORMAT.md "Fields: FDEF and FLDS"): integers on the field's
// grid from its min, or float bits when lossless.
struct FieldGrid {
  double min;
  double step;
  bool lossless;

  explicit FieldGrid(const ProgressiveField& f)
      : min(f.min), step(f.quant_step), lossless(f.lossless) {}
  int64_t q(float x) const {
    if (lossless) return std::bit_cast<uint32_t>(x);
    return std::llround((x - min) / step);
  }
  float value(int64_t q) const {
    if (lossless) return std::bit_cast<float>(static_cast<uint32_t>(q));
    return static_cast<float>(min + static_cast<double>(q) * step);
  }
  int64_t add(int64_t prediction, int64_t residual) const {
    return wrap_add(prediction, residual, lossless);
  }
  int64_t residual(int64_t value, int64_t prediction) const {
    return wrap_residual(value, prediction, lossless);
  }
};

// Heirs are in the file only when some field is per element.
inline bool has_element_field(const ProgressiveMesh& mesh) {
  for (const ProgressiveField& f : mesh.fields)
    if (f.info.location == FieldLocation::kElement) return true;
  return false;
}

// Node and element ids lie strictly within ±2^51 (FORMAT.md "BASE payload"): exact as
// JavaScript numbers, also through a split's sum of a guess, an index step and a residual, and no
// int64 sum of them overflows. A BASE delta (an id's or an original index's) lies strictly within
// ±2^52: any two valid ids differ by less, and its zigzag fits the 53 bits a number holds exactly.
inline constexpr int64_t kIdLimit = int64_t{1} << 51;
inline constexpr const char* kIdOutOfRange = "an id is not within ±2^51";
inline bool id_fits(int64_t id) { return id > -kIdLimit && id < kIdLimit; }
// value += delta, for a BASE delta: false when the delta or the sum is out of range (the sum
// must lie in [low, end)); value is then meaningless, the file refused.
inline bool add_base_delta(int64_t& value, int64_t delta, int64_t low = 1 - kIdLimit,
                           int64_t end = kIdLimit) {
  if (delta <= -2 * kIdLimit || delta >= 2 * kIdLimit) return false;
  value += delta;  // |value| < 2^51 before: no overflow
  return value >= low && value < end;
}

// Attribute deltas continue across chunks (docs/FORMAT.md).
struct Deltas {
  int64_t vertex_index = 0, node_id = 0, element_id = 0, face_index = 0;
};

}  // namespace dynpm::progressive
