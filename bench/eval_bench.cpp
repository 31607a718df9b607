// Speed of the Metro-style Hausdorff distance (src/eval): a 1 M-face original against a coarse
// version of it, both directions, default sampling (10 area samples per face of the larger mesh
// on each surface, plus vertices and edges). Prints the median of several runs.
//
// The original is a 1000 × 1000 quad grid over a bumpy height field (as in io_bench); the coarse
// version is a 224 × 224 grid over the same height field (50,176 quads, 5% of the faces).
// With two files, measures those instead (e.g. ../shared/data/meshes/dragon.obj against a
// simplified dragon).
//
//   eval_bench [--runs N] [--threads T] [ORIGINAL SIMPLIFIED]
//   eval_bench --write-plate DIR [--size N] [--steps S]
//
// --write-plate writes the input of `dynpm eval` at scale (bench/eval_scale.sh) and stops: an
// N × N quad plate (default 1000: 1,002,001 vertices) over the bumpy height field, S steps
// (default 25) of a wave running across it, as DIR/frame_000.ply … (binary PLY).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <functional>
#include <string>
#include <vector>

#include "dynpm/eval.h"
#include "dynpm/io.h"

namespace {

using Clock = std::chrono::steady_clock;

// Wall-clock seconds of each run, sorted; `cpu` gets the median processor seconds (all
// threads), which tells a busy shared machine from slow code.
std::vector<double> timed_runs(int runs, const std::function<void()>& work, double* cpu = nullptr) {
  std::vector<double> seconds, cpu_seconds;
  for (int i = 0; i < runs; ++i) {
    const auto start = Clock::now();
    const std::clock_t cpu_start = std::clock();
    work();
    cpu_seconds.push_back(double(std::clock() - cpu_start) / CLOCKS_PER_SEC);
    seconds.push_back(std::chrono::duration<double>(Clock::now() - start).count());
  }
  std::sort(seconds.begin(), seconds.end());
  std::sort(cpu_seconds.begin(), cpu_seconds.end());
  if (cpu) *cpu = cpu_seconds[cpu_seconds.size() / 2];
  return seconds;
}

struct Mesh {
  dynpm::Topology topology;
  std::vector<float> positions;
};

// n × n quads over [0, 1370]², z = the height field of io_bench's grid.
Mesh bumpy_grid(uint32_t n) {
  constexpr double kSide = 1370.0;
  Mesh m;
  m.topology = dynpm::Topology::with_vertices((n + 1) * (n + 1));
  m.positions.reserve(size_t{m.topology.vertex_count} * 3);
  for (uint32_t j = 0; j <= n; ++j)
    for (uint32_t i = 0; i <= n; ++i) {
      const double x = kSide * i / n, y = kSide * j / n;
      m.positions.insert(
          m.positions.end(),
          {float(x), float(y), float(3.1 * std::sin(x / 1.37 * 0.05) * std::cos(y / 1.37 * 0.07))});
    }
  for (uint32_t j = 0; j < n; ++j)
    for (uint32_t i = 0; i < n; ++i) {
      const uint32_t v = j * (n + 1) + i;
      m.topology.add_quad(v, v + 1, v + n + 2, v + n + 1);
    }
  return m;
}

// Step s of S of the animated plate: the bumpy grid plus a travelling wave whose height grows
// with s, so that every step differs and the simplified model's error moves over the plate.
void write_plate(const std::string& dir, uint32_t n, int steps) {
  Mesh m = bumpy_grid(n);
  std::vector<float> xyz(m.positions.size());
  for (int s = 0; s < steps; ++s) {
    const double phase = 6.283 * s / std::max(1, steps - 1), height = 40.0 * s / std::max(1, steps);
    for (size_t v = 0; v < xyz.size(); v += 3) {
      const double x = m.positions[v], y = m.positions[v + 1];
      xyz[v] = m.positions[v], xyz[v + 1] = m.positions[v + 1];
      xyz[v + 2] = float(m.positions[v + 2] +
                         height * std::sin(x / 200.0 - phase) * std::cos(y / 310.0 + 0.5 * phase));
    }
    char name[32];
    std::snprintf(name, sizeof name, "/frame_%03d.ply", s);
    const dynpm::Status status = dynpm::write_mesh(dir + name, m.topology, xyz);
    if (!status.ok()) {
      std::fprintf(stderr, "%s\n", status.message().c_str());
      std::exit(1);
    }
  }
  std::printf("wrote %s/frame_000.ply … frame_%03d.ply: %u vertices, %zu quads\n", dir.c_str(),
              steps - 1, m.topology.vertex_count, m.topology.faces.size());
}

Mesh read(const std::string& path) {
  auto a = dynpm::read_mesh(path);
  if (!a) {
    std::fprintf(stderr, "%s\n", a.message().c_str());
    std::exit(1);
  }
  return {a->topology, std::vector<float>(a->frames.step(0).begin(), a->frames.step(0).end())};
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 3;
  dynpm::HausdorffOptions options;
  std::vector<std::string> files;
  std::string plate_dir;
  int plate_size = 1000, plate_steps = 25;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--write-plate") == 0 && i + 1 < argc)
      plate_dir = argv[++i];
    else if (std::strcmp(argv[i], "--size") == 0 && i + 1 < argc)
      plate_size = std::max(1, std::atoi(argv[++i]));
    else if (std::strcmp(argv[i], "--steps") == 0 && i + 1 < argc)
      plate_steps = std::max(1, std::atoi(argv[++i]));
    else if (std::strcmp(argv[i], "--runs") == 0 && i + 1 < argc)
      runs = std::max(1, std::atoi(argv[++i]));
    else if (std::strcmp(argv[i], "--threads") == 0 && i + 1 < argc)
      options.threads = unsigned(std::atoi(argv[++i]));
    else
      files.push_back(argv[i]);
  }
  if (!plate_dir.empty()) {
    write_plate(plate_dir, uint32_t(plate_size), plate_steps);
    return 0;
  }
  if (files.size() != 0 && files.size() != 2) {
    std::fprintf(stderr, "usage: eval_bench [--runs N] [--threads T] [ORIGINAL SIMPLIFIED]\n");
    return 2;
  }
  const Mesh a = files.empty() ? bumpy_grid(1000) : read(files[0]);
  const Mesh b = files.empty() ? bumpy_grid(224) : read(files[1]);
  std::printf("A: %s, %zu faces (%zu quads)\nB: %s, %zu faces (%zu quads)\n",
              files.empty() ? "bumpy grid 1000 x 1000" : files[0].c_str(), a.topology.faces.size(),
              a.topology.quad_count(), files.empty() ? "bumpy grid 224 x 224" : files[1].c_str(),
              b.topology.faces.size(), b.topology.quad_count());

