// Little-endian byte streams with LEB128 varints and zigzag signed varints (docs/FORMAT.md).
// The reader never reads past its end: every read checks, and the first failure sticks, so a
// decoder can read a whole section and test ok() once.
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

namespace dynpm::progressive {

class ByteWriter {
 public:
  std::string bytes;

  template <typename T>
  void put(T value) {  // fixed-size little-endian (the host is little-endian; see the assert)
    static_assert(std::endian::native == std::endian::little);
    bytes.append(reinterpret_cast<const char*>(&value), sizeof value);
  }
  void varint(uint64_t v) {
    while (v >= 0x80) {
      bytes.push_back(static_cast<char>((v & 0x7f) | 0x80));
      v >>= 7;
    }
    bytes.push_back(static_cast<char>(v));
  }
  void svarint(int64_t v) {
    varint((static_cast<uint64_t>(v) << 1) ^ static_cast<uint64_t>(v >> 63));
  }
  void text(std::string_view s) {
    put(static_cast<uint16_t>(s.size()));
    bytes.append(s);
  }
};

class ByteReader {
 public:
  explicit ByteReader(std::string_view bytes) : bytes_(bytes) {}

  bool ok() const { return ok_; }
  size_t offset() const { return pos_; }
  size_t remaining() const { return bytes_.size() - pos_; }
  // A count of items of at least min_bytes each is plausible only if the rest can hold them.
  bool can_hold(uint64_t count, size_t min_bytes) {
    if (count > remaining() / (min_bytes ? min_bytes : 1)) ok_ = false;
    return ok_;
  }

  template <typename T>
  T get() {
    T value{};
    if (!ok_ || remaining() < sizeof value) {
      ok_ = false;
      return value;
    }
    std::memcpy(&value, bytes_.data() + pos_, sizeof value);
    pos_ += sizeof value;
    return value;
  }
  uint64_t varint() {
    uint64_t v = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      if (!ok_ || pos_ >= bytes_.size()) break;
      const uint8_t byte = static_cast<uint8_t>(bytes_[pos_++]);
      v |= uint64_t{byte & 0x7fu} << shift;
      if ((byte & 0x80) == 0) return v;
    }
    ok_ = false;
    return 0;
  }
  int64_t svarint() {
    const uint64_t u = varint();
    return static_cast<int64_t>((u >> 1) ^ (~(u & 1) + 1));
  }
  // The next n bytes as they are.
  std::string_view bytes(size_t n) {
    if (!ok_ || remaining() < n) {
      ok_ = false;
      return {};
    }
    pos_ += n;
    return bytes_.substr(pos_ - n, n);
  }
  std::string text() {
    const uint16_t n = get<uint16_t>();
    return std::string(bytes(n));
  }

 private:
  std::string_view bytes_;
  size_t pos_ = 0;
  bool ok_ = true;
};

}  // namespace dynpm::progressive
