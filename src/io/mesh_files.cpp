// Format detection, one-file reads and writes, and animations as sequences of per-step files.
#include <glob.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <filesystem>

#include "d3plot.h"
#include "file_bytes.h"
#include "formats.h"

namespace dynpm {
namespace {

std::string lowercase_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

Result<io::ParsedMesh> parse_mesh_file(const std::string& path, const ReadOptions& options,
                                       io::FaceParsing faces = io::FaceParsing::kParse) {
  auto format = detect_format(path);
  if (!format) return format.status();
  if (*format == FileFormat::kFrd || *format == FileFormat::kExodus ||
      *format == FileFormat::kD3plot || *format == FileFormat::kPvd)
    return Status::error(path + ": a " + std::string(to_string(*format)) +
                         " file holds every time step, not one step of a sequence; give it alone");
  auto bytes = io::read_file(path);
  if (!bytes) return bytes.status();
  if (bytes->empty()) return Status::error(path + ": the file is empty");
  if (*format == FileFormat::kPly) return io::parse_ply(*bytes, path, options, faces);
  if (*format == FileFormat::kVtk) return io::parse_vtk(*bytes, path, options);
  if (*format == FileFormat::kVtu) return io::parse_vtu(*bytes, path, options);
  return io::parse_obj(*bytes, path, options, faces);
}

std::string face_text(const Face& f) {
  std::string s;
  for (uint32_t c : f.v)
    if (c != kNoVertex) {
      if (!s.empty()) s += ' ';
      s += std::to_string(c);
    }
  return "(" + s + ")";
}

// Step t of an animation lives in paths[t]; each read parses that file and checks that it
// repeats the first file's faces. OBJ and PLY files are checked cheaply: their face bytes are
// hashed, not parsed, and only a file whose hash differs from the first file's is parsed whole
// and compared face by face (the same faces written otherwise pass; others fail, named). Reads
// keep no state, so several threads may read at once.
class FileSequence final : public FrameSource {
 public:
  // `topology`: the first file's, to compare the others' with (none for a single file).
  FileSequence(std::vector<std::string> paths, std::vector<double> times, uint32_t vertex_count,
               std::shared_ptr<const Topology> topology, std::vector<float> first_step,
               std::vector<io::MeshField> first_fields, std::optional<uint64_t> first_faces_hash,
               ReadOptions options)
      : paths_(std::move(paths)),
        times_(std::move(times)),
        vertex_count_(vertex_count),
        topology_(std::move(topology)),
        first_step_(std::move(first_step)),
        first_fields_(std::move(first_fields)),
        first_faces_hash_(first_faces_hash),
        options_(std::move(options)) {}

  uint32_t vertex_count() const override { return vertex_count_; }
  size_t step_count() const override { return paths_.size(); }
  double step_time(size_t t) const override { return times_[t]; }
  bool parallel_reads() const override { return true; }

  Status read_step(size_t t, std::span<float> out) const override {
    assert(t < paths_.size() && out.size() == size_t{vertex_count()} * 3);
    if (t == 0) {
      std::copy(first_step_.begin(), first_step_.end(), out.begin());
      return {};
    }
    auto mesh = parse_later_step(t);
    if (!mesh) return mesh.status();
    std::copy(mesh->positions.begin(), mesh->positions.end(), out.begin());
    return {};
  }

  // The fields of the first file (VTK point and cell data), looked up by name and location in
  // the others.
  std::vector<FieldInfo> fields() const override {
    std::vector<FieldInfo> infos;
    for (const io::MeshField& f : first_fields_) infos.push_back({f.name, f.location, {}});
    return infos;
  }
  Status read_field(size_t field, size_t t, std::span<float> out) const override {
    assert(field < first_fields_.size() && t < paths_.size() &&
           out.size() == first_fields_[field].values.size());
    const std::string& name = first_fields_[field].name;
    const FieldLocation location = first_fields_[field].location;
    if (t == 0) {
      std::copy(first_fields_[field].values.begin(), first_fields_[field].values.end(),
                out.begin());
      return {};
    }
    auto mesh = parse_later_step(t);
    if (!mesh) return mesh.status();
    for (const io::MeshField& f : mesh->fields)
      if (f.name == name && f.location == location) {
        std::copy(f.values.begin(), f.values.end(), out.begin());
        return {};
      }
    return Status::error(paths_[t] + ": no " +
                         (location == FieldLocation::kNode ? "point" : "cell") + " field '" + name +
                         "' (" + paths_[0] + " has it; every time step must have the same fields)");
  }

