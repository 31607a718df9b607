// LS-DYNA d3plot reader, following the published "LS-DYNA Database Binary Output Format".
//
// A d3plot family is a row of files (d3plot, d3plot01, d3plot02, …) made of fixed-size words:
// 4 bytes (single precision) or 8 (double precision, integers then 64-bit too), in the byte order
// of the machine that wrote them. The first file holds
//   control block   64 words (+ EXTRA more): counts and flags (NDIM, NUMNP, NEL8, NEL4, IU, …)
//   geometry        node coordinates; solids (8 nodes + material), thick shells (8 + 1),
//                   beams (5 + 1), shells (4 + 1); user numbers (NARBS words); part titles
// and the states follow, each one:
//   time, NGLBV global values, nodal data (coordinates if IU, temperatures if IT, velocities if
//   IV, accelerations if IA, …), element data (NV3D per solid, NV2D per shell, …), deletion flags.
// LS-DYNA pads every file with zero words to a multiple of 512 words, starts a new file when a
// state would not fit, and writes -999999.0 after the last state. The reader indexes where every
// state starts (file, byte) on open and reads only the coordinates of a state when asked.
#include "d3plot.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <optional>

#include "dynpm/text.h"
#include "formats.h"
#include "solid_surface.h"

namespace dynpm::io {
namespace {

constexpr double kEndMarker = -999999.0;
constexpr int64_t kMaxCount = int64_t{1} << 31;  // counts are 32-bit in single precision files

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

// Control block word positions (0-based), as the format description numbers them from 1.
enum ControlWord : int {
  kFileType = 11,
  kNdim = 15,
  kNumnp = 16,
  kNglbv = 18,
  kIt = 19,
  kIu = 20,
  kIv = 21,
  kIa = 22,
  kNel8 = 23,
  kNv3d = 27,
  kNel2 = 28,
  kNv1d = 30,
  kNel4 = 31,
  kNv2d = 33,
  kMaxint = 36,
  kNmsph = 37,
  kNarbs = 39,
  kNelt = 40,
  kNv3dt = 42,
  kIalemat = 47,
  kNcfdv1 = 48,
  kNadapt = 50,
  kNmmat = 51,
  kNpefg = 54,
  kNel48 = 55,
  kIdtdt = 56,
  kExtra = 57,
  // EXTRA words, present when word 57 > 0.
  kNel20 = 64,
  kNt3d = 65,
  kNel27 = 66,
  kNel21p = 68,
  kNel15t = 69,
  kNel20t = 71,
  kNel40p = 72,
  kNel64 = 73,
};

int64_t control_word(const Words& w, std::string_view head, int index) {
  return w.integer(head.data() + static_cast<size_t>(index) * w.size);
}

// The word encoding under which head starts with a plausible control block: a d3plot file type
// (1, or 1001 with 64-bit user numbers; d3part 5 and d3eigv 11 share the layout), a known NDIM
// and non-negative element counts.
std::optional<Words> detect_words(std::string_view head) {
  for (int size : {4, 8}) {
    if (head.size() < 64u * size) continue;
    for (bool swap : {false, true}) {
      const Words w{size, swap};
      auto word = [&](int i) { return control_word(w, head, i); };
      int64_t type = word(kFileType);
      if (type > 1000) type -= 1000;
      if (type != 1 && type != 5 && type != 11) continue;
      if (word(kNdim) < 2 || word(kNdim) > 9) continue;
      bool counts_ok = true;
      for (int i : {kNumnp, kNglbv, kNel2, kNel4, kNelt, kNarbs, kNmmat, kExtra})
        if (word(i) < 0 || word(i) >= kMaxCount) counts_ok = false;
      if (std::abs(word(kNel8)) >= kMaxCount) counts_ok = false;
      if (counts_ok) return w;
    }
  }
  return std::nullopt;
}

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
  uint64_t header_words = 64;
};

std::string byte_error(const std::string& path, uint64_t byte, const std::string& cause) {
  return path + ": byte " + std::to_string(byte) + ": " + cause;
}

Result<Control> parse_control(const std::string& path, std::string_view head, const Words& w) {
  Control c;
  c.words = w;
  auto word = [&](int i) { return control_word(w, head, i); };
  c.raw_ndim = static_cast<int>(word(kNdim));
  const uint64_t ndim_byte = uint64_t{kNdim} * w.size;
  switch (c.raw_ndim) {
    case 2: c.ndim = 2; break;
    case 3:
    case 4:  // 4: connectivity unpacked, still three coordinates
    case 5:  // 5: a material type section follows the control block
      c.ndim = 3;
      break;
    default:
      return Status::error(byte_error(
          path, ndim_byte,
          "NDIM " + std::to_string(c.raw_ndim) +
              ": rigid road surfaces and rigid body data (NDIM 6 to 9) are not supported"));
  }
  c.numnp = word(kNumnp);
  c.nglbv = word(kNglbv);
  c.it = word(kIt);
  c.iu = word(kIu);
  c.iv = word(kIv);
  c.ia = word(kIa);
  c.nel8 = std::abs(word(kNel8));
  c.ten_node_solids = word(kNel8) < 0;
  c.nv3d = word(kNv3d);
  c.nel2 = word(kNel2);
  c.nv1d = word(kNv1d);
  c.nel4 = word(kNel4);
  c.nv2d = word(kNv2d);
  c.nelt = word(kNelt);
  c.nv3dt = word(kNv3dt);
  c.narbs = word(kNarbs);
  c.nmmat = word(kNmmat);
  c.ialemat = word(kIalemat);
  c.nel48 = word(kNel48);
  c.nadapt = word(kNadapt);
  c.idtdt = word(kIdtdt);
  const int64_t maxint = word(kMaxint);
  c.mdlopt = maxint <= -10000 ? 2 : maxint < 0 ? 1 : 0;
  const int64_t extra = word(kExtra);
  c.header_words = 64 + static_cast<uint64_t>(extra);

  for (auto [index, name] : {std::pair{kNumnp, "NUMNP"},
                             {kNglbv, "NGLBV"},
                             {kNv3d, "NV3D"},
                             {kNel2, "NEL2"},
                             {kNv1d, "NV1D"},
                             {kNel4, "NEL4"},
                             {kNv2d, "NV2D"},
                             {kNelt, "NELT"},
                             {kNv3dt, "NV3DT"},
                             {kNarbs, "NARBS"},
                             {kNmmat, "NMMAT"},
                             {kIalemat, "IALEMAT"},
                             {kNel48, "NEL48"},
                             {kNadapt, "NADAPT"},
                             {kExtra, "EXTRA"},
                             {kIt, "IT"},
                             {kIdtdt, "IDTDT"}})
    if (word(index) < 0 || word(index) >= kMaxCount)
      return Status::error(byte_error(
          path, uint64_t(index) * w.size,
          std::string(name) + " = " + std::to_string(word(index)) + " is not a plausible count"));
  if (word(kNmsph) != 0)
    return Status::error(
        byte_error(path, uint64_t{kNmsph} * w.size, "SPH particles (NMSPH > 0) are not supported"));
  if (word(kNpefg) != 0)
    return Status::error(byte_error(path, uint64_t{kNpefg} * w.size,
                                    "airbag particle data (NPEFG > 0) is not supported"));
  if (word(kNcfdv1) != 0)
    return Status::error(byte_error(path, uint64_t{kNcfdv1} * w.size,
                                    "CFD or multi-solver data (NCFDV1 != 0) is not supported"));
  if (extra > 0) {
    if (head.size() < c.header_words * w.size)
      return Status::error(
          byte_error(path, head.size(), "the file ends inside the extended control block"));
    c.nel20 = word(kNel20);
    c.nt3d = word(kNt3d);
    for (auto [index, name] : {std::pair{kNel27, "NEL27"},
                               {kNel21p, "NEL21P"},
                               {kNel15t, "NEL15T"},
                               {kNel20t, "NEL20T"},
                               {kNel40p, "NEL40P"},
                               {kNel64, "NEL64"}})
      if (word(index) != 0)
        return Status::error(
            byte_error(path, uint64_t(index) * w.size,
                       std::string("higher-order solids (") + name + " > 0) are not supported"));
    if (c.nel20 < 0 || c.nel20 >= kMaxCount || c.nt3d < 0 || c.nt3d >= kMaxCount)
      return Status::error(
          byte_error(path, uint64_t{kNel20} * w.size, "NEL20 or NT3D is not a plausible count"));
  }
  return c;
}

// Where each part of a state lies, in words from the state's start.
struct StateLayout {
  uint64_t words = 0;
  uint64_t coordinates = 0;  // IU: ndim words per node
  bool has_coordinates = false;
  std::optional<uint64_t> temperature;  // one word per node, or three (layers) when stride 3
  int temperature_stride = 1;
  std::optional<uint64_t> velocity;  // ndim words per node
};

StateLayout state_layout(const Control& c) {
  StateLayout s;
  uint64_t at = 1 + static_cast<uint64_t>(c.nglbv);
  const uint64_t n = static_cast<uint64_t>(c.numnp), d = static_cast<uint64_t>(c.ndim);
  if (c.iu != 0) {
    s.has_coordinates = true;
    s.coordinates = at;
    at += d * n;
  }
  const int64_t it = c.it % 10;
  if (it >= 1 && it <= 3) {
    s.temperature = at;
    s.temperature_stride = it == 3 ? 3 : 1;
    at += uint64_t(s.temperature_stride) * n;
    if (it >= 2) at += 3 * n;  // heat flux
  }
  if ((c.it / 10) % 10 == 1) at += n;         // mass scaling
  if (c.idtdt % 10 == 1) at += n;             // temperature change rate
  if ((c.idtdt / 10) % 10 == 1) at += 6 * n;  // residual forces and moments
  if (c.iv != 0) {
    s.velocity = at;
    at += d * n;
  }
  if (c.ia != 0) at += d * n;
  at += uint64_t(c.nel8) * uint64_t(c.nt3d + c.nv3d) + uint64_t(c.nelt) * uint64_t(c.nv3dt) +
        uint64_t(c.nel2) * uint64_t(c.nv1d) + uint64_t(c.nel4) * uint64_t(c.nv2d);
  if (c.mdlopt == 1) at += n;
  if (c.mdlopt == 2) at += uint64_t(c.nel8 + c.nelt + c.nel4 + c.nel2);
  s.words = at;
  return s;
}

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

// The name of member k of the family of path: path, path01, … path99, path100, …
std::string member_name(const std::string& path, int k) {
  if (k == 0) return path;
  return path + (k < 10 ? "0" : "") + std::to_string(k);
}

Result<Family> find_family(const std::string& path) {
  Family family;
  std::error_code ec;
  int k = 0;
  for (; k < 10000; ++k) {
    const std::string member = member_name(path, k);
    if (!std::filesystem::is_regular_file(member, ec)) {
      if (k == 0) return Status::error(path + ": no such file");
      break;
    }
    const uint64_t size = std::filesystem::file_size(member, ec);
    if (ec) return Status::error(member + ": " + ec.message());
    family.paths.push_back(member);
    family.sizes.push_back(size);
  }
  // A member after the gap means the gap is a lost file, not the family's end: reading on
  // would silently drop every state from the gap on.
  const std::filesystem::path first(path);
  const std::filesystem::path folder =
      first.has_parent_path() ? first.parent_path() : std::filesystem::path(".");
  const std::string stem = first.filename().string();
  // increment(ec), not ++: an unreadable folder must not throw.
  std::error_code listing;
  for (std::filesystem::directory_iterator it(folder, listing), end; !listing && it != end;
       it.increment(listing)) {
    const std::string name = it->path().filename().string();
    if (name.size() < stem.size() + 2 || name.compare(0, stem.size(), stem) != 0) continue;
    int64_t later = 0;
    if (parse_integer(std::string_view(name).substr(stem.size()), 1, 9999, later) !=
            NumberError::kNone ||
        later <= k || member_name(stem, static_cast<int>(later)) != name)
      continue;
    return Status::error(member_name(path, k) + ": missing from the d3plot family (" +
                         member_name(path, static_cast<int>(later)) +
                         " follows it): a family must be complete, or its states from there on "
                         "are lost");
  }
  return family;
}

// Decodes n reals (4- or 8-byte words) into floats.
void decode_reals(const Words& w, const char* in, size_t n, float* out) {
  if (w.size == 4 && !w.swap) {
    std::memcpy(out, in, n * 4);
    return;
  }
  if (w.size == 4) {
    for (size_t i = 0; i < n; ++i) {
      const uint32_t bits = __builtin_bswap32([&] {
        uint32_t v;
        std::memcpy(&v, in + 4 * i, 4);
        return v;
      }());
      std::memcpy(out + i, &bits, 4);
    }
    return;
  }
  for (size_t i = 0; i < n; ++i) out[i] = static_cast<float>(w.real(in + 8 * i));
}

// Streams the nodal data of each state from the family files.
class D3plotSource final : public FrameSource {
 public:
  struct Place {
    size_t file;
    uint64_t offset;
  };

