// dynpm thumbnail: the picture of a .dpm that 'dynpm serve' shows (render_thumbnail(), stored as
// the THMB chunk: docs/FORMAT.md). For files built before 'dynpm build' stored one, or to look at
// it as a PNG.
#include <iostream>

#include "args.h"
#include "commands.h"
#include "dynpm/core.h"
#include "dynpm/pipeline.h"
#include "dynpm/progressive.h"
#include "report.h"

namespace dynpm::cli {
namespace {

const VerbSpec kSpec{
    "thumbnail",
    "dynpm thumbnail MODEL.dpm [-o PICTURE.png]",
    "Draws the model at 5 % of its vertices at its last step, as 'dynpm build' does for the\n"
    "catalogue ('dynpm serve'): 256x192, the viewer's first view, flat shaded, parts in\n"
    "their colours. Without -o the picture is stored in MODEL.dpm (its THMB chunk, replacing\n"
    "one it has; the file is rewritten atomically, the model's bytes unchanged); with -o it\n"
    "is written as a PNG and the model is left as it is.",
    {{"--output", "-o", true, "PICTURE.png", "write the picture here instead"}, kQuietFlag}};

}  // namespace

int run_thumbnail(std::span<char* const> arguments) {
  Args args;
  if (auto exit = parse_verb_args(arguments, kSpec, args)) return *exit;
  if (args.positional.size() != 1)
    return fail(kSpec.name, kExitUsage, "expected one .dpm file", help_text(kSpec));
  const std::string model = args.positional.front();
  if (auto png_path = args.value("--output")) {
    auto mesh = read_dpm(model, thumbnail_read_limits());
    if (!mesh) return fail(kSpec.name, kExitFailure, mesh.message());
    if (Status s = write_file_atomically(*png_path, render_thumbnail(*mesh)); !s.ok())
      return fail(kSpec.name, kExitFailure, s.message());
    if (!args.has("--quiet")) std::cout << "wrote " << *png_path << "\n";
    return kExitOk;
  }
  auto bytes = read_file(model);
  if (!bytes) return fail(kSpec.name, kExitFailure, bytes.message());
  auto with_picture = add_thumbnail(*bytes, model);
  if (!with_picture) return fail(kSpec.name, kExitFailure, with_picture.message());
  if (Status s = write_file_atomically(model, *with_picture); !s.ok())
    return fail(kSpec.name, kExitFailure, s.message());
  if (!args.has("--quiet"))
    std::cout << "stored the thumbnail in " << model << " (" << with_picture->size() - bytes->size()
              << " bytes more)\n";
  return kExitOk;
}

}  // namespace dynpm::cli
