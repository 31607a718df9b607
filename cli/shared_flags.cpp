#include "shared_flags.h"

#include <cmath>
#include <string>

namespace dynpm::cli {

Status parse_simplify_flags(const Args& args, SimplifyOptions& options, KeyStepRule& key_steps) {
  auto rule = parse_key_step_rule(args.value("--key-steps").value_or("all"));
  if (!rule) return rule.status();
  key_steps = *rule;
  if (auto v = args.value("--boundary-weight")) {
    auto r = parse_number("--boundary-weight", *v, kBoundaryWeights);
    if (!r) return r.status();
    options.boundary_weight = *r;
  }
  for (const char* flag : {"--field-weight", "--regularize"})
    if (auto v = args.value(flag)) {
      auto r = parse_number(flag, *v, kBoundaryWeights);
      if (!r) return r.status();
      (flag == std::string("--regularize") ? options.regularize : options.field_weight) = *r;
    }
  for (const std::string& text : args.values("--field")) {
    // NAME or NAME:W; a name may itself hold ':', so the weight is after the last one.
    SimplifyOptions::FieldWeight field{text, std::nullopt};
    if (const size_t colon = text.rfind(':'); colon != std::string::npos) {
      auto r = parse_number("--field " + text.substr(0, colon), text.substr(colon + 1),
                            kBoundaryWeights);
      if (!r) return r.status();
      field = {text.substr(0, colon), *r};
    }
    if (field.name.empty()) return Status::error("--field needs a field name: --field NAME[:W]");
    options.field_weights.push_back(field);
  }
  if (auto v = args.value("--field-cost")) {
    std::string form = *v, combine;
    if (const size_t comma = form.find(','); comma != std::string::npos)
      combine = form.substr(comma + 1), form.resize(comma);
    if (form == "spread")
      options.field_form = FieldForm::kSpread;
    else if (form == "attributes")
      options.field_form = FieldForm::kAttributes;
    else if (form == "quadric")
      options.field_form = FieldForm::kQuadric;
    else
      return Status::error("--field-cost: unknown form '" + form +
                           "' (spread, attributes, quadric)");
    if (combine == "add")
      options.field_combine = FieldCombine::kAdd;
    else if (combine == "scale")
      options.field_combine = FieldCombine::kScale;
    else if (!combine.empty())
      return Status::error("--field-cost: unknown combination '" + combine + "' (add, scale)");
  }
  if (auto v = args.value("--rounds")) {
    auto r = parse_number("--rounds", *v, kRoundFractions);
    if (!r) return r.status();
    options.independent_rounds = *r;
  }
  options.keep_part_boundaries = !args.has("--ignore-parts");
  if (const auto text = args.value("--threads")) {
    auto r = parse_whole("--threads", *text, 0, kMaxThreads);
    if (!r) return r.status();
    options.threads = static_cast<unsigned>(*r);
  }
  return {};
}

Status check_cost_fields(const SimplifyOptions& options, const FrameSource& frames) {
  auto fields = cost_fields(options, frames);
  if (!fields) return Status::error("--field: " + fields.message());
  return {};
}

Result<std::optional<StepChoice>> parse_step_flag(const Args& args) {
  auto v = args.value("--step");
  if (!v) return std::optional<StepChoice>();
  StepChoice step;
  step.text = *v;
  step.last = *v == "last";
  if (!step.last) {
    auto r = parse_number("--step", *v, kNonNegative);
    if (!r) return Status::error("--step needs a number ≥ 0 or 'last', got " + quoted_value(*v));
    step.value = *r;
  }
  return std::optional<StepChoice>(step);
}

std::optional<size_t> StepChoice::last_step_to_read() const {
  if (last) return std::nullopt;
  return static_cast<size_t>(std::ceil(value));
}

Result<double> StepChoice::in_model(size_t steps, const std::string& path) const {
  if (last) return double(steps - 1);
  if (value <= double(steps - 1)) return value;
  return Status::error("--step needs a number in [0, " + std::to_string(steps - 1) +
                       "] or 'last' (" + path + " has " + std::to_string(steps) +
                       (steps == 1 ? " step), got " : " steps), got ") + quoted_value(text));
}

Result<LevelFlags> parse_level_flags(const Args& args) {
  LevelFlags level;
  if (auto v = args.value("--ratio")) {
    auto r = parse_number("--ratio", *v, kFraction);
    if (!r) return r.status();
    level.ratio = *r;
  }
  if (auto v = args.value("--vertices")) {
    auto r = parse_whole("--vertices", *v, 1, kMaxVertexCount);
    if (!r) return r.status();
    level.vertices = *r;
  }
  if (auto v = args.value("--faces")) {
    auto r = parse_whole("--faces", *v, 1, kMaxFaceCount);
    if (!r) return r.status();
    level.faces = *r;
  }
  if (auto v = args.value("--max-error")) {
    std::string text = *v;
    level.max_error_in_percent = !text.empty() && text.back() == '%';
    if (level.max_error_in_percent) text.pop_back();
    auto r = level.max_error_in_percent ? parse_number("--max-error (in %)", text, kPercent)
                                        : parse_number("--max-error", text, kNonNegative);
    if (!r) return r.status();
    level.max_error = *r;
  }
  return level;
}

Status parse_sampling_flags(const Args& args, HausdorffOptions& options) {
  struct WholeFlag {
    const char* name;
    uint64_t max;
    uint64_t* value;
  };
  uint64_t threads = 0;
  for (const WholeFlag& flag : {WholeFlag{"--samples", kMaxSamples, &options.face_samples},
                                WholeFlag{"--seed", UINT64_MAX, &options.seed},
                                WholeFlag{"--threads", kMaxThreads, &threads}})
    if (const auto text = args.value(flag.name)) {
      auto r = parse_whole(flag.name, *text, 0, flag.max);
      if (!r) return r.status();
      *flag.value = *r;
    }
  options.threads = static_cast<unsigned>(threads);
  if (const auto text = args.value("--samples-per-face")) {
    auto r = parse_number("--samples-per-face", *text, {0, 1e4, true});
    if (!r) return r.status();
    options.samples_per_face = *r;
  }
  return {};
}

Result<QuantizationFlags> parse_quantization_flags(const Args& args) {
  QuantizationFlags flags;
  flags.lossless = args.has("--lossless");
  if (auto v = args.value("--position-error")) {
    // In diagonals: above one the grid keeps nothing of the shape (and inf cannot be stored).
    auto r = parse_number("--position-error", *v, kFraction);
    if (!r) return r.status();
    flags.position_error = *r;
  }
  if (auto v = args.value("--field-bound")) {
    // In % of each field's range: 0 would be lossless (--lossless says so), above 100 keeps
    // nothing.
    auto r = parse_number("--field-bound", *v, NumberRange{0, 100, true});
    if (!r) return r.status();
    flags.field_bound = *r / 100;
  }
  return flags;
}

}  // namespace dynpm::cli