  D3plotSource(Family family, Control control, StateLayout layout, std::vector<Place> places,
               std::vector<double> times, std::vector<uint32_t> kept_nodes,
               std::vector<float> initial)
      : family_(std::move(family)),
        control_(control),
        layout_(layout),
        places_(std::move(places)),
        times_(std::move(times)),
        kept_nodes_(std::move(kept_nodes)),
        initial_(std::move(initial)) {
    // Without a state the geometry stands in for one; it has no results.
    if (layout_.temperature && !places_.empty()) field_names_.push_back("temperature");
    if (layout_.velocity && !places_.empty()) field_names_.push_back("|V|");
  }

  uint32_t vertex_count() const override { return static_cast<uint32_t>(initial_.size() / 3); }
  size_t step_count() const override { return std::max<size_t>(places_.size(), 1); }
  double step_time(size_t t) const override { return places_.empty() ? 0.0 : times_[t]; }

  Status read_step(size_t t, std::span<float> out) const override {
    assert(t < step_count() && out.size() == initial_.size());
    if (places_.empty() || !layout_.has_coordinates) {
      std::copy(initial_.begin(), initial_.end(), out.begin());
      return {};
    }
    const size_t n = static_cast<size_t>(control_.numnp) * control_.ndim;
    const Words& w = control_.words;
    if (kept_nodes_.empty() && control_.ndim == 3 && w.size == 4 && !w.swap)
      return read_words(t, layout_.coordinates, n, reinterpret_cast<char*>(out.data()));
    thread_local std::vector<char> bytes;
    bytes.resize(n * w.size);
    DYNPM_RETURN_IF_ERROR(read_words(t, layout_.coordinates, n, bytes.data()));
    const int d = control_.ndim;
    const size_t vertices = out.size() / 3;
    if (kept_nodes_.empty() && d == 3) {
      decode_reals(w, bytes.data(), n, out.data());
      return {};
    }
    for (size_t v = 0; v < vertices; ++v) {
      const size_t node = kept_nodes_.empty() ? v : kept_nodes_[v];
      const char* p = bytes.data() + node * d * w.size;
      out[3 * v] = static_cast<float>(w.real(p));
      out[3 * v + 1] = static_cast<float>(w.real(p + w.size));
      out[3 * v + 2] = d == 3 ? static_cast<float>(w.real(p + 2 * w.size)) : 0.0f;
    }
    return {};
  }

