// dynpm build: an animation pre-processed once into a progressive mesh file (.dpm).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <future>
#include <iostream>
#include <optional>
#include <system_error>

#include "args.h"
#include "commands.h"
#include "dynpm/pipeline.h"
#include "dynpm/text.h"
#include "family_inputs.h"
#include "inputs.h"
#include "json.h"
#include "outputs.h"
#include "report.h"
#include "shared_flags.h"

namespace dynpm::cli {
namespace {

const VerbSpec kSpec{
    "build",
    "dynpm build INPUT... -o MODEL.dpm [--family] [--key-steps all|paper|auto:K|LIST]\n"
    "                   [--lossless]\n"
    "                   [--position-error E] [--field-bound F] [--threads T] [--json]\n"
    "                   [--progress FORM] [--quiet] [--no-memory-check]",
    "Simplifies the animation to its coarsest legal mesh, recording every half-edge collapse,\n"
    "and writes the base mesh plus the vertex splits that rebuild the input, with every\n"
    "vertex's position at every time step (docs/FORMAT.md). Any resolution can then be shown\n"
    "at any time step ('dynpm extract', 'dynpm view'); fully refined it is the input again.\n"
    "Positions are quantized so that none moves more than --position-error (default 2^-18 of\n"
    "the bounding-box diagonal); --lossless stores float32 exactly. Result fields (plastic "
    "strain,\n"
    "stress, … per node or per element) are stored with each value within --field-bound percent\n"
    "of the field's range (default 0.1 %), float32 exactly with --lossless.\n"
    "Before the work it prints its memory estimate, and stops when that is more than the memory\n"
    "it may have (free memory, ulimit -v, the cgroup's limit) unless --no-memory-check. Progress\n"
    "goes to stderr: a live line on a terminal, a line every 5 s otherwise (docs/build.md).\n"
    "--family: each INPUT is a variant of one mesh (same node and element ids; the first\n"
    "difference is refused); one hierarchy for all, each distinct step stored once; extract,\n"
    "info, eval and view take --variant NAME|INDEX (docs/family.md).",
    {{"--output", "-o", true, "MODEL.dpm", "the progressive mesh file to write"},
     kFamilyFlag,
     kKeyStepsFlag,
     kLosslessFlag,
     kPositionErrorFlag,
     kFieldBoundFlag,
     kBoundaryWeightFlag,
     kFieldFlag,
     kFieldWeightFlag,
     kFieldCostFlag,
     kRegularizeFlag,
     kRoundsFlag,
     kIgnorePartsFlag,
     kThreadsFlag,
     {"--json", "", false, "", "print the result as JSON"},
     kNoMemoryCheckFlag,
     {"--no-thumbnail", "", false, "",
      "store no thumbnail (the picture 'dynpm serve' shows; docs/FORMAT.md THMB)"},
     kSplitPolygonsFlag,
     kIntegrationPointFlag,
     kProgressFlag,
     kQuietFlag}};

// "1.6 GB", "45 MB".
std::string memory_text(uint64_t bytes) {
  char text[32];
  if (bytes >= (1ull << 30))
    std::snprintf(text, sizeof text, "%.1f GB", double(bytes) / double(1ull << 30));
  else
    std::snprintf(text, sizeof text, "%.0f MB", double(bytes) / double(1ull << 20));
  return text;
}

// How many key steps the rule will choose (before reading a step to choose them).
uint64_t key_step_count(const KeyStepRule& rule, uint64_t steps) {
  switch (rule.kind) {
    case KeyStepRule::Kind::kAll: return steps;
    case KeyStepRule::Kind::kPaper: return std::min<uint64_t>(3, steps);
    case KeyStepRule::Kind::kAuto: return std::min<uint64_t>(rule.count, steps);
    case KeyStepRule::Kind::kExplicit: return std::min<uint64_t>(rule.steps.size(), steps);
  }
  return steps;
}

// The estimate before the work, and the refusal when it cannot fit: the message names the
// memory the process can have (`have`: free memory, ulimit -v, the cgroup's limit, taken before
// the faces' check built its adjacency, which is given back before the peak) and the most key
// steps that would fit. On a mesh of islands fewer of them at once are tried first (the same
// file, in less memory and time on fewer cores): `simplify` gets the number that fits. An error
// message, or "".
std::string check_memory(const Topology& input, const FrameSource& frames, const KeyStepRule& rule,
                         SimplifyOptions& simplify, bool refuse, uint64_t have) {
  const uint64_t vertices = input.vertex_count, steps = frames.step_count();
  uint64_t field_values = 0;  // per step, of every result field
  for (const FieldInfo& f : frames.fields())
    field_values += f.location == FieldLocation::kElement ? input.faces.size() : vertices;
  const std::vector<size_t> islands = island_vertex_counts(input, simplify);
  const auto estimate = [&](uint64_t keys) {
    return build_memory_estimate(vertices, input.faces.size(), steps, keys, simplify.threads,
                                 field_values,
                                 quadric_vertices_held(islands, simplify, input.vertex_count));
  };
  const uint64_t keys = key_step_count(rule, steps);
  uint64_t need = estimate(keys);
  std::string at_once;  // " with K of N islands at once" when fewer are chosen
  if (refuse && have > 0 && need > have && islands.size() > 1) {
    // Each island fewer holds its quadrics no more (the first that fits is below the default);
    // if even one at a time is too many, the key steps are suggested for one at a time.
    simplify.islands_at_once = static_cast<unsigned>(islands.size());
    while (simplify.islands_at_once > 1 && estimate(keys) > have) --simplify.islands_at_once;
    need = estimate(keys);
    if (need <= have)
      at_once = " with " + std::to_string(simplify.islands_at_once) + " of " +
                std::to_string(islands.size()) + " islands at once";
  }
  progress_remark("needs about " + memory_text(need) + at_once + " (have " +
                      (have ? memory_text(have) : std::string("unknown")) + ")",
                  "{\"memory_estimate_bytes\":" + std::to_string(need) +
                      ",\"memory_available_bytes\":" + (have ? std::to_string(have) : "null") +
                      "}");
  if (!refuse || have == 0 || need <= have) return "";
  std::string message = "needs about " + memory_text(need) + ", have " + memory_text(have);
  uint64_t fits = 0;  // the most key steps that fit
  for (uint64_t k = keys; k-- > 1;)
    if (estimate(k) <= have) {
      fits = k;
      break;
    }
  if (fits > 0) message += "; try --key-steps auto:" + std::to_string(fits);
  return message + " (--no-memory-check builds anyway)";
}

size_t total_variant_steps(const std::vector<MeshVariant>& variants) {
  size_t total = 0;
  for (const MeshVariant& v : variants) total += v.steps.size();
  return total;
}

}  // namespace

int run_build(std::span<char* const> arguments) {
  Args args;
  if (auto exit_code = parse_verb_args(arguments, kSpec, args)) return *exit_code;
  if (auto exit_code = require_inputs_and_output(args, kSpec, "MODEL.dpm")) return *exit_code;
  const auto output = args.value("--output");
  BuildOptions options;
  auto quantization = parse_quantization_flags(args);
  if (!quantization) return fail(kSpec.name, kExitUsage, quantization.message());
  options.lossless = quantization->lossless;
  if (quantization->position_error) options.max_position_error = *quantization->position_error;
  if (quantization->field_bound) options.field_bound = *quantization->field_bound;
  KeyStepRule key_rule;
  if (Status s = parse_simplify_flags(args, options.simplify, key_rule); !s.ok())
    return fail(kSpec.name, kExitUsage, s.message());

  const ProgressCallback report = progress;
  std::optional<InputToSimplify> single;
  std::optional<FamilyInputs> family;
  if (args.has("--family")) {
    auto opened = open_family(args, *output, report, options.simplify.threads);
    if (!opened) return fail(kSpec.name, kExitFailure, opened.message());
    family.emplace(std::move(*opened));
    options.variants = family->steps->variants();
    options.simplify.checked = family->checked;
  } else {
    auto opened = open_input_unchecked(args, *output);
    if (!opened) return fail(kSpec.name, kExitFailure, opened.message());
    single.emplace(std::move(*opened));
  }
  Topology& input = family ? family->members[0].topology : single->stream.topology;
  const FrameSource& frames = family ? *family->steps : *single->stream.frames;
  if (Status s = check_cost_fields(options.simplify, frames); !s.ok())
    return fail(kSpec.name, kExitUsage, s.message());
  const auto start = std::chrono::steady_clock::now();
  // What the process can have, before the faces' check below builds its adjacency (a family's
  // was built while opening it).
  uint64_t have = available_memory_bytes();
  if (family && have > 0 && options.simplify.checked)
    have += options.simplify.checked->adjacency_bytes();
  // A single input's faces are checked on a thread of their own while the memory is estimated
  // and the key steps are chosen (reading every step): both are about one core's work for as
  // long. A failed check stops the reading; its message comes first, as when they ran in turn.
  std::atomic<bool> stop_reading{false};
  std::optional<ValidationProof> proof;  // the check's, handed to the simplifier once it ended
  std::future<Status> faces_checked;
  const auto check_faces = [&] {
    Status checked = check_input_faces(*single, proof);
    if (!checked.ok()) stop_reading = true;
    return checked;
  };
  if (single) {
    try {
      faces_checked = std::async(std::launch::async, check_faces);
    } catch (const std::system_error&) {  // no thread to be had (limits): checked here, first
      std::promise<Status> now;
      now.set_value(check_faces());
      faces_checked = now.get_future();
    }
  }
  const auto faces_error = [&]() -> std::optional<int> {
    if (!faces_checked.valid()) return std::nullopt;
    Phase phase("checking the input");
    const Status checked = faces_checked.get();
    if (!checked.ok()) return fail(kSpec.name, kExitFailure, checked.message());
    options.simplify.checked = std::move(proof);
    return std::nullopt;
  };
  if (std::string refused = check_memory(input, frames, key_rule, options.simplify,
                                         !args.has("--no-memory-check"), have);
      !refused.empty()) {
    stop_reading = true;
    if (auto exit_code = faces_error()) return *exit_code;
    return fail(kSpec.name, kExitFailure, refused);
  }
  std::optional<Phase> phase(std::in_place, "choosing the key steps");
  auto key_steps =
      choose_key_steps(frames, key_rule, options.simplify.threads, report, &stop_reading);
  if (auto exit_code = faces_error()) return *exit_code;
  if (!key_steps) return fail(kSpec.name, kExitFailure, key_steps.message());
  options.simplify.key_steps = key_steps->steps;
  options.all_steps_box = key_steps->all_steps_box;  // the last pass quantizes as it reads
  const bool json = args.has("--json");
  if (!json)
    for (const std::string& reason : key_steps->reasons)
      std::printf("key step  %s\n", reason.c_str());
  options.note = "dynpm build of " + std::filesystem::path(args.positional[0]).filename().string() +
                 (args.positional.size() > 1 ? " …" : "");
  options.progress = report;
  // The catalogue's picture of the model, at 5 %, drawn as the build ends.
  if (!args.has("--no-thumbnail")) options.thumbnail = ThumbnailOptions{};

  phase.emplace("simplifying, recording and encoding");
  const size_t faces = input.faces.size(), quads = input.quad_count(),
               triangles = input.triangle_count();
  auto built = build_dpm(std::move(input), frames, options);  // its faces freed when recorded
  if (!built) return fail(kSpec.name, kExitFailure, built.message());
  const ProgressiveMesh& mesh = built->mesh;
  const std::string& bytes = built->bytes;
  phase.emplace("writing the .dpm file");
  progress("writing", 0, 1);
  if (Status s = write_file_atomically(*output, bytes); !s.ok())
    return fail(kSpec.name, kExitFailure, s.message());
  progress("writing", 1, 1);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  const size_t steps = mesh.step_count();
  const double raw = double(input.vertex_count) * steps * 12.0;  // float32 xyz per step
  const double per_vertex_step = double(bytes.size()) / (double(input.vertex_count) * steps);
  if (json) {
    Json j;
    j.begin_object();
    j.value("output", *output);
    j.value("vertices", uint64_t{input.vertex_count});
    j.value("faces", uint64_t{faces});
    j.value("quads", uint64_t{quads});
    j.value("triangles", uint64_t{triangles});
    j.value("steps", uint64_t{steps});
    j.begin_array("variants");
    for (const MeshVariant& v : options.variants) {
      j.begin_object();
      j.value("name", v.name);
      j.value("steps", uint64_t{v.steps.size()});
      j.end_object();
    }
    j.end_array();
    j.begin_array("key_steps");
    for (size_t k : mesh.key_steps) j.item(int64_t(k));
    j.end_array();
    j.value("base_vertices", uint64_t{mesh.base_vertex_count});
    j.value("base_faces", uint64_t{mesh.base_face_count});
    j.value("splits", uint64_t{mesh.split_count()});
    j.value("lossless", mesh.lossless);
    j.value("position_error", mesh.max_error);
    j.value("diagonal", mesh.diagonal());
    j.value("base_error", mesh.base_error);
    j.value("bytes", uint64_t{bytes.size()});
    j.value("bytes_per_vertex_step", per_vertex_step);
    j.value("ratio_to_float32", raw / double(bytes.size()));
    j.value("seconds", seconds);
    j.value("peak_rss_mb", peak_rss_mb());
    j.end_object();
    std::cout << j.str();
    return kExitOk;
  }
  std::printf("input   %u vertices, %zu faces (%zu quads, %zu triangles), %zu steps\n",
              input.vertex_count, faces, quads, triangles, steps);
  if (!options.variants.empty())
    std::printf("family  %zu variants, %zu distinct steps stored of %zu\n", options.variants.size(),
                steps, total_variant_steps(options.variants));
  std::printf("base    %u vertices, %u faces; %u vertex splits rebuild the input\n",
              mesh.base_vertex_count, mesh.base_face_count, mesh.split_count());
  if (mesh.lossless)
    std::printf("positions lossless (float32)\n");
  else
    std::printf("positions within %.3g (%.2g of the diagonal %.4g)\n", mesh.max_error,
                of_diagonal(mesh.max_error, mesh.diagonal()), mesh.diagonal());
  // Fields: each quantized to its bound (docs/FORMAT.md "Fields"), in the cost unless weighed 0.
  for (const ProgressiveField& f : mesh.fields) {
    std::printf("field   %s (%s), %.4g … %.4g: ", printable(f.info.name).c_str(),
                to_string(f.info.location), f.min, f.max);
    if (f.lossless)
      std::printf("lossless\n");
    else
      std::printf("within %.3g\n", f.max_error);
  }
  // "0.7x smaller" reads as a gain: a file larger than the floats says so.
  const double ratio = raw / double(bytes.size());
  std::printf("wrote   %s: %zu bytes, %.2f bytes per vertex per step, %.1f× %s than float32\n",
              output->c_str(), bytes.size(), per_vertex_step, ratio >= 1 ? ratio : 1 / ratio,
              ratio >= 1 ? "smaller" : "larger");
  std::printf("%.3f s; peak memory %.0f MB\n", seconds, peak_rss_mb());
  return kExitOk;
}

}  // namespace dynpm::cli