 private:
  // Step t's file (t > 0), parsed, with the first file's faces: the same face bytes, or else
  // the same faces face by face.
  Result<io::ParsedMesh> parse_later_step(size_t t) const {
    if (first_faces_hash_) {
      auto mesh = parse_mesh_file(paths_[t], options_, io::FaceParsing::kHashOnly);
      if (!mesh) return mesh;
      if (mesh->faces_hash == first_faces_hash_ && mesh->topology.vertex_count == vertex_count_)
        return mesh;
    }
    auto mesh = parse_mesh_file(paths_[t], options_);
    if (mesh) DYNPM_RETURN_IF_ERROR(check_same_faces(t, *mesh));
    return mesh;
  }

  Status check_same_faces(size_t t, const io::ParsedMesh& mesh) const {
    const Topology& first = *topology_;
    const std::string& path = paths_[t];
    if (mesh.topology.vertex_count != first.vertex_count)
      return Status::error(path + ": " + std::to_string(mesh.topology.vertex_count) +
                           " vertices, but " + paths_[0] + " has " +
                           std::to_string(first.vertex_count) +
                           " (every time step must have the same vertices)");
    if (mesh.topology.faces.size() != first.faces.size())
      return Status::error(path + ": " + std::to_string(mesh.topology.faces.size()) +
                           " faces, but " + paths_[0] + " has " +
                           std::to_string(first.faces.size()) +
                           " (every time step must have the same faces)");
    for (size_t fi = 0; fi < first.faces.size(); ++fi) {
      if (mesh.topology.faces[fi] == first.faces[fi]) continue;
      std::string place = mesh.places_are_lines ? ":" : ": byte ";
      place += std::to_string(mesh.face_places[fi]);
      return Status::error(path + place + ": face " + std::to_string(fi) + " is " +
                           face_text(mesh.topology.faces[fi]) + " here but " +
                           face_text(first.faces[fi]) + " in " + paths_[0] +
                           " (vertex numbers from 0; every time step must have the same faces)");
    }
    return {};
  }