  std::vector<std::string> field_names() const override { return field_names_; }

  Status read_field(size_t field, size_t t, std::span<float> out) const override {
    assert(field < field_names_.size() && out.size() == vertex_count());
    if (places_.empty()) {
      std::fill(out.begin(), out.end(), 0.0f);
      return {};
    }
    const bool temperature = field_names_[field] == "temperature";
    const int per_node = temperature ? layout_.temperature_stride : control_.ndim;
    const uint64_t start = temperature ? *layout_.temperature : *layout_.velocity;
    const Words& w = control_.words;
    const size_t n = static_cast<size_t>(control_.numnp) * per_node;
    thread_local std::vector<char> bytes;
    bytes.resize(n * w.size);
    DYNPM_RETURN_IF_ERROR(read_words(t, start, n, bytes.data()));
    for (size_t v = 0; v < out.size(); ++v) {
      const size_t node = kept_nodes_.empty() ? v : kept_nodes_[v];
      const char* p = bytes.data() + node * per_node * w.size;
      if (temperature) {
        out[v] = static_cast<float>(w.real(p));  // with layers: the first (mid-surface) value
      } else {
        double sum = 0;
        for (int k = 0; k < per_node; ++k) sum += std::pow(w.real(p + k * w.size), 2);
        out[v] = static_cast<float>(std::sqrt(sum));
      }
    }
    return {};
  }

