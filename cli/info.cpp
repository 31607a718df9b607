// dynpm info: what a mesh or animation holds, and whether dynpm can work on it.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <sstream>

#include "args.h"
#include "commands.h"
#include "dynpm/lod.h"
#include "dynpm/text.h"
#include "family_inputs.h"
#include "inputs.h"
#include "json.h"
#include "report.h"

namespace dynpm::cli {
namespace {

const VerbSpec kSpec{
    "info",
    "dynpm info INPUT... [--json] [--problems N] [--split-polygons] [--integration-point P]",
    "Reads a mesh (OBJ, PLY, VTK, VTU), an animation given as one file per time step (a list\n"
    "or a glob such as 'frames/frame_*.obj', sorted naturally) or a result holding every step\n"
    "(CalculiX .frd, .pvd, Exodus II, d3plot) and prints vertices, faces (triangles and\n"
    "quads), time steps, result fields (per node or element, with their range over all steps\n"
    "and unit), edges, boundary, non-manifold edges and vertices,\n"
    "parts, the bounding box over all steps, and the validation result: the paper's (M1)\n"
    "manifold, (M2) inner valence >= 3, (M3) face degree >= 3, and more.\n"
    "Given a progressive mesh (MODEL.dpm), prints its levels, steps, position bound and size;\n"
    "of a family file, its variants (--variant: that variant's steps and times).\n"
    "Exit code: 0 valid, 1 unreadable input, 2 bad usage, 3 read but invalid.",
    {{"--json", "", false, "", "print the result as JSON on stdout"},
     {"--problems", "", true, "N", "list at most N problems of each severity (default 10)"},
     kSplitPolygonsFlag,
     kIntegrationPointFlag,
     kVariantFlag,
     kProgressFlag,
     kQuietFlag}};

// Passes steps through to validate() and extends the bounding box of all steps on the way,
// so every step is read once. validate() reads several steps at once where the source allows
// it: each step's box is its own, merged by box().
class BoxingSource final : public FrameSource {
 public:
  explicit BoxingSource(const FrameSource& source) : source_(source), boxes_(source.step_count()) {}
  uint32_t vertex_count() const override { return source_.vertex_count(); }
  size_t step_count() const override { return source_.step_count(); }
  double step_time(size_t t) const override { return source_.step_time(t); }
  size_t step_float_count(size_t t) const override { return source_.step_float_count(t); }
  bool parallel_reads() const override { return source_.parallel_reads(); }
  std::vector<FieldInfo> fields() const override { return source_.fields(); }
  Status read_field(size_t field, size_t t, std::span<float> out) const override {
    return source_.read_field(field, t, out);
  }
  Status read_step(size_t t, std::span<float> out) const override {
    Status s = source_.read_step(t, out);
    if (s.ok()) boxes_[t].extend(out);
    progress("reading step", ++read_, step_count());
    return s;
  }
  BoundingBox box() const {
    BoundingBox all;
    for (const BoundingBox& b : boxes_) all.extend(b);
    return all;
  }

