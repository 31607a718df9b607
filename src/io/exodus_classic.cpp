// netCDF's classic header, checked before netCDF reads the file (exodus_classic.h).
#include "exodus_classic.h"

#include <fcntl.h>
#include <netcdf.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <string_view>
#include <utility>
#include <vector>

namespace dynpm::io {
namespace {

// netCDF's classic formats (CDF-1, CDF-2 "64-bit offset", CDF-5) are checked here, before
// nc_open sees the file, for two reasons:
//  - nc_open allocates what the header declares before it has read it: a name of 4 GB, a
//    billion dimensions, attribute values past the end of the file (fuzzing finding 4,
//    docs/RELIABILITY.md). Every count and length is checked against the bytes left in the file.
//  - netCDF reads a file cut short as if the missing bytes were zeros, so the file must hold
//    every byte of data the header describes.
// The layout is netCDF's "classic format specification" (netCDF Users Guide, appendix B):
//   header = 'C' 'D' 'F' version  numrecs  dim_list  gatt_list  var_list
//   list   = tag nelems [item ...]        tag 0x0A dimensions, 0x0B variables, 0x0C attributes
//   dim    = name length                  (length 0: the record dimension)
//   attr   = name nc_type nelems values   (values padded to 4 bytes)
//   var    = name nelems [dimid ...] attr_list nc_type vsize begin
//   name   = nelems chars                 (padded to 4 bytes)
// Counts, lengths and ids take 4 bytes (8 in CDF-5), begin 4 (8 in CDF-2 and CDF-5), tags and
// types 4; all big-endian. As in netCDF, a list of 0 items is absent whatever its tag.
// Other files (netCDF-4, "\x89HDF") are read in a child process, see open_exodus.
class ClassicHeaderCheck {
 public:
  ClassicHeaderCheck(std::string path, uint64_t file_size, char version)
      : path_(std::move(path)),
        file_size_(file_size),
        version_(version),
        in_(path_, std::ios::binary) {}

  Result<ClassicLayout> run() {
    if (!in_) return Status::error(path_ + ": cannot open the file");
    in_.seekg(4);
    pos_ = 4;
    const uint64_t numrecs = count();
    // Dimensions: their lengths, 0 for the record (unlimited) dimension.
    std::vector<uint64_t> dim_lengths;
    const uint64_t dim_count = list(0x0A, "dimensions", 2 * count_size());
    for (uint64_t i = 0; i < dim_count && ok(); ++i) {
      name();
      dim_lengths.push_back(count());
    }
    attributes("global attribute");
    const uint64_t var_size = 4 * count_size() + 8 + offset_size();
    const uint64_t var_count = list(0x0B, "variables", var_size);
    struct Extent {
      uint64_t begin, size, padded;
    };
    std::vector<Extent> fixed, records;
    ClassicLayout layout;
    for (uint64_t i = 0; i < var_count && ok(); ++i) {
      ClassicLayout::Variable& described = layout.variables.emplace_back();
      const std::string var = "variable " + name();
      const uint64_t rank_at = pos_;
      const uint64_t rank = count();
      if (ok() && rank > left() / count_size())
        fail(rank_at, var + " has " + std::to_string(rank) + " dimensions, more than the " +
                          std::to_string(left()) + " bytes left in the file can hold");
      bool record = false;
      uint64_t elements = 1;
      for (uint64_t d = 0; d < rank && ok(); ++d) {
        const uint64_t id_at = pos_;
        const uint64_t id = count();
        if (!ok()) break;
        if (id >= dim_lengths.size()) {
          fail(id_at, var + ": dimension id " + std::to_string(id) + ", but the header has " +
                          std::to_string(dim_lengths.size()) + " dimensions");
          break;
        }
        if (d == 0 && dim_lengths[id] == 0) {
          record = true;
        } else {
          elements = saturating_product(elements, dim_lengths[id]);
          described.lengths.push_back(dim_lengths[id]);
        }
      }
      attributes(var + " attribute");
      const uint64_t type_size = type(var, &described.type);
      count();  // vsize: recomputed from the shape, the header's may be clipped to 32 bits
      const uint64_t begin = offset_size() == 4 ? u32() : u64();
      const uint64_t size = saturating_product(elements, type_size);
      described.begin = begin, described.record = record;
      (record ? records : fixed).push_back({begin, size, saturating_sum(size, 3) / 4 * 4});
    }
    if (!ok()) return error_;

    uint64_t end = 0;
    for (const Extent& v : fixed) end = std::max(end, saturating_sum(v.begin, v.size));
    // Records interleave the record variables, each padded to 4 bytes, except that a single
    // record variable is not padded.
    const bool streaming = numrecs == (version_ == 5 ? ~uint64_t{0} : 0xffffffffu);
    uint64_t record_size = 0;
    for (const Extent& v : records)
      record_size = saturating_sum(record_size, records.size() == 1 ? v.size : v.padded);
    if (numrecs > 0 && !streaming) {
      for (const Extent& v : records)
        end = std::max(end, saturating_sum(saturating_sum(v.begin, v.size),
                                           saturating_product(numrecs - 1, record_size)));
    }
    if (end > file_size_)
      return Status::error(path_ + ": byte " + std::to_string(file_size_) +
                           ": the file ends before its data does (the header describes " +
                           std::to_string(end) + " bytes): cut short?");
    layout.records = numrecs, layout.record_size = record_size, layout.streaming = streaming;
    return layout;
  }

