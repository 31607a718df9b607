// Reading speed of the mesh readers and of the derived connectivity, on a generated 1 M-face
// quad mesh (a 1000 × 1000 grid with a bumpy height field, written by dynpm's own OBJ and PLY
// writers) and on any files given on the command line. Prints the median of several runs.
//
//   io_bench [--runs N] [FILE...]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "dynpm/io.h"

namespace {

using Clock = std::chrono::steady_clock;

double median_seconds(int runs, const std::function<void()>& work) {
  std::vector<double> seconds;
  for (int i = 0; i < runs; ++i) {
    const auto start = Clock::now();
    work();
    seconds.push_back(std::chrono::duration<double>(Clock::now() - start).count());
  }
  std::sort(seconds.begin(), seconds.end());
  return seconds[seconds.size() / 2];
}

dynpm::Animation bumpy_grid(uint32_t n) {
  dynpm::Animation a;
  a.topology = dynpm::Topology::with_vertices((n + 1) * (n + 1));
  std::vector<float> xyz;
  xyz.reserve(size_t{a.topology.vertex_count} * 3);
  for (uint32_t j = 0; j <= n; ++j)
    for (uint32_t i = 0; i <= n; ++i)
      xyz.insert(xyz.end(),
                 {i * 1.37f, j * 1.37f, 3.1f * std::sin(i * 0.05f) * std::cos(j * 0.07f)});
  for (uint32_t j = 0; j < n; ++j)
    for (uint32_t i = 0; i < n; ++i) {
      const uint32_t v = j * (n + 1) + i;
      a.topology.add_quad(v, v + 1, v + n + 2, v + n + 1);
    }
  a.frames.set_vertex_count(a.topology.vertex_count);
  a.frames.add_step(std::move(xyz), 0.0);
  return a;
}

void bench_file(const std::string& path, int runs) {
  const double mb = double(std::filesystem::file_size(path)) / 1e6;
  size_t faces = 0;
  const double read = median_seconds(runs, [&] {
    auto a = dynpm::read_mesh(path);
    if (!a) {
      std::fprintf(stderr, "%s\n", a.message().c_str());
      std::exit(1);
    }
    faces = a->topology.faces.size();
  });
  auto a = dynpm::read_mesh(path);
  const double adjacency = median_seconds(runs, [&] { dynpm::Adjacency::build(a->topology); });
  const double validation = median_seconds(runs, [&] { dynpm::validate(*a); });
  std::printf(
      "%-40s %9zu faces %7.1f MB  read %6.3f s (%5.0f MB/s)  adjacency %6.3f s  validate %6.3f s\n",
      std::filesystem::path(path).filename().c_str(), faces, mb, read, mb / read, adjacency,
      validation);
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 5;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--runs") == 0 && i + 1 < argc)
      runs = std::atoi(argv[++i]);
    else
      files.push_back(argv[i]);
  }
  std::printf("median of %d runs\n", runs);
  if (files.empty()) {
    const auto dir = std::filesystem::temp_directory_path() / "dynpm-io-bench";
    std::filesystem::create_directories(dir);
    const auto grid = bumpy_grid(1000);
    for (const char* name : {"grid_1M_quads.obj", "grid_1M_quads.ply"}) {
      const std::string path = (dir / name).string();
      if (!dynpm::write_mesh(path, grid.topology, grid.frames.step(0)).ok()) return 1;
      files.push_back(path);
    }
  }
  for (const std::string& f : files) bench_file(f, runs);
  return 0;
}
