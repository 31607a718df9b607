// Exodus II reader, through the netCDF C library (classic, 64-bit offset and netCDF-4/HDF5).
// Long: one format's reader (nodal and element variables, blocks, the netCDF access) kept whole.
//
// Exodus II is netCDF with conventions (Sandia's "EXODUS II: A Finite Element Data Model"):
//   dims  num_nodes, num_dim, num_elem, num_el_blk, num_el_in_blk<b>, num_nod_per_el<b>,
//         time_step (unlimited), num_nod_var
//   vars  coordx coordy [coordz] (or coord[num_dim][num_nodes]); connect<b> with the attribute
//         elem_type; eb_prop1 (block ids); node_num_map, elem_num_map (user numbers);
//         time_whole; name_nod_var; vals_nod_var<i>[time_step][num_nodes] (or one vals_nod_var
//         [time_step][num_nod_var][num_nodes] in old files); num_elem_var, name_elem_var,
//         vals_elem_var<v>eb<b>[time_step][num_el_in_blk<b>], elem_var_tab[num_el_blk]
//         [num_elem_var] (which blocks hold which element variable; absent: all)
// Shell and 2-D blocks (SHELL*, QUAD*, TRI*) become faces; solid blocks (HEX, TETRA, WEDGE,
// PYRAMID) give their outer faces; beams, bars and others are ignored with a warning. Nodal
// variables named DISPL_X/Y/Z (or DISP_X, DISPLX, DISPLACEMENT_X, …) move the nodes: positions
// are coordinates + displacement. The other nodal variables are node fields; element variables
// are element fields on the faces made from each element (a solid's value on each of its outer
// faces), 0 on the faces of a block that lacks the variable. Exodus names no units.
//
// Classic netCDF files are read here, in dynpm's process: their header is checked by our own
// code first (ClassicHeaderCheck, exodus_classic.cpp) and netCDF's classic reader is fuzzed with
// ours. Every other file (netCDF-4, i.e. HDF5) is read in a child process (contained_read.h):
// libhdf5 crashes on damaged files (issue 16), and that must end the child, not dynpm.
#include <netcdf.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <mutex>
#include <optional>

#include "contained_read.h"
#include "exodus_classic.h"
#include "formats.h"
#include "solid_surface.h"

namespace dynpm::io {
namespace {

std::string upper(std::string s) {
  for (char& ch : s) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  return s;
}

std::string trimmed(std::string s) {
  while (!s.empty() && (s.back() == '\0' || s.back() == ' ')) s.pop_back();
  const size_t nul = s.find('\0');
  if (nul != std::string::npos) s.resize(nul);
  return s;
}

// An open netCDF file; closed when the last owner lets go. netCDF keeps its own state per id,
// so every call names the file and the variable on failure.
class NcFile {
 public:
  NcFile(std::string path, int id, uint64_t file_size, bool compressed,
         std::optional<ClassicValues> classic)
      : path_(std::move(path)),
        id_(id),
        file_size_(file_size),
        compressed_(compressed),
        classic_(std::move(classic)) {}
  ~NcFile() { nc_close(id_); }
  NcFile(const NcFile&) = delete;
  NcFile& operator=(const NcFile&) = delete;

  const std::string& path() const { return path_; }
  int id() const { return id_; }
  bool compressed() const { return compressed_; }
  // read_doubles() may run on several threads at once: a classic file's float and double
  // values are read without netCDF (ClassicValues), and the rest under a lock.
  bool parallel_reads() const { return classic_.has_value(); }

