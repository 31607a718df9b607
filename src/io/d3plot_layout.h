// LS-DYNA d3plot files, what the reader (d3plot.cpp) needs to know of their layout: the words,
// the control block, where each part of a state lies, the files of a family, and where the
// states start. d3plot.cpp describes the format.
#pragma once

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "dynpm/core.h"

namespace dynpm::io::d3plot {

inline constexpr double kEndMarker = -999999.0;
// Counts are 32-bit in single precision files.
inline constexpr int64_t kMaxCount = int64_t{1} << 31;

// How the words of a file are encoded.
struct Words {
  int size = 4;  // bytes: 4 or 8
  bool swap = false;

  uint32_t u32(const char* p) const {
    uint32_t v;
    std::memcpy(&v, p, 4);
    return swap ? __builtin_bswap32(v) : v;
  }
  uint64_t u64(const char* p) const {
    uint64_t v;
    std::memcpy(&v, p, 8);
    return swap ? __builtin_bswap64(v) : v;
  }
  int64_t integer(const char* p) const {
    return size == 4 ? int64_t{static_cast<int32_t>(u32(p))} : static_cast<int64_t>(u64(p));
  }
  double real(const char* p) const {
    if (size == 4) {
      const uint32_t bits = u32(p);
      float f;
      std::memcpy(&f, &bits, 4);
      return f;
    }
    const uint64_t bits = u64(p);
    double d;
    std::memcpy(&d, &bits, 8);
    return d;
  }
  bool is_zero(const char* p) const {
    for (int i = 0; i < size; ++i)
      if (p[i] != 0) return false;
    return true;
  }
};

// The control block, decoded.
struct Control {
  Words words;
  int raw_ndim = 3, ndim = 3;
  int64_t numnp = 0, nglbv = 0, it = 0, iu = 0, iv = 0, ia = 0;
  int64_t nel8 = 0, nv3d = 0, nel2 = 0, nv1d = 0, nel4 = 0, nv2d = 0, nelt = 0, nv3dt = 0;
  bool ten_node_solids = false;
  int mdlopt = 0;  // deletion data per state: 0 none, 1 per node, 2 per element
  int64_t narbs = 0, nmmat = 0, ialemat = 0, nel48 = 0, nadapt = 0, idtdt = 0, nt3d = 0;
  int64_t nel20 = 0;
  // Shell element data: MAXINT integration points (its sign and 10000s carry MDLOPT), NEIPS
  // history values per point, IOSHL(1..4) whether stresses, plastic strain, resultants and
  // thickness with energy are written; NEIPH history values per solid.
  int64_t maxint = 0, neips = 0, neiph = 0;
  std::array<bool, 4> ioshl{};
  uint64_t header_words = 64;
};

// "path: byte N: cause".
std::string byte_error(const std::string& path, uint64_t byte, const std::string& cause);

// The word encoding under which head starts with a plausible control block: a d3plot file type
// (1, or 1001 with 64-bit user numbers; d3part 5 and d3eigv 11 share the layout), a known NDIM
// and non-negative element counts.
std::optional<Words> detect_words(std::string_view head);

// The control block in head, whose words detect_words() found; errors name the word.
Result<Control> parse_control(const std::string& path, std::string_view head, const Words& w);

// Where each part of a state lies, in words from the state's start.
struct StateLayout {
  uint64_t words = 0;
  uint64_t coordinates = 0;  // IU: ndim words per node
  bool has_coordinates = false;
  std::optional<uint64_t> temperature;  // one word per node, or three (layers) when stride 3
  int temperature_stride = 1;
  std::optional<uint64_t> velocity;  // ndim words per node
};

StateLayout state_layout(const Control& c);

// The words each shell writes per state (NV2D of them), in order:
//   per integration point (MAXINT of them; for MAXINT = 3 mid, bottom, top, otherwise bottom to
//   top): 6 stresses (σxx σyy σzz σxy σyz σzx) if IOSHL(1), the effective plastic strain if
//   IOSHL(2), NEIPS history values;
//   8 resultants (Mxx Myy Mxy Qxz Qyz Nxx Nyy Nxy) if IOSHL(3);
//   thickness, 2 element-dependent values and the internal energy if IOSHL(4);
//   12 strains (lower and upper surface tensors) if ISTRN.
// Thick shells write the same points and strains without resultants and thickness (NV3DT).
struct ShellWords {
  int points = 0;     // MAXINT
  int per_point = 0;  // words of one integration point
  bool stress = false, plastic_strain = false;
  std::optional<int> thickness;  // word of the thickness, when written
};

// The shell layout the control block describes; an error when its words do not add up to NV2D
// (a layout this reader does not know, whose values it would misread).
Result<ShellWords> shell_words(const std::string& path, const Control& c);

// Where the element data of a state starts (words from the state's start): solids (NEL8 ×
// (NT3D + NV3D)), thick shells (NELT × NV3DT), beams (NEL2 × NV1D), shells (NEL4 × NV2D).
struct ElementData {
  uint64_t solids = 0, thick_shells = 0, shells = 0;
};
ElementData element_data(const Control& c);

// An open file for positioned reads; closed when it goes out of scope.
class File {
 public:
  explicit File(const std::string& path) : fd_(::open(path.c_str(), O_RDONLY | O_CLOEXEC)) {}
  ~File() {
    if (fd_ >= 0) ::close(fd_);
  }
  File(const File&) = delete;
  File& operator=(const File&) = delete;
  bool ok() const { return fd_ >= 0; }
  // Reads exactly n bytes at offset, or returns false.
  bool read(uint64_t offset, size_t n, char* out) const {
    while (n > 0) {
      const ssize_t got = ::pread(fd_, out, n, static_cast<off_t>(offset));
      if (got <= 0) return false;
      out += got;
      n -= static_cast<size_t>(got);
      offset += static_cast<uint64_t>(got);
    }
    return true;
  }