 private:
  bool ok() const { return error_.ok(); }
  uint64_t left() const { return file_size_ - std::min(pos_, file_size_); }
  uint64_t count_size() const { return version_ == 5 ? 8 : 4; }
  uint64_t offset_size() const { return version_ == 1 ? 4 : 8; }

  void fail(uint64_t at, const std::string& what) {
    if (ok()) error_ = Status::error(path_ + ": byte " + std::to_string(at) + ": " + what);
  }
  // Reads `n` bytes of a field the file must hold; false (and the error) past its end.
  bool read(char* out, uint64_t n) {
    if (!ok()) return false;
    if (n > left() || !in_.read(out, static_cast<std::streamsize>(n))) {
      fail(pos_, "the file ends inside the netCDF header: cut short?");
      return false;
    }
    pos_ += n;
    return true;
  }
  uint64_t big_endian(int bytes) {
    char b[8];
    if (!read(b, static_cast<uint64_t>(bytes))) return 0;
    uint64_t v = 0;
    for (int i = 0; i < bytes; ++i) v = (v << 8) | static_cast<unsigned char>(b[i]);
    return v;
  }
  uint64_t u32() { return big_endian(4); }
  uint64_t u64() { return big_endian(8); }
  uint64_t count() { return version_ == 5 ? u64() : u32(); }

