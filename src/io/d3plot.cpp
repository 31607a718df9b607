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
//
// Here: open_d3plot()'s phases and the state reader. The words, the control block, the state
// layout and the family of files are d3plot_layout.h.
#include "d3plot.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <optional>

#include "d3plot_elements.h"
#include "d3plot_layout.h"
#include "formats.h"
#include "solid_surface.h"

namespace dynpm::io {
namespace {

using namespace d3plot;

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
               std::vector<float> initial, ElementFields elements)
      : family_(std::move(family)),
        control_(control),
        layout_(layout),
        places_(std::move(places)),
        times_(std::move(times)),
        kept_nodes_(std::move(kept_nodes)),
        initial_(std::move(initial)),
        elements_(std::move(elements)) {
    // Without a state the geometry stands in for one; it has no results.
    if (layout_.temperature && !places_.empty()) field_names_.push_back("temperature");
    if (layout_.velocity && !places_.empty()) field_names_.push_back("|V|");
  }

  uint32_t vertex_count() const override { return static_cast<uint32_t>(initial_.size() / 3); }
  size_t step_count() const override { return std::max<size_t>(places_.size(), 1); }
  double step_time(size_t t) const override { return places_.empty() ? 0.0 : times_[t]; }
  // Each read opens its file anew (Family::read) into buffers of its own thread.
  bool parallel_reads() const override { return true; }

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

  // The node fields, then the element fields (without a state, none).
  std::vector<FieldInfo> fields() const override {
    std::vector<FieldInfo> infos;
    for (const std::string& name : field_names_) infos.push_back({name, FieldLocation::kNode, {}});
    if (!places_.empty())
      infos.insert(infos.end(), elements_.fields().begin(), elements_.fields().end());
    return infos;
  }

  Status read_field(size_t field, size_t t, std::span<float> out) const override {
    assert(field < field_names_.size() + elements_.fields().size() && !places_.empty());
    if (field >= field_names_.size())
      return elements_.read(
          field - field_names_.size(),
          [&](uint64_t first, size_t n, char* into) { return read_words(t, first, n, into); }, out);
    assert(out.size() == vertex_count());
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
  ElementFields elements_;
};

// ---------------------------------------------------------------------------------------------
// open_d3plot()'s phases

// The control block of the family's first file, its word encoding in Control::words. A file
// that is no d3plot gets a hint when its name looks like a later member of a family.
Result<Control> read_control(const std::string& path, const Family& family, const File& first) {
  const uint64_t size0 = family.sizes[0];
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
  for (size_t f = 0; f < family.paths.size(); ++f)
    if (family.sizes[f] % w.size != 0)
      return Status::error(byte_error(family.paths[f], family.sizes[f] / w.size * w.size,
                                      std::to_string(family.sizes[f]) +
                                          " bytes is not a whole number of words: the file is "
                                          "cut short"));
  if (size0 < 64u * w.size)
    return Status::error(byte_error(path, size0, "the file ends inside the control block"));
  if (w.size == 8 && head.size() < 64 * 8u)
    return Status::error(byte_error(path, size0, "the file ends inside the control block"));
  auto parsed = parse_control(path, head, w);
  if (!parsed) return parsed.status();
  if (parsed->header_words * w.size > head.size()) {
    head.resize(parsed->header_words * w.size);
    DYNPM_RETURN_IF_ERROR(need(path, size0, 0, head.size(), "extended control block"));
    if (!first.read(0, head.size(), head.data()))
      return Status::error(path + ": cannot read the control block");
  }
  return parsed;
}

// The geometry of the first file: where each section starts, and the bytes from the node
// coordinates to the end of the user numbers, read at once.
struct Geometry {
  uint64_t coords_at = 0, solids_at = 0, tshells_at = 0, beams_at = 0, shells_at = 0;
  uint64_t numbers_at = 0;
  uint64_t end = 0;  // after the skipped sections too: where the part titles or states follow
  std::string bytes;
  const char* word(uint64_t byte) const { return bytes.data() + (byte - coords_at); }
};

// Sections in file order, with their sizes in words: every count is checked against the file
// size before anything is allocated.
Result<Geometry> read_geometry(const std::string& path, const File& first, uint64_t size0,
                               const Control& c) {
  const Words& w = c.words;
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
  Geometry g;
  g.coords_at = at;
  g.solids_at = g.coords_at + uint64_t(c.numnp) * c.ndim * ws;
  g.tshells_at = g.solids_at + uint64_t(c.nel8) * 9 * ws;
  g.beams_at = g.tshells_at + uint64_t(c.nelt) * 9 * ws;
  g.shells_at = g.beams_at + uint64_t(c.nel2) * 6 * ws;
  g.numbers_at = g.shells_at + uint64_t(c.nel4) * 5 * ws;
  g.end = g.numbers_at + uint64_t(c.narbs) * ws;
  // Extra corners of 10-node solids, 8-node shells and 20-node solids, then the parents of
  // adapted elements: skipped.
  if (c.ten_node_solids) g.end += 2 * uint64_t(c.nel8) * ws;
  g.end += (5 * uint64_t(c.nel48) + 13 * uint64_t(c.nel20) + 2 * uint64_t(c.nadapt)) * ws;
  for (auto [start, end, section] : {std::tuple{g.coords_at, g.solids_at, "node coordinates"},
                                     {g.solids_at, g.tshells_at, "solid elements"},
                                     {g.tshells_at, g.beams_at, "thick shell elements"},
                                     {g.beams_at, g.shells_at, "beam elements"},
                                     {g.shells_at, g.numbers_at, "shell elements"},
                                     {g.numbers_at, g.end, "user numbers"}})
    DYNPM_RETURN_IF_ERROR(need(path, size0, start, end - start, section));
  g.bytes.assign(static_cast<size_t>(g.numbers_at + uint64_t(c.narbs) * ws - g.coords_at), '\0');
  if (!first.read(g.coords_at, g.bytes.size(), g.bytes.data()))
    return Status::error(path + ": cannot read the geometry");
  return g;
}

// The user numbers of nodes and elements, and the part id of each material; empty where the
// file has none (numbers then count from 1, parts are the material numbers).
struct UserNumbers {
  std::vector<int64_t> node_ids, solid_ids, beam_ids, shell_ids, tshell_ids, part_of_material;