 private:
  // Reads n words from word `first` of state t on.
  Status read_words(size_t t, uint64_t first, size_t n, char* out) const {
    const auto [file, offset] =
        family_.advance(places_[t].file, places_[t].offset, first * control_.words.size);
    return family_.read(file, offset, n * control_.words.size, out);
  }

  Family family_;
  Control control_;
  StateLayout layout_;
  std::vector<Place> places_;
  std::vector<double> times_;
  std::vector<uint32_t> kept_nodes_;  // empty: every node is a vertex
  std::vector<float> initial_;        // xyz per vertex, from the geometry section
  std::vector<std::string> field_names_;
};

// Checks that [start, start + words·size) lies in a file of `size` bytes.
Status need(const std::string& path, uint64_t size, uint64_t start, uint64_t bytes,
            const char* section) {
  if (start + bytes <= size) return {};
  return Status::error(byte_error(path, size,
                                  std::string("the file ends inside the ") + section + " (" +
                                      std::to_string(bytes) + " bytes from byte " +
                                      std::to_string(start) + ")"));
}

// The byte where the states start: after the part titles that newer versions write behind an
// end marker following the geometry. Title entries are 72 bytes even in double precision.
Result<uint64_t> skip_titles(const std::string& path, const File& file, uint64_t size,
                             const Words& w, uint64_t at) {
  std::array<char, 16> buf{};
  auto word_at = [&](uint64_t pos, bool real) -> std::optional<double> {
    if (pos + w.size > size || !file.read(pos, w.size, buf.data())) return std::nullopt;
    return real ? w.real(buf.data()) : static_cast<double>(w.integer(buf.data()));
  };
  auto marker = word_at(at, true);
  if (!marker || *marker != kEndMarker) return at;
  at += w.size;
  for (int section = 0; section < 64; ++section) {
    const auto ntype = word_at(at, false);
    if (!ntype) return at;
    const int64_t type = static_cast<int64_t>(*ntype);
    if (type == 90000) {
      at += w.size + 72;
    } else if (type == 90001 || type == 90002 || type == 90020 || type == 90100) {
      const auto count = word_at(at + w.size, false);
      if (!count || *count < 0 || *count > double(size))
        return Status::error(byte_error(path, at + w.size, "bad title count"));
      const uint64_t entry = type == 90100 ? 80 : w.size + 72;
      at += 2 * w.size + static_cast<uint64_t>(*count) * entry;
      if (at > size)
        return Status::error(byte_error(path, size, "the file ends inside the part titles"));
    } else {
      break;
    }
  }
  const auto closing = word_at(at, true);
  if (closing && *closing == kEndMarker) at += w.size;
  return at;
}

// True if the bytes from offset to the end of the file are all zero (LS-DYNA's padding).
Result<bool> rest_is_zero(const std::string& path, uint64_t size, uint64_t offset) {
  File f(path);
  if (!f.ok()) return Status::error(path + ": cannot open: " + std::strerror(errno));
  std::vector<char> chunk(1 << 16);
  while (offset < size) {
    const size_t n = static_cast<size_t>(std::min<uint64_t>(chunk.size(), size - offset));
    if (!f.read(offset, n, chunk.data()))
      return Status::error(byte_error(path, offset, "cannot read"));
    for (size_t i = 0; i < n; ++i)
      if (chunk[i] != 0) return false;
    offset += n;
  }
  return true;
}

}  // namespace

