// The code path of each fuzz harness, as inline functions: the libFuzzer entry points
// (fuzz/<name>.cpp) and the regression replay (tests/fuzz_regressions_test.cpp) call the same
// function. Every one returns normally on any input (an error Result is fine); a crash, a
// sanitizer report or a failed check (abort) is a finding. Only the functions a program uses are
// emitted, so each harness links only the library it tests.
#pragma once

#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <span>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "dynpm/core.h"
#include "dynpm/io.h"
#include "dynpm/lod.h"
#include "dynpm/progressive.h"
#include "io/formats.h"

namespace dynpm::fuzz {

// Inputs larger than this are skipped by the readers that take a path.
inline constexpr size_t kMaxPathInput = size_t{1} << 20;

inline ReadOptions quiet_options(bool split_polygons) {
  ReadOptions options;
  options.split_polygons = split_polygons;
  options.warn = [](const std::string&) {};
  return options;
}

// A failed invariant of the code under test: print and abort, so libFuzzer records the input.
[[noreturn]] inline void fail(const std::string& what) {
  std::fprintf(stderr, "dynpm fuzz check failed: %s\n", what.c_str());
  std::abort();
}

// What every reader's result must satisfy: parallel arrays, corners in range.
inline void check_topology(const Topology& topology, const char* who) {
  const ValidationReport report = validate(topology);
  for (const Problem& problem : report.problems)
    if (problem.kind == ProblemKind::kIndexOutOfRange || problem.kind == ProblemKind::kArraySize)
      fail(std::string(who) + " returned a topology with index errors: " + problem.message);
}

inline void check_parsed(const Result<io::ParsedMesh>& mesh, const char* who) {
  if (!mesh.ok()) return;
  check_topology(mesh->topology, who);
  if (mesh->positions.size() != size_t{mesh->topology.vertex_count} * 3)
    fail(std::string(who) + ": positions are not 3 x vertex_count");
}

inline void run_obj(std::string_view bytes) {
  for (bool split : {false, true})
    check_parsed(io::parse_obj(bytes, "fuzz.obj", quiet_options(split)), "parse_obj");
}

inline void run_ply(std::string_view bytes) {
  check_parsed(io::parse_ply(bytes, "fuzz.ply", quiet_options(true)), "parse_ply");
}

inline void run_vtk(std::string_view bytes) {
  const ReadOptions options = quiet_options(true);
  check_parsed(io::parse_vtk(bytes, "fuzz.vtk", options), "parse_vtk");
  check_parsed(io::parse_vtu(bytes, "fuzz.vtu", options), "parse_vtu");
  (void)io::parse_pvd(bytes, "fuzz.pvd");
}

// A per-process folder holding only the input file (d3plot looks for d3plot01, … beside it),
// removed when the process ends so that test runs leave nothing behind.
struct InputFolder {
  std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("dynpm-fuzz-" + std::to_string(::getpid()));
  InputFolder() { std::filesystem::create_directories(path); }
  InputFolder(const InputFolder&) = delete;
  InputFolder& operator=(const InputFolder&) = delete;
  ~InputFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
  }
};

inline std::string input_path(const char* file_name) {
  static const InputFolder folder;
  return (folder.path / file_name).string();
}

// Every step and every field of a stream that opened.
inline void read_everything(const Result<AnimationStream>& stream, const char* who) {
  if (!stream.ok()) return;
  check_topology(stream->topology, who);
  const FrameSource* frames = stream->frames.get();
  if (frames == nullptr) fail(std::string(who) + " returned a stream without frames");
  const uint32_t n = frames->vertex_count();
  if (n != stream->topology.vertex_count)
    fail(std::string(who) + ": frames and topology disagree on the vertex count");
  std::vector<float> xyz(size_t{n} * 3);
  std::vector<float> values;
  const std::vector<FieldInfo> fields = frames->fields();
  for (size_t t = 0; t < frames->step_count(); ++t) {
    (void)frames->step_time(t);
    (void)frames->read_step(t, xyz);
    for (size_t f = 0; f < fields.size(); ++f) {
      // One value per vertex, or per face for an element field.
      values.assign(
          fields[f].location == FieldLocation::kElement ? stream->topology.face_count() : size_t{n},
          0.0f);
      (void)frames->read_field(f, t, values);
    }
  }
}

template <typename Open>
void run_path_reader(std::string_view bytes, const char* file_name, Open open, const char* who) {
  if (bytes.size() > kMaxPathInput) return;
  const std::string path = input_path(file_name);
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!out) fail("cannot write " + path);
  }
  read_everything(open(path, quiet_options(true)), who);
}

