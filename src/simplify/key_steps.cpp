// Key steps (paper §3): which time steps rate the collapses. The paper keeps the first, the
// last and the step of strongest deformation; auto:K generalises that by farthest-point
// sampling over the steps, with the largest vertex displacement as the distance.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <numeric>

#include "dynpm/simplify.h"
#include "dynpm/text.h"

namespace dynpm {
namespace {

// The largest distance any probe vertex moves between two steps.
double max_displacement(std::span<const float> a, std::span<const float> b) {
  double worst = 0;
  for (size_t i = 0; i + 2 < a.size(); i += 3) {
    const double dx = double{a[i]} - b[i], dy = double{a[i + 1]} - b[i + 1],
                 dz = double{a[i + 2]} - b[i + 2];
    worst = std::max(worst, dx * dx + dy * dy + dz * dz);
  }
  return std::sqrt(worst);
}

std::string format_mm(double d) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.4g", d);
  return buffer;
}

}  // namespace

Result<KeyStepRule> parse_key_step_rule(const std::string& text) {
  KeyStepRule rule;
  const auto bad = [&] {
    return Status::error("key steps " + quoted_bytes(text) +
                         ": use all, paper, auto:K or a list such as 0,12,24");
  };
  if (text == "all") return rule;
  if (text == "paper") {
    rule.kind = KeyStepRule::Kind::kPaper;
    return rule;
  }
  if (text.rfind("auto:", 0) == 0) {
    rule.kind = KeyStepRule::Kind::kAuto;
    const char* begin = text.data() + 5;
    auto [end, ec] = std::from_chars(begin, text.data() + text.size(), rule.count);
    if (ec != std::errc() || end != text.data() + text.size() || rule.count == 0) return bad();
    return rule;
  }
  rule.kind = KeyStepRule::Kind::kExplicit;
  const char* p = text.data();
  const char* end = text.data() + text.size();
  while (p < end) {
    size_t step = 0;
    auto [next, ec] = std::from_chars(p, end, step);
    if (ec != std::errc()) return bad();
    rule.steps.push_back(step);
    p = next;
    if (p < end && (*p++ != ',' || p == end)) return bad();
  }
  if (rule.steps.empty()) return bad();
  return rule;
}

Result<KeyStepChoice> choose_key_steps(const FrameSource& frames, const KeyStepRule& rule,
                                       unsigned threads, const ProgressCallback& progress,
                                       const std::atomic<bool>* stop) {
  const size_t steps = frames.step_count();
  if (steps == 0) return Status::error("the animation has no time step");
  KeyStepChoice choice;
  using Kind = KeyStepRule::Kind;
  if (rule.kind == Kind::kAll || steps == 1) {
    for (size_t t = 0; t < steps; ++t) choice.steps.push_back(t);
    choice.reasons.push_back("all " + std::to_string(steps) + " steps");
    return choice;
  }
  if (rule.kind == Kind::kExplicit) {
    choice.steps = rule.steps;
    std::sort(choice.steps.begin(), choice.steps.end());
    choice.steps.erase(std::unique(choice.steps.begin(), choice.steps.end()), choice.steps.end());
    for (size_t t : choice.steps) {
      if (t >= steps)
        return Status::error("key step " + std::to_string(t) +
                             " does not exist (the animation has " + std::to_string(steps) +
                             " steps, 0 to " + std::to_string(steps - 1) + ")");
      choice.reasons.push_back("step " + std::to_string(t) + ": given");
    }
    return choice;
  }

  // Probe positions of every step, on evenly spread vertices.
  const uint32_t n = frames.vertex_count();
  const uint32_t stride = std::max<uint32_t>(1, (n + kMaxProbeVertices - 1) / kMaxProbeVertices);
  std::vector<std::vector<float>> probes(steps);
  std::vector<size_t> every(steps);
  std::iota(every.begin(), every.end(), size_t{0});
  if (progress) progress("choosing key steps", 0, steps);
  size_t done = 0;
  BoundingBox box;
  DYNPM_RETURN_IF_ERROR(
      for_each_step(frames, every, threads, [&](size_t t, std::span<const float> xyz) {
        if (stop && stop->load()) return Status::error("choosing the key steps was stopped");
        box.extend(xyz);
        for (uint32_t v = 0; v < n; v += stride)
          probes[t].insert(probes[t].end(), &xyz[size_t{v} * 3], &xyz[size_t{v} * 3] + 3);
        if (progress) progress("choosing key steps", ++done, steps);
        return Status{};
      }));
  choice.all_steps_box = box;

  if (rule.kind == Kind::kPaper) {
    choice.steps = {0};
    choice.reasons.push_back("step 0: the first");
    if (steps > 2) {
      size_t strongest = 1;
      double largest = -1;
      for (size_t t = 1; t + 1 < steps; ++t) {
        const double d = max_displacement(probes[t], probes[0]);
        if (d > largest) largest = d, strongest = t;
      }
      choice.steps.push_back(strongest);
      choice.reasons.push_back("step " + std::to_string(strongest) +
                               ": the strongest deformation in between (a vertex moved " +
                               format_mm(largest) + " from the first step)");
    }
    choice.steps.push_back(steps - 1);
    choice.reasons.push_back("step " + std::to_string(steps - 1) + ": the last (a vertex moved " +
                             format_mm(max_displacement(probes[steps - 1], probes[0])) +
                             " from the first step)");
    return choice;
  }

  // auto:K — farthest-point sampling over the steps.
  const size_t k = std::min(rule.count, steps);
  std::vector<double> distance(steps, std::numeric_limits<double>::infinity());
  size_t next = 0;
  choice.steps.push_back(next);
  choice.reasons.push_back("step 0: the first");
  while (choice.steps.size() < k) {
    const size_t last = choice.steps.back();
    double farthest = -1;
    for (size_t t = 0; t < steps; ++t) {
      distance[t] = std::min(distance[t], max_displacement(probes[t], probes[last]));
      if (distance[t] > farthest) farthest = distance[t], next = t;
    }
    if (farthest <= 0) break;  // every step coincides with a chosen one
    choice.steps.push_back(next);
    choice.reasons.push_back("step " + std::to_string(next) +
                             ": farthest from the steps chosen before (" + format_mm(farthest) +
                             ")");
  }
  // Keep the reasons in the order the steps will be listed.
  std::vector<size_t> order(choice.steps.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return choice.steps[a] < choice.steps[b]; });
  KeyStepChoice sorted;
  sorted.all_steps_box = choice.all_steps_box;
  for (size_t i : order) {
    sorted.steps.push_back(choice.steps[i]);
    sorted.reasons.push_back(choice.reasons[i]);
  }
  return sorted;
}

}  // namespace dynpm
