// dynpm — dynamic progressive triangle-quadrilateral meshes for FE animations.
// main() only picks the verb; each verb lives in its own file.
#include <clocale>
#include <cstring>
#include <iostream>
#include <new>
#include <span>
#include <stdexcept>
#include <string>

#include "commands.h"
#include "dynpm/core.h"
#include "huge_pages.h"
#include "report.h"

namespace {

using namespace dynpm::cli;

// The verbs, in the order the usage text lists them; each one's run_ is in its own file.
struct Verb {
  const char* name;
  int (*run)(std::span<char* const> arguments);
  const char* summary;
};
constexpr Verb kVerbs[] = {
    {"info", run_info, "counts, topology, bounding box and validation of a mesh or animation"},
    {"convert", run_convert, "convert a mesh or animation between OBJ, PLY and VTK"},
    {"hausdorff", run_hausdorff, "Metro-style distance between two meshes or step sequences"},
    {"simplify", run_simplify, "simplify a mixed triangle/quad mesh or animation"},
    {"build", run_build, "pre-process an animation into a progressive mesh (.dpm)"},
    {"extract", run_extract, "a .dpm at a chosen resolution and time step, as OBJ/PLY/VTK"},
    {"eval", run_eval, "Hausdorff error of a .dpm against the original, per resolution and step"},
    {"view", run_view, "browse a .dpm in the web browser (time and resolution sliders)"},
    {"batch", run_batch, "build many variants into one folder, here or as a Slurm job array"},
    {"catalogue", run_catalogue, "index.json of every .dpm below a folder (name, counts, fields)"},
    {"serve", run_serve, "the catalogue of a folder of .dpm files in the browser, with the viewer"},
    {"thumbnail", run_thumbnail, "the picture of a .dpm a catalogue shows: stored in it, or a PNG"},
};

std::string usage() {
  std::string text =
      "dynpm — dynamic progressive triangle-quadrilateral meshes for FE animations\n"
      "\n"
      "usage: dynpm <verb> [options]\n"
      "\n"
      "verbs:\n";
  for (const Verb& verb : kVerbs) {
    std::string name = verb.name;
    name.resize(9, ' ');
    text += "  " + name + " " + verb.summary + "\n";
  }
  return text + "\nRun 'dynpm <verb> --help' for a verb's options.\n";
}

int run_verb(const std::string& name, std::span<char* const> rest) {
  for (const Verb& verb : kVerbs)
    if (name == verb.name) return verb.run(rest);
  std::cerr << "dynpm: unknown verb '" << name << "'\n\n" << usage();
  return kExitUsage;
}

}  // namespace

int main(int argc, char** argv) {
  dynpm::cli::start_again_with_huge_pages(argv);
  std::setlocale(LC_ALL, "C");  // numbers are read and written the same everywhere
  dynpm::return_freed_arrays_to_the_system();
  if (argc < 2 || std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0 ||
      std::strcmp(argv[1], "help") == 0) {
    std::cout << usage();
    return argc < 2 ? kExitUsage : kExitOk;
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
    return out_of_memory(verb);
  } catch (const std::length_error&) {  // a size past what a container can hold
    return out_of_memory(verb);
  }
}