  int32_t part_id(int64_t material) const {
    if (material >= 1 && material <= int64_t(part_of_material.size()))
      return static_cast<int32_t>(part_of_material[size_t(material - 1)]);
    return static_cast<int32_t>(material);
  }
};

// A 10-word header (16 when NSORT < 0), then the node, solid, beam, shell and thick shell
// numbers, then NMMAT part ids in material order (NORDER) and two more arrays.
UserNumbers read_user_numbers(const std::string& path, const Geometry& g, const Control& c,
                              const ReadOptions& options) {
  UserNumbers numbers;
  if (c.narbs <= 0) return numbers;
  const Words& w = c.words;
  const uint64_t ws = static_cast<uint64_t>(w.size);
  const int64_t nsort = w.integer(g.word(g.numbers_at));
  const uint64_t header = nsort < 0 ? 16 : 10;
  const uint64_t ids = uint64_t(c.numnp) + uint64_t(c.nel8 + c.nel2 + c.nel4 + c.nelt);
  if (uint64_t(c.narbs) < header + ids) {
    if (options.warn)
      options.warn(byte_error(path, g.numbers_at,
                              "NARBS is too small for the user numbers; numbering nodes and "
                              "elements from 1"));
    return numbers;
  }
  uint64_t p = g.numbers_at + header * ws;
  auto take = [&](std::vector<int64_t>& into, int64_t count) {
    into.resize(static_cast<size_t>(count));
    for (auto& id : into) id = w.integer(g.word(p)), p += ws;
  };
  take(numbers.node_ids, c.numnp);
  take(numbers.solid_ids, c.nel8);
  take(numbers.beam_ids, c.nel2);
  take(numbers.shell_ids, c.nel4);
  take(numbers.tshell_ids, c.nelt);
  if (uint64_t(c.narbs) >= header + ids + 3 * uint64_t(c.nmmat))
    take(numbers.part_of_material, c.nmmat);
  return numbers;
}

// Faces: shells as they are (a repeated 4th node makes a triangle), solids and thick shells as
// their outer surface, beams ignored; over every node (unused ones are dropped later). elements
// receives the element of each face, for element results.
Result<Topology> read_faces(const std::string& path, const Geometry& g, const Control& c,
                            const UserNumbers& numbers, const ReadOptions& options,
                            std::vector<FaceElement>& elements) {
  const Words& w = c.words;
  const uint64_t ws = static_cast<uint64_t>(w.size);
  const uint64_t n = static_cast<uint64_t>(c.numnp);
  if (n > kNoVertex - 1) return Status::error(path + ": too many nodes");
  Topology topology = Topology::with_vertices(static_cast<uint32_t>(n));
  if (!numbers.node_ids.empty()) topology.node_ids = numbers.node_ids;
  auto node_index = [&](uint64_t byte, int64_t element, const char* kind) -> Result<uint32_t> {
    const int64_t node = w.integer(g.word(byte));
    if (node < 1 || uint64_t(node) > n)
      return Status::error(byte_error(path, byte,
                                      std::string(kind) + " " + std::to_string(element + 1) +
                                          " names node " + std::to_string(node) +
                                          ", but there are " + std::to_string(n) + " nodes"));
    return static_cast<uint32_t>(node - 1);
  };
  size_t degenerate = 0;
  for (int64_t e = 0; e < c.nel4; ++e) {
    const uint64_t p = g.shells_at + uint64_t(e) * 5 * ws;
    std::array<uint32_t, 4> corners{};
    for (int k = 0; k < 4; ++k) {
      auto v = node_index(p + k * ws, e, "shell");
      if (!v) return v.status();
      corners[size_t(k)] = *v;
    }
    const auto face = distinct_corner_face(corners);
    if (!face) {
      ++degenerate;
      continue;
    }
    topology.add_face(*face, numbers.part_id(w.integer(g.word(p + 4 * ws))),
                      numbers.shell_ids.empty() ? e + 1 : numbers.shell_ids[size_t(e)]);
    elements.push_back({ElementKind::kShell, static_cast<uint32_t>(e)});
  }
  SolidSurface solids;
  for (auto [start, count, ids, kind] :
       {std::tuple{g.solids_at, c.nel8, &numbers.solid_ids, "solid"},
        {g.tshells_at, c.nelt, &numbers.tshell_ids, "thick shell"}}) {
    std::array<uint32_t, 8> corners{};
    for (int64_t e = 0; e < count; ++e) {
      const uint64_t p = start + uint64_t(e) * 9 * ws;
      for (int k = 0; k < 8; ++k) {
        auto v = node_index(p + k * ws, e, kind);
        if (!v) return v.status();
        corners[size_t(k)] = *v;
      }
      solids.add_cell(SolidKind::kHex, corners, numbers.part_id(w.integer(g.word(p + 8 * ws))),
                      ids->empty() ? e + 1 : (*ids)[size_t(e)]);
    }
  }
  std::vector<uint32_t> cells;  // solids first, then thick shells
  const size_t solid_faces = solids.append_outer_faces(topology, &cells);
  for (uint32_t cell : cells)
    elements.push_back(cell < uint64_t(c.nel8)
                           ? FaceElement{ElementKind::kSolid, cell}
                           : FaceElement{ElementKind::kThickShell,
                                         static_cast<uint32_t>(cell - uint64_t(c.nel8))});
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
  return topology;
}

// The coordinates of the vertices kept (kept[v] is vertex v's node; empty: every node).
std::vector<float> initial_positions(const Geometry& g, const Control& c, uint32_t vertex_count,
                                     const std::vector<uint32_t>& kept) {
  const Words& w = c.words;
  const uint64_t ws = static_cast<uint64_t>(w.size);
  std::vector<float> initial(size_t{vertex_count} * 3);
  for (size_t v = 0; v < vertex_count; ++v) {
    const size_t node = kept.empty() ? v : kept[v];
    const char* p = g.word(g.coords_at + node * c.ndim * ws);
    initial[3 * v] = static_cast<float>(w.real(p));
    initial[3 * v + 1] = static_cast<float>(w.real(p + ws));
    initial[3 * v + 2] = c.ndim == 3 ? static_cast<float>(w.real(p + 2 * ws)) : 0.0f;
  }
  return initial;
}

// Where each state starts (file, byte) and its time, from states_at on through the family: a
// state of state_bytes each, zero padding skipped, the end marker or the family's end last.
struct StateIndex {
  std::vector<D3plotSource::Place> places;
  std::vector<double> times;
};

Result<StateIndex> index_states(const std::string& path, const Family& family, const Words& w,
                                uint64_t states_at, uint64_t state_bytes,
                                const ReadOptions& options) {
  const uint64_t ws = static_cast<uint64_t>(w.size);
  StateIndex index;
  std::vector<D3plotSource::Place>& places = index.places;
  std::vector<double>& times = index.times;
  size_t file = 0;
  uint64_t offset = states_at;
  bool warned_order = false;
  std::array<char, 16> buf{};
  while (file < family.paths.size()) {
    const std::string& name = family.paths[file];
    const uint64_t file_size = family.sizes[file];
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
    if (family.bytes_from(file, offset) < state_bytes)
      return Status::error(byte_error(
          name, offset,
          "state " + std::to_string(places.size() + 1) + " (time " + std::to_string(time) +
              ") needs " + std::to_string(state_bytes) + " bytes, but the family ends after " +
              std::to_string(family.bytes_from(file, offset)) + ": the file is cut short"));
    if (!times.empty() && time < times.back() && !warned_order && options.warn) {
      warned_order = true;
      options.warn(byte_error(name, offset, "state times decrease (a restart?)"));
    }
    places.push_back({file, offset});
    times.push_back(time);
    std::tie(file, offset) = family.advance(file, offset, state_bytes);
  }
  if (places.empty() && options.warn)
    options.warn(path +
                 ": the d3plot family holds no state; its geometry is given as one step "
                 "at time 0");
  return index;
}

}  // namespace

