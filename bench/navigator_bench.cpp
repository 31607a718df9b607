// Navigator throughput: full refine and full coarsen of a .dpm, in splits (collapses) per
// second, and decode speed. Median of repeated runs (the machine is shared and noisy).
//   navigator_bench MODEL.dpm [repeats]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "dynpm/lod.h"

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: navigator_bench MODEL.dpm [repeats]\n");
    return 2;
  }
  const int repeats = argc > 2 ? std::atoi(argv[2]) : 9;
  auto bytes = dynpm::read_file(argv[1]);
  if (!bytes) {
    std::fprintf(stderr, "%s\n", bytes.message().c_str());
    return 1;
  }
  std::vector<double> decode, refine, coarsen;
  for (int r = 0; r < repeats; ++r) {
    auto start = std::chrono::steady_clock::now();
    auto mesh = dynpm::decode_dpm(*bytes, argv[1]);
    decode.push_back(seconds_since(start));
    if (!mesh) {
      std::fprintf(stderr, "%s\n", mesh.message().c_str());
      return 1;
    }
    dynpm::Navigator nav(*mesh);
    start = std::chrono::steady_clock::now();
    nav.set_level(mesh->split_count());
    refine.push_back(seconds_since(start));
    start = std::chrono::steady_clock::now();
    nav.set_level(0);
    coarsen.push_back(seconds_since(start));
    if (r == repeats - 1) {
      const double splits = mesh->split_count();
      std::printf(
          "{\"vertices\": %u, \"steps\": %zu, \"bytes\": %zu, \"decode_s\": %.4f, "
          "\"decode_mb_s\": %.1f, \"splits_per_s\": %.0f, \"collapses_per_s\": %.0f}\n",
          mesh->full_vertex_count, mesh->step_count(), bytes->size(), median(decode),
          bytes->size() / 1e6 / median(decode), splits / median(refine), splits / median(coarsen));
    }
  }
  return 0;
}