  std::vector<std::string> paths_;
  std::vector<double> times_;
  uint32_t vertex_count_;
  std::shared_ptr<const Topology> topology_;
  std::vector<float> first_step_;
  std::vector<io::MeshField> first_fields_;
  std::optional<uint64_t> first_faces_hash_;  // OBJ and PLY
  ReadOptions options_;
};

// The time a step file states in its header comments, without reading the whole file; an
// error names the file and line of a time note that is not a finite number.
Result<std::optional<double>> peek_time(const std::string& path) {
  auto head = io::read_file_head(path, 512);
  if (!head) return std::optional<double>();
  std::string_view text = *head;
  auto note = [&](size_t line, std::string_view comment) -> Result<std::optional<double>> {
    auto t = io::time_from_comment(comment);
    if (!t) return Status::error(path + ":" + std::to_string(line) + ": " + t.message());
    return t;
  };
  if (text.starts_with("# vtk DataFile")) {  // the title (second line) may say "time <t>"
    const size_t a = text.find('\n');
    if (a == std::string_view::npos) return std::optional<double>();
    return note(2, text.substr(a + 1, text.find('\n', a + 1) - a - 1));
  }
  const bool ply = text.substr(0, 3) == "ply";
  // PLY: comment lines of the header; OBJ: comment lines before the first data line.
  size_t pos = 0;
  for (size_t line = 1; pos < text.size(); ++line) {
    const size_t eol = std::min(text.find('\n', pos), text.size());
    const std::string_view row = text.substr(pos, eol - pos);
    if (ply ? row.starts_with("end_header") : !row.starts_with("#")) break;
    if (!ply || row.starts_with("comment")) {
      auto t = note(line, row);
      if (!t || *t) return t;
    }
    pos = eol + 1;
  }
  return std::optional<double>();
}

}  // namespace

const char* to_string(FileFormat format) {
  switch (format) {
    case FileFormat::kObj: return "OBJ";
    case FileFormat::kPly: return "PLY";
    case FileFormat::kVtk: return "VTK";
    case FileFormat::kVtu: return "VTU";
    case FileFormat::kPvd: return "PVD";
    case FileFormat::kFrd: return "CalculiX FRD";
    case FileFormat::kExodus: return "Exodus II";
    case FileFormat::kD3plot: return "LS-DYNA d3plot";
    case FileFormat::kUnknown: return "unknown";
  }
  return "unknown";
}

const char* to_string(IntegrationPoint point) {
  switch (point) {
    case IntegrationPoint::kMid: return "mid";
    case IntegrationPoint::kTop: return "top";
    case IntegrationPoint::kBottom: return "bottom";
    case IntegrationPoint::kMax: return "max";
  }
  return "mid";
}

bool can_write(FileFormat format) {
  return format == FileFormat::kObj || format == FileFormat::kPly || format == FileFormat::kVtk ||
         format == FileFormat::kVtu;
}

FileFormat format_from_extension(const std::string& path) {
  const std::string ext = lowercase_extension(path);
  if (ext == ".obj") return FileFormat::kObj;
  if (ext == ".ply") return FileFormat::kPly;
  if (ext == ".vtk") return FileFormat::kVtk;
  if (ext == ".vtu") return FileFormat::kVtu;
  if (ext == ".pvd") return FileFormat::kPvd;
  if (ext == ".frd") return FileFormat::kFrd;
  if (ext == ".e" || ext == ".exo" || ext == ".ex2" || ext == ".exii") return FileFormat::kExodus;
  if (std::filesystem::path(path).filename().string().starts_with("d3plot"))
    return FileFormat::kD3plot;
  return FileFormat::kUnknown;
}

Result<FileFormat> detect_format(const std::string& path) {
  auto head = io::read_file_head(path, 64);
  if (!head) return head.status();
  std::string_view text = *head;
  if (text.substr(0, 4) == "ply\n" || text.substr(0, 5) == "ply\r\n") return FileFormat::kPly;
  if (text.substr(0, 14) == "# vtk DataFile") return FileFormat::kVtk;
  // netCDF classic / 64-bit offset / CDF5, or HDF5 (netCDF-4): Exodus II is netCDF.
  if (text.substr(0, 3) == "CDF" || text.substr(0, 8) == "\x89HDF\r\n\x1a\n")
    return FileFormat::kExodus;
  if (text.substr(0, 6) == "    1C") return FileFormat::kFrd;
  if (text.find("<VTKFile") != std::string_view::npos || text.starts_with("<?xml")) {
    auto more = io::read_file_head(path, 4096);
    if (!more) return more.status();
    if (more->find("\"Collection\"") != std::string::npos) return FileFormat::kPvd;
    if (more->find("\"UnstructuredGrid\"") != std::string::npos) return FileFormat::kVtu;
  }
  if (text.starts_with("\x1f\x8b"))
    return Status::error(path + ": is gzip-compressed; gunzip it first");
  // dynpm's own output (docs/FORMAT.md: 0x89 'D' 'P' 'M' …) is no input of a reader.
  const bool dpm_signature = text.size() >= 4 && text[0] == '\x89' && text.substr(1, 3) == "DPM";
  if (dpm_signature || lowercase_extension(path) == ".dpm")
    return Status::error(path +
                         ": a progressive mesh (.dpm) is not a mesh or result input "
                         "('dynpm extract' writes meshes from it, 'dynpm info' describes it)");
  const FileFormat by_name = format_from_extension(path);
  if (by_name != FileFormat::kUnknown) return by_name;
  // LS-DYNA names its results freely (d3plot, qd_d3plot, run7.d3plot): a plausible control
  // block, or "d3plot" in the name for a family's continuation files.
  {
    auto d3plot_head = io::read_file_head(path, io::kD3plotHeadBytes);
    if (!d3plot_head) return d3plot_head.status();
    if (io::looks_like_d3plot(*d3plot_head)) return FileFormat::kD3plot;
  }
  if (std::filesystem::path(path).filename().string().find("d3plot") != std::string::npos)
    return FileFormat::kD3plot;
  return Status::error(path +
                       ": cannot tell the file format (expected OBJ, PLY, VTK, VTU, PVD, "
                       "CalculiX .frd, Exodus II or an LS-DYNA d3plot)");
}

Result<AnimationStream> open_input(std::span<const std::string> paths, const ReadOptions& options) {
  if (paths.empty()) return Status::error("no input file given");
  auto format = detect_format(paths[0]);
  if (!format) return format.status();
  const bool whole_result = *format == FileFormat::kFrd || *format == FileFormat::kExodus ||
                            *format == FileFormat::kD3plot || *format == FileFormat::kPvd;
  if (whole_result && paths.size() > 1)
    return Status::error(paths[1] + ": a " + std::string(to_string(*format)) +
                         " result holds every time step; give it alone");
  switch (*format) {
    case FileFormat::kFrd: return io::open_frd(paths[0], options);
    case FileFormat::kExodus: return io::open_exodus(paths[0], options);
    case FileFormat::kD3plot: return io::open_d3plot(paths[0], options);
    case FileFormat::kPvd: return io::open_vtk_series(paths[0], options);
    default: return open_animation(paths, options);
  }
}

Result<Animation> read_mesh(const std::string& path, const ReadOptions& options) {
  auto mesh = parse_mesh_file(path, options);
  if (!mesh) return mesh.status();
  Animation animation;
  animation.topology = std::move(mesh->topology);
  animation.frames.set_vertex_count(animation.topology.vertex_count);
  animation.frames.add_step(std::move(mesh->positions), mesh->time.value_or(0.0));
  for (io::MeshField& f : mesh->fields)
    animation.fields.push_back(
        ScalarField{std::move(f.name), {std::move(f.values)}, f.location, {}});
  return animation;
}

namespace io {

Result<AnimationStream> open_file_sequence(std::span<const std::string> paths,
                                           std::span<const double> given_times,
                                           const ReadOptions& options) {
  if (paths.empty()) return Status::error("no input file given");
  assert(given_times.empty() || given_times.size() == paths.size());
  // 1. The first file: the mesh, and step 0's positions and fields.
  auto first = parse_mesh_file(paths[0], options);
  if (!first) return first.status();

  // 2. The step times: as given, else each file's time note, else its place in the list.
  std::vector<double> times(given_times.begin(), given_times.end());
  if (times.empty()) {
    times.resize(paths.size());
    times[0] = first->time.value_or(0.0);
    for (size_t t = 1; t < paths.size(); ++t) {
      auto time = peek_time(paths[t]);
      if (!time) return time.status();
      times[t] = time->value_or(static_cast<double>(t));
    }
  }

  // 3. The other files stay on disk, each read when its step is asked for.
  AnimationStream stream;
  // The later files' faces are compared with a copy of the first's (the stream's may be freed
  // by its user); a single file needs none.
  std::shared_ptr<const Topology> topology;
  if (paths.size() > 1) topology = std::make_shared<const Topology>(first->topology);
  const uint32_t vertex_count = first->topology.vertex_count;
  stream.topology = std::move(first->topology);
  // The first step's warnings were given already; the others would repeat them per file.
  ReadOptions quiet = options;
  quiet.warn = nullptr;
  stream.frames = std::make_unique<FileSequence>(
      std::vector<std::string>(paths.begin(), paths.end()), std::move(times), vertex_count,
      std::move(topology), std::move(first->positions), std::move(first->fields), first->faces_hash,
      std::move(quiet));
  return stream;
}

}  // namespace io

Result<AnimationStream> open_animation(std::span<const std::string> paths,
                                       const ReadOptions& options) {
  return io::open_file_sequence(paths, {}, options);
}

Result<Animation> read_animation(std::span<const std::string> paths, const ReadOptions& options) {
  auto stream = open_animation(paths, options);
  if (!stream) return stream.status();
  return load_all_steps(std::move(stream).value());
}

bool natural_less(const std::string& a, const std::string& b) {
  size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    const bool da = std::isdigit(static_cast<unsigned char>(a[i]));
    const bool db = std::isdigit(static_cast<unsigned char>(b[j]));
    if (da && db) {
      size_t ie = i, je = j;
      while (ie < a.size() && std::isdigit(static_cast<unsigned char>(a[ie]))) ++ie;
      while (je < b.size() && std::isdigit(static_cast<unsigned char>(b[je]))) ++je;
      size_t is = i, js = j;  // skip leading zeros, then the longer run is the larger number
      while (is + 1 < ie && a[is] == '0') ++is;
      while (js + 1 < je && b[js] == '0') ++js;
      if (ie - is != je - js) return ie - is < je - js;
      const int c = a.compare(is, ie - is, b, js, je - js);
      if (c != 0) return c < 0;
      if (ie - i != je - j) return ie - i < je - j;  // "01" after "1": a stable tie-break
      i = ie, j = je;
    } else {
      if (a[i] != b[j]) return a[i] < b[j];
      ++i, ++j;
    }
  }
  return a.size() - i < b.size() - j;
}