inline void run_frd(std::string_view bytes) {
  run_path_reader(bytes, "input.frd", io::open_frd, "open_frd");
}
inline void run_d3plot(std::string_view bytes) {
  run_path_reader(bytes, "d3plot", io::open_d3plot, "open_d3plot");
}
inline void run_exodus(std::string_view bytes) {
  run_path_reader(bytes, "input.exo", io::open_exodus, "open_exodus");
}

// run_exodus with the HDF5 signature laid over the first 8 bytes: every input takes the
// contained path (src/io/contained_read.h). In fuzz_exodus most mutants lose the signature and
// are read in this process as classic netCDF (32 of 35 corpus entries after 10 minutes).
inline void run_exodus_hdf5(std::string_view bytes) {
  static constexpr std::string_view kSignature("\x89HDF\r\n\x1a\n", 8);
  std::string file(bytes);
  if (file.size() < kSignature.size()) file.resize(kSignature.size());
  file.replace(0, kSignature.size(), kSignature);
  run_exodus(file);
}

// decode_dpm, then a Navigator at the finest level, the base, and levels taken from the bytes.
// Selective refinement of any file the reader accepts: the dependencies, then sets of splits
// closed under them, refined and coarsened out of stream order (one split and its ancestors,
// every other split, a prefix), each mesh's corners in range and its shown field values made.
inline void run_selective(const ProgressiveMesh& mesh, std::span<const uint32_t> levels) {
  const uint32_t splits = mesh.split_count();
  const SplitDependencies deps = derive_split_dependencies(mesh);
  if (deps.split_count() != splits) fail("dependencies for another number of splits");
  SelectiveNavigator nav(mesh, deps);
  std::vector<uint8_t> wanted(splits, 0);
  std::vector<uint32_t> stack;
  auto show = [&](const char* what) {
    nav.set_active(wanted);
    const SelectiveMesh shown = nav.active_mesh();
    check_topology(shown.topology, what);
    for (size_t f = 0; f < mesh.fields.size() && mesh.step_count() > 0; ++f)
      nav.field_values(f, mesh.step_count() - 1, shown);
  };
  for (uint32_t level : levels) {
    if (level == 0 || level > splits) continue;
    std::fill(wanted.begin(), wanted.end(), uint8_t{0});
    add_with_dependencies(deps, wanted, level - 1, stack);
    show("SelectiveNavigator (a split and its ancestors)");
  }
  for (uint32_t i = 0; i < splits; ++i) wanted[i] = i % 2;
  close_under_dependencies(deps, wanted);
  show("SelectiveNavigator (every other split, closed)");
  std::fill(wanted.begin(), wanted.end(), uint8_t{0});
  std::fill_n(wanted.begin(), splits / 2, uint8_t{1});
  show("SelectiveNavigator (a prefix)");
}

inline void run_dpm(std::string_view bytes) {
  const Result<ProgressiveMesh> decoded = decode_dpm(bytes, "fuzz.dpm");
  if (!decoded.ok()) return;
  const ProgressiveMesh& mesh = *decoded;
  Navigator nav(mesh);
  const uint32_t max_level = mesh.split_count();
  std::vector<uint32_t> levels = {max_level, 0};
  for (size_t i = 0; i + 4 <= std::min<size_t>(bytes.size(), 16); i += 4) {
    uint32_t v = 0;
    for (size_t j = 0; j < 4; ++j)
      v = (v << 8) | static_cast<uint8_t>(bytes[bytes.size() - 1 - i - j]);
    levels.push_back(v % (max_level + 1));
  }
  levels.push_back(max_level / 2);
  std::vector<float> xyz;
  for (uint32_t level : levels) {
    nav.set_level(level);
    if (nav.level() != level) fail("set_level did not reach the level asked for");
    if (mesh.step_count() > 0) {
      xyz.assign(size_t{nav.vertex_count()} * 3, 0.0f);
      nav.positions(0.5 * static_cast<double>(mesh.step_count() - 1) + 0.25, xyz);
    }
    check_topology(nav.topology(), "Navigator::topology");
    // Result fields: the shown values of any file the reader accepts (heirs and parents in range).
    for (size_t f = 0; f < mesh.fields.size(); ++f) {
      xyz.assign(std::max(nav.vertex_count(), nav.face_count()), 0.0f);
      nav.field_values(f, mesh.step_count() - 1, xyz);
      nav.field_values(f, 0, xyz, FieldAggregate::kMean);
      if (!(nav.field_error(f) >= 0 && nav.field_error(f) <= 1))
        fail("a field error outside [0, 1]");
    }
  }
  run_selective(mesh, levels);
}

}  // namespace dynpm::fuzz
