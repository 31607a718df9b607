// Navigator throughput: full refine and full coarsen of a .dpm, in splits (collapses) per
// second, and decode speed. Median of repeated runs (the machine is shared and noisy): in wall
// time, and in this thread's CPU time (_cpu), which time spent waiting for a core does not count.
//   navigator_bench MODEL.dpm [repeats [decodes]]
// The first refine also learns what each split writes (navigator.cpp); it is one of the repeats.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <vector>

#include "dynpm/lod.h"
#include "timing.h"

using dynpm::bench::cpu_now;
using dynpm::bench::median;
using dynpm::bench::seconds_since;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: navigator_bench MODEL.dpm [repeats [decodes]]\n");
    return 2;
  }
  const int repeats = argc > 2 ? std::atoi(argv[2]) : 9;
  const int decodes = std::max(1, argc > 3 ? std::atoi(argv[3]) : std::min(repeats, 3));
  auto bytes = dynpm::read_file(argv[1]);
  if (!bytes) {
    std::fprintf(stderr, "%s\n", bytes.message().c_str());
    return 1;
  }
  // Decoding is slow at this size and not what is measured here: at most 3 decodes unless told;
  // the navigator refines and coarsens `repeats` times on the last one.
  std::vector<double> decode, refine, coarsen, refine_cpu, coarsen_cpu;
  dynpm::Result<dynpm::ProgressiveMesh> mesh = dynpm::Status::error("not decoded");
  for (int r = 0; r < decodes; ++r) {
    const auto start = std::chrono::steady_clock::now();
    mesh = dynpm::decode_dpm(*bytes, argv[1]);
    decode.push_back(seconds_since(start));
    if (!mesh) {
      std::fprintf(stderr, "%s\n", mesh.message().c_str());
      return 1;
    }
  }
  dynpm::Navigator nav(*mesh);
  for (int r = 0; r < repeats; ++r) {
    double cpu = cpu_now();
    auto start = std::chrono::steady_clock::now();
    nav.set_level(mesh->split_count());
    refine.push_back(seconds_since(start));
    refine_cpu.push_back(cpu_now() - cpu);
    cpu = cpu_now();
    start = std::chrono::steady_clock::now();
    nav.set_level(0);
    coarsen.push_back(seconds_since(start));
    coarsen_cpu.push_back(cpu_now() - cpu);
  }
  const double splits = mesh->split_count();
  std::printf(
      "{\"vertices\": %u, \"steps\": %zu, \"bytes\": %zu, \"decode_s\": %.4f, "
      "\"decode_mb_s\": %.1f, \"splits_per_s\": %.0f, \"collapses_per_s\": %.0f, "
      "\"splits_per_s_cpu\": %.0f, \"collapses_per_s_cpu\": %.0f}\n",
      mesh->full_vertex_count, mesh->step_count(), bytes->size(), median(decode),
      bytes->size() / 1e6 / median(decode), splits / median(refine), splits / median(coarsen),
      splits / median(refine_cpu), splits / median(coarsen_cpu));
  return 0;
}