Result<std::vector<std::string>> expand_inputs(std::span<const std::string> arguments) {
  std::vector<std::string> paths;
  for (const std::string& arg : arguments) {
    std::error_code ec;
    // A file that exists under this very name is that file, even if the name has [ or *.
    const bool literal = std::filesystem::exists(arg, ec);
    if (literal || arg.find_first_of("*?[") == std::string::npos) {
      if (std::filesystem::is_directory(arg, ec))
        return Status::error(arg + ": is a directory; give the files (e.g. '" + arg +
                             "/frame_*.obj')");
      if (!std::filesystem::exists(arg, ec)) return Status::error(arg + ": no such file");
      paths.push_back(arg);
      continue;
    }
    glob_t matches{};
    const int rc = ::glob(arg.c_str(), 0, nullptr, &matches);
    std::vector<std::string> found;
    if (rc == 0)
      for (size_t i = 0; i < matches.gl_pathc; ++i) found.emplace_back(matches.gl_pathv[i]);
    ::globfree(&matches);
    if (found.empty()) return Status::error(arg + ": no file matches this pattern");
    std::sort(found.begin(), found.end(), natural_less);
    paths.insert(paths.end(), found.begin(), found.end());
  }
  return paths;
}

Status write_mesh(const std::string& path, const Topology& topology,
                  std::span<const float> positions, const WriteOptions& options,
                  std::span<const NamedValues> point_fields,
                  std::span<const NamedValues> cell_fields) {
  assert(positions.size() == size_t{topology.vertex_count} * 3);
  std::string bytes;
  switch (format_from_extension(path)) {
    case FileFormat::kObj: bytes = io::write_obj(topology, positions, options); break;
    case FileFormat::kPly:
      bytes = io::write_ply(topology, positions, options, point_fields, cell_fields);
      break;
    case FileFormat::kVtk:
      bytes = io::write_vtk(topology, positions, options, point_fields, cell_fields);
      break;
    case FileFormat::kVtu:
      bytes = io::write_vtu(topology, positions, options, point_fields, cell_fields);
      break;
    default:
      return Status::error(path +
                           ": cannot tell the output format from the extension "
                           "(use .obj, .ply, .vtk or .vtu)");
  }
  return io::write_file_atomically(path, bytes);
}

