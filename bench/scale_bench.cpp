// Time and memory at scale (the time issue's benchmark): a ≥ 1 M-vertex, 25-step "vehicle" of
// many disconnected parts, tiled from a real CalculiX crash-box run, simplified to 5 % with
// several key-step rules. Peak memory is read from the process (VmHWM) and reported beyond
// what the input animation itself holds.
//
//   scale_bench [--tiles N] [--steps S] [--ratio R] [--rules all,auto:3]
//               [--write-triangles FILE.obj] CRASHBOX_FOLDER
//
// --write-triangles writes the vehicle's last step with every quad split in two and stops: a
// ≥ 1 M-triangle input for the side-by-side run with the peers (bench/simplify_bench.py).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "../cli/huge_pages.h"
#include "dynpm/io.h"
#include "dynpm/simplify.h"

namespace {

double rss_mb(const char* field) {
  std::FILE* f = std::fopen("/proc/self/status", "r");
  if (!f) return 0;
  char line[256];
  double kb = 0;
  const size_t n = std::strlen(field);
  while (std::fgets(line, sizeof line, f))
    if (std::strncmp(line, field, n) == 0) kb = std::atof(line + n + 1);
  std::fclose(f);
  return kb / 1024.0;
}

}  // namespace

int main(int argc, char** argv) {
  dynpm::cli::start_again_with_huge_pages(argv);  // as the dynpm tool does
  int tiles = 205, steps = 25;
  double ratio = 0.05;
  dynpm::return_freed_arrays_to_the_system();  // as the dynpm tool does
  std::string rules = "all,auto:3", folder, triangles_path;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--tiles") && i + 1 < argc)
      tiles = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--steps") && i + 1 < argc)
      steps = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--ratio") && i + 1 < argc)
      ratio = std::atof(argv[++i]);
    else if (!std::strcmp(argv[i], "--rules") && i + 1 < argc)
      rules = argv[++i];
    else if (!std::strcmp(argv[i], "--write-triangles") && i + 1 < argc)
      triangles_path = argv[++i];
    else
      folder = argv[i];
  }
  auto paths = dynpm::expand_inputs(std::vector<std::string>{folder + "/frame_*.obj"});
  if (!paths) return std::fprintf(stderr, "%s\n", paths.message().c_str()), 1;
  // Steps spread over the whole run.
  std::vector<std::string> chosen;
  for (int s = 0; s < steps; ++s)
    chosen.push_back((*paths)[size_t(s) * (paths->size() - 1) / size_t(steps - 1)]);
  auto box = dynpm::read_animation(chosen);
  if (!box) return std::fprintf(stderr, "%s\n", box.message().c_str()), 1;

  // Tile the tube into a grid of parts, each its own part id and a little rotated, so the
  // parts are not copies of one another in space.
  const dynpm::Topology& one = box->topology;
  dynpm::Animation vehicle;
  vehicle.topology.vertex_count = one.vertex_count * uint32_t(tiles);
  const int columns = int(std::ceil(std::sqrt(double(tiles))));
  for (int t = 0; t < tiles; ++t) {
    const uint32_t offset = one.vertex_count * uint32_t(t);
    for (uint32_t v = 0; v < one.vertex_count; ++v)
      vehicle.topology.node_ids.push_back(int64_t(offset + v) + 1);
    for (const dynpm::Face& f : one.faces) {
      dynpm::Face g = f;
      for (uint32_t& c : g.v)
        if (c != dynpm::kNoVertex) c += offset;
      vehicle.topology.add_face(g, t + 1);
    }
  }
  vehicle.frames.set_vertex_count(vehicle.topology.vertex_count);
  for (int s = 0; s < steps; ++s) {
    std::vector<float> xyz;
    xyz.reserve(size_t(vehicle.topology.vertex_count) * 3);
    for (int t = 0; t < tiles; ++t) {
      const double angle = 0.1 * t, c = std::cos(angle), sn = std::sin(angle);
      const float dx = float(t % columns) * 120.f, dy = float(t / columns) * 120.f;
      auto step = box->frames.step(size_t(s));
      for (uint32_t v = 0; v < one.vertex_count; ++v) {
        const float x = step[v * 3], y = step[v * 3 + 1], z = step[v * 3 + 2];
        xyz.insert(xyz.end(), {float(c * x - sn * y) + dx, float(sn * x + c * y) + dy, z});
      }
    }
    vehicle.frames.add_step(std::move(xyz), double(s));
  }
  box = dynpm::Animation{};
  if (!triangles_path.empty()) {
    dynpm::Topology triangles = dynpm::Topology::with_vertices(vehicle.topology.vertex_count);
    for (const dynpm::Face& f : vehicle.topology.faces) {
      triangles.add_triangle(f.v[0], f.v[1], f.v[2]);
      if (!f.is_triangle()) triangles.add_triangle(f.v[0], f.v[2], f.v[3]);
    }
    const dynpm::Status s =
        dynpm::write_mesh(triangles_path, triangles, vehicle.frames.step(size_t(steps - 1)));
    std::printf("wrote %s: %u vertices, %zu triangles\n", triangles_path.c_str(),
                triangles.vertex_count, triangles.faces.size());
    return s.ok() ? 0 : 1;
  }
  const double input_mb = rss_mb("VmRSS:");
  std::printf("vehicle: %d parts, %u vertices, %zu faces, %d steps; input in memory %.0f MB\n",
              tiles, vehicle.topology.vertex_count, vehicle.topology.faces.size(), steps, input_mb);

  size_t start = 0;
  while (start <= rules.size()) {
    const size_t comma = std::min(rules.find(',', start), rules.size());
    const std::string text = rules.substr(start, comma - start);
    start = comma + 1;
    auto rule = dynpm::parse_key_step_rule(text);
    if (!rule) return std::fprintf(stderr, "%s\n", rule.message().c_str()), 1;
    const auto begin = std::chrono::steady_clock::now();
    auto keys = dynpm::choose_key_steps(vehicle.frames, *rule);
    dynpm::SimplifyOptions options;
    options.target_ratio = ratio;
    options.key_steps = keys->steps;
    auto result = dynpm::simplify(vehicle.topology, vehicle.frames, options);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
    if (!result) return std::fprintf(stderr, "%s\n", result.message().c_str()), 1;
    const double peak = rss_mb("VmHWM:");
    std::printf(
        "key steps %-8s (%2zu): %8.2f s, %u vertices left, peak %.0f MB = %.0f B per vertex beyond "
        "the input\n",
        text.c_str(), keys->steps.size(), seconds, result->topology.vertex_count, peak,
        (peak - input_mb) * 1024 * 1024 / vehicle.topology.vertex_count);
  }
  return 0;
}