  // Skips `bytes` plus the padding to 4, all of which the file must hold.
  void skip_padded(uint64_t at, uint64_t bytes, const std::string& what) {
    if (!ok()) return;
    const uint64_t padded = bytes > left() ? bytes : (bytes + 3) / 4 * 4;
    if (padded > left()) {
      fail(at, what + " of " + std::to_string(bytes) + " bytes, but the file has " +
                   std::to_string(left()) + " bytes left");
      return;
    }
    in_.seekg(static_cast<std::streamoff>(padded), std::ios::cur);
    pos_ += padded;
  }
  // A list's item count, after checking its tag; each item takes at least `item_size` bytes.
  uint64_t list(uint64_t tag, const std::string& items, uint64_t item_size) {
    const uint64_t at = pos_;
    const uint64_t found = u32(), n = count();
    if (!ok() || n == 0) return 0;
    if (found != tag) {
      fail(at, "the netCDF header has tag " + std::to_string(found) + " where its list of " +
                   items + " (tag " + std::to_string(tag) + ") should be");
      return 0;
    }
    if (n > left() / item_size)
      fail(at + 4, "the netCDF header declares " + std::to_string(n) + " " + items +
                       ", more than the " + std::to_string(left()) +
                       " bytes left in the file can hold");
    return ok() ? n : 0;
  }
  // A name: short printable ones are kept for the messages, others are "#<byte>".
  std::string name() {
    const uint64_t at = pos_;
    const uint64_t length = count();
    if (!ok()) return "";
    const uint64_t padded = (length + 3) / 4 * 4;
    if (length > 64 || padded > left()) {
      skip_padded(at, length, "the netCDF header declares a name");
      return "#" + std::to_string(at);
    }
    std::string s(static_cast<size_t>(padded), '\0');
    if (!read(s.data(), padded)) return "";
    s.resize(static_cast<size_t>(length));
    const bool printable =
        !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return c > ' ' && c < 127; });
    return printable ? s : "#" + std::to_string(at);
  }
  // The size of one value of a netCDF type (1 byte … 8 bytes: NC_BYTE … NC_UINT64); the type
  // into `code` when given.
  uint64_t type(const std::string& owner, int* code = nullptr) {
    const uint64_t at = pos_;
    const uint64_t t = u32();
    if (!ok()) return 1;
    if (code) *code = static_cast<int>(t);
    switch (t) {
      case NC_BYTE:
      case NC_CHAR:
      case NC_UBYTE: return 1;
      case NC_SHORT:
      case NC_USHORT: return 2;
      case NC_INT:
      case NC_UINT:
      case NC_FLOAT: return 4;
      case NC_DOUBLE:
      case NC_INT64:
      case NC_UINT64: return 8;
      default: fail(at, owner + ": unknown netCDF type " + std::to_string(t)); return 1;
    }
  }
  void attributes(const std::string& kind) {
    const uint64_t n = list(0x0C, kind + "s", 2 * count_size() + 4);
    for (uint64_t i = 0; i < n && ok(); ++i) {
      const std::string attribute = kind + " " + name();
      const uint64_t size = type(attribute);
      const uint64_t values_at = pos_;
      const uint64_t values = count();
      if (!ok()) return;
      if (values > left() / size) {
        fail(values_at, attribute + ": the netCDF header declares " + std::to_string(values) +
                            " values of " + std::to_string(size) + " bytes, but the file has " +
                            std::to_string(left()) + " bytes left");
        return;
      }
      skip_padded(values_at, values * size, attribute + ": values");
    }
  }
  static uint64_t saturating_sum(uint64_t a, uint64_t b) {
    uint64_t s;
    return __builtin_add_overflow(a, b, &s) ? ~uint64_t{0} : s;
  }
  static uint64_t saturating_product(uint64_t a, uint64_t b) {
    uint64_t p;
    return __builtin_mul_overflow(a, b, &p) ? ~uint64_t{0} : p;
  }

  std::string path_;
  uint64_t file_size_;
  char version_;
  std::ifstream in_;
  uint64_t pos_ = 0;
  Status error_;
};

}  // namespace

Result<ClassicLayout> check_classic_header(const std::string& path, uint64_t file_size,
                                           char version) {
  return ClassicHeaderCheck(path, file_size, version).run();
}

char classic_version(const std::string& path) {
  char magic[4] = {};
  std::ifstream in(path, std::ios::binary);
  if (!in.read(magic, 4) || std::string_view(magic, 3) != "CDF") return 0;
  return magic[3] == 1 || magic[3] == 2 || magic[3] == 5 ? magic[3] : 0;
}

std::optional<ClassicValues> ClassicValues::open(const std::string& path, ClassicLayout layout) {
  if (layout.streaming) return std::nullopt;
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return std::nullopt;
  return ClassicValues(path, fd, std::move(layout));
}

ClassicValues::ClassicValues(std::string path, int fd, ClassicLayout layout)
    : path_(std::move(path)), fd_(fd), layout_(std::move(layout)) {}
ClassicValues::ClassicValues(ClassicValues&& other) noexcept
    : path_(std::move(other.path_)),
      fd_(std::exchange(other.fd_, -1)),
      layout_(std::move(other.layout_)) {}
