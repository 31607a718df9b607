// CalculiX .frd results ("Result Format" in the cgx manual): a node block (2C), an element block
// (3C) and nodal result blocks (100C), each either ASCII fixed-column records or, when the
// block header's format flag says so, raw native-endian binary records without the closing
// " -3" line (what ccx writes for *NODE OUTPUT / *ELEMENT OUTPUT).
//
// open_frd() reads the mesh and scans the rest of the file once, keeping only where each DISP
// block (and each result-field block) starts; read_step(t) / read_field() seek there and parse
// that one block, so a result much larger than memory can be streamed.
//
//   step 0        the undeformed node coordinates, time 0 (as our OBJ sequences' frame_000)
//   step k ≥ 1    coordinates + the k-th DISP block, time = the block's 100C value
//   fields        STRESS → "S_MISES" (von Mises), PE → "PEEQ", any other one-component block
//                 by its name; zeros at step 0 and where a step has no such block
#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <set>

#include "formats.h"

namespace dynpm::io {
namespace {

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
    if (buf_.size() < end_ + kChunk) buf_.resize(end_ + kChunk);
    const size_t n = std::fread(buf_.data() + end_, 1, kChunk, file_);
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

std::string_view columns(std::string_view line, size_t a, size_t b) {
  if (a >= line.size()) return {};
  return line.substr(a, std::min(b, line.size()) - a);
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

std::optional<int64_t> to_int(std::string_view s) {
  s = trim(s);
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
constexpr double kPow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                             1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

// ccx's E12.5 ("-1.23456E+01"), parsed without the general algorithm; nullopt if s has
// another form.
std::optional<double> fast_real(std::string_view s) {
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

std::optional<double> to_real(std::string_view s) {
  s = trim(s);
  if (s.empty()) return std::nullopt;
  if (auto v = fast_real(s)) return v;
  double v = 0;  // the rule of every text reader (text.h): 1E+39 is inf, as in OBJ
  if (parse_real(s, v) != NumberError::kNone) return std::nullopt;
  return v;
}

// The record key of a data line: " -1", " -2", " -3", …
int record_key(std::string_view line) {
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

// frd element types (cgx manual, "Element Types"): node count and what dynpm makes of it.
struct ElementType {
  int nodes = 0;
  int corners = 0;  // 3 or 4 for shells, 0 for solids and beams (skipped)
  bool quadratic = false;
};

std::optional<ElementType> element_type(int64_t type) {
  switch (type) {
    case 1: return ElementType{8, 0, false};   // he8  (C3D8)
    case 2: return ElementType{6, 0, false};   // pe6  (C3D6)
    case 3: return ElementType{4, 0, false};   // te4  (C3D4)
    case 4: return ElementType{20, 0, false};  // he20 (C3D20, and shells expanded by ccx)
    case 5: return ElementType{15, 0, false};  // pe15 (C3D15)
    case 6: return ElementType{10, 0, false};  // te10 (C3D10)
    case 7: return ElementType{3, 3, false};   // tr3  (S3)
    case 8: return ElementType{6, 3, true};    // tr6  (S6), corners first
    case 9: return ElementType{4, 4, false};   // qu4  (S4, S4R)
    case 10: return ElementType{8, 4, true};   // qu8  (S8, S8R), corners first
    case 11: return ElementType{2, 0, false};  // be2  (B31)
    case 12: return ElementType{3, 0, false};  // be3  (B32)
    default: return std::nullopt;
  }
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

struct Step {
  double time = 0;
  ResultBlock disp;
  std::vector<int64_t> field_block;  // per field, index into FrdLayout::blocks or -1
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

class FrdScanner {
 public:
  explicit FrdScanner(const std::string& path) : path_(path) {}

  Status scan() {
    DYNPM_RETURN_IF_ERROR(reader_.open(path_));
    char magic[2] = {0, 0};
    if (reader_.size() >= 2 && reader_.read(magic, 2) && magic[0] == '\x1f' && magic[1] == '\x8b')
      return Status::error(path_ + ": is gzip-compressed; gunzip it first");
    reader_.seek(0, 1);

    std::string_view line;
    while (!ended && next(line)) {
      if (trim(line).empty()) continue;
      const auto key = to_int(columns(line, 0, 5));
      const char code = line.size() > 5 ? line[5] : ' ';
      if (!key) return fail("not a CalculiX .frd record (expected a block key such as '    2C')");
      if (*key == 9999) {
        ended = true;
      } else if (*key == 1) {
        continue;  // 1C model header, 1U user header, 1P parameter lines
      } else if (*key == 2 && code == 'C') {
        if (saw_nodes_) return fail("a second node block (2C); one mesh per file is supported");
        saw_nodes_ = true;
        DYNPM_RETURN_IF_ERROR(read_nodes(line));
      } else if (*key == 3 && code == 'C') {
        if (saw_elements_)
          return fail("a second element block (3C); one mesh per file is supported");
        saw_elements_ = true;
        DYNPM_RETURN_IF_ERROR(read_elements(line));
      } else if (*key == 100 && code == 'C') {
        if (!saw_nodes_) return fail("a result block (100C) before the node block (2C)");
        DYNPM_RETURN_IF_ERROR(scan_result(line));
      } else {
        return fail("unexpected record outside any block");
      }
    }
    if (!saw_nodes_)
      return Status::error(path_ + ": no node block (2C); is this a CalculiX .frd file?");
    if (!saw_elements_) return Status::error(path_ + ": no element block (3C)");
    return {};
  }

  bool ended = false;  // the ' 9999' record that ends a file CalculiX has finished
  std::vector<NodeRecord> nodes;
  std::vector<ElementRecord> elements;
  std::vector<ResultBlock> blocks;
  std::vector<std::string> field_names;
  std::set<std::string> ignored_blocks;
  size_t skipped_elements = 0, quadratic_elements = 0;
  bool binary = false;

 private:
  bool next(std::string_view& line) {
    line_offset_ = reader_.offset();
    return reader_.next_line(line);
  }
  // "path:line" while the file is all text; "path: byte N" once binary records have appeared,
  // since line numbers mean nothing after them.
  std::string where() const {
    if (binary) return path_ + ": byte " + std::to_string(line_offset_);
    return path_ + ":" + std::to_string(reader_.line() - 1);
  }
  Status fail(const std::string& cause) const { return Status::error(where() + ": " + cause); }
  Status fail_at_byte(uint64_t offset, const std::string& cause) const {
    return Status::error(path_ + ": byte " + std::to_string(offset) + ": " + cause);
  }
  // Placed where the file ends: after its last line, or at its size once binary records have
  // appeared.
  Status truncated(const std::string& what) const {
    std::string end = binary ? ": byte " : ":";  // appended, not "literal" + string: gcc 12
    end += binary ? std::to_string(reader_.size()) : std::to_string(reader_.line() - 1);
    return Status::error(path_ + end + ": the file ends inside " + what + " (truncated?)");
  }

  // Format flag and record count of a 2C / 3C header: (1X,'   2','C',18X,I12,37X,I1).
  Status block_header(std::string_view line, const char* what, int max_format, int& format,
                      uint64_t& count) {
    const auto n = to_int(columns(line, 24, 36));
    const auto f = to_int(columns(line, 36, line.size()));
    if (!n && !trim(columns(line, 24, 36)).empty())
      return fail(std::string("the record count of the ") + what + " header, " +
                  quoted_bytes(trim(columns(line, 24, 36))) + ", is not a whole number");
    if (n && *n < 0) return fail(std::string("negative record count in the ") + what + " header");
    count = n ? static_cast<uint64_t>(*n) : 0;
    if (!f && line.size() > 36)
      return fail(std::string("cannot read the format flag of the ") + what + " header");
    if (f && (*f < 0 || *f > max_format))
      return fail("unknown format flag " + std::to_string(*f) + " in the " + what + " header");
    format = f ? static_cast<int>(*f) : 0;
    return {};
  }

  // A count from a header must fit in the bytes left, each record taking at least min_bytes.
  Status check_count(uint64_t count, uint64_t min_bytes, const char* what) const {
    if (count > reader_.left() / min_bytes)
      return fail("the header announces " + std::to_string(count) + " " + what + ", more than " +
                  std::to_string(reader_.left()) + " bytes left in the file can hold");
    return {};
  }

  Status read_nodes(std::string_view header) {
    int format = 0;
    uint64_t count = 0;
    DYNPM_RETURN_IF_ERROR(block_header(header, "node block (2C)", 3, format, count));
    if (format >= 2) {
      binary = true;
      const size_t real = format == 2 ? 4 : 8;
      const size_t record = 4 + 3 * real;
      DYNPM_RETURN_IF_ERROR(check_count(count, record, "nodes"));
      nodes.resize(count);
      char b[28];
      for (NodeRecord& node : nodes) {
        if (!reader_.read(b, record)) return truncated("the node block");
        node.id = from_native<int32_t>(b);
        for (int k = 0; k < 3; ++k)
          node.xyz[k] =
              real == 4 ? from_native<float>(b + 4 + 4 * k) : from_native<double>(b + 4 + 8 * k);
      }
      return {};
    }
    const size_t width = format == 1 ? 10 : 5;
    DYNPM_RETURN_IF_ERROR(check_count(count, 3 + width + 36, "nodes"));
    nodes.reserve(count);
    std::string_view line;
    while (true) {
      if (!next(line)) return truncated("the node block (no ' -3' line)");
      const int key = record_key(line);
      if (key == 3) break;
      if (key != 1) return fail("expected a ' -1' node record or the ' -3' end of the node block");
      NodeRecord node;
      const auto id = to_int(columns(line, 3, 3 + width));
      if (!id) return fail("cannot read the node number");
      node.id = *id;
      for (int k = 0; k < 3; ++k) {
        const size_t a = 3 + width + 12 * size_t(k);
        const auto v = to_real(columns(line, a, a + 12));
        if (!v)
          return fail("cannot read coordinate " + std::to_string(k + 1) + " of node " +
                      std::to_string(node.id));
        node.xyz[k] = *v;
      }
      nodes.push_back(node);
    }
    return {};
  }

  // Adds an element of the given type if it is a shell; counts the others.
  Status add_element(int64_t id, int64_t type, int64_t group, int64_t material,
                     std::span<const int64_t> node_ids, uint64_t place) {
    const auto t = element_type(type);
    assert(t);
    if (t->corners == 0) {
      ++skipped_elements;
      return {};
    }
    if (t->quadratic) ++quadratic_elements;
    ElementRecord e;
    e.id = id;
    // ccx writes group 0 and the material number (1, 2, … in the order of the 1UMAT lines);
    // other writers may fill the group: it is the part when it is set.
    const int64_t part = group != 0 ? group : material;
    if (part < INT32_MIN || part > INT32_MAX)
      return fail("element " + std::to_string(id) + ": group/material number out of range");
    e.part = static_cast<int32_t>(part);
    e.corners = static_cast<uint8_t>(t->corners);
    std::copy_n(node_ids.begin(), t->corners, e.nodes);
    e.place = place;
    elements.push_back(e);
    return {};
  }

  Status read_elements(std::string_view header) {
    int format = 0;
    uint64_t count = 0;
    DYNPM_RETURN_IF_ERROR(block_header(header, "element block (3C)", 2, format, count));
    int64_t node_ids[20];
    if (format == 2) {
      binary = true;
      DYNPM_RETURN_IF_ERROR(check_count(count, 4 * 6, "elements"));
      elements.reserve(count);
      char b[4 * 24];
      for (uint64_t i = 0; i < count; ++i) {
        const uint64_t place = reader_.offset();
        if (!reader_.read(b, 16)) return truncated("the element block");
        const int32_t id = from_native<int32_t>(b);
        const int32_t type = from_native<int32_t>(b + 4);
        const auto t = element_type(type);
        if (!t)
          return fail_at_byte(place, "element " + std::to_string(id) +
                                         " has the unknown frd type " + std::to_string(type));
        if (!reader_.read(b + 16, 4 * size_t(t->nodes))) return truncated("the element block");
        for (int k = 0; k < t->nodes; ++k) node_ids[k] = from_native<int32_t>(b + 16 + 4 * k);
        DYNPM_RETURN_IF_ERROR(add_element(id, type, from_native<int32_t>(b + 8),
                                          from_native<int32_t>(b + 12),
                                          std::span(node_ids, size_t(t->nodes)), place));
      }
      return {};
    }
    const size_t width = format == 1 ? 10 : 5;
    const size_t per_line = format == 1 ? 10 : 15;
    // The smallest element record is a triangle: its " -1" line and one " -2" line of 3 nodes.
    DYNPM_RETURN_IF_ERROR(
        check_count(count, (3 + width + 15 + 1) + (3 + 3 * width + 1), "elements"));
    elements.reserve(count);
    std::string_view line;
    while (true) {
      if (!next(line)) return truncated("the element block (no ' -3' line)");
      const int key = record_key(line);
      if (key == 3) break;
      if (key != 1)
        return fail("expected a ' -1' element record or the ' -3' end of the element block");
      const uint64_t place = reader_.line() - 1;
      const auto id = to_int(columns(line, 3, 3 + width));
      const auto type = to_int(columns(line, 3 + width, 8 + width));
      const auto group = to_int(columns(line, 8 + width, 13 + width));
      const auto material = to_int(columns(line, 13 + width, 18 + width));
      if (!id || !type) return fail("cannot read the element number and type");
      const auto t = element_type(*type);
      if (!t)
        return fail("element " + std::to_string(*id) + " has the unknown frd type " +
                    std::to_string(*type));
      int have = 0;
      while (have < t->nodes) {
        if (!next(line)) return truncated("the node list of element " + std::to_string(*id));
        if (record_key(line) != 2)
          return fail("expected the ' -2' node list of element " + std::to_string(*id) + " (" +
                      std::to_string(t->nodes) + " nodes)");
        size_t on_line = 0;
        for (size_t a = 3; a < line.size() && on_line < per_line && have < t->nodes;
             a += width, ++on_line) {
          const auto n = to_int(columns(line, a, a + width));
          if (!n) return fail("cannot read a node number of element " + std::to_string(*id));
          node_ids[have++] = *n;
        }
        if (on_line == 0) return fail("an empty ' -2' node list line");
      }
      DYNPM_RETURN_IF_ERROR(add_element(*id, *type, group.value_or(0), material.value_or(0),
                                        std::span(node_ids, size_t(t->nodes)), place));
    }
    return {};
  }

  size_t field_index(const std::string& name) {
    auto it = std::find(field_names.begin(), field_names.end(), name);
    if (it != field_names.end()) return static_cast<size_t>(it - field_names.begin());
    field_names.push_back(name);
    return field_names.size() - 1;
  }

  // A 100C block: (1X,' 100','C',6A1,E12.5,I12,20A1,I2,I5,10A1,I2), then " -4" (name, number
  // of components), one " -5" line per component, the data records. Only where the data start
  // is kept; ASCII data are skipped line by line, binary data by their size.
  Status scan_result(std::string_view header) {
    ResultBlock block;
    block.value_text = std::string(trim(columns(header, 12, 24)));
    const auto time = to_real(block.value_text);
    if (!time)
      return fail("cannot read the step time " + quoted_bytes(block.value_text) +
                  " (columns 13-24 of the 100C line)");
    if (!std::isfinite(*time))
      return fail("the step time " + quoted_bytes(block.value_text) +
                  " (columns 13-24 of the 100C line) is not a finite number");
    block.time = *time;
    // Integer fields: blank means not given; anything else must be a whole number.
    auto field = [&](size_t a, size_t b, const char* what) -> Result<int64_t> {
      const std::string_view text = trim(columns(header, a, b));
      if (text.empty()) return int64_t{0};
      const auto v = to_int(text);
      if (!v)
        return fail(std::string("the ") + what + " of the 100C line, " + quoted_bytes(text) +
                    ", is not a whole number");
      return *v;
    };
    const auto n = field(24, 36, "node count");
    if (!n) return n.status();
    if (*n < 0) return fail("negative node count in the 100C line");
    block.node_count = static_cast<uint64_t>(*n);
    const auto step_number = field(58, 63, "step number");
    if (!step_number) return step_number.status();
    block.step_number = *step_number;
    const auto format = field(73, header.size(), "format flag");
    if (!format) return format.status();
    if (*format < 0 || *format > 3)
      return fail("unknown format flag " + std::to_string(*format) + " in the 100C line");
    block.format = static_cast<int>(*format);
    if (block.format >= 2 && header.size() < 74)
      return fail("a binary block without a format flag");
    if (block.format >= 2) binary = true;

    std::string_view line;
    // " -4" record: (1X,I2,2X,8A1,2I5)
    do {
      if (!next(line)) return truncated("a result block header");
    } while (record_key(line) == 0 && trim(line).empty());
    if (record_key(line) != 4) return fail("expected the ' -4' record after a 100C line");
    // Shown in messages and used as a field name: only printable characters.
    const std::string name = printable(trim(columns(line, 5, 13)));
    const auto components = to_int(columns(line, 13, 18));
    if (!components || *components < 1 || *components > 1000)
      return fail("cannot read the component count of result block " + name);
    // " -5" records, one per component: (1X,I2,2X,8A1,5I5,8A1); IEXIST = 1 marks a component
    // the reader computes (DISP's "ALL"), which has no value in the data records.
    uint32_t stored = 0;
    for (int64_t c = 0; c < *components;) {
      if (!next(line)) return truncated("the components of result block " + name);
      const int key = record_key(line);
      if (key == 6 && block.format < 2) continue;  // " -6": predefined calculations (unused)
      if (key != 5)
        return fail("expected " + std::to_string(*components) + " ' -5' component records in " +
                    "result block " + name);
      if (to_int(columns(line, 33, 38)).value_or(0) != 1) ++stored;
      ++c;
    }
    if (stored == 0) return fail("result block " + name + " has no stored component");
    block.values = stored;
    block.data_offset = reader_.offset();
    block.data_line = reader_.line();

    if (name == "DISP") {
      if (stored < 3) return fail("result block DISP has fewer than 3 components");
      block.kind = BlockKind::kDisp;
    } else if (name == "STRESS" && stored >= 6) {
      block.kind = BlockKind::kStress;
      block.field = field_index("S_MISES");
    } else if (stored == 1) {
      block.kind = BlockKind::kScalar;
      block.field = field_index(name == "PE" ? "PEEQ" : name);
    } else {
      ignored_blocks.insert(name);
    }
    const bool keep = block.kind == BlockKind::kDisp || !ignored_blocks.count(name);

    if (block.format >= 2) {
      const uint64_t record = 4 + uint64_t{stored} * (block.format == 2 ? 4 : 8);
      if (block.node_count > reader_.left() / record)
        return fail("result block " + name + " announces " + std::to_string(block.node_count) +
                    " nodes, more than the " + std::to_string(reader_.left()) +
                    " bytes left in the file can hold");
      reader_.skip(block.node_count * record);
    } else {
      while (true) {
        if (!next(line)) return truncated("result block " + name + " (no ' -3' line)");
        if (record_key(line) == 3) break;
      }
    }
    if (keep) blocks.push_back(std::move(block));
    return {};
  }

  const std::string& path_;
  ChunkReader reader_;
  uint64_t line_offset_ = 0;
  bool saw_nodes_ = false, saw_elements_ = false;
};

// ---------------------------------------------------------------------------------------------
// The FrameSource: the mesh in memory, the steps on disk

class FrdSource final : public FrameSource {
 public:
  FrdSource(std::string path, std::vector<int64_t> node_ids, std::vector<double> base,
            std::vector<Step> steps, std::vector<ResultBlock> field_blocks,
            std::vector<std::string> field_names)
      : path_(std::move(path)),
        node_ids_(std::move(node_ids)),
        base_(std::move(base)),
        steps_(std::move(steps)),
        field_blocks_(std::move(field_blocks)),
        field_names_(std::move(field_names)) {
    // node number → vertex: a table when the numbers are dense enough, else binary search
    if (!node_ids_.empty()) {
      const int64_t lo = node_ids_.front(), hi = node_ids_.back();
      if (hi - lo < int64_t(node_ids_.size()) * 8 + 1024) {
        table_first_ = lo;
        table_.assign(size_t(hi - lo + 1), kNoVertex);
        for (size_t v = 0; v < node_ids_.size(); ++v)
          table_[size_t(node_ids_[v] - lo)] = uint32_t(v);
      }
    }
  }

  uint32_t vertex_count() const override { return uint32_t(node_ids_.size()); }
  size_t step_count() const override { return steps_.size() + 1; }
  double step_time(size_t t) const override { return t == 0 ? 0.0 : steps_[t - 1].time; }
  std::vector<std::string> field_names() const override { return field_names_; }

  Status read_step(size_t t, std::span<float> out) const override {
    assert(t < step_count() && out.size() == base_.size());
    if (t == 0) {
      std::transform(base_.begin(), base_.end(), out.begin(),
                     [](double c) { return static_cast<float>(c); });
      return {};
    }
    // Nodes a DISP block leaves out keep their coordinates.
    std::vector<double> xyz = base_;
    DYNPM_RETURN_IF_ERROR(read_block(steps_[t - 1].disp, [&](uint32_t v, const double* d) {
      for (int k = 0; k < 3; ++k) xyz[size_t(v) * 3 + k] += d[k];
    }));
    std::transform(xyz.begin(), xyz.end(), out.begin(),
                   [](double c) { return static_cast<float>(c); });
    return {};
  }

  Status read_field(size_t field, size_t t, std::span<float> out) const override {
    assert(field < field_names_.size() && t < step_count() && out.size() == vertex_count());
    std::fill(out.begin(), out.end(), 0.0f);
    if (t == 0 || steps_[t - 1].field_block[field] < 0) return {};
    const ResultBlock& block = field_blocks_[size_t(steps_[t - 1].field_block[field])];
    if (block.kind == BlockKind::kStress)
      return read_block(block, [&](uint32_t v, const double* s) {
        // von Mises from SXX SYY SZZ SXY SYZ SZX
        const double d1 = s[0] - s[1], d2 = s[1] - s[2], d3 = s[2] - s[0];
        out[v] = static_cast<float>(std::sqrt(0.5 * (d1 * d1 + d2 * d2 + d3 * d3) +
                                              3.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5])));
      });
    return read_block(block, [&](uint32_t v, const double* s) { out[v] = float(s[0]); });
  }

 private:
  uint32_t vertex_of(int64_t node) const {
    if (!table_.empty()) {
      if (node < table_first_ || node - table_first_ >= int64_t(table_.size())) return kNoIndex;
      return table_[size_t(node - table_first_)];
    }
    auto it = std::lower_bound(node_ids_.begin(), node_ids_.end(), node);
    if (it == node_ids_.end() || *it != node) return kNoIndex;
    return uint32_t(it - node_ids_.begin());
  }

  // Calls visit(vertex, values) for every record of the block whose node is a vertex (nodes of
  // skipped solids are not).
  template <class Visit>
  Status read_block(const ResultBlock& block, Visit&& visit) const {
    ChunkReader reader;
    DYNPM_RETURN_IF_ERROR(reader.open(path_));
    reader.seek(block.data_offset, block.data_line);
    std::vector<double> values(block.values);
    if (block.format >= 2) {
      const size_t real = block.format == 2 ? 4 : 8;
      const size_t record = 4 + block.values * real;
      std::vector<char> b(record);
      for (uint64_t i = 0; i < block.node_count; ++i) {
        const uint64_t place = reader.offset();
        if (!reader.read(b.data(), record))
          return Status::error(path_ + ": byte " + std::to_string(place) +
                               ": the file ends inside a result block (changed since opened?)");
        const uint32_t v = vertex_of(from_native<int32_t>(b.data()));
        if (v == kNoIndex) continue;
        for (size_t k = 0; k < block.values; ++k)
          values[k] = real == 4 ? from_native<float>(b.data() + 4 + 4 * k)
                                : from_native<double>(b.data() + 4 + 8 * k);
        visit(v, values.data());
      }
      return {};
    }
    const size_t width = block.format == 1 ? 10 : 5;
    const size_t first = 3 + width;
    std::string_view line;
    auto fail = [&](const std::string& cause) {
      return Status::error(path_ + ":" + std::to_string(reader.line() - 1) + ": " + cause);
    };
    while (true) {
      if (!reader.next_line(line))
        return Status::error(path_ +
                             ": the file ends inside a result block (changed since "
                             "opened?)");
      const int key = record_key(line);
      if (key == 3) return {};
      if (key != 1) return fail("expected a ' -1' data record or the ' -3' end of the block");
      const auto node = to_int(columns(line, 3, first));
      if (!node) return fail("cannot read the node number");
      size_t have = 0;
      while (true) {
        for (size_t on_line = 0; on_line < 6 && have < block.values; ++on_line) {
          const size_t a = first + 12 * on_line;
          const auto v = to_real(columns(line, a, a + 12));
          if (!v)
            return fail("cannot read value " + std::to_string(have + 1) + " of node " +
                        std::to_string(*node));
          values[have++] = *v;
        }
        if (have == block.values) break;
        if (!reader.next_line(line) || record_key(line) != 2)
          return fail("expected a ' -2' continuation line for node " + std::to_string(*node));
      }
      const uint32_t v = vertex_of(*node);
      if (v != kNoIndex) visit(v, values.data());
    }
  }

  std::string path_;
  std::vector<int64_t> node_ids_;  // ascending: the vertices
  std::vector<double> base_;       // 3 · #V undeformed coordinates
  std::vector<Step> steps_;        // steps 1 …
  std::vector<ResultBlock> field_blocks_;
  std::vector<std::string> field_names_;
  std::vector<uint32_t> table_;
  int64_t table_first_ = 0;
};

}  // namespace

Result<AnimationStream> open_frd(const std::string& path, const ReadOptions& options) {
  FrdScanner scan(path);
  DYNPM_RETURN_IF_ERROR(scan.scan());
  AnimationStream stream;
  auto note = [&](const std::string& text) {
    if (options.warn) options.warn(text);
  };
  // A result still being written, or a file cut at a line boundary after a complete block.
  if (!scan.ended)
    note(path + ": no ' 9999' end record: the file may be cut short or still being written; " +
         "reading the steps it holds");

  // Vertices: the nodes the shells use, in ascending node number (as our OBJ sequences).
  std::vector<NodeRecord>& nodes = scan.nodes;
  auto by_id = [](const auto& a, const auto& b) { return a.id < b.id; };
  if (!std::is_sorted(nodes.begin(), nodes.end(), by_id))
    std::sort(nodes.begin(), nodes.end(), by_id);
  for (size_t i = 1; i < nodes.size(); ++i)
    if (nodes[i].id == nodes[i - 1].id)
      return Status::error(path + ": node " + std::to_string(nodes[i].id) +
                           " is defined twice in the node block");
  if (nodes.size() > kNoVertex - 1)
    return Status::error(path + ": more nodes than dynpm can index");
  // node number → index in nodes: a table when the numbers are dense enough (ccx numbers from
  // 1), else a binary search.
  std::vector<uint32_t> table;
  const int64_t first_id = nodes.empty() ? 0 : nodes.front().id;
  if (!nodes.empty() && nodes.back().id - first_id < int64_t(nodes.size()) * 8 + 1024) {
    table.assign(size_t(nodes.back().id - first_id + 1), kNoIndex);
    for (size_t k = 0; k < nodes.size(); ++k) table[size_t(nodes[k].id - first_id)] = uint32_t(k);
  }
  auto node_index = [&](int64_t id) -> size_t {
    if (!table.empty()) {
      if (id < first_id || id - first_id >= int64_t(table.size())) return SIZE_MAX;
      const uint32_t k = table[size_t(id - first_id)];
      return k == kNoIndex ? SIZE_MAX : k;
    }
    auto it = std::lower_bound(nodes.begin(), nodes.end(), id,
                               [](const NodeRecord& n, int64_t v) { return n.id < v; });
    return it != nodes.end() && it->id == id ? size_t(it - nodes.begin()) : SIZE_MAX;
  };
  const std::string place_prefix = scan.binary ? ": byte " : ":";
  std::vector<uint32_t> vertex_of_node(nodes.size(), kNoVertex);
  for (const ElementRecord& e : scan.elements)
    for (int k = 0; k < e.corners; ++k) {
      const size_t i = node_index(e.nodes[k]);
      if (i == SIZE_MAX)
        return Status::error(path + place_prefix + std::to_string(e.place) + ": element " +
                             std::to_string(e.id) + " uses node " + std::to_string(e.nodes[k]) +
                             ", which the node block does not define");
      vertex_of_node[i] = 0;
    }
  if (scan.elements.empty())
    return Status::error(path + ": no shell elements (S3, S4, S6, S8); " +
                         std::to_string(scan.skipped_elements) +
                         " solid or beam elements were skipped. ccx writes shells as 20-node "
                         "bricks unless the deck asks for *NODE FILE, OUTPUT=2D");

  std::vector<int64_t> node_ids;
  std::vector<double> base;
  for (size_t i = 0; i < nodes.size(); ++i) {
    if (vertex_of_node[i] == kNoVertex) continue;
    vertex_of_node[i] = uint32_t(node_ids.size());
    node_ids.push_back(nodes[i].id);
    base.insert(base.end(), nodes[i].xyz, nodes[i].xyz + 3);
  }

  // Faces in ascending element number (as our OBJ sequences).
  if (!std::is_sorted(scan.elements.begin(), scan.elements.end(), by_id))
    std::stable_sort(scan.elements.begin(), scan.elements.end(), by_id);
  Topology& topology = stream.topology;
  topology.vertex_count = uint32_t(node_ids.size());
  topology.faces.reserve(scan.elements.size());
  for (const ElementRecord& e : scan.elements) {
    Face f;
    for (int k = 0; k < e.corners; ++k) f.v[k] = vertex_of_node[node_index(e.nodes[k])];
    topology.faces.push_back(f);
    topology.part_ids.push_back(e.part);
    topology.element_ids.push_back(e.id);
  }
  topology.node_ids = node_ids;
  std::vector<NodeRecord>().swap(scan.nodes);

  if (scan.quadratic_elements)
    note(path + ": " + std::to_string(scan.quadratic_elements) +
         " quadratic shells (S6, S8) reduced to their corner nodes");
  if (scan.skipped_elements)
    note(path + ": skipped " + std::to_string(scan.skipped_elements) +
         " solid and beam elements (dynpm reads the shells S3, S4, S6, S8)");
  if (!scan.ignored_blocks.empty()) {
    std::string names;
    for (const std::string& n : scan.ignored_blocks) names += (names.empty() ? "" : ", ") + n;
    note(path +
         ": result blocks not read (only DISP, STRESS, PE and one-component blocks): " + names);
  }

  // Steps: one per DISP block; other blocks join the step whose DISP block has the same step
  // number and time in its 100C line (ccx writes DISP, STRESS, PE … of one increment together).
  std::vector<Step> steps;
  std::vector<ResultBlock> field_blocks;
  std::map<std::pair<int64_t, std::string>, size_t> step_of_key;
  for (ResultBlock& b : scan.blocks)
    if (b.kind == BlockKind::kDisp) {
      step_of_key[{b.step_number, b.value_text}] = steps.size();
      Step s;
      s.time = b.time;
      s.disp = b;
      s.field_block.assign(scan.field_names.size(), -1);
      steps.push_back(std::move(s));
    }
  size_t unmatched = 0;
  for (ResultBlock& b : scan.blocks) {
    if (b.kind == BlockKind::kDisp) continue;
    auto it = step_of_key.find({b.step_number, b.value_text});
    if (it == step_of_key.end()) {
      ++unmatched;
      continue;
    }
    int64_t& slot = steps[it->second].field_block[b.field];
    if (slot >= 0) continue;  // the first block of a name in a step counts
    slot = int64_t(field_blocks.size());
    field_blocks.push_back(b);
  }
  if (unmatched)
    note(path + ": " + std::to_string(unmatched) +
         " result blocks without a DISP block of the same step and time were not read");
  if (steps.empty()) note(path + ": no DISP block: only the undeformed mesh (one step)");

  stream.frames =
      std::make_unique<FrdSource>(path, std::move(node_ids), std::move(base), std::move(steps),
                                  std::move(field_blocks), std::move(scan.field_names));
  return stream;
}

}  // namespace dynpm::io