bool looks_like_d3plot(std::string_view head) { return detect_words(head).has_value(); }

Result<AnimationStream> open_d3plot(const std::string& path, const ReadOptions& options) {
  // 1. The family of files (d3plot, d3plot01, …) and the first file's control block.
  auto family = find_family(path);
  if (!family) return family.status();
  const uint64_t size0 = family->sizes[0];
  File first(path);
  if (!first.ok()) return Status::error(path + ": cannot open: " + std::strerror(errno));
  auto control = read_control(path, *family, first);
  if (!control) return control.status();
  const Control& c = *control;
  // 2. The geometry: its sections located and read.
  auto geometry = read_geometry(path, first, size0, c);
  if (!geometry) return geometry.status();
  // 3. User numbers and parts, then the faces: shells, and solids as their outer faces.
  const UserNumbers numbers = read_user_numbers(path, *geometry, c, options);
  std::vector<FaceElement> face_elements;
  auto topology = read_faces(path, *geometry, c, numbers, options, face_elements);
  if (!topology) return topology.status();
  // A shell layout that does not add up is refused before the states are sized by it.
  if (auto shells = shell_words(path, c); !shells) return shells.status();
  // 4. The nodes no face uses are dropped; the others' coordinates are step 0.
  std::vector<uint32_t> kept = drop_unused_vertices(*topology);
  std::vector<float> initial = initial_positions(*geometry, c, topology->vertex_count, kept);
  const uint64_t geometry_end = geometry->end;
  geometry = Geometry{};  // its bytes are no longer needed
  // 5. The state index: where each state starts, after the part titles.
  std::vector<PartName> titles;
  auto states_at = skip_titles(path, first, size0, c.words, geometry_end, &titles);
  if (!states_at) return states_at.status();
  const std::vector<int32_t> parts = topology->parts();
  for (const PartName& title : titles)
    if (std::binary_search(parts.begin(), parts.end(), title.id))
      topology->set_part_name(title.id, title.name);
  const StateLayout layout = state_layout(c);
  auto states = index_states(path, *family, c.words, *states_at,
                             layout.words * uint64_t(c.words.size), options);
  if (!states) return states.status();
  // 6. The element results on the faces; without a state there are none to note.
  const auto quiet = [](const std::string&) {};
  auto elements = ElementFields::make(
      path, c, std::move(face_elements), options.integration_point,
      states->places.empty() ? std::function<void(const std::string&)>(quiet) : options.warn);
  if (!elements) return elements.status();
  // 7. The states stay on disk, read one by one.
  AnimationStream stream;
  stream.topology = std::move(topology).value();
  stream.frames = std::make_unique<D3plotSource>(
      std::move(family).value(), c, layout, std::move(states->places), std::move(states->times),
      std::move(kept), std::move(initial), std::move(elements).value());
  return stream;
}

}  // namespace dynpm::io