  // Building the BVH of the larger mesh on its own: the part that does not run in parallel.
  const auto triangles = dynpm::surface_triangles(a.topology, a.positions);
  double bvh_cpu = 0;
  const auto bvh_seconds = timed_runs(
      runs, [&] { dynpm::TriangleBvh bvh(triangles, options.threads); }, &bvh_cpu);
  const dynpm::TriangleBvh bvh(triangles);
  std::printf("BVH of A: %zu triangles, %zu nodes, build %.3f s (median of %d; %.3f s CPU)\n",
              bvh.triangle_count(), bvh.node_count(), bvh_seconds[bvh_seconds.size() / 2], runs,
              bvh_cpu);

  dynpm::HausdorffResult result;
  double cpu = 0;
  const auto seconds = timed_runs(
      runs,
      [&] {
        auto r = dynpm::hausdorff(a.topology, a.positions, b.topology, b.positions, options);
        if (!r) {
          std::fprintf(stderr, "%s\n", r.message().c_str());
          std::exit(1);
        }
        result = *r;
      },
      &cpu);
  const auto samples = [](const dynpm::OneSidedDistance& d) {
    return double(d.vertex_samples + d.edge_samples + d.face_samples);
  };
  const double total = samples(result.a_to_b) + samples(result.b_to_a);
  std::printf(
      "samples: A→B %.0f (%llu area, %llu edge, %llu vertex), B→A %.0f (%llu area, "
      "%llu edge, %llu vertex)\n",
      samples(result.a_to_b), (unsigned long long)result.a_to_b.face_samples,
      (unsigned long long)result.a_to_b.edge_samples,
      (unsigned long long)result.a_to_b.vertex_samples, samples(result.b_to_a),
      (unsigned long long)result.b_to_a.face_samples,
      (unsigned long long)result.b_to_a.edge_samples,
      (unsigned long long)result.b_to_a.vertex_samples);
  std::printf(
      "hausdorff %.6g (%.4f %% of %.6g), A→B %.4f %%, B→A %.4f %%, mean %.4f %%, rms "
      "%.4f %%\n",
      result.hausdorff, result.percent(result.hausdorff), result.diagonal,
      result.percent(result.a_to_b.max), result.percent(result.b_to_a.max),
      result.percent(result.mean), result.percent(result.rms));
  const double median = seconds[seconds.size() / 2];
  std::printf(
      "hausdorff(), both directions: median %.3f s of %d runs (min %.3f, max %.3f), "
      "%.2f M samples/s; %.3f s CPU\n",
      median, runs, seconds.front(), seconds.back(), total / median / 1e6, cpu);
  return 0;
}
