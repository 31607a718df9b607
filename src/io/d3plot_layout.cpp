// LS-DYNA d3plot files: the control block decoded, the state layout, the family of files found,
// and the part titles skipped (d3plot_layout.h).
#include "d3plot_layout.h"

#include <array>
#include <cmath>
#include <filesystem>

#include "dynpm/text.h"

namespace dynpm::io::d3plot {
namespace {

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
  kNeiph = 34,
  kNeips = 35,
  kMaxint = 36,
  kNmsph = 37,
  kNarbs = 39,
  kNelt = 40,
  kNv3dt = 42,
  kIoshl = 43,  // IOSHL(1..4): 1000 written, 999 not
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

}  // namespace

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
  c.maxint = maxint <= -10000 ? -maxint - 10000 : maxint < 0 ? -maxint : maxint;
  c.neips = word(kNeips);
  c.neiph = word(kNeiph);
  for (int k = 0; k < 4; ++k) c.ioshl[size_t(k)] = word(kIoshl + k) == 1000;
  if (c.maxint >= 10000)
    return Status::error(byte_error(
        path, uint64_t{kMaxint} * w.size,
        "MAXINT = " + std::to_string(maxint) + " is not a plausible number of integration points"));
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
                             {kNeips, "NEIPS"},
                             {kNeiph, "NEIPH"},
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
    // Words past the EXTRA the file states are not in it: absent counts are 0 (a 69-word control
    // block with EXTRA = 5 was read up to word 73, past the file: fuzz/regressions/d3plot/).
    const auto extended = [&](int i) -> int64_t {
      return uint64_t(i) < c.header_words ? word(i) : 0;
    };
    c.nel20 = extended(kNel20);
    c.nt3d = extended(kNt3d);
    for (auto [index, name] : {std::pair{kNel27, "NEL27"},
                               {kNel21p, "NEL21P"},
                               {kNel15t, "NEL15T"},
                               {kNel20t, "NEL20T"},
                               {kNel40p, "NEL40P"},
                               {kNel64, "NEL64"}})
      if (extended(index) != 0)
        return Status::error(
            byte_error(path, uint64_t(index) * w.size,
                       std::string("higher-order solids (") + name + " > 0) are not supported"));
    if (c.nel20 < 0 || c.nel20 >= kMaxCount || c.nt3d < 0 || c.nt3d >= kMaxCount)
      return Status::error(
          byte_error(path, uint64_t{kNel20} * w.size, "NEL20 or NT3D is not a plausible count"));
  }
  return c;
}

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

ElementData element_data(const Control& c) {
  ElementData e;
  const StateLayout s = state_layout(c);
  const uint64_t after = s.words - (c.mdlopt == 1   ? uint64_t(c.numnp)
                                    : c.mdlopt == 2 ? uint64_t(c.nel8 + c.nelt + c.nel4 + c.nel2)
                                                    : 0);
  e.shells = after - uint64_t(c.nel4) * uint64_t(c.nv2d);
  const uint64_t beams = e.shells - uint64_t(c.nel2) * uint64_t(c.nv1d);
  e.thick_shells = beams - uint64_t(c.nelt) * uint64_t(c.nv3dt);
  e.solids = e.thick_shells - uint64_t(c.nel8) * uint64_t(c.nt3d + c.nv3d);
  return e;
}

Result<ShellWords> shell_words(const std::string& path, const Control& c) {
  ShellWords s;
  s.points = static_cast<int>(c.maxint);
  s.stress = c.ioshl[0];
  s.plastic_strain = c.ioshl[1];
  s.per_point = 6 * s.stress + s.plastic_strain + static_cast<int>(c.neips);
  const int64_t points = int64_t{s.points} * s.per_point;
  const int64_t known = points + 8 * c.ioshl[2] + 4 * c.ioshl[3];
  if (c.ioshl[3]) s.thickness = static_cast<int>(points + 8 * c.ioshl[2]);
  // ISTRN (the 12 strain words) is not in the control block of older files: what is left says.
  if (c.nel4 == 0 || c.nv2d == known || c.nv2d == known + 12) return s;
  return Status::error(byte_error(
      path, uint64_t{kNv2d} * c.words.size,
      "NV2D = " + std::to_string(c.nv2d) + " words per shell does not add up: MAXINT " +
          std::to_string(s.points) + " × (" + (s.stress ? "6 stresses + " : "") +
          (s.plastic_strain ? "1 plastic strain + " : "") + std::to_string(c.neips) + " NEIPS) + " +
          std::to_string(8 * c.ioshl[2]) + " resultants + " + std::to_string(4 * c.ioshl[3]) +
          " thickness and energy words = " + std::to_string(known) + ", or " +
          std::to_string(known + 12) +
          " with strains (a d3plot layout this reader does not know)"));
}

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
                             const Words& w, uint64_t at, std::vector<PartName>* part_titles) {
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
      const uint64_t first = at + 2 * w.size;
      at = first + static_cast<uint64_t>(*count) * entry;
      if (at > size)
        return Status::error(byte_error(path, size, "the file ends inside the part titles"));
      // NTYPE 90001: the parts' titles, each its user id and 72 characters.
      for (uint64_t k = 0; type == 90001 && part_titles && k < uint64_t(*count); ++k) {
        const auto id = word_at(first + k * entry, false);
        std::string title(72, '\0');
        if (!id || !file.read(first + k * entry + w.size, 72, title.data()))
          return Status::error(byte_error(path, first + k * entry, "cannot read a part title"));
        if (*id >= INT32_MIN && *id <= INT32_MAX)
          part_titles->push_back({static_cast<int32_t>(*id), std::move(title)});
      }
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

}  // namespace dynpm::io::d3plot