ClassicValues::~ClassicValues() {
  if (fd_ >= 0) ::close(fd_);
}

bool ClassicValues::reads(int var) const {
  if (var < 0 || static_cast<size_t>(var) >= layout_.variables.size()) return false;
  const int type = layout_.variables[static_cast<size_t>(var)].type;
  return type == NC_FLOAT || type == NC_DOUBLE;
}

Status ClassicValues::read(int var, const std::string& name, std::span<const size_t> start,
                           std::span<const size_t> count, std::vector<double>& values) const {
  if (!reads(var)) return Status::error(path_ + ": " + name + ": not a float or double variable");
  const ClassicLayout::Variable& v = layout_.variables[static_cast<size_t>(var)];
  // The dimensions: the record one (counted by numrecs) first, then the others.
  std::vector<uint64_t> lengths;
  if (v.record) lengths.push_back(layout_.records);
  lengths.insert(lengths.end(), v.lengths.begin(), v.lengths.end());
  const size_t rank = lengths.size();
  if (start.size() != rank || count.size() != rank)
    return Status::error(path_ + ": " + name + ": " + std::to_string(start.size()) +
                         " indices for a variable of " + std::to_string(rank) + " dimensions");
  size_t total = 1;
  for (size_t d = 0; d < rank; ++d) {
    if (start[d] > lengths[d] || count[d] > lengths[d] - start[d])
      return Status::error(path_ + ": " + name + ": values " + std::to_string(start[d]) + " … " +
                           std::to_string(start[d] + count[d]) + " of dimension " +
                           std::to_string(d) + ", which has " + std::to_string(lengths[d]));
    total *= count[d];
  }
  values.resize(total);
  if (total == 0) return {};
  const size_t size = v.type == NC_DOUBLE ? 8 : 4;
  // The last dimension's values lie side by side and are read as one run; a record variable
  // of one dimension has one value a record, a record apart.
  const bool record_runs = v.record && rank == 1;
  const size_t run = record_runs ? 1 : count[rank - 1];
  const size_t stepped = record_runs ? rank : rank - 1;  // the dimensions stepped through
  std::vector<size_t> at(start.begin(), start.end());
  thread_local std::vector<unsigned char> bytes;
  bytes.resize(run * size);
  for (size_t done = 0; done < total; done += run) {
    uint64_t linear = 0;
    for (size_t d = v.record ? 1 : 0; d < rank; ++d) linear = linear * lengths[d] + at[d];
    uint64_t offset = v.begin + linear * size;
    if (v.record) offset += at[0] * layout_.record_size;
    for (size_t got = 0; got < bytes.size();) {
      const ssize_t n =
          ::pread(fd_, bytes.data() + got, bytes.size() - got, static_cast<off_t>(offset + got));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0)
        return Status::error(path_ + ": " + name + ": byte " + std::to_string(offset + got) + ": " +
                             (n < 0 ? std::strerror(errno) : "the file ends here") +
                             " (changed since it was opened?)");
      got += static_cast<size_t>(n);
    }
    double* out = values.data() + done;
    // Big-endian, as the classic formats store every value: swapped on a little-endian host.
    constexpr bool swap = std::endian::native == std::endian::little;
    for (size_t i = 0; i < run; ++i) {
      if (size == 8) {
        uint64_t raw;
        std::memcpy(&raw, &bytes[i * 8], 8);
        out[i] = std::bit_cast<double>(swap ? __builtin_bswap64(raw) : raw);
      } else {
        uint32_t raw;
        std::memcpy(&raw, &bytes[i * 4], 4);
        out[i] = double(std::bit_cast<float>(swap ? __builtin_bswap32(raw) : raw));
      }
    }
    for (size_t d = stepped; d-- > 0;) {
      if (++at[d] < start[d] + count[d]) break;
      at[d] = start[d];
    }
  }
  return {};
}

}  // namespace dynpm::io
