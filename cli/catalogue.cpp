// dynpm catalogue: DIR/index.json, the list of every .dpm below DIR with its metadata.
#include "catalogue.h"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <set>

#include "args.h"
#include "commands.h"
#include "dynpm/progressive.h"
#include "family_inputs.h"
#include "json.h"
#include "report.h"

namespace dynpm::cli {
namespace {

const VerbSpec kSpec{
    "catalogue",
    "dynpm catalogue DIR [--quiet]",
    "Writes DIR/index.json: one entry per .dpm file below DIR (name, path, source file, vertices,\n"
    "faces, steps, time range, fields, parts, size, date), for scripts and for the catalogue\n"
    "page. The file is replaced atomically. Symbolic links and temporary files of builds\n"
    "still running are left out. Exit code 1 when some .dpm cannot be read (the index lists\n"
    "them under \"problems\" and holds the others). docs/batch.md describes the JSON.",
    {{"--quiet", "-q", false, "", "print nothing but errors"}}};

constexpr int kIndexVersion = 1;

// "2026-12-02T22:40:07Z".
std::string utc_text(std::chrono::system_clock::time_point when) {
  const std::time_t t = std::chrono::system_clock::to_time_t(when);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

// The file's last change (GCC 12 has no clock_cast: the two clocks' offset now is used).
std::chrono::system_clock::time_point modified(const std::filesystem::path& path) {
  std::error_code ec;
  const auto written = std::filesystem::last_write_time(path, ec);
  return std::chrono::time_point_cast<std::chrono::system_clock::duration>(
      written - std::filesystem::file_time_type::clock::now() + std::chrono::system_clock::now());
}

// What 'dynpm build' keeps in the note: "dynpm build of <input file>[ …]".
std::string source_of(const std::string& note) {
  const std::string prefix = "dynpm build of ";
  if (!note.starts_with(prefix)) return "";
  std::string source = note.substr(prefix.size());
  if (source.ends_with(" …")) source.resize(source.size() - std::string(" …").size());
  return source;
}

}  // namespace

std::vector<std::string> catalogue_files(const std::string& dir) {
  std::vector<std::string> files;
  std::error_code ec;
  for (std::filesystem::recursive_directory_iterator it(dir, ec), end; !ec && it != end;
       it.increment(ec)) {
    const auto& entry = *it;
    if (!entry.is_regular_file(ec) || entry.is_symlink(ec)) continue;
    const std::string name = entry.path().filename().string();
    if (entry.path().extension() != ".dpm" || name.find(".tmp-") != std::string::npos) continue;
    files.push_back(std::filesystem::relative(entry.path(), dir, ec).generic_string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

// Only the base level at the first step is asked for: the
// header, base mesh, parts and field definitions give the entry, so a file without fields is
// not decoded past its base (a 1 M-vertex file: 0.1 s instead of 4.4 s); a file with fields
// still reads its splits, whose field values a coarse vertex needs.
Result<std::string> catalogue_entry(const std::string& dir, const std::string& relative) {
  const std::filesystem::path path = std::filesystem::path(dir) / relative;
  DpmReadLimits limits;
  limits.vertices = 1;
  limits.last_step = 0;
  auto mesh = read_dpm(path.string(), limits);
  if (!mesh) return mesh.status();
  const ProgressiveMesh& m = *mesh;
  // Read with limits, `complete` is false by design; a file that ends early is no entry.
  if (m.prefix) return Status::error(path.string() + ": the file is incomplete");
  auto thumbnail = read_dpm_thumbnail(path.string());
  if (!thumbnail) return thumbnail.status();
  std::error_code ec;
  Json j;
  j.begin_object();
  j.value("name", std::filesystem::path(relative).stem().string());
  j.value("path", relative);
  j.value("source", source_of(m.note));
  j.value("note", m.note);
  j.value("vertices", uint64_t{m.full_vertex_count});
  j.value("faces", uint64_t{m.full_face_count});
  j.value("base_vertices", uint64_t{m.base_vertex_count});
  j.value("steps", uint64_t{m.step_count()});
  j.value("first_time", m.times.front());
  j.value("last_time", m.times.back());
  j.begin_array("fields");
  for (const ProgressiveField& f : m.fields) {
    j.begin_object();
    json_field_range(j, f);
    j.end_object();
  }
  j.end_array();
  const std::set<int32_t> ids(m.part_ids.begin(), m.part_ids.end());
  j.begin_array("parts");
  for (int32_t id : ids) {
    const auto named = std::find_if(m.part_names.begin(), m.part_names.end(),
                                    [id](const PartName& p) { return p.id == id; });
    j.begin_object();
    j.value("id", int64_t{id});
    j.value("name", named == m.part_names.end() ? std::string() : named->name);
    j.end_object();
  }
  j.end_array();
  j.value("lossless", m.lossless);
  j.value("position_error", m.max_error);
  j.value("diagonal", m.diagonal());
  j.value("bytes", uint64_t{std::filesystem::file_size(path, ec)});
  j.value("built", utc_text(modified(path)));
  j.value("thumbnail", thumbnail->has_value());
  // A family file's members (docs/family.md); "steps" above counts its stored steps.
  if (!m.variants.empty()) json_variants(j, m.variants);
  j.end_object();
  return j.str();
}

std::string catalogue_index(const std::vector<std::string>& files, const CatalogueEntryMaker& entry,
                            CatalogueResult& result) {
  Json j;
  j.begin_object();
  j.value("format", "dynpm-catalogue");
  j.value("version", kIndexVersion);
  j.value("generated", utc_text(std::chrono::system_clock::now()));
  j.begin_array("entries");
  for (const std::string& relative : files) {
    auto made = entry(relative);
    if (!made) {
      result.problems.push_back(made.message());
      continue;
    }
    j.raw({}, *made);
    ++result.entries;
  }
  j.end_array();
  j.begin_array("problems");
  for (const std::string& problem : result.problems) j.item(problem);
  j.end_array();
  j.end_object();
  return j.str() + "\n";
}

Result<CatalogueResult> write_catalogue_index(const std::string& dir) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) return Status::error(dir + ": no such folder");
  CatalogueResult result;
  const std::string json = catalogue_index(
      catalogue_files(dir),
      [&](const std::string& relative) { return catalogue_entry(dir, relative); }, result);
  const std::string index = (std::filesystem::path(dir) / "index.json").string();
  DYNPM_RETURN_IF_ERROR(write_file_atomically(index, json));
  return result;
}

int run_catalogue(std::span<char* const> arguments) {
  Args args;
  if (auto exit_code = parse_verb_args(arguments, kSpec, args)) return *exit_code;
  if (args.positional.size() != 1)
    return fail(kSpec.name, kExitUsage, "needs one folder DIR", help_text(kSpec));
  auto result = write_catalogue_index(args.positional[0]);
  if (!result) return fail(kSpec.name, kExitFailure, result.message());
  for (const std::string& problem : result->problems) note(kSpec.name, problem);
  if (!args.has("--quiet"))
    std::cout << "wrote " << (std::filesystem::path(args.positional[0]) / "index.json").string()
              << ": " << result->entries << " files\n";
  if (!result->problems.empty())
    return fail(kSpec.name, kExitFailure,
                std::to_string(result->problems.size()) + " file(s) could not be read");
  return kExitOk;
}

}  // namespace dynpm::cli
