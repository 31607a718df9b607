// CalculiX .frd results, what the scan (frd_scan.cpp) and the step reader (frd.cpp) share: the
// file read in chunks, the fixed-column fields of its ASCII records, and the layout one scan
// finds (the mesh, and where each result block starts). frd.cpp describes the format.
#pragma once

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "formats.h"

namespace dynpm::io::frd {

// ---------------------------------------------------------------------------------------------
// Reading a file in chunks: lines for the ASCII records, raw bytes for the binary ones.

class ChunkReader {
 public:
  static constexpr size_t kChunk = size_t{1} << 20;

  ChunkReader() = default;
  ChunkReader(const ChunkReader&) = delete;
  ChunkReader& operator=(const ChunkReader&) = delete;
  ~ChunkReader() {
    if (file_) std::fclose(file_);
  }

  Status open(const std::string& path) {
    file_ = std::fopen(path.c_str(), "rb");
    if (!file_) return Status::error(path + ": cannot open (" + std::strerror(errno) + ")");
    if (::fseeko(file_, 0, SEEK_END) != 0)
      return Status::error(path + ": cannot seek (not a regular file?)");
    size_ = static_cast<uint64_t>(::ftello(file_));
    seek(0, 1);
    return {};
  }

  uint64_t size() const { return size_; }
  uint64_t offset() const { return base_ + begin_; }  // of the next unread byte
  uint64_t line() const { return line_; }             // number of the next line
  uint64_t left() const { return size_ - offset(); }

  void seek(uint64_t offset, uint64_t line) {
    ::fseeko(file_, static_cast<off_t>(offset), SEEK_SET);
    base_ = offset;
    begin_ = end_ = 0;
    eof_ = false;
    line_ = line;
  }

  // The next line without its "\n" or "\r\n"; false at the end of the file. A line longer than
  // kChunk comes back cut (no FRD record is that long; the caller reports it as malformed).
  bool next_line(std::string_view& out) {
    while (true) {
      const char* start = buf_.data() + begin_;
      const size_t have = end_ - begin_;
      const void* nl = std::memchr(start, '\n', have);
      size_t length = 0, used = 0;
      if (nl) {
        length = static_cast<size_t>(static_cast<const char*>(nl) - start);
        used = length + 1;
      } else if (have >= kChunk || (eof_ && have > 0)) {
        length = used = std::min(have, kChunk);
      } else if (eof_) {
        return false;
      } else {
        refill();
        continue;
      }
      if (length > 0 && start[length - 1] == '\r') --length;
      out = std::string_view(start, length);
      begin_ += used;
      ++line_;
      return true;
    }
  }

  // Copies the next n raw bytes; false if the file ends first.
  bool read(char* out, size_t n) {
    while (n > 0) {
      if (begin_ == end_) {
        if (eof_) return false;
        refill();
        continue;
      }
      const size_t take = std::min(n, end_ - begin_);
      std::memcpy(out, buf_.data() + begin_, take);
      begin_ += take, out += take, n -= take;
    }
    return true;
  }

  // Skips n raw bytes (binary records); false if the file ends first.
  bool skip(uint64_t n) {
    if (n > left()) return false;
    if (n <= end_ - begin_) {
      begin_ += n;
    } else {
      const uint64_t line = line_;
      seek(offset() + n, line);
    }
    return true;
  }

 private:
  void refill() {
    if (begin_ > 0) {
      std::memmove(buf_.data(), buf_.data() + begin_, end_ - begin_);
      base_ += begin_;
      end_ -= begin_;
      begin_ = 0;
    }
    // At most what the file has left: a reader opened per step of a small file zero-filled a
    // whole chunk each time (most of fuzz_frd's time went to that memset).
    const size_t want = static_cast<size_t>(std::min<uint64_t>(kChunk, size_ - (base_ + end_)));
    if (buf_.size() < end_ + want) buf_.resize(end_ + want);
    const size_t n = want == 0 ? 0 : std::fread(buf_.data() + end_, 1, want, file_);
    end_ += n;
    if (n == 0) eof_ = true;
  }