  Status error(const std::string& what, int code) const {
    return Status::error(path_ + ": " + what + ": " + nc_strerror(code));
  }
  std::optional<size_t> dim(const std::string& name) const {
    int d;
    size_t len;
    if (nc_inq_dimid(id_, name.c_str(), &d) != NC_NOERR) return std::nullopt;
    if (nc_inq_dimlen(id_, d, &len) != NC_NOERR) return std::nullopt;
    return len;
  }
  std::optional<int> var(const std::string& name) const {
    int v;
    if (nc_inq_varid(id_, name.c_str(), &v) != NC_NOERR) return std::nullopt;
    return v;
  }
  // The lengths of a variable's dimensions.
  Result<std::vector<size_t>> shape(int var, const std::string& name) const {
    int ndims = 0;
    if (int rc = nc_inq_varndims(id_, var, &ndims); rc != NC_NOERR) return error(name, rc);
    std::vector<int> dims(static_cast<size_t>(std::max(ndims, 0)));
    if (int rc = nc_inq_vardimid(id_, var, dims.data()); rc != NC_NOERR) return error(name, rc);
    std::vector<size_t> lengths(dims.size());
    for (size_t i = 0; i < dims.size(); ++i)
      if (int rc = nc_inq_dimlen(id_, dims[i], &lengths[i]); rc != NC_NOERR) return error(name, rc);
    return lengths;
  }
  // Refuses to read `count` values of a variable when they could not be in a file this size:
  // uncompressed formats store every value; deflate, netCDF-4's usual filter, shrinks data at
  // most about 1032:1.
  Status check_count(int var, const std::string& name, size_t count) const {
    nc_type type;
    size_t type_size = 8;
    if (nc_inq_vartype(id_, var, &type) == NC_NOERR) nc_inq_type(id_, type, nullptr, &type_size);
    const double stored = double(count) * double(type_size);
    const double limit = compressed_ ? double(file_size_) * 1100.0 + 65536.0 : double(file_size_);
    if (stored > limit)
      return Status::error(path_ + ": " + name + ": " + std::to_string(count) +
                           " values cannot be stored in a file of " + std::to_string(file_size_) +
                           " bytes (a corrupt header?)");
    return {};
  }
  // Into `values`, whose memory is reused: a step's read of a 5 M-node variable into fresh
  // memory costs 40 MB of page faults.
  Status read_doubles(int var, const std::string& name, std::span<const size_t> start,
                      std::span<const size_t> count, std::vector<double>& values) const {
    if (classic_ && classic_->reads(var)) return classic_->read(var, name, start, count, values);
    const std::lock_guard<std::mutex> netcdf(netcdf_);
    size_t total = 1;
    for (size_t c : count) total *= c;
    DYNPM_RETURN_IF_ERROR(check_count(var, name, total));
    values.resize(total);
    if (total == 0) return {};
    if (int rc = nc_get_vara_double(id_, var, start.data(), count.data(), values.data());
        rc != NC_NOERR)
      return error(name, rc);
    return {};
  }
  Result<std::vector<double>> doubles(int var, const std::string& name,
                                      std::span<const size_t> start,
                                      std::span<const size_t> count) const {
    std::vector<double> values;
    DYNPM_RETURN_IF_ERROR(read_doubles(var, name, start, count, values));
    return values;
  }
  // The whole variable.
  Result<std::vector<double>> doubles(int var, const std::string& name) const {
    auto dims = shape(var, name);
    if (!dims) return dims.status();
    std::vector<size_t> start(dims->size(), 0);
    return doubles(var, name, start, *dims);
  }
  Result<std::vector<long long>> integers(int var, const std::string& name) const {
    auto dims = shape(var, name);
    if (!dims) return dims.status();
    size_t total = 1;
    for (size_t c : *dims) total *= c;
    DYNPM_RETURN_IF_ERROR(check_count(var, name, total));
    std::vector<long long> values(total);
    if (total == 0) return values;
    if (int rc = nc_get_var_longlong(id_, var, values.data()); rc != NC_NOERR)
      return error(name, rc);
    return values;
  }
  std::string text_attribute(int var, const char* attribute) const {
    size_t len = 0;
    if (nc_inq_attlen(id_, var, attribute, &len) != NC_NOERR || len > 4096) return "";
    std::string s(len, '\0');
    if (nc_get_att_text(id_, var, attribute, s.data()) != NC_NOERR) return "";
    return trimmed(s);
  }

 private:
  std::string path_;
  int id_;
  uint64_t file_size_;
  bool compressed_;
  std::optional<ClassicValues> classic_;
  mutable std::mutex netcdf_;  // netCDF's C library is not safe on several threads
};

// Where a nodal variable's values for one step live.
struct NodalVariable {
  std::string name;
  int var = -1;
  std::string var_name;
  bool combined = false;  // vals_nod_var[time][index][node]
  size_t index = 0;
};

// The element each face comes from: its block (0-based) and its index in the block.
struct FaceOrigin {
  uint32_t block;
  uint32_t element;
};

// An element variable: per block, its netCDF variable (-1 where the block has none).
struct ElementVariable {
  std::string name;
  std::vector<int> block_var;
};

// What the faces need to show element variables.
struct ElementData {
  std::vector<size_t> block_sizes;  // num_el_in_blk<b>
  std::vector<FaceOrigin> origins;  // per face
  std::vector<ElementVariable> variables;
};

class ExodusSource final : public FrameSource {
 public:
  ExodusSource(std::shared_ptr<const NcFile> file, size_t node_count, std::vector<uint32_t> kept,
               std::vector<float> coordinates, std::vector<double> times,
               std::vector<NodalVariable> displacement, std::vector<NodalVariable> fields,
               ElementData elements)
      : file_(std::move(file)),
        node_count_(node_count),
        kept_(std::move(kept)),
        coordinates_(std::move(coordinates)),
        times_(std::move(times)),
        displacement_(std::move(displacement)),
        fields_(std::move(fields)),
        elements_(std::move(elements)) {}