 private:
  const FrameSource& source_;
  mutable std::vector<BoundingBox> boxes_;
  mutable std::atomic<size_t> read_{0};
};

// A field's range over every step (NaN values left out; NaN bounds when there is no value).
struct FieldRange {
  FieldInfo info;
  float min = std::numeric_limits<float>::quiet_NaN();
  float max = std::numeric_limits<float>::quiet_NaN();
};

// Reads every step of every field once, with progress.
Result<std::vector<FieldRange>> field_ranges(const FrameSource& frames, size_t face_count) {
  std::vector<FieldRange> ranges;
  std::vector<float> values;
  const std::vector<FieldInfo> fields = frames.fields();
  const size_t steps = frames.step_count();
  for (size_t f = 0; f < fields.size(); ++f) {
    FieldRange range{fields[f]};
    values.assign(
        fields[f].location == FieldLocation::kElement ? face_count : frames.vertex_count(), 0.0f);
    for (size_t t = 0; t < steps; ++t) {
      progress("reading fields", f * steps + t + 1, fields.size() * steps);
      DYNPM_RETURN_IF_ERROR(frames.read_field(f, t, values));
      for (float v : values) {
        if (std::isnan(v)) continue;
        if (!(v >= range.min)) range.min = v;
        if (!(v <= range.max)) range.max = v;
      }
    }
    ranges.push_back(std::move(range));
  }
  return ranges;
}

std::string join(const std::vector<int32_t>& ids, size_t limit) {
  std::ostringstream s;
  for (size_t i = 0; i < ids.size() && i < limit; ++i) s << (i ? ", " : "") << ids[i];
  if (ids.size() > limit) s << ", …";
  return s.str();
}

// Each part (ascending id): its id, its name ("" when the input gives none) and its faces.
struct PartRow {
  int32_t id = 0;
  std::string_view name;
  size_t faces = 0;
};
std::vector<PartRow> part_rows(const Topology& topology) {
  std::vector<PartRow> rows;
  for (int32_t id : topology.parts()) rows.push_back({id, topology.part_name(id), 0});
  for (int32_t id : topology.part_ids)
    ++std::lower_bound(rows.begin(), rows.end(), id, [](const PartRow& r, int32_t v) {
        return r.id < v;
      })->faces;
  return rows;
}

// "parts  N (ids …)" and a line per part: id, faces, name (at most kListedParts of them). Names
// are printed as they are: clean_part_name() made them UTF-8 without control characters.
constexpr size_t kListedParts = 100;
void print_parts(std::ostream& out, const Topology& topology) {
  const std::vector<PartRow> rows = part_rows(topology);
  std::vector<int32_t> ids;
  for (const PartRow& r : rows) ids.push_back(r.id);
  out << "parts         " << rows.size() << " (ids " << join(ids, 12) << ")\n";
  for (size_t k = 0; k < rows.size() && k < kListedParts; ++k)
    out << "  part " << rows[k].id << "  " << rows[k].faces << " faces"
        << (rows[k].name.empty() ? "" : "  ") << rows[k].name << "\n";
  if (rows.size() > kListedParts) out << "  … and " << rows.size() - kListedParts << " more\n";
}

// "part_list": [{id, name, faces}], name "" when the part has none.
void json_parts(Json& j, const Topology& topology) {
  j.begin_array("part_list");
  for (const PartRow& r : part_rows(topology)) {
    j.begin_object();
    j.value("id", int64_t{r.id});
    j.value("name", r.name);
    j.value("faces", uint64_t{r.faces});
    j.end_object();
  }
  j.end_array();
}

void print_text(std::span<const std::string> inputs, const Topology& topology,
                const FrameSource& frames, std::span<const FieldRange> fields,
                const TopologyStats& stats, const BoundingBox& box, const ValidationReport& report,
                size_t problems_per_severity) {
  std::ostream& out = std::cout;
  out << "input         " << inputs.front();
  if (inputs.size() > 1) out << " … " << inputs.back() << " (" << inputs.size() << " files)";
  out << "\n";
  out << "vertices      " << stats.vertices;
  if (stats.referenced_vertices != stats.vertices)
    out << " (" << stats.referenced_vertices << " in faces)";
  out << "\n";
  out << "faces         " << stats.faces << " (" << stats.quads << " quads, " << stats.triangles
      << " triangles)\n";
  out << "time steps    " << frames.step_count();
  if (frames.step_count() > 0)
    out << " (t = " << frames.step_time(0) << " … " << frames.step_time(frames.step_count() - 1)
        << ")";
  out << "\n";
  if (!fields.empty()) {
    out << "fields        " << fields.size() << " (per node: one value per vertex and step; per "
        << "element: one per face and step)\n";
    for (const FieldRange& f : fields) {
      out << "  " << printable(f.info.name) << "  " << to_string(f.info.location) << ", " << f.min
          << " … " << f.max << " over all steps";
      if (!f.info.unit.empty()) out << ", unit " << printable(f.info.unit);
      out << "\n";
    }
  }
  out << "edges         " << stats.edges << "\n";
  out << "boundary      " << stats.boundary_edges << " edges in " << stats.boundary_loops
      << " loops\n";
  out << "non-manifold  " << stats.non_manifold_edges << " edges, " << stats.non_manifold_vertices
      << " vertices (kept as features)\n";
  print_parts(out, topology);
  out << "components    " << stats.components << "\n";
  out << "euler         " << stats.euler_characteristic << "\n";
  if (!box.empty)
    out << "bounding box  [" << box.min[0] << ", " << box.min[1] << ", " << box.min[2] << "] … ["
        << box.max[0] << ", " << box.max[1] << ", " << box.max[2] << "] over all steps, diagonal "
        << box.diagonal() << "\n";
  out << "validation    " << (report.ok() ? "ok" : "INVALID") << " ("
      << report.count(Severity::kError) << " errors, " << report.count(Severity::kFeature)
      << " features, " << report.count(Severity::kWarning) << " warnings)\n";
  for (Severity severity : {Severity::kError, Severity::kFeature, Severity::kWarning}) {
    size_t shown = 0;
    for (const Problem& p : report.problems) {
      if (p.severity != severity) continue;
      if (shown++ == problems_per_severity) break;
      out << "  " << to_string(severity) << ": " << to_string(p.kind) << ": " << p.message << "\n";
    }
    const size_t total = report.count(severity);
    if (total > problems_per_severity && problems_per_severity > 0)
      out << "  … and " << (total - problems_per_severity) << " more " << to_string(severity)
          << "s\n";
  }
}

void print_json(std::span<const std::string> inputs, const Topology& topology,
                const FrameSource& frames, std::span<const FieldRange> fields,
                const TopologyStats& stats, const BoundingBox& box,
                const ValidationReport& report) {
  Json j;
  j.begin_object();
  j.begin_array("inputs");
  for (const std::string& path : inputs) j.item(path);
  j.end_array();
  j.value("vertices", uint64_t{stats.vertices});
  j.value("referenced_vertices", uint64_t{stats.referenced_vertices});
  j.value("faces", uint64_t{stats.faces});
  j.value("quads", uint64_t{stats.quads});
  j.value("triangles", uint64_t{stats.triangles});
  j.value("steps", uint64_t{frames.step_count()});
  j.begin_array("times");
  for (size_t t = 0; t < frames.step_count(); ++t) j.item(frames.step_time(t));
  j.end_array();
  j.begin_array("fields");
  for (const FieldRange& f : fields) {
    j.begin_object();
    j.value("name", f.info.name);
    j.value("location", to_string(f.info.location));
    j.value("unit", f.info.unit);
    j.value("min", double(f.min));
    j.value("max", double(f.max));
    j.end_object();
  }
  j.end_array();
  j.value("edges", uint64_t{stats.edges});
  j.value("boundary_edges", uint64_t{stats.boundary_edges});
  j.value("boundary_loops", uint64_t{stats.boundary_loops});
  j.value("non_manifold_edges", uint64_t{stats.non_manifold_edges});
  j.value("non_manifold_vertices", uint64_t{stats.non_manifold_vertices});
  j.begin_array("parts");
  for (int32_t id : topology.parts()) j.item(int64_t{id});
  j.end_array();
  json_parts(j, topology);
  j.value("components", uint64_t{stats.components});
  j.value("euler_characteristic", stats.euler_characteristic);
  j.begin_object("bounding_box");
  j.begin_array("min");
  for (float c : box.min) j.item(double{c});
  j.end_array();
  j.begin_array("max");
  for (float c : box.max) j.item(double{c});
  j.end_array();
  j.value("diagonal", box.diagonal());
  j.end_object();
  j.begin_object("validation");
  j.value("ok", report.ok());
  j.value("errors", uint64_t{report.count(Severity::kError)});
  j.value("features", uint64_t{report.count(Severity::kFeature)});
  j.value("warnings", uint64_t{report.count(Severity::kWarning)});
  j.begin_array("problems");
  for (const Problem& p : report.problems) {
    j.begin_object();
    j.value("kind", to_string(p.kind));
    j.value("severity", to_string(p.severity));
    if (p.face != kNoIndex) j.value("face", int64_t{p.face});
    if (p.vertex != kNoIndex) j.value("vertex", int64_t{p.vertex});
    if (p.step != kNoIndex) j.value("step", int64_t{p.step});
    j.value("message", p.message);
    j.end_object();
  }
  j.end_array();
  j.end_object();
  j.end_object();
  std::cout << j.str();
}

// A progressive mesh file: what it holds and at what levels.
int print_dpm_info(const std::string& path, bool json, const std::optional<std::string>& which) {
  auto mesh = read_dpm(path);
  if (!mesh) return fail(kSpec.name, kExitFailure, mesh.message());
  const std::vector<MeshVariant> variants = mesh->variants;  // a family's, for the list
  const size_t stored_steps = mesh->step_count();
  std::optional<size_t> chosen;
  if (which) {
    auto found = find_variant(*mesh, *which);
    if (!found) return fail(kSpec.name, kExitFailure, path + ": --variant: " + found.message());
    chosen = *found;
    select_variant(*mesh, *chosen);
  }
  const ProgressiveMesh& m = *mesh;
  Navigator nav(m);
  const Topology base = nav.topology();
  nav.set_level(m.split_count());
  const Topology full = nav.topology();
  std::error_code ec;
  const double size = double(std::filesystem::file_size(path, ec));
  const double per_vertex_step = size / (double(m.full_vertex_count) * double(m.step_count()));
  if (json) {
    Json j;
    j.begin_object();
    j.value("file", path);
    j.value("format", "dpm");
    j.value("complete", m.complete);
    j.value("vertices", uint64_t{m.full_vertex_count});
    j.value("faces", uint64_t{m.full_face_count});
    j.value("vertices_present", uint64_t{m.vertex_count()});
    j.value("faces_present", uint64_t{full.faces.size()});
    j.value("quads_present", uint64_t{full.quad_count()});
    j.value("triangles_present", uint64_t{full.triangle_count()});
    j.value("base_vertices", uint64_t{m.base_vertex_count});
    j.value("base_faces", uint64_t{m.base_face_count});
    j.value("splits", uint64_t{m.split_count()});
    j.value("steps", uint64_t{m.step_count()});
    j.value("first_time", m.times.front());
    j.value("last_time", m.times.back());
    j.begin_array("key_steps");
    for (size_t k : m.key_steps) j.item(int64_t(k));
    j.end_array();
    j.begin_array("fields");
    for (const ProgressiveField& f : m.fields) {
      j.begin_object();
      json_field_range(j, f);
      j.value("lossless", f.lossless);
      j.value("value_error", f.max_error);
      j.value("base_field_error_pct", 100.0 * f.base_error);
      j.end_object();
    }
    j.end_array();
    j.value("parts", uint64_t{full.parts().size()});
    json_parts(j, full);
    j.value("lossless", m.lossless);
    j.value("position_error", m.max_error);
    j.value("diagonal", m.diagonal());
    j.value("base_error", m.base_error);
    j.value("bytes", uint64_t(size));
    j.value("bytes_per_vertex_step", per_vertex_step);
    j.value("note", m.note);
    if (!variants.empty()) {
      j.value("stored_steps", uint64_t{stored_steps});
      if (chosen) j.value("variant", uint64_t{*chosen});
      json_variants(j, variants);
    }
    j.end_object();
    std::cout << j.str();
    return kExitOk;
  }
  std::printf("%s: dynamic progressive mesh (.dpm version 7)%s\n", path.c_str(),
              m.complete ? "" : ", a PREFIX of the file");
  if (m.complete) {
    std::printf("full      %u vertices, %u faces (%zu quads, %zu triangles), %zu parts\n",
                m.full_vertex_count, m.full_face_count, full.quad_count(), full.triangle_count(),
                full.parts().size());
  } else {
    std::printf("full      %u vertices, %u faces\n", m.full_vertex_count, m.full_face_count);
    std::printf("present   %u vertices, %zu faces (%zu quads, %zu triangles): %u of %u splits\n",
                m.vertex_count(), full.faces.size(), full.quad_count(), full.triangle_count(),
                m.split_count(), m.full_split_count);
  }
  std::printf(
      "base      %u vertices, %u faces (%zu quads, %zu triangles); error %.4g (%.3g%% of "
      "the diagonal)\n",
      m.base_vertex_count, m.base_face_count, base.quad_count(), base.triangle_count(),
      m.base_error, 100 * of_diagonal(m.base_error, m.diagonal()));
  std::printf("steps     %zu, time %g to %g; key steps %zu\n", m.step_count(), m.times.front(),
              m.times.back(), m.key_steps.size());
  std::fflush(stdout);
  print_parts(std::cout, full);
  std::cout.flush();
  // One line a field: where it lives, its range and unit, how exactly it is stored, and how far
  // the base mesh's shown values may be from the values they stand for.
  for (const ProgressiveField& f : m.fields) {
    const std::string unit = f.info.unit.empty() ? "" : " " + printable(f.info.unit);
    std::printf("field     %s (%s): %.4g … %.4g%s; ", printable(f.info.name).c_str(),
                to_string(f.info.location), f.min, f.max, unit.c_str());
    if (f.lossless)
      std::printf("lossless");
    else
      std::printf("within %.3g%s", f.max_error, unit.c_str());
    std::printf("; base mesh field error %.3g%% of the range\n", 100.0 * f.base_error);
  }
  if (m.lossless)
    std::printf("positions lossless (float32)\n");
  else
    std::printf("positions within %.3g (%.2g of the diagonal %.4g)\n", m.max_error,
                of_diagonal(m.max_error, m.diagonal()), m.diagonal());
  std::printf("size      %.0f bytes, %.2f bytes per vertex per step\n", size, per_vertex_step);
  if (!m.note.empty()) std::printf("note      %s\n", printable(m.note).c_str());
  if (!variants.empty()) {
    std::printf("family    %zu variants, %zu distinct steps stored%s\n", variants.size(),
                stored_steps, chosen ? "" : " (--variant NAME|INDEX shows one)");
    print_variants(variants, chosen);
  }
  return kExitOk;
}

}  // namespace

int run_info(std::span<char* const> arguments) {
  Args args;
  if (auto exit_code = parse_verb_args(arguments, kSpec, args)) return *exit_code;
  if (args.positional.empty())
    return fail(kSpec.name, kExitUsage, "no input given", help_text(kSpec));
  size_t problems = 10;
  if (auto n = args.value("--problems")) {
    auto r = parse_whole("--problems", *n, 0, 1'000'000'000);
    if (!r) return fail(kSpec.name, kExitUsage, r.message());
    problems = *r;
  }
  auto inputs = expand_inputs(args.positional);
  if (!inputs) return fail(kSpec.name, kExitFailure, inputs.message());
  if (inputs->size() == 1) {
    // By signature, or by name: a damaged .dpm gets the .dpm reader's message.
    auto head = read_file_head(inputs->front(), 8);
    const std::string ext = std::filesystem::path(inputs->front()).extension().string();
    if ((head && looks_like_dpm(*head)) || ext == ".dpm" || ext == ".DPM")
      return print_dpm_info(inputs->front(), args.has("--json"), args.value("--variant"));
  }
  if (args.has("--variant"))
    return fail(kSpec.name, kExitUsage, "--variant is for a family file (.dpm)");
  auto stream = open_inputs(*inputs, args, InputChecks::kNone);
  if (!stream) return fail(kSpec.name, kExitFailure, stream.message());
  const Topology& topology = stream->topology;
  BoxingSource frames(*stream->frames);
  const ValidationReport report = validate(topology, &frames);
  // A step that cannot be read (another face list, a broken file) is an input error.
  for (const Problem& p : report.problems) {
    if (p.kind == ProblemKind::kUnreadableStep) return fail(kSpec.name, kExitFailure, p.message);
  }
  auto fields = field_ranges(frames, topology.face_count());
  if (!fields) return fail(kSpec.name, kExitFailure, fields.message());
  const TopologyStats stats = topology_stats(topology, Adjacency::build(topology));
  if (args.has("--json"))
    print_json(*inputs, topology, frames, *fields, stats, frames.box(), report);
  else
    print_text(*inputs, topology, frames, *fields, stats, frames.box(), report, problems);
  return report.ok() ? kExitOk : kExitInvalidMesh;
}

}  // namespace dynpm::cli