  std::FILE* file_ = nullptr;
  uint64_t size_ = 0;
  std::string buf_;
  uint64_t base_ = 0;  // file offset of buf_[0]
  size_t begin_ = 0, end_ = 0;
  bool eof_ = false;
  uint64_t line_ = 1;
};

// ---------------------------------------------------------------------------------------------
// Fixed-column fields

inline std::string_view columns(std::string_view line, size_t a, size_t b) {
  if (a >= line.size()) return {};
  return line.substr(a, std::min(b, line.size()) - a);
}

inline std::optional<int64_t> to_int(std::string_view s) {
  s = trim_blanks(s);
  if (!s.empty() && s.size() <= 18) {  // the common case: plain digits
    int64_t v = 0;
    size_t i = s[0] == '-' ? 1 : 0;
    if (i < s.size()) {
      for (; i < s.size() && s[i] >= '0' && s[i] <= '9'; ++i) v = v * 10 + (s[i] - '0');
      if (i == s.size()) return s[0] == '-' ? -v : v;
    }
  }
  // Within ±2^62, so that differences of node numbers cannot overflow.
  int64_t v = 0;
  if (parse_integer(s, -(int64_t(1) << 62), int64_t(1) << 62, v) != NumberError::kNone)
    return std::nullopt;
  return v;
}

// Exactly representable powers of ten: a mantissa of up to 15 digits times or over one of them
// rounds once, so the result is the correctly rounded value std::from_chars would give.
inline constexpr double kPow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                    1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                    1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

// ccx's E12.5 ("-1.23456E+01"), parsed without the general algorithm; nullopt if s has
// another form.
inline std::optional<double> fast_real(std::string_view s) {
  size_t i = 0;
  const bool negative = i < s.size() && s[i] == '-';
  if (negative || (i < s.size() && s[i] == '+')) ++i;
  uint64_t mantissa = 0;
  int digits = 0, fraction = 0;
  for (; i < s.size() && s[i] >= '0' && s[i] <= '9'; ++i, ++digits)
    mantissa = mantissa * 10 + uint64_t(s[i] - '0');
  if (i < s.size() && s[i] == '.')
    for (++i; i < s.size() && s[i] >= '0' && s[i] <= '9'; ++i, ++digits, ++fraction)
      mantissa = mantissa * 10 + uint64_t(s[i] - '0');
  if (digits == 0 || digits > 15) return std::nullopt;
  int exponent = 0;
  if (i < s.size() && (s[i] == 'E' || s[i] == 'e')) {
    ++i;
    const bool minus = i < s.size() && s[i] == '-';
    if (minus || (i < s.size() && s[i] == '+')) ++i;
    int e = 0, n = 0;
    for (; i < s.size() && s[i] >= '0' && s[i] <= '9' && n < 4; ++i, ++n) e = e * 10 + (s[i] - '0');
    if (n == 0) return std::nullopt;
    exponent = minus ? -e : e;
  }
  if (i != s.size()) return std::nullopt;
  const int scale = exponent - fraction;
  if (scale < -22 || scale > 22) return std::nullopt;
  double v = double(mantissa);
  v = scale < 0 ? v / kPow10[-scale] : v * kPow10[scale];
  return negative ? -v : v;
}

inline std::optional<double> to_real(std::string_view s) {
  s = trim_blanks(s);
  if (s.empty()) return std::nullopt;
  if (auto v = fast_real(s)) return v;
  double v = 0;  // the rule of every text reader (text.h): 1E+39 is inf, as in OBJ
  if (parse_real(s, v) != NumberError::kNone) return std::nullopt;
  return v;
}

// The record key of a data line: " -1", " -2", " -3", …
inline int record_key(std::string_view line) {
  if (line.size() < 3 || line[0] != ' ' || line[1] != '-' || line[2] < '0' || line[2] > '9')
    return 0;
  return line[2] - '0';
}

template <class T>
T from_native(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) {
    // ccx writes its binary records in the byte order of the machine that ran it: in practice
    // little-endian (x86-64, AArch64).
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    std::reverse(b, b + sizeof(T));
    std::memcpy(&v, b, sizeof(T));
  }
  return v;
}

// ---------------------------------------------------------------------------------------------
// The file's layout, found by one scan

enum class BlockKind { kDisp, kStress, kScalar };

// One 100C block: where its data records start and how to read them.
struct ResultBlock {
  uint64_t data_offset = 0;  // first data record
  uint64_t data_line = 0;
  int format = 0;           // 0 short, 1 long ASCII; 2 binary float, 3 binary double
  uint32_t values = 0;      // values stored per node (components minus the computed ones)
  uint64_t node_count = 0;  // NUMNOD of the header (0: not given, ASCII only)
  BlockKind kind = BlockKind::kScalar;
  size_t field = 0;         // index into field_names for kStress / kScalar
  int64_t step_number = 0;  // NUMSTP
  std::string value_text;   // VALUE as written: with NUMSTP, the key that pairs blocks
  double time = 0;
};

struct NodeRecord {
  int64_t id = 0;
  double xyz[3] = {0, 0, 0};
};

struct ElementRecord {
  int64_t id = 0;
  int32_t part = 0;
  uint8_t corners = 0;
  int64_t nodes[4] = {0, 0, 0, 0};
  uint64_t place = 0;
};

// What one scan of the file finds: the mesh's records, and the result blocks it keeps.
struct Layout {
  bool ended = false;  // the ' 9999' record that ends a file CalculiX has finished
  std::vector<NodeRecord> nodes;
  std::vector<ElementRecord> elements;  // the shells; solids and beams are only counted
  std::vector<ResultBlock> blocks;
  std::vector<std::string> field_names;
  std::set<std::string> ignored_blocks;  // names of the blocks not kept
  size_t skipped_elements = 0, quadratic_elements = 0;
  bool binary = false;  // binary records appeared: places are bytes, not lines
};

// Reads the header blocks, the node block (2C) and the element block (3C), and indexes the result
// blocks (100C) by where their data start, skipping the data: one pass over the file.
Result<Layout> scan(const std::string& path);

}  // namespace dynpm::io::frd