  uint32_t vertex_count() const override { return static_cast<uint32_t>(coordinates_.size() / 3); }
  size_t step_count() const override { return std::max<size_t>(times_.size(), 1); }
  bool parallel_reads() const override { return file_->parallel_reads(); }
  double step_time(size_t t) const override { return times_.empty() ? 0.0 : times_[t]; }

  Status read_step(size_t t, std::span<float> out) const override {
    assert(t < step_count() && out.size() == coordinates_.size());
    std::copy(coordinates_.begin(), coordinates_.end(), out.begin());
    if (times_.empty()) return {};
    for (size_t axis = 0; axis < displacement_.size(); ++axis)
      DYNPM_RETURN_IF_ERROR(read_nodal(displacement_[axis], t, [&](size_t v, double value) {
        out[3 * v + axis] += static_cast<float>(value);
      }));
    return {};
  }

  // The nodal variables, then the element variables.
  std::vector<FieldInfo> fields() const override {
    std::vector<FieldInfo> infos;
    for (const auto& f : fields_) infos.push_back({f.name, FieldLocation::kNode, {}});
    for (const auto& f : elements_.variables)
      infos.push_back({f.name, FieldLocation::kElement, {}});
    return infos;
  }
  Status read_field(size_t field, size_t t, std::span<float> out) const override {
    assert(field < fields_.size() + elements_.variables.size());
    if (times_.empty()) {
      std::fill(out.begin(), out.end(), 0.0f);
      return {};
    }
    if (field >= fields_.size())
      return read_element(elements_.variables[field - fields_.size()], t, out);
    assert(out.size() == vertex_count());
    return read_nodal(fields_[field], t,
                      [&](size_t v, double value) { out[v] = static_cast<float>(value); });
  }

 private:
  // One step of a nodal variable: use(v, value) for every vertex v, with its node's value, in
  // vertex order. Read a slab of nodes at a time into this thread's buffer, reused: a whole step
  // held 8 B per node for each reading thread for the rest of the run. A compressed file is
  // read a step at a time (a slab would decompress its chunk again).
  template <class Use>
  Status read_nodal(const NodalVariable& nodal, size_t t, Use&& use) const {
    constexpr size_t kSlabNodes = size_t{1} << 16;
    thread_local std::vector<double> values;
    const std::string name = nodal.var_name + " (" + nodal.name + ")";
    const size_t slab = file_->compressed() ? std::max<size_t>(node_count_, 1) : kSlabNodes;
    const size_t vertices = vertex_count();
    size_t v = 0;  // the next vertex: kept_ ascends
    for (size_t first = 0; first < node_count_; first += slab) {
      const size_t count = std::min(slab, node_count_ - first);
      if (nodal.combined) {
        const size_t start[3] = {t, nodal.index, first}, counts[3] = {1, 1, count};
        DYNPM_RETURN_IF_ERROR(file_->read_doubles(nodal.var, name, start, counts, values));
      } else {
        const size_t start[2] = {t, first}, counts[2] = {1, count};
        DYNPM_RETURN_IF_ERROR(file_->read_doubles(nodal.var, name, start, counts, values));
      }
      if (kept_.empty())
        for (size_t i = 0; i < count; ++i) use(first + i, values[i]);
      else
        for (; v < vertices && kept_[v] < first + count; ++v) use(v, values[kept_[v] - first]);
    }
    return {};
  }

  // One value per face: its element's, each block's values read once.
  Status read_element(const ElementVariable& variable, size_t t, std::span<float> out) const {
    assert(out.size() == elements_.origins.size());
    thread_local std::vector<std::vector<double>> blocks;  // reused, as read_nodal's
    blocks.resize(elements_.block_sizes.size());
    for (auto& block : blocks) block.clear();
    std::vector<bool> used(blocks.size(), false);
    for (const FaceOrigin& o : elements_.origins) used[o.block] = true;
    for (size_t b = 0; b < blocks.size(); ++b) {
      if (!used[b] || variable.block_var[b] < 0) continue;
      const size_t start[2] = {t, 0}, count[2] = {1, elements_.block_sizes[b]};
      DYNPM_RETURN_IF_ERROR(file_->read_doubles(
          variable.block_var[b],
          "vals_elem_var eb" + std::to_string(b + 1) + " (" + variable.name + ")", start, count,
          blocks[b]));
    }
    for (size_t i = 0; i < out.size(); ++i) {
      const FaceOrigin o = elements_.origins[i];
      out[i] = blocks[o.block].empty() ? 0.0f : static_cast<float>(blocks[o.block][o.element]);
    }
    return {};
  }

