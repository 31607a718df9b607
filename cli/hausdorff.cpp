// dynpm hausdorff: how far apart two meshes (or two step sequences) are, measured as Metro does.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <string>

#include "args.h"
#include "commands.h"
#include "dynpm/eval.h"
#include "inputs.h"
#include "json.h"
#include "report.h"
#include "shared_flags.h"

namespace dynpm::cli {
namespace {

const VerbSpec kSpec{
    "hausdorff",
    "dynpm hausdorff A B [--samples N] [--seed S] [--json]",
    "Measures the distance between the surfaces A and B as Metro does (Cignoni et al. 1998):\n"
    "each surface is sampled (vertices, edges, and faces in proportion to area) and every\n"
    "sample's distance to the other surface is computed exactly. Prints the one-sided max,\n"
    "mean and RMS both ways, and the two-sided Hausdorff distance (the larger max), mean and\n"
    "RMS, in absolute units and in % of A's bounding-box diagonal. Quads are measured as four\n"
    "triangles through their centroid. A and B are each a mesh file or a quoted glob of step\n"
    "files ('frames/frame_*.obj'); two sequences are compared step by step, and a single mesh\n"
    "against every step of a sequence. Results depend on the seed only, not on the threads.",
    {kSamplesFlag,
     kSamplesPerFaceFlag,
     kSeedFlag,
     {"--diagonal", "", true, "D", "percentages of D instead of A's bounding-box diagonal"},
     kThreadsFlag,
     {"--json", "", false, "", "print the result as JSON on stdout"},
     kSplitPolygonsFlag,
     kIntegrationPointFlag,
     kProgressFlag,
     kQuietFlag}};

std::string describe(const std::vector<std::string>& files, const AnimationStream& stream) {
  std::string text = files.front();
  if (files.size() > 1) text += " … " + files.back();
  const size_t steps = stream.frames->step_count();
  text += " (" + std::to_string(steps) + (steps == 1 ? " step, " : " steps, ") +
          std::to_string(stream.topology.quad_count()) + " quads, " +
          std::to_string(stream.topology.triangle_count()) + " triangles)";
  return text;
}

// `label` comes padded to the 14 columns of the other labels ("→" is one column, three bytes).
void print_one_sided(const char* label, const OneSidedDistance& d, const HausdorffResult& r) {
  std::printf("%smax %.6g (%.4g %%)  mean %.6g (%.4g %%)  rms %.6g (%.4g %%)\n", label, d.max,
              r.percent(d.max), d.mean, r.percent(d.mean), d.rms, r.percent(d.rms));
}

void print_text(const std::string& a, const std::string& b, const HausdorffSteps& s,
                const HausdorffResult& all, bool diagonal_given) {
  std::printf("A             %s\nB             %s\n", a.c_str(), b.c_str());
  std::printf(
      "samples       A: %llu area, %llu edge, %llu vertex; B: %llu area, %llu edge, "
      "%llu vertex%s\n",
      static_cast<unsigned long long>(all.a_to_b.face_samples),
      static_cast<unsigned long long>(all.a_to_b.edge_samples),
      static_cast<unsigned long long>(all.a_to_b.vertex_samples),
      static_cast<unsigned long long>(all.b_to_a.face_samples),
      static_cast<unsigned long long>(all.b_to_a.edge_samples),
      static_cast<unsigned long long>(all.b_to_a.vertex_samples),
      s.steps.size() > 1 ? " (all steps)" : "");
  std::printf("diagonal      %.6g (%s)\n", s.diagonal,
              diagonal_given       ? "--diagonal"
              : s.steps.size() > 1 ? "A's bounding box over all steps"
                                   : "A's bounding box");
  if (s.steps.size() > 1) {
    std::printf(
        "\n  step     hausdorff        mean         rms     A→B max     B→A max"
        "   (%% of the diagonal)\n");
    for (size_t t = 0; t < s.steps.size(); ++t) {
      const HausdorffResult& r = s.steps[t];
      std::printf("%6zu  %12.5g  %10.5g  %10.5g  %10.5g  %10.5g\n", t, r.percent(r.hausdorff),
                  r.percent(r.mean), r.percent(r.rms), r.percent(r.a_to_b.max),
                  r.percent(r.b_to_a.max));
    }
    for (bool is_max : {false, true}) {
      auto v = [&](const OverSteps& o) { return all.percent(is_max ? o.max : o.mean); };
      std::printf("%6s  %12.5g  %10.5g  %10.5g  %10.5g  %10.5g\n", is_max ? "max" : "mean",
                  v(s.hausdorff), v(s.mean), v(s.rms), v(s.a_to_b_max), v(s.b_to_a_max));
    }
    std::printf("\nover all steps (max of maxima, mean of means, RMS of RMS values):\n");
  }
  print_one_sided("A → B         ", all.a_to_b, all);
  print_one_sided("B → A         ", all.b_to_a, all);
  std::printf("two-sided     hausdorff %.6g (%.4g %%)  mean %.6g (%.4g %%)  rms %.6g (%.4g %%)\n",
              all.hausdorff, all.percent(all.hausdorff), all.mean, all.percent(all.mean), all.rms,
              all.percent(all.rms));
}

void json_one_sided(Json& j, const char* key, const OneSidedDistance& d, const HausdorffResult& r) {
  j.begin_object(key);
  j.value("max", d.max);
  j.value("mean", d.mean);
  j.value("rms", d.rms);
  j.value("max_pct", r.percent(d.max));
  j.value("mean_pct", r.percent(d.mean));
  j.value("rms_pct", r.percent(d.rms));
  j.begin_array("max_at");
  for (double c : d.max_at) j.item(c);
  j.end_array();
  j.value("vertex_samples", uint64_t{d.vertex_samples});
  j.value("edge_samples", uint64_t{d.edge_samples});
  j.value("face_samples", uint64_t{d.face_samples});
  j.end_object();
}

void print_json(const std::vector<std::string>& a, const std::vector<std::string>& b,
                const HausdorffSteps& s, const HausdorffResult& all, uint64_t seed) {
  Json j;
  j.begin_object();
  for (auto [key, files] : {std::pair{"a", &a}, std::pair{"b", &b}}) {
    j.begin_array(key);
    for (const std::string& f : *files) j.item(f);
    j.end_array();
  }
  j.value("steps", uint64_t{s.steps.size()});
  j.value("seed", seed);
  j.value("diagonal", all.diagonal);
  j.value("hausdorff", all.hausdorff);
  j.value("mean", all.mean);
  j.value("rms", all.rms);
  j.value("hausdorff_pct", all.percent(all.hausdorff));
  j.value("mean_pct", all.percent(all.mean));
  j.value("rms_pct", all.percent(all.rms));
  j.value("a_to_b_pct", all.percent(all.a_to_b.max));
  j.value("b_to_a_pct", all.percent(all.b_to_a.max));
  json_one_sided(j, "a_to_b", all.a_to_b, all);
  json_one_sided(j, "b_to_a", all.b_to_a, all);
  if (s.steps.size() > 1) {
    using Measure = double (*)(const HausdorffResult&);
    const std::pair<const char*, Measure> columns[] = {
        {"hausdorff", [](const HausdorffResult& r) { return r.hausdorff; }},
        {"hausdorff_pct", [](const HausdorffResult& r) { return r.percent(r.hausdorff); }},
        {"mean_pct", [](const HausdorffResult& r) { return r.percent(r.mean); }},
        {"rms_pct", [](const HausdorffResult& r) { return r.percent(r.rms); }},
        {"a_to_b_pct", [](const HausdorffResult& r) { return r.percent(r.a_to_b.max); }},
        {"b_to_a_pct", [](const HausdorffResult& r) { return r.percent(r.b_to_a.max); }}};
    j.begin_object("per_step");
    for (const auto& [key, measure] : columns) {
      j.begin_array(key);
      for (const HausdorffResult& r : s.steps) j.item(measure(r));
      j.end_array();
    }
    j.end_object();
    j.begin_object("over_steps");
    for (auto [key, o] : {std::pair{"hausdorff_pct", &s.hausdorff}, std::pair{"mean_pct", &s.mean},
                          std::pair{"rms_pct", &s.rms}, std::pair{"a_to_b_pct", &s.a_to_b_max},
                          std::pair{"b_to_a_pct", &s.b_to_a_max}}) {
      j.begin_object(key);
      j.value("mean", all.percent(o->mean));
      j.value("max", all.percent(o->max));
      j.end_object();
    }
    j.end_object();
  }
  j.end_object();
  std::cout << j.str();
}

}  // namespace

int run_hausdorff(std::span<char* const> arguments) {
  Args args;
  if (auto exit_code = parse_verb_args(arguments, kSpec, args)) return *exit_code;
  if (args.positional.size() != 2)
    return fail(kSpec.name, kExitUsage, "needs two inputs, A and B (quote a glob of step files)",
                help_text(kSpec));
  StepsOptions options;
  HausdorffOptions& h = options.hausdorff;
  auto fail_usage = [](const std::string& message) {
    return fail(kSpec.name, kExitUsage, message);
  };
  if (Status s = parse_sampling_flags(args, h); !s.ok()) return fail_usage(s.message());
  if (const auto text = args.value("--diagonal")) {
    auto r = parse_number("--diagonal", *text, {0, kAnyNumber.max, true});
    if (!r) return fail_usage(r.message());
    h.reference_diagonal = *r;
  }

  std::vector<std::string> files[2];
  AnimationStream streams[2];
  for (int side = 0; side < 2; ++side) {
    const std::string argument = args.positional[side];
    auto expanded = expand_inputs(std::span<const std::string>(&argument, 1));
    if (!expanded) return fail(kSpec.name, kExitFailure, expanded.message());
    files[side] = *expanded;
    auto stream = open_inputs(files[side], args);
    if (!stream) return fail(kSpec.name, kExitFailure, stream.message());
    streams[side] = std::move(*stream);
  }
  const size_t steps = std::max(streams[0].frames->step_count(), streams[1].frames->step_count());
  if (steps > 1)
    options.progress = [](size_t done, size_t total) { progress("measuring step", done, total); };
  auto result = hausdorff_steps(streams[0].topology, *streams[0].frames, streams[1].topology,
                                *streams[1].frames, options);
  if (!result) return fail(kSpec.name, kExitFailure, result.message());
  const HausdorffResult all = as_one_result(*result);
  if (args.has("--json"))
    print_json(files[0], files[1], *result, all, h.seed);
  else
    print_text(describe(files[0], streams[0]), describe(files[1], streams[1]), *result, all,
               h.reference_diagonal > 0);
  return kExitOk;
}

}  // namespace dynpm::cli
