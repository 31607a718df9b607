// dynpm — dynamic progressive triangle-quadrilateral meshes for FE animations.
// main() only picks the verb; each verb lives in its own file.
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#include <clocale>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <iostream>
#include <new>
#include <set>
#include <stdexcept>

#include "commands.h"

namespace dynpm::cli {
namespace {

// Hands steps through and refuses a NaN or infinite coordinate, naming the file, the step and
// the vertex (and its node number): such a position must never reach the simplifier, a writer
// or the distance measure. Readers keep such values (validation judges them), so 'dynpm info'
// lists them instead.
class FinitePositions final : public FrameSource {
 public:
  FinitePositions(std::unique_ptr<FrameSource> source, std::vector<std::string> paths,
                  std::vector<int64_t> node_ids)
      : source_(std::move(source)), paths_(std::move(paths)), node_ids_(std::move(node_ids)) {}
  uint32_t vertex_count() const override { return source_->vertex_count(); }
  size_t step_count() const override { return source_->step_count(); }
  double step_time(size_t t) const override { return source_->step_time(t); }
  size_t step_float_count(size_t t) const override { return source_->step_float_count(t); }
  std::vector<std::string> field_names() const override { return source_->field_names(); }
  Status read_field(size_t field, size_t t, std::span<float> out) const override {
    return source_->read_field(field, t, out);
  }
  Status read_step(size_t t, std::span<float> out) const override {
    DYNPM_RETURN_IF_ERROR(source_->read_step(t, out));
    for (size_t i = 0; i < out.size(); ++i) {
      if (std::isfinite(out[i])) continue;
      const size_t v = i / 3;
      char xyz[96];
      std::snprintf(xyz, sizeof xyz, "(%g, %g, %g)", double(out[v * 3]), double(out[v * 3 + 1]),
                    double(out[v * 3 + 2]));
      // One file per step, or one file holding every step.
      const std::string& file = paths_.size() == step_count() ? paths_[t] : paths_.front();
      std::string node;
      if (v < node_ids_.size()) node = " (node " + std::to_string(node_ids_[v]) + ")";
      return Status::error(file + ": step " + std::to_string(t) + ": vertex " + std::to_string(v) +
                           node + " is at " + xyz + ", not a finite position");
    }
    return {};
  }

 private:
  std::unique_ptr<FrameSource> source_;
  std::vector<std::string> paths_;
  std::vector<int64_t> node_ids_;
};

// The first error validate() finds in the faces, named by the file they came from (the first
// one of a sequence), with the element or node number where the file has one.
Status check_faces(const Topology& topology, const std::string& file) {
  const ValidationReport report = validate(topology);
  for (const Problem& p : report.problems) {
    if (p.severity != Severity::kError) continue;
    std::string message = file + ": " + p.message;
    if (p.face < topology.element_ids.size() && topology.element_ids[p.face] != 0)
      message += " (element " + std::to_string(topology.element_ids[p.face]) + ")";
    else if (p.face == kNoIndex && p.vertex < topology.node_ids.size())
      message += " (node " + std::to_string(topology.node_ids[p.vertex]) + ")";
    const size_t errors = report.count(Severity::kError);
    if (errors > 1)
      message += "; " + std::to_string(errors - 1) + " more errors ('dynpm info' lists them)";
    return Status::error(message);
  }
  return {};
}

}  // namespace

Result<AnimationStream> open_inputs(std::span<const std::string> arguments, bool split_polygons,
                                    InputChecks checks) {
  auto paths = expand_inputs(arguments);
  if (!paths) return paths.status();
  ReadOptions options;
  options.split_polygons = split_polygons;
  options.warn = [](const std::string& note) { std::cerr << "warning: " << note << "\n"; };
  auto stream = open_input(*paths, options);
  if (!stream || checks == InputChecks::kNone) return stream;
  if (checks == InputChecks::kSimplifiable)
    DYNPM_RETURN_IF_ERROR(check_faces(stream->topology, paths->front()));
  stream->frames = std::make_unique<FinitePositions>(std::move(stream->frames), *paths,
                                                     stream->topology.node_ids);
  return stream;
}

Status check_output_folder(const std::string& output) {
  std::error_code ec;
  if (std::filesystem::is_directory(output, ec))
    return Status::error(output + ": is a directory; give a file name");
  const std::filesystem::path folder = std::filesystem::path(output).parent_path();
  if (!folder.empty() && !std::filesystem::is_directory(folder, ec))
    return Status::error(output + ": no folder '" + folder.string() + "' to write into");
  return {};
}

StagedOutputs::~StagedOutputs() {
  for (const auto& [staged, target] : files_) std::remove(staged.c_str());
}

std::string StagedOutputs::stage(const std::string& path) {
  const std::filesystem::path target(path);
  std::filesystem::path staged = target;
  staged.replace_filename(target.stem().string() + ".tmp-" + std::to_string(::getpid()) +
                          target.extension().string());
  files_.emplace_back(staged.string(), path);
  return staged.string();
}

Status StagedOutputs::commit() {
  // What killed runs left beside the targets: one listing of each folder for all of them (one
  // per file made 10,000 steps quadratic).
  std::vector<std::string> targets;
  targets.reserve(files_.size());
  for (const auto& [staged, target] : files_) targets.push_back(target);
  remove_stale_temporaries(targets);
  for (const auto& [staged, target] : files_)
    if (std::rename(staged.c_str(), target.c_str()) != 0)
      return Status::error(target +
                           ": cannot rename the finished file into place: " + std::strerror(errno));
  // Once per folder, not per file: an fsync each costs milliseconds.
  std::set<std::filesystem::path> folders;
  for (const auto& [staged, target] : files_)
    if (folders.insert(std::filesystem::path(target).parent_path()).second)
      sync_directory_of(target);
  files_.clear();
  return {};
}

namespace {
const char* failed_phase = nullptr;
}  // namespace

Phase::Phase(const char* what) : what_(what), exceptions_(std::uncaught_exceptions()) {}

Phase::~Phase() {
  if (std::uncaught_exceptions() > exceptions_ && !failed_phase) failed_phase = what_;
}

const char* Phase::failed() { return failed_phase; }

int out_of_memory(const std::string& verb) {
  std::string limit;
  if (rlimit r{}; ::getrlimit(RLIMIT_AS, &r) == 0 && r.rlim_cur != RLIM_INFINITY)
    limit = "; address-space limit " + std::to_string(r.rlim_cur >> 20) + " MB (ulimit -v)";
  else if (const long pages = ::sysconf(_SC_PHYS_PAGES), size = ::sysconf(_SC_PAGESIZE);
           pages > 0 && size > 0)
    limit = "; the machine has " + std::to_string((uint64_t(pages) * uint64_t(size)) >> 20) + " MB";
  const char* phase = Phase::failed();
  std::fprintf(stderr, "dynpm %s: out of memory%s%s (peak %.0f MB resident%s)\n", verb.c_str(),
               phase ? " while " : "", phase ? phase : "", peak_rss_mb(), limit.c_str());
  return kExitFailure;
}

double of_diagonal(double length, double diagonal) {
  return diagonal > 0 && std::isfinite(diagonal) ? length / diagonal : 0.0;
}

void progress(const std::string& label, size_t done, size_t total) {
  if (!::isatty(STDERR_FILENO)) return;
  std::fprintf(stderr, "\r%s %zu/%zu", label.c_str(), done, total);
  if (done == total) std::fprintf(stderr, "\r%*s\r", static_cast<int>(label.size() + 24), "");
  std::fflush(stderr);
}

double peak_rss_mb() {
  std::FILE* f = std::fopen("/proc/self/status", "r");
  if (!f) return 0;
  char line[256];
  double kb = 0;
  while (std::fgets(line, sizeof line, f))
    if (std::sscanf(line, "VmHWM: %lf kB", &kb) == 1) break;
  std::fclose(f);
  return kb / 1024.0;
}

}  // namespace dynpm::cli

