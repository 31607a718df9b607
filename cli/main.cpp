// dynpm — dynamic progressive triangle-quadrilateral meshes for FE animations.
// main() only picks the verb; each verb lives in its own file.
#include <unistd.h>

#include <clocale>
#include <cstdio>
#include <cstring>
#include <iostream>

#include "commands.h"

namespace dynpm::cli {

Result<AnimationStream> open_inputs(std::span<const std::string> arguments, bool split_polygons) {
  auto paths = expand_inputs(arguments);
  if (!paths) return paths.status();
  ReadOptions options;
  options.split_polygons = split_polygons;
  options.warn = [](const std::string& note) { std::cerr << "warning: " << note << "\n"; };
  return open_input(*paths, options);
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
  if (verb == "info") return dynpm::cli::run_info(rest);
  if (verb == "convert") return dynpm::cli::run_convert(rest);
  if (verb == "hausdorff") return dynpm::cli::run_hausdorff(rest);
  if (verb == "simplify") return dynpm::cli::run_simplify(rest);
  if (verb == "build") return dynpm::cli::run_build(rest);
  if (verb == "extract") return dynpm::cli::run_extract(rest);
  if (verb == "eval") return dynpm::cli::run_eval(rest);
  if (verb == "view") return dynpm::cli::run_view(rest);
  std::cerr << "dynpm: unknown verb '" << verb << "'\n\n" << kUsage;
  return dynpm::cli::kExitUsage;
}
