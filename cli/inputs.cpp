#include "inputs.h"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <vector>

#include "commands.h"
#include "outputs.h"
#include "report.h"

namespace dynpm::cli {
namespace {
// Hands steps through and refuses a NaN or infinite coordinate, naming the file, the step and
// the vertex (and its node number): such a position must never reach the simplifier, a writer
// or the distance measure. Readers keep such values (validation judges them), so 'dynpm info'
// lists them instead.
class FinitePositions final : public FrameSource {
 public:
  // node_ids: the stream's own (moving the stream moves the vector, not its array), not a copy
  // of 8 B per vertex that would only serve a message.
  FinitePositions(std::unique_ptr<FrameSource> source, std::vector<std::string> paths,
                  std::span<const int64_t> node_ids)
      : source_(std::move(source)), paths_(std::move(paths)), node_ids_(node_ids) {}
  uint32_t vertex_count() const override { return source_->vertex_count(); }
  size_t step_count() const override { return source_->step_count(); }
  double step_time(size_t t) const override { return source_->step_time(t); }
  size_t step_float_count(size_t t) const override { return source_->step_float_count(t); }
  bool parallel_reads() const override { return source_->parallel_reads(); }  // keeps no state
  std::vector<FieldInfo> fields() const override { return source_->fields(); }
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
  std::span<const int64_t> node_ids_;
};

// The first error validate() finds in the faces, named by the file they came from (the first
// one of a sequence), with the element or node number where the file has one; else the proof
// that there is none in `proof`.
Status check_faces(const Topology& topology, const std::string& file,
                   std::optional<ValidationProof>& proof) {
  const ValidationReport report = check_topology(topology, proof);
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

// The reading flags every verb that opens inputs offers.
Result<ReadOptions> read_options(const Args& args) {
  ReadOptions options;
  options.split_polygons = args.has("--split-polygons");
  if (const auto point = args.value("--integration-point")) {
    bool known = false;
    for (IntegrationPoint p : {IntegrationPoint::kMid, IntegrationPoint::kTop,
                               IntegrationPoint::kBottom, IntegrationPoint::kMax})
      if (*point == to_string(p)) options.integration_point = p, known = true;
    if (!known)
      return Status::error("--integration-point: expected mid, top, bottom or max, not '" + *point +
                           "'");
  }
  return options;
}

// open_inputs() of files already expanded.
Result<AnimationStream> open_files(const std::vector<std::string>& paths, const Args& args,
                                   InputChecks checks, std::optional<ValidationProof>* checked) {
  auto read = read_options(args);
  if (!read) return read.status();
  ReadOptions options = std::move(read).value();
  options.warn = [](const std::string& note) { std::cerr << "warning: " << note << "\n"; };
  auto stream = open_input(paths, options);
  if (!stream || checks == InputChecks::kNone) return stream;
  if (checks == InputChecks::kSimplifiable) {
    std::optional<ValidationProof> proof;
    DYNPM_RETURN_IF_ERROR(check_faces(stream->topology, paths.front(), proof));
    if (checked) *checked = proof;
  }
  stream->frames = std::make_unique<FinitePositions>(std::move(stream->frames), paths,
                                                     stream->topology.node_ids);
  return stream;
}

}  // namespace

Result<AnimationStream> open_inputs(std::span<const std::string> arguments, const Args& args,
                                    InputChecks checks, std::optional<ValidationProof>* checked) {
  auto paths = expand_inputs(arguments);
  if (!paths) return paths.status();
  return open_files(*paths, args, checks, checked);
}

std::optional<int> require_inputs_and_output(const Args& args, const VerbSpec& spec,
                                             const std::string& output_name) {
  if (!args.positional.empty() && args.value("--output")) return std::nullopt;
  return fail(spec.name, kExitUsage, "needs INPUT... and -o " + output_name, help_text(spec));
}

Result<AnimationStream> open_input_to_simplify(const Args& args, const std::string& output,
                                               std::optional<ValidationProof>& checked) {
  DYNPM_RETURN_IF_ERROR(check_output_folder(output));
  Phase phase("reading the input");
  return open_inputs(args.positional, args, InputChecks::kSimplifiable, &checked);
}

Result<InputToSimplify> open_input_unchecked(const Args& args, const std::string& output) {
  DYNPM_RETURN_IF_ERROR(check_output_folder(output));
  Phase phase("reading the input");
  auto paths = expand_inputs(args.positional);
  if (!paths) return paths.status();
  auto stream = open_files(*paths, args, InputChecks::kFinite, nullptr);
  if (!stream) return stream.status();
  return InputToSimplify{std::move(stream).value(), paths->front()};
}

Status check_input_faces(const InputToSimplify& input, std::optional<ValidationProof>& checked) {
  return check_faces(input.stream.topology, input.first_file, checked);
}

}  // namespace dynpm::cli
