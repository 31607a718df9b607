// Hausdorff distances over time steps (hausdorff.cpp measures one step): step t of A against
// step t of B, one step of each read at a time, and the mean and max of each measure over the
// steps.
#include <algorithm>
#include <cmath>
#include <string>

#include "dynpm/eval.h"

namespace dynpm {
namespace {

Result<HausdorffResult> measure_step(const SurfaceTopology& a, std::span<const float> a_positions,
                                     const SurfaceTopology& b, std::span<const float> b_positions,
                                     const HausdorffOptions& options) {
  auto a_step = prepare_surface("A", a, a_positions, options.threads);
  if (!a_step) return a_step.status();
  auto b_step = prepare_surface("B", b, b_positions, options.threads);
  if (!b_step) return b_step.status();
  return hausdorff(*a_step, *b_step, options);
}

void summarize(HausdorffSteps& s) {
  auto over = [&](auto&& value) {
    OverSteps o;
    for (const HausdorffResult& r : s.steps) {
      o.mean += value(r);
      o.max = std::max(o.max, value(r));
    }
    if (!s.steps.empty()) o.mean /= double(s.steps.size());
    return o;
  };
  s.hausdorff = over([](const HausdorffResult& r) { return r.hausdorff; });
  s.mean = over([](const HausdorffResult& r) { return r.mean; });
  s.rms = over([](const HausdorffResult& r) { return r.rms; });
  s.a_to_b_max = over([](const HausdorffResult& r) { return r.a_to_b.max; });
  s.b_to_a_max = over([](const HausdorffResult& r) { return r.b_to_a.max; });
}

}  // namespace

Result<HausdorffSteps> hausdorff_steps(const Topology& a_topology, const FrameSource& a_frames,
                                       const Topology& b_topology, const FrameSource& b_frames,
                                       const StepsOptions& options) {
  const size_t a_steps = a_frames.step_count(), b_steps = b_frames.step_count();
  if (a_steps == 0 || b_steps == 0) return Status::error("no time steps to compare");
  if (a_steps != b_steps && a_steps != 1 && b_steps != 1)
    return Status::error("A has " + std::to_string(a_steps) + " time steps and B " +
                         std::to_string(b_steps) + "; step-by-step comparison needs equal counts");
  if (a_frames.vertex_count() != a_topology.vertex_count ||
      b_frames.vertex_count() != b_topology.vertex_count)
    return Status::error("the time steps and the faces disagree on the vertex count");
  auto a = prepare_topology("A", a_topology);
  if (!a) return a.status();
  auto b = prepare_topology("B", b_topology);
  if (!b) return b.status();

  HausdorffSteps result;
  const size_t steps = std::max(a_steps, b_steps);
  std::vector<float> a_xyz(size_t{a_topology.vertex_count} * 3);
  std::vector<float> b_xyz(size_t{b_topology.vertex_count} * 3);
  BoundingBox a_box;
  for (size_t t = 0; t < steps; ++t) {
    if (t == 0 || a_steps > 1) {
      DYNPM_RETURN_IF_ERROR(a_frames.read_step(t, a_xyz));
      a_box.extend(a_xyz);
    }
    if (t == 0 || b_steps > 1) DYNPM_RETURN_IF_ERROR(b_frames.read_step(t, b_xyz));
    auto r = measure_step(*a, a_xyz, *b, b_xyz, options.hausdorff);
    if (!r) return Status::error("step " + std::to_string(t) + ": " + r.message());
    result.steps.push_back(*r);
    if (options.progress) options.progress(t + 1, steps);
  }
  result.diagonal = options.hausdorff.reference_diagonal > 0 ? options.hausdorff.reference_diagonal
                                                             : a_box.diagonal();
  for (HausdorffResult& r : result.steps) r.diagonal = result.diagonal;
  summarize(result);
  return result;
}

HausdorffResult as_one_result(const HausdorffSteps& s) {
  HausdorffResult all;
  all.diagonal = s.diagonal;
  const double n = double(s.steps.size());
  for (const HausdorffResult& r : s.steps) {
    for (auto [to, d] : {std::pair{&all.a_to_b, &r.a_to_b}, std::pair{&all.b_to_a, &r.b_to_a}}) {
      if (d->max > to->max || &r == &s.steps.front()) to->max_at = d->max_at;
      to->max = std::max(to->max, d->max);
      to->mean += d->mean / n;
      to->rms += d->rms * d->rms / n;
      to->vertex_samples += d->vertex_samples, to->edge_samples += d->edge_samples;
      to->face_samples += d->face_samples;
    }
    all.mean += r.mean / n;
    all.rms += r.rms * r.rms / n;
  }
  all.a_to_b.rms = std::sqrt(all.a_to_b.rms);
  all.b_to_a.rms = std::sqrt(all.b_to_a.rms);
  all.rms = std::sqrt(all.rms);
  all.hausdorff = std::max(all.a_to_b.max, all.b_to_a.max);
  return all;
}

}  // namespace dynpm