namespace {

// The "{...}" field of a step pattern: its position, length and zero-padded width.
struct StepField {
  size_t at = std::string::npos, length = 0;
  int width = 0;
};

Result<StepField> find_step_field(const std::string& pattern) {
  const size_t open = pattern.find('{');
  if (open == std::string::npos)
    return Status::error(pattern +
                         ": an output for several steps needs a step field such as "
                         "'frame_{:03d}.obj'");
  const size_t close = pattern.find('}', open);
  if (close == std::string::npos) return Status::error(pattern + ": '{' without '}'");
  if (pattern.find('{', close) != std::string::npos)
    return Status::error(pattern + ": more than one '{...}' step field");
  std::string spec = pattern.substr(open + 1, close - open - 1);
  StepField field{open, close - open + 1, 0};
  if (spec.empty() || spec == ":d") return field;
  if (spec.size() >= 3 && spec[0] == ':' && spec.back() == 'd') {
    const std::string digits = spec.substr(1, spec.size() - 2);
    int width = 0;
    auto [p, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), width);
    if (ec == std::errc() && p == digits.data() + digits.size() && width >= 0 && width <= 12) {
      field.width = width;
      return field;
    }
  }
  return Status::error(pattern + ": unsupported step field '{" + spec +
                       "}' (use {}, {:d} or {:03d})");
}

}  // namespace

bool has_step_field(const std::string& pattern) { return find_step_field(pattern).ok(); }

Result<std::string> step_path(const std::string& pattern, size_t step) {
  auto field = find_step_field(pattern);
  if (!field) return field.status();
  std::string number = std::to_string(step);
  if (static_cast<int>(number.size()) < field->width)
    number.insert(0, static_cast<size_t>(field->width) - number.size(), '0');
  std::string path = pattern;
  path.replace(field->at, field->length, number);
  return path;
}

}  // namespace dynpm