  std::shared_ptr<const NcFile> file_;
  size_t node_count_;
  std::vector<uint32_t> kept_;
  std::vector<float> coordinates_;
  std::vector<double> times_;
  std::vector<NodalVariable> displacement_;
  std::vector<NodalVariable> fields_;
  ElementData elements_;
};

// The displacement component (0, 1, 2) a nodal variable name stands for, if it is one:
// DISPL_X, DISP_X, DISPLX, DISPX, DISPLACEMENT_X, displacement_x, … .
std::optional<size_t> displacement_axis(const std::string& name) {
  const std::string u = upper(name);
  if (!u.starts_with("DISP") || u.size() < 5) return std::nullopt;
  std::string stem = u.substr(0, u.size() - 1);
  while (!stem.empty() && (stem.back() == '_' || stem.back() == '-')) stem.pop_back();
  if (stem != "DISP" && stem != "DISPL" && stem != "DISPLACEMENT") return std::nullopt;
  const char axis = u.back();
  if (axis < 'X' || axis > 'Z') return std::nullopt;
  return static_cast<size_t>(axis - 'X');
}

enum class BlockKind { kFace, kSolid, kIgnored };

struct BlockType {
  BlockKind kind = BlockKind::kIgnored;
  int corners = 0;  // face: 3 or 4
  SolidKind solid = SolidKind::kHex;
};

BlockType block_type(const std::string& elem_type, size_t nodes_per_element) {
  const std::string t = upper(elem_type);
  auto face = [&](int corners) {
    return nodes_per_element >= size_t(corners) ? BlockType{BlockKind::kFace, corners}
                                                : BlockType{};
  };
  auto solid = [&](SolidKind kind) {
    return nodes_per_element >= size_t(corner_count(kind)) ? BlockType{BlockKind::kSolid, 0, kind}
                                                           : BlockType{};
  };
  if (t.starts_with("TRI")) return face(3);  // TRI, TRI3, TRIANGLE, TRISHELL, TRI6, …
  if (t.starts_with("QUAD")) return face(4);
  if (t.starts_with("SHELL")) return nodes_per_element == 3 ? face(3) : face(4);
  if (t.starts_with("HEX")) return solid(SolidKind::kHex);
  if (t.starts_with("TET")) return solid(SolidKind::kTet);
  if (t.starts_with("WEDGE")) return solid(SolidKind::kWedge);
  if (t.starts_with("PYRA")) return solid(SolidKind::kPyramid);
  return {};
}

// ---------------------------------------------------------------------------------------------
// read_exodus()'s phases

// The node coordinates, one array per axis (num_dim of them, num_nodes values each).
Result<std::vector<std::vector<double>>> read_coordinates(const NcFile& nc,
                                                          const std::string& path) {
  const auto node_count = nc.dim("num_nodes");
  const auto dims = nc.dim("num_dim");
  if (!node_count || !dims)
    return Status::error(path + ": no num_nodes or num_dim dimension: not an Exodus II file");
  if (*dims < 1 || *dims > 3)
    return Status::error(path + ": num_dim is " + std::to_string(*dims) + " (expected 2 or 3)");
  if (*node_count >= kNoVertex) return Status::error(path + ": too many nodes");
  const size_t n = *node_count;
  std::vector<std::vector<double>> axes;
  if (auto coord = nc.var("coord")) {
    auto all = nc.doubles(*coord, "coord");
    if (!all) return all.status();
    if (all->size() != *dims * n)
      return Status::error(path + ": coord: " + std::to_string(all->size()) +
                           " values, expected num_dim × num_nodes");
    for (size_t a = 0; a < *dims; ++a)
      axes.emplace_back(all->begin() + a * n, all->begin() + (a + 1) * n);
    return axes;
  }
  for (size_t a = 0; a < *dims; ++a) {
    const std::string name = std::string("coord") + "xyz"[a];
    auto var = nc.var(name);
    if (!var) return Status::error(path + ": no variable " + name + " (node coordinates)");
    auto values = nc.doubles(*var, name);
    if (!values) return values.status();
    if (values->size() != n)
      return Status::error(path + ": " + name + ": " + std::to_string(values->size()) +
                           " values for " + std::to_string(n) + " nodes");
    axes.push_back(std::move(values).value());
  }
  return axes;
}

// The user numbers of nodes and elements and the block ids (the parts); empty where the file
// has none.
struct UserNumbers {
  std::vector<long long> node_ids, element_ids, block_ids;
};

Result<UserNumbers> read_user_numbers(const NcFile& nc) {
  UserNumbers numbers;
  for (auto [name, into] : {std::pair{"node_num_map", &numbers.node_ids},
                            {"elem_num_map", &numbers.element_ids},
                            {"eb_prop1", &numbers.block_ids}})
    if (auto var = nc.var(name)) {
      auto ids = nc.integers(*var, name);
      if (!ids) return ids.status();
      *into = std::move(ids).value();
    }
  return numbers;
}

// Block b's part id: its eb_prop1 id, else its number from 1.
int32_t block_part(const UserNumbers& numbers, size_t b) {
  return b < numbers.block_ids.size() ? static_cast<int32_t>(numbers.block_ids[b])
                                      : static_cast<int32_t>(b + 1);
}

// The element blocks: shells and 2-D elements as faces, solids as their outer faces, the rest
// ignored with a warning.
Status read_blocks(const NcFile& nc, const std::string& path, const UserNumbers& numbers,
                   const ReadOptions& options, Topology& topology, ElementData& elements) {
  const size_t n = topology.vertex_count;
  const size_t block_count = nc.dim("num_el_blk").value_or(0);
  if (block_count > kNoVertex)
    return Status::error(path + ": num_el_blk " + std::to_string(block_count) +
                         " is not plausible");
  SolidSurface solids;
  std::vector<FaceOrigin> cell_origins;
  elements.block_sizes.assign(block_count, 0);
  size_t element = 0, ignored = 0, degenerate = 0;
  std::vector<std::string> ignored_types;
  // The shells' faces reserved, not grown: each doubling of an array of a megabyte or more
  // would be a fresh mapping, its pages faulted in again.
  size_t shells = 0;
  for (size_t b = 0; b < block_count; ++b) {
    const std::string suffix = std::to_string(b + 1), var_name = "connect" + suffix;
    const auto var = nc.var(var_name);
    if (!var) continue;
    const auto shape = nc.shape(*var, var_name);
    const size_t in_block = nc.dim("num_el_in_blk" + suffix).value_or(0);
    // What the loop below refuses, or could not be in the file, reserves nothing.
    if (!shape || shape->size() != 2 || (*shape)[0] != in_block || in_block >= kNoVertex ||
        !nc.check_count(*var, var_name, in_block).ok())
      continue;
    const std::string elem_type = nc.text_attribute(*var, "elem_type");
    if (block_type(elem_type, (*shape)[1]).kind == BlockKind::kFace) shells += in_block;
  }
  if (shells < kNoVertex) {
    topology.reserve_faces(topology.faces.size() + shells);
    elements.origins.reserve(elements.origins.size() + shells);
  }
  for (size_t b = 0; b < block_count; ++b) {
    const std::string suffix = std::to_string(b + 1);
    const size_t in_block = nc.dim("num_el_in_blk" + suffix).value_or(0);
    const std::string var_name = "connect" + suffix;
    const auto var = nc.var(var_name);
    if (in_block == 0 || !var) continue;
    if (in_block >= kNoVertex)
      return Status::error(path + ": num_el_in_blk" + suffix + " is not plausible");
    elements.block_sizes[b] = in_block;
    auto shape = nc.shape(*var, var_name);
    if (!shape) return shape.status();
    if (shape->size() != 2 || (*shape)[0] != in_block)
      return Status::error(path + ": " + var_name + ": expected num_el_in_blk" + suffix +
                           " × num_nod_per_el" + suffix + " node numbers");
    const size_t per_element = (*shape)[1];
    const std::string elem_type = nc.text_attribute(*var, "elem_type");
    const BlockType type = block_type(elem_type, per_element);
    const int32_t part = block_part(numbers, b);
    if (type.kind == BlockKind::kIgnored) {
      ignored += in_block;
      if (std::find(ignored_types.begin(), ignored_types.end(), elem_type) == ignored_types.end())
        ignored_types.push_back(elem_type.empty() ? "(no elem_type)" : elem_type);
      element += in_block;
      continue;
    }
    auto connect = nc.integers(*var, var_name);
    if (!connect) return connect.status();
    for (size_t e = 0; e < in_block; ++e, ++element) {
      const long long* nodes = connect->data() + e * per_element;
      const int corners = type.kind == BlockKind::kFace ? type.corners : corner_count(type.solid);
      std::array<uint32_t, 8> v{};
      for (int k = 0; k < corners; ++k) {
        if (nodes[k] < 1 || static_cast<unsigned long long>(nodes[k]) > n)
          return Status::error(path + ": " + var_name + ": element " + std::to_string(e + 1) +
                               " names node " + std::to_string(nodes[k]) + ", but there are " +
                               std::to_string(n) + " nodes");
        v[size_t(k)] = static_cast<uint32_t>(nodes[k] - 1);
      }
      const int64_t user_id = element < numbers.element_ids.size()
                                  ? numbers.element_ids[element]
                                  : static_cast<int64_t>(element + 1);
      const FaceOrigin origin{static_cast<uint32_t>(b), static_cast<uint32_t>(e)};
      if (type.kind == BlockKind::kSolid) {
        solids.add_cell(type.solid, std::span(v.data(), size_t(corners)), part, user_id);
        cell_origins.push_back(origin);
        continue;
      }
      const auto face = distinct_corner_face(std::span(v.data(), size_t(corners)));
      if (!face) {
        ++degenerate;
        continue;
      }
      topology.add_face(*face, part, user_id);
      elements.origins.push_back(origin);
    }
  }
  std::vector<uint32_t> cells;
  const size_t outer = solids.append_outer_faces(topology, &cells);
  for (uint32_t cell : cells) elements.origins.push_back(cell_origins[cell]);
  if (options.warn) {
    if (solids.cell_count() > 0)
      options.warn(path + ": " + std::to_string(solids.cell_count()) +
                   " solid elements given as their " + std::to_string(outer) + " outer faces");
    if (ignored > 0) {
      std::string types;
      for (const auto& t : ignored_types) types += (types.empty() ? "" : ", ") + t;
      options.warn(path + ": " + std::to_string(ignored) + " elements ignored (" + types +
                   "): neither shells nor solids");
    }
    if (degenerate > 0)
      options.warn(path + ": " + std::to_string(degenerate) +
                   " faces with fewer than 3 distinct nodes skipped");
  }
  if (topology.faces.empty())
    return Status::error(path + ": no shell faces and no solid elements (" +
                         std::to_string(element) + " elements in " + std::to_string(block_count) +
                         " blocks, none of them shells or solids)");
  return {};
}

// The step times; a step whose time was never written (netCDF's fill value) gets its index.
Result<std::vector<double>> read_times(const NcFile& nc, const std::string& path,
                                       const ReadOptions& options) {
  std::vector<double> times;
  const size_t steps = nc.dim("time_step").value_or(0);
  if (steps > 0) {
    auto var = nc.var("time_whole");
    if (var) {
      auto values = nc.doubles(*var, "time_whole");
      if (!values) return values.status();
      times = std::move(values).value();
    }
    times.resize(steps, NC_FILL_DOUBLE);
    for (size_t t = 0; t < steps; ++t)
      if (!std::isfinite(times[t]) || std::abs(times[t]) >= 0.99 * NC_FILL_FLOAT)
        times[t] = static_cast<double>(t);
  } else if (options.warn) {
    options.warn(path + ": no time step; the mesh is given as one step at time 0");
  }
  return times;
}

// The names of a char[count][length] variable (name_nod_var, name_elem_var); empty names where
// the variable is missing or not of that shape.
Result<std::vector<std::string>> read_names(const NcFile& nc, const char* variable, size_t count) {
  std::vector<std::string> names(count);
  const auto var = nc.var(variable);
  if (!var) return names;
  auto shape = nc.shape(*var, variable);
  if (!shape) return shape.status();
  if (shape->size() != 2 || (*shape)[0] != count || (*shape)[1] > 4096) return names;
  std::string text(count * (*shape)[1], '\0');
  if (int rc = nc_get_var_text(nc.id(), *var, text.data()); rc != NC_NOERR)
    return nc.error(variable, rc);
  for (size_t i = 0; i < count; ++i) names[i] = trimmed(text.substr(i * (*shape)[1], (*shape)[1]));
  return names;
}

// The nodal variables: the displacement components (all of them, or none), and the fields.
struct NodalVariables {
  std::vector<NodalVariable> displacement, fields;
};

Result<NodalVariables> read_nodal_variables(const NcFile& nc, const std::string& path, size_t n,
                                            size_t dims, size_t steps, const ReadOptions& options) {
  NodalVariables out;
  std::vector<NodalVariable>& displacement = out.displacement;
  std::vector<NodalVariable>& fields = out.fields;
  displacement.resize(dims);
  const size_t variable_count = nc.dim("num_nod_var").value_or(0);
  if (variable_count > 0 && steps > 0) {
    auto read = read_names(nc, "name_nod_var", variable_count);
    if (!read) return read.status();
    const std::vector<std::string>& names = *read;
    const auto combined = nc.var("vals_nod_var");
    for (size_t i = 0; i < variable_count; ++i) {
      NodalVariable nodal;
      nodal.name = names[i].empty() ? "nodal variable " + std::to_string(i + 1) : names[i];
      if (combined) {
        nodal.var = *combined;
        nodal.var_name = "vals_nod_var";
        nodal.combined = true;
        nodal.index = i;
      } else {
        nodal.var_name = "vals_nod_var" + std::to_string(i + 1);
        const auto var = nc.var(nodal.var_name);
        if (!var) continue;
        nodal.var = *var;
      }
      auto shape = nc.shape(nodal.var, nodal.var_name);
      if (!shape) return shape.status();
      const bool fits =
          nodal.combined ? shape->size() == 3 && (*shape)[1] == variable_count && (*shape)[2] == n
                         : shape->size() == 2 && (*shape)[1] == n;
      if (!fits) {
        if (options.warn)
          options.warn(path + ": " + nodal.var_name + " (" + nodal.name +
                       "): not one value per node and step; skipped");
        continue;
      }
      const auto axis = displacement_axis(nodal.name);
      if (axis && *axis < dims && displacement[*axis].var < 0)
        displacement[*axis] = nodal;
      else
        fields.push_back(nodal);
    }
  }
  const bool displaced = std::all_of(displacement.begin(), displacement.end(),
                                     [](const NodalVariable& d) { return d.var >= 0; });
  if (!displaced) {
    // A partial set of components is a field like any other.
    for (auto& d : displacement)
      if (d.var >= 0) fields.push_back(d);
    displacement.clear();
    if (steps > 1 && options.warn)
      options.warn(path +
                   ": no nodal displacement (DISPL_X/Y/Z): every step has the initial "
                   "coordinates");
  }
  return out;
}

// The element variables: per block, vals_elem_var<v>eb<b> where the truth table (elem_var_tab)
// says the block has it; each checked to hold one value per element of its block and step.
Status read_element_variables(const NcFile& nc, const std::string& path, size_t steps,
                              const ReadOptions& options, ElementData& elements) {
  const size_t count = nc.dim("num_elem_var").value_or(0);
  const size_t blocks = elements.block_sizes.size();
  if (count == 0 || steps == 0) return {};
  if (count > 100000)
    return Status::error(path + ": num_elem_var " + std::to_string(count) + " is not plausible");
  auto names = read_names(nc, "name_elem_var", count);
  if (!names) return names.status();
  std::vector<long long> table;
  if (auto var = nc.var("elem_var_tab")) {
    auto values = nc.integers(*var, "elem_var_tab");
    if (!values) return values.status();
    if (values->size() != blocks * count)
      return Status::error(
          path + ": elem_var_tab: " + std::to_string(values->size()) +
          " entries, expected num_el_blk × num_elem_var = " + std::to_string(blocks * count));
    table = std::move(values).value();
  }
  std::vector<bool> used(blocks, false);
  for (const FaceOrigin& o : elements.origins) used[o.block] = true;
  for (size_t v = 0; v < count; ++v) {
    ElementVariable variable{
        (*names)[v].empty() ? "element variable " + std::to_string(v + 1) : (*names)[v],
        std::vector<int>(blocks, -1)};
    std::string lacking;
    bool any = false;
    for (size_t b = 0; b < blocks; ++b) {
      if (!used[b]) continue;
      const std::string name =
          "vals_elem_var" + std::to_string(v + 1) + "eb" + std::to_string(b + 1);
      const auto var = nc.var(name);
      if (!var || (!table.empty() && table[b * count + v] == 0)) {
        lacking += (lacking.empty() ? "" : ", ") + std::to_string(b + 1);
        continue;
      }
      auto shape = nc.shape(*var, name);
      if (!shape) return shape.status();
      if (shape->size() != 2 || (*shape)[0] != steps || (*shape)[1] != elements.block_sizes[b])
        return Status::error(path + ": " + name + " (" + variable.name +
                             "): expected time_step × num_el_in_blk" + std::to_string(b + 1) +
                             " = " + std::to_string(steps) + " × " +
                             std::to_string(elements.block_sizes[b]) + " values");
      variable.block_var[b] = *var;
      any = true;
    }
    if (!any) continue;
    if (!lacking.empty() && options.warn)
      options.warn(path + ": element variable " + variable.name + " is 0 on the faces of block" +
                   (lacking.find(',') == std::string::npos ? " " : "s ") + lacking +
                   ", which do not hold it");
    elements.variables.push_back(std::move(variable));
  }
  return {};
}

// Everything from nc_open on; in dynpm's process for classic files, in a child for the others.
// `classic`: a classic file's layout, whose steps are then read without netCDF.
Result<AnimationStream> read_exodus(const std::string& path, uint64_t file_size,
                                    const ReadOptions& options,
                                    std::optional<ClassicLayout> classic) {
  int id = -1;
  if (int rc = nc_open(path.c_str(), NC_NOWRITE, &id); rc != NC_NOERR)
    return Status::error(path + ": not a readable netCDF (Exodus II) file: " + nc_strerror(rc));
  int format = 0, mode = 0;
  nc_inq_format_extended(id, &format, &mode);
  std::optional<ClassicValues> values =
      classic ? ClassicValues::open(path, std::move(*classic)) : std::nullopt;
  auto file = std::make_shared<const NcFile>(path, id, file_size, format != NC_FORMATX_NC3,
                                             std::move(values));
  const NcFile& nc = *file;
  // 1. The nodes' coordinates, and the user numbers of nodes, elements and blocks.
  auto axes = read_coordinates(nc, path);
  if (!axes) return axes.status();
  const size_t n = (*axes)[0].size();
  auto numbers = read_user_numbers(nc);
  if (!numbers) return numbers.status();
  Topology topology = Topology::with_vertices(static_cast<uint32_t>(n));
  if (numbers->node_ids.size() == n)
    topology.node_ids.assign(numbers->node_ids.begin(), numbers->node_ids.end());
  // 2. The element blocks: faces, and solids as their outer faces.
  ElementData elements;
  DYNPM_RETURN_IF_ERROR(read_blocks(nc, path, *numbers, options, topology, elements));
  // The blocks' names (eb_names) name the parts that have faces.
  const size_t block_count = elements.block_sizes.size();
  auto block_names = read_names(nc, "eb_names", block_count);
  if (!block_names) return block_names.status();
  const std::vector<int32_t> parts = topology.parts();
  for (size_t b = 0; b < block_count; ++b)
    if (std::binary_search(parts.begin(), parts.end(), block_part(*numbers, b)))
      topology.set_part_name(block_part(*numbers, b), (*block_names)[b]);
  // 3. The nodes no face uses are dropped; the others' coordinates are the initial positions.
  std::vector<uint32_t> kept = drop_unused_vertices(topology);
  std::vector<float> coordinates(size_t{topology.vertex_count} * 3, 0.0f);
  for (size_t v = 0; v < topology.vertex_count; ++v)
    for (size_t a = 0; a < axes->size(); ++a)
      coordinates[3 * v + a] = static_cast<float>((*axes)[a][kept.empty() ? v : kept[v]]);
  // 4. The step times and the nodal variables: displacements move the nodes, the rest are
  //    fields.
  auto times = read_times(nc, path, options);
  if (!times) return times.status();
  auto nodal = read_nodal_variables(nc, path, n, axes->size(), times->size(), options);
  if (!nodal) return nodal.status();
  DYNPM_RETURN_IF_ERROR(read_element_variables(nc, path, times->size(), options, elements));
  // The faces' elements serve only to read element variables: without any, 8 B per face freed.
  if (elements.variables.empty()) std::vector<FaceOrigin>().swap(elements.origins);
  // 5. The steps stay in the file, read one by one.
  AnimationStream stream;
  stream.topology = std::move(topology);
  stream.frames = std::make_unique<ExodusSource>(
      std::move(file), n, std::move(kept), std::move(coordinates), std::move(times).value(),
      std::move(nodal->displacement), std::move(nodal->fields), std::move(elements));
  return stream;
}

}  // namespace

Result<AnimationStream> open_exodus(const std::string& path, const ReadOptions& options) {
  std::error_code ec;
  const uint64_t file_size = std::filesystem::file_size(path, ec);
  if (ec) return Status::error(path + ": " + ec.message());
  if (const char version = classic_version(path)) {
    auto layout = check_classic_header(path, file_size, version);
    if (!layout) return layout.status();
    return read_exodus(path, file_size, options, std::move(layout).value());
  }
  return open_in_child(path, options, "HDF5", [&](const ReadOptions& child_options) {
    return read_exodus(path, file_size, child_options, std::nullopt);
  });
}

}  // namespace dynpm::io