namespace {

const char* kUsage =
    "dynpm — dynamic progressive triangle-quadrilateral meshes for FE animations\n"
    "\n"
    "usage: dynpm <verb> [options]\n"
    "\n"
    "verbs:\n"
    "  info      counts, topology, bounding box and validation of a mesh or animation\n"
    "  convert   convert a mesh or animation between OBJ, PLY and VTK\n"
    "  hausdorff Metro-style distance between two meshes or step sequences\n"
    "  simplify  simplify a mixed triangle/quad mesh or animation\n"
    "  build     pre-process an animation into a progressive mesh (.dpm)\n"
    "  extract   a .dpm at a chosen resolution and time step, as OBJ/PLY/VTK\n"
    "  eval      Hausdorff error of a .dpm against the original, per resolution and step\n"
    "  view      browse a .dpm in the web browser (time and resolution sliders)\n"
    "\n"
    "Run 'dynpm <verb> --help' for a verb's options.\n";

int run_verb(const std::string& verb, std::span<char* const> rest) {
  using namespace dynpm::cli;
  if (verb == "info") return run_info(rest);
  if (verb == "convert") return run_convert(rest);
  if (verb == "hausdorff") return run_hausdorff(rest);
  if (verb == "simplify") return run_simplify(rest);
  if (verb == "build") return run_build(rest);
  if (verb == "extract") return run_extract(rest);
  if (verb == "eval") return run_eval(rest);
  if (verb == "view") return run_view(rest);
  std::cerr << "dynpm: unknown verb '" << verb << "'\n\n" << kUsage;
  return kExitUsage;
}

}  // namespace

int main(int argc, char** argv) {
  std::setlocale(LC_ALL, "C");  // numbers are read and written the same everywhere
  dynpm::return_freed_arrays_to_the_system();
  if (argc < 2 || std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0 ||
      std::strcmp(argv[1], "help") == 0) {
    std::cout << kUsage;
    return argc < 2 ? dynpm::cli::kExitUsage : dynpm::cli::kExitOk;
  }
  if (std::strcmp(argv[1], "--version") == 0) {
    std::cout << "dynpm 0.1.0\n";
    return 0;
  }
  const std::string verb = argv[1];
  std::span<char* const> rest(argv + 2, static_cast<size_t>(argc - 2));
  // Caught here, after the verb's stack has unwound: its staged outputs are removed, and the
  // memory is back for the message.
  try {
    return run_verb(verb, rest);
  } catch (const std::bad_alloc&) {
    return dynpm::cli::out_of_memory(verb);
  } catch (const std::length_error&) {  // a size past what a container can hold
    return dynpm::cli::out_of_memory(verb);
  }
}