bool looks_like_d3plot(std::string_view head) { return detect_words(head).has_value(); }

Result<AnimationStream> open_d3plot(const std::string& path, const ReadOptions& options) {
  auto family = find_family(path);
  if (!family) return family.status();
  const uint64_t size0 = family->sizes[0];
  File first(path);
  if (!first.ok()) return Status::error(path + ": cannot open: " + std::strerror(errno));

  // Control block.
  std::string head(static_cast<size_t>(std::min<uint64_t>(size0, kD3plotHeadBytes)), '\0');
  if (!first.read(0, head.size(), head.data()))
    return Status::error(path + ": cannot read the control block");
  const auto words = detect_words(head);
  if (!words) {
    std::string hint;
    const std::string name = std::filesystem::path(path).filename().string();
    if (name.size() > 2 && std::isdigit(static_cast<unsigned char>(name.back())) &&
        std::isdigit(static_cast<unsigned char>(name[name.size() - 2])))
      hint = " (a continuation file of a family? give the family's first file)";
    if (size0 < 64 * 4)
      return Status::error(
          byte_error(path, size0, "the file ends inside the control block" + hint));
    return Status::error(path + ": byte 0: no LS-DYNA d3plot control block" + hint);
  }
  const Words w = *words;
  // LS-DYNA writes whole words (and pads to 512 of them): a stray byte means a cut file.
  for (size_t f = 0; f < family->paths.size(); ++f)
    if (family->sizes[f] % w.size != 0)
      return Status::error(byte_error(family->paths[f], family->sizes[f] / w.size * w.size,
                                      std::to_string(family->sizes[f]) +
                                          " bytes is not a whole number of words: the file is "
                                          "cut short"));
  if (size0 < 64u * w.size)
    return Status::error(byte_error(path, size0, "the file ends inside the control block"));
  if (w.size == 8 && head.size() < 64 * 8u)
    return Status::error(byte_error(path, size0, "the file ends inside the control block"));
  auto parsed = parse_control(path, head, w);
  if (!parsed) return parsed.status();
  Control c = *parsed;
  if (c.header_words * w.size > head.size()) {
    head.resize(c.header_words * w.size);
    DYNPM_RETURN_IF_ERROR(need(path, size0, 0, head.size(), "extended control block"));
    if (!first.read(0, head.size(), head.data()))
      return Status::error(path + ": cannot read the control block");
  }

  // Geometry sections, in file order, with their sizes in words: every count is checked
  // against the file size before anything is allocated.
  const uint64_t ws = static_cast<uint64_t>(w.size);
  uint64_t at = c.header_words * ws;
  if (c.raw_ndim == 5) {  // material types: NUMRBE, NUMMAT, then NUMMAT words
    DYNPM_RETURN_IF_ERROR(need(path, size0, at, 2 * ws, "material type section"));
    std::array<char, 16> buf{};
    if (!first.read(at + ws, w.size, buf.data())) return Status::error(path + ": cannot read");
    const int64_t nummat = w.integer(buf.data());
    if (nummat < 0 || nummat >= kMaxCount)
      return Status::error(byte_error(path, at + ws, "NUMMAT is not a plausible count"));
    at += (2 + static_cast<uint64_t>(nummat)) * ws;
  }
  at += static_cast<uint64_t>(c.ialemat) * ws;  // ALE fluid material ids
  const uint64_t n = static_cast<uint64_t>(c.numnp);
  const uint64_t coords_at = at;
  const uint64_t solids_at = coords_at + n * c.ndim * ws;
  const uint64_t tshells_at = solids_at + uint64_t(c.nel8) * 9 * ws;
  const uint64_t beams_at = tshells_at + uint64_t(c.nelt) * 9 * ws;
  const uint64_t shells_at = beams_at + uint64_t(c.nel2) * 6 * ws;
  const uint64_t numbers_at = shells_at + uint64_t(c.nel4) * 5 * ws;
  uint64_t geometry_end = numbers_at + uint64_t(c.narbs) * ws;
  // Extra corners of 10-node solids, 8-node shells and 20-node solids, then the parents of
  // adapted elements: skipped.
  if (c.ten_node_solids) geometry_end += 2 * uint64_t(c.nel8) * ws;
  geometry_end += (5 * uint64_t(c.nel48) + 13 * uint64_t(c.nel20) + 2 * uint64_t(c.nadapt)) * ws;
  for (auto [start, end, section] : {std::tuple{coords_at, solids_at, "node coordinates"},
                                     {solids_at, tshells_at, "solid elements"},
                                     {tshells_at, beams_at, "thick shell elements"},
                                     {beams_at, shells_at, "beam elements"},
                                     {shells_at, numbers_at, "shell elements"},
                                     {numbers_at, geometry_end, "user numbers"}})
    DYNPM_RETURN_IF_ERROR(need(path, size0, start, end - start, section));
  std::string geometry(static_cast<size_t>(numbers_at + uint64_t(c.narbs) * ws - coords_at), '\0');
  if (!first.read(coords_at, geometry.size(), geometry.data()))
    return Status::error(path + ": cannot read the geometry");
  auto word_ptr = [&](uint64_t byte) { return geometry.data() + (byte - coords_at); };

  // User numbers: a 10-word header (16 when NSORT < 0), then the node, solid, beam, shell and
  // thick shell numbers, then NMMAT part ids in material order (NORDER) and two more arrays.
  std::vector<int64_t> node_ids, solid_ids, beam_ids, shell_ids, tshell_ids, part_of_material;
  if (c.narbs > 0) {
    const int64_t nsort = w.integer(word_ptr(numbers_at));
    const uint64_t header = nsort < 0 ? 16 : 10;
    const uint64_t ids = n + uint64_t(c.nel8 + c.nel2 + c.nel4 + c.nelt);
    if (uint64_t(c.narbs) < header + ids) {
      if (options.warn)
        options.warn(byte_error(path, numbers_at,
                                "NARBS is too small for the user numbers; numbering nodes and "
                                "elements from 1"));
    } else {
      uint64_t p = numbers_at + header * ws;
      auto take = [&](std::vector<int64_t>& into, int64_t count) {
        into.resize(static_cast<size_t>(count));
        for (auto& id : into) id = w.integer(word_ptr(p)), p += ws;
      };
      take(node_ids, c.numnp);
      take(solid_ids, c.nel8);
      take(beam_ids, c.nel2);
      take(shell_ids, c.nel4);
      take(tshell_ids, c.nelt);
      if (uint64_t(c.narbs) >= header + ids + 3 * uint64_t(c.nmmat))
        take(part_of_material, c.nmmat);
    }
  }
  auto part_id = [&](int64_t material) -> int32_t {
    if (material >= 1 && material <= int64_t(part_of_material.size()))
      return static_cast<int32_t>(part_of_material[size_t(material - 1)]);
    return static_cast<int32_t>(material);
  };

  // Faces: shells as they are (a repeated 4th node makes a triangle), solids and thick shells
  // as their outer surface, beams ignored.
  if (n > kNoVertex - 1) return Status::error(path + ": too many nodes");
  Topology topology = Topology::with_vertices(static_cast<uint32_t>(n));
  if (!node_ids.empty()) topology.node_ids = node_ids;
  auto node_index = [&](uint64_t byte, int64_t element, const char* kind) -> Result<uint32_t> {
    const int64_t node = w.integer(word_ptr(byte));
    if (node < 1 || uint64_t(node) > n)
      return Status::error(byte_error(path, byte,
                                      std::string(kind) + " " + std::to_string(element + 1) +
                                          " names node " + std::to_string(node) +
                                          ", but there are " + std::to_string(n) + " nodes"));
    return static_cast<uint32_t>(node - 1);
  };
  size_t degenerate = 0;
  for (int64_t e = 0; e < c.nel4; ++e) {
    const uint64_t p = shells_at + uint64_t(e) * 5 * ws;
    Face face;
    int corners = 0;
    for (int k = 0; k < 4; ++k) {
      auto v = node_index(p + k * ws, e, "shell");
      if (!v) return v.status();
      if (std::find(face.v.begin(), face.v.begin() + corners, *v) == face.v.begin() + corners)
        face.v[corners++] = *v;
    }
    if (corners < 3) {
      ++degenerate;
      continue;
    }
    topology.add_face(face, part_id(w.integer(word_ptr(p + 4 * ws))),
                      shell_ids.empty() ? e + 1 : shell_ids[size_t(e)]);
  }
  SolidSurface solids;
  for (auto [start, count, ids, kind] : {std::tuple{solids_at, c.nel8, &solid_ids, "solid"},
                                         {tshells_at, c.nelt, &tshell_ids, "thick shell"}}) {
    std::array<uint32_t, 8> corners{};
    for (int64_t e = 0; e < count; ++e) {
      const uint64_t p = start + uint64_t(e) * 9 * ws;
      for (int k = 0; k < 8; ++k) {
        auto v = node_index(p + k * ws, e, kind);
        if (!v) return v.status();
        corners[size_t(k)] = *v;
      }
      solids.add_cell(SolidKind::kHex, corners, part_id(w.integer(word_ptr(p + 8 * ws))),
                      ids->empty() ? e + 1 : (*ids)[size_t(e)]);
    }
  }
  const size_t solid_faces = solids.append_outer_faces(topology);
  if (options.warn) {
    if (degenerate > 0)
      options.warn(path + ": " + std::to_string(degenerate) +
                   " shells with fewer than 3 distinct nodes skipped");
    if (solids.cell_count() > 0)
      options.warn(path + ": " + std::to_string(solids.cell_count()) +
                   " solid and thick shell elements given as their " + std::to_string(solid_faces) +
                   " outer faces");
    if (c.nel2 > 0) options.warn(path + ": " + std::to_string(c.nel2) + " beam elements ignored");
  }
  if (topology.faces.empty())
    return Status::error(path + ": no shell faces: the model has " + std::to_string(c.nel4) +
                         " shells, " + std::to_string(c.nel8 + c.nelt) + " solids and " +
                         std::to_string(c.nel2) + " beams (beams are ignored)");
  std::vector<uint32_t> kept = drop_unused_vertices(topology);

  std::vector<float> initial(size_t{topology.vertex_count} * 3);
  for (size_t v = 0; v < topology.vertex_count; ++v) {
    const size_t node = kept.empty() ? v : kept[v];
    const char* p = word_ptr(coords_at + node * c.ndim * ws);
    initial[3 * v] = static_cast<float>(w.real(p));
    initial[3 * v + 1] = static_cast<float>(w.real(p + ws));
    initial[3 * v + 2] = c.ndim == 3 ? static_cast<float>(w.real(p + 2 * ws)) : 0.0f;
  }
  geometry.clear();
  geometry.shrink_to_fit();

  // States: index where each one starts.
  auto states_at = skip_titles(path, first, size0, w, geometry_end);
  if (!states_at) return states_at.status();
  const StateLayout layout = state_layout(c);
  const uint64_t state_bytes = layout.words * ws;
  std::vector<D3plotSource::Place> places;
  std::vector<double> times;
  size_t file = 0;
  uint64_t offset = *states_at;
  bool warned_order = false;
  std::array<char, 16> buf{};
  while (file < family->paths.size()) {
    const std::string& name = family->paths[file];
    const uint64_t file_size = family->sizes[file];
    if (offset + ws > file_size) {
      ++file, offset = 0;
      continue;
    }
    File f(name);
    if (!f.ok() || !f.read(offset, w.size, buf.data()))
      return Status::error(byte_error(name, offset, "cannot read"));
    const double time = w.real(buf.data());
    if (time == kEndMarker) break;
    if (w.is_zero(buf.data())) {
      auto padding = rest_is_zero(name, file_size, offset);
      if (!padding) return padding.status();
      if (*padding) {
        ++file, offset = 0;
        continue;
      }
    }
    if (!std::isfinite(time))
      return Status::error(byte_error(name, offset,
                                      "state " + std::to_string(places.size() + 1) +
                                          " has no valid time: the state layout was not understood "
                                          "(a d3plot variant this reader does not support?)"));
    if (family->bytes_from(file, offset) < state_bytes)
      return Status::error(byte_error(
          name, offset,
          "state " + std::to_string(places.size() + 1) + " (time " + std::to_string(time) +
              ") needs " + std::to_string(state_bytes) + " bytes, but the family ends after " +
              std::to_string(family->bytes_from(file, offset)) + ": the file is cut short"));
    if (!times.empty() && time < times.back() && !warned_order && options.warn) {
      warned_order = true;
      options.warn(byte_error(name, offset, "state times decrease (a restart?)"));
    }
    places.push_back({file, offset});
    times.push_back(time);
    std::tie(file, offset) = family->advance(file, offset, state_bytes);
  }
  if (places.empty() && options.warn)
    options.warn(path +
                 ": the d3plot family holds no state; its geometry is given as one step "
                 "at time 0");

  AnimationStream stream;
  stream.topology = std::move(topology);
  stream.frames =
      std::make_unique<D3plotSource>(std::move(family).value(), c, layout, std::move(places),
                                     std::move(times), std::move(kept), std::move(initial));
  return stream;
}

}  // namespace dynpm::io