 private:
  int fd_;
};

// The files of a family in order, with their sizes; a state may continue from the end of one
// file at the start of the next.
struct Family {
  std::vector<std::string> paths;
  std::vector<uint64_t> sizes;

  // Reads n bytes from (file, offset) on, across file ends.
  Status read(size_t file, uint64_t offset, size_t n, char* out) const {
    while (n > 0) {
      if (file >= paths.size())
        return Status::error(paths.back() + ": byte " + std::to_string(sizes.back()) +
                             ": the d3plot family ends inside a state");
      if (offset >= sizes[file]) {
        ++file, offset = 0;
        continue;
      }
      const size_t take = static_cast<size_t>(std::min<uint64_t>(n, sizes[file] - offset));
      File f(paths[file]);
      if (!f.ok()) return Status::error(paths[file] + ": cannot open: " + std::strerror(errno));
      if (!f.read(offset, take, out))
        return Status::error(byte_error(
            paths[file], offset,
            "cannot read " + std::to_string(take) + " bytes (was the file changed or cut?)"));
      out += take;
      n -= take;
      ++file, offset = 0;
    }
    return {};
  }
  // The place n bytes after (file, offset), across file ends.
  std::pair<size_t, uint64_t> advance(size_t file, uint64_t offset, uint64_t n) const {
    while (file < sizes.size() && offset + n > sizes[file]) {
      n -= sizes[file] - std::min(offset, sizes[file]);
      ++file, offset = 0;
    }
    return {file, offset + n};
  }
  uint64_t bytes_from(size_t file, uint64_t offset) const {
    uint64_t total = 0;
    for (size_t f = file; f < sizes.size(); ++f) total += sizes[f] - (f == file ? offset : 0);
    return total;
  }
};

// The family of path: path, path01, path02, … as far as they go; a gap followed by a later
// member is an error.
Result<Family> find_family(const std::string& path);

// Checks that [start, start + words·size) lies in a file of `size` bytes.
Status need(const std::string& path, uint64_t size, uint64_t start, uint64_t bytes,
            const char* section);

// The byte where the states start: after the part titles that newer versions write behind an
// end marker following the geometry. Title entries are 72 bytes even in double precision. The
// part titles (user part id, raw title) go to `part_titles` when given.
Result<uint64_t> skip_titles(const std::string& path, const File& file, uint64_t size,
                             const Words& w, uint64_t at,
                             std::vector<PartName>* part_titles = nullptr);

// True if the bytes from offset to the end of the file are all zero (LS-DYNA's padding).
Result<bool> rest_is_zero(const std::string& path, uint64_t size, uint64_t offset);

}  // namespace dynpm::io::d3plot
