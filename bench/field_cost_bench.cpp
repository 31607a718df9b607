// Fields in the cost and the shape regularizer, measured (docs/simplify.md, "Measured"): for
// each configuration (field weight, regularize) and ratio, the simplification time, the
// two-sided Hausdorff distance (max over the steps, % of the diagonal) and mean distance (mean
// over the steps), the field error of
// every node field and the triangle aspect ratios at the first step.
//
// Field error (until `dynpm eval --field` exists): each original vertex u is followed to the
// vertex that stands for it at the level (its ancestor through the collapses); that vertex
// shows the value of largest magnitude of those it stands for (FieldAggregate::kMaxAbs). The
// error of a step is max over u of |shown − f(u)|, in % of the field's range over every step;
// reported is the max over the steps. Element fields are not measured here.
//
//   field_cost_bench [--ratios 0.05,0.25] [--config FW/REG]... INPUT...
//   e.g. --config 0/0 --config 0.01/0 --config 0/0.001
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "dynpm/eval.h"
#include "dynpm/io.h"
#include "dynpm/simplify.h"

namespace {

struct Config {
  double field_weight = 0, regularize = 0;
};

// v0 → v1 of every collapse, in order.
class Recorder final : public dynpm::CollapseListener {
 public:
  explicit Recorder(uint32_t n) : parent(n, dynpm::kNoVertex) {}
  void on_collapse(const dynpm::CollapseRecord& r) override { parent[r.v0] = r.v1; }
  uint32_t ancestor(uint32_t v) {
    uint32_t root = v;
    while (parent[root] != dynpm::kNoVertex) root = parent[root];
    while (parent[v] != dynpm::kNoVertex) {  // path compression
      const uint32_t next = parent[v];
      parent[v] = root;
      v = next;
    }
    return root;
  }
  std::vector<uint32_t> parent;
};

// Triangle aspect ratio: longest edge × perimeter / (4√3 · area); 1 for an equilateral one.
double aspect(const float* a, const float* b, const float* c) {
  auto d = [](const float* p, const float* q) {
    return std::sqrt(double(p[0] - q[0]) * (p[0] - q[0]) + double(p[1] - q[1]) * (p[1] - q[1]) +
                     double(p[2] - q[2]) * (p[2] - q[2]));
  };
  const double ab = d(a, b), bc = d(b, c), ca = d(c, a);
  const double s = (ab + bc + ca) / 2;
  const double area = std::sqrt(std::max(0.0, s * (s - ab) * (s - bc) * (s - ca)));
  if (area <= 0) return 1e9;
  return std::max({ab, bc, ca}) * (ab + bc + ca) / (4 * std::sqrt(3.0) * area);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<double> ratios = {0.05, 0.25};
  std::vector<Config> configs;
  std::vector<std::string> paths;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--ratios") && i + 1 < argc) {
      ratios.clear();
      for (char* p = std::strtok(argv[++i], ","); p; p = std::strtok(nullptr, ","))
        ratios.push_back(std::atof(p));
    } else if (!std::strcmp(argv[i], "--config") && i + 1 < argc) {
      Config c;
      if (std::sscanf(argv[++i], "%lf/%lf", &c.field_weight, &c.regularize) != 2) return 2;
      configs.push_back(c);
    } else {
      paths.push_back(argv[i]);
    }
  }
  if (configs.empty()) configs = {{0, 0}, {dynpm::kDefaultFieldWeight, 0}};
  auto stream = dynpm::open_input(paths);
  if (!stream) {
    std::fprintf(stderr, "%s\n", stream.message().c_str());
    return 1;
  }
  const dynpm::Topology& input = stream->topology;
  const dynpm::FrameSource& frames = *stream->frames;
  const uint32_t n = input.vertex_count;
  const size_t steps = frames.step_count();
  std::vector<std::vector<float>> positions(steps, std::vector<float>(size_t{n} * 3));
  for (size_t t = 0; t < steps; ++t)
    if (!frames.read_step(t, positions[t]).ok()) return 1;
  // Node fields at every step, and their ranges over every step.
  std::vector<dynpm::FieldInfo> infos = frames.fields();
  std::vector<size_t> node_fields;
  std::vector<std::vector<std::vector<float>>> values;  // [field][step][vertex]
  std::vector<double> range;
  for (size_t f = 0; f < infos.size(); ++f) {
    if (infos[f].location != dynpm::FieldLocation::kNode) continue;
    node_fields.push_back(f);
    values.emplace_back(steps, std::vector<float>(n));
    double lo = HUGE_VAL, hi = -HUGE_VAL;
    for (size_t t = 0; t < steps; ++t) {
      if (!frames.read_field(f, t, values.back()[t]).ok()) return 1;
      for (float x : values.back()[t]) lo = std::min(lo, double{x}), hi = std::max(hi, double{x});
    }
    range.push_back(hi > lo ? hi - lo : 1);
  }

  std::printf("%-6s %6s %6s %8s %8s %9s %9s", "ratio", "fw", "reg", "verts", "seconds", "haus%",
              "mean%");
  for (size_t f : node_fields) std::printf(" %10s%%", infos[f].name.c_str());
  std::printf(" %9s %9s %9s\n", "aspect", "asp_p95", ">5 %");
  for (double ratio : ratios) {
    for (const Config& config : configs) {
      dynpm::SimplifyOptions options;
      options.target_ratio = ratio;
      options.field_weight = config.field_weight;
      options.regularize = config.regularize;
      Recorder recorder(n);
      const auto start = std::chrono::steady_clock::now();
      auto result = dynpm::simplify(input, frames, options, &recorder);
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (!result) {
        std::fprintf(stderr, "%s\n", result.message().c_str());
        return 1;
      }
      // The level as an animation, for the Hausdorff distance.
      dynpm::Frames level(uint32_t(result->original_vertex.size()));
      for (size_t t = 0; t < steps; ++t) {
        std::vector<float> xyz;
        for (uint32_t v : result->original_vertex)
          xyz.insert(xyz.end(), &positions[t][size_t{v} * 3], &positions[t][size_t{v} * 3] + 3);
        level.add_step(std::move(xyz), double(t));
      }
      auto haus = dynpm::hausdorff_steps(input, frames, result->topology, level);
      if (!haus) return 1;
      std::printf("%-6.3g %6.3g %6.3g %8zu %8.3f %9.4f %9.4f", ratio, config.field_weight,
                  config.regularize, result->original_vertex.size(), seconds,
                  100.0 * haus->hausdorff.max / haus->diagonal,
                  100.0 * haus->mean.mean / haus->diagonal);
      std::vector<uint32_t> ancestor(n);
      for (uint32_t v = 0; v < n; ++v) ancestor[v] = recorder.ancestor(v);
      for (size_t i = 0; i < node_fields.size(); ++i) {
        double worst = 0;
        std::vector<float> shown(n, 0.0f);
        for (size_t t = 0; t < steps; ++t) {
          const std::vector<float>& f = values[i][t];
          std::fill(shown.begin(), shown.end(), 0.0f);
          for (uint32_t u = 0; u < n; ++u)
            if (std::fabs(f[u]) > std::fabs(shown[ancestor[u]])) shown[ancestor[u]] = f[u];
          for (uint32_t u = 0; u < n; ++u)
            worst = std::max(worst, std::fabs(double{shown[ancestor[u]]} - f[u]) / range[i]);
        }
        std::printf(" %11.3f", 100 * worst);
      }
      std::vector<double> aspects;
      for (const dynpm::Face& face : result->topology.faces) {
        if (!face.is_triangle()) continue;
        auto p = [&](int c) {
          return &positions[0][size_t{result->original_vertex[face.v[c]]} * 3];
        };
        aspects.push_back(aspect(p(0), p(1), p(2)));
      }
      std::sort(aspects.begin(), aspects.end());
      double mean = 0, over5 = 0;
      for (double a : aspects) mean += std::min(a, 1e3), over5 += a > 5;
      const size_t m = std::max<size_t>(aspects.size(), 1);
      std::printf(" %9.3f %9.3f %9.2f\n", mean / double(m),
                  aspects.empty() ? 0 : aspects[aspects.size() * 95 / 100],
                  100 * over5 / double(m));
      std::fflush(stdout);
    }
  }
  return 0;
}
