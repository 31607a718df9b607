// Reading speed of the mesh readers and of the derived connectivity, on a generated 1 M-face
// quad mesh (a 1000 × 1000 grid with a bumpy height field, written by dynpm's own OBJ and PLY
// writers) and on any files given on the command line. Prints the median of several runs.
// Whole-result files (CalculiX .frd, …) are timed from opening to the last step and field read;
// a generated 400 × 400 quad result with 10 DISP steps is timed as ASCII and as binary .frd.
//
//   io_bench [--runs N] [FILE...]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
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

// A CalculiX result of the grid with `steps` DISP blocks: ASCII long format or binary (node
// coordinates as doubles, displacements as floats, as ccx writes them).
void write_frd(const std::string& path, const dynpm::Animation& grid, int steps, bool binary) {
  std::string s = "    1C\n    1UPGM               io_bench\n";
  char line[160];
  auto raw = [&s](auto v) { s.append(reinterpret_cast<const char*>(&v), sizeof v); };
  const uint32_t n = grid.topology.vertex_count;
  const auto xyz = grid.frames.step(0);
  std::snprintf(line, sizeof line, "    2C%18s%12u%37s%d\n", "", n, "", binary ? 3 : 1);
  s += line;
  for (uint32_t v = 0; v < n; ++v) {
    if (binary) {
      raw(int32_t(v + 1));
      for (int k = 0; k < 3; ++k) raw(double(xyz[3 * v + k]));
    } else {
      std::snprintf(line, sizeof line, " -1%10u%12.5E%12.5E%12.5E\n", v + 1, xyz[3 * v],
                    xyz[3 * v + 1], xyz[3 * v + 2]);
      s += line;
    }
  }
  if (!binary) s += " -3\n";
  const size_t faces = grid.topology.faces.size();
  std::snprintf(line, sizeof line, "    3C%18s%12zu%37s%d\n", "", faces, "", binary ? 2 : 1);
  s += line;
  for (size_t f = 0; f < faces; ++f) {
    const auto& c = grid.topology.faces[f].v;
    if (binary) {
      for (int32_t w : {int32_t(f + 1), 9, 0, 1}) raw(w);
      for (int k = 0; k < 4; ++k) raw(int32_t(c[k] + 1));
    } else {
      std::snprintf(line, sizeof line, " -1%10zu    9    0    1\n -2%10u%10u%10u%10u\n", f + 1,
                    c[0] + 1, c[1] + 1, c[2] + 1, c[3] + 1);
      s += line;
    }
  }
  if (!binary) s += " -3\n";
  for (int t = 1; t <= steps; ++t) {
    std::snprintf(line, sizeof line, "  100CL  %3d%12.5E%12u%20s%2d%5d%10s%2d\n", 100 + t, 0.1 * t,
                  n, "", 0, t, "", binary ? 2 : 1);
    s += line;
    s += " -4  DISP        4    1\n -5  D1          1    2    1    0\n"
         " -5  D2          1    2    2    0\n -5  D3          1    2    3    0\n"
         " -5  ALL         1    2    0    0    1ALL\n";
    for (uint32_t v = 0; v < n; ++v) {
      const float d[3] = {0.01f * t * xyz[3 * v + 2], 0.0f, -0.5f * t};
      if (binary) {
        raw(int32_t(v + 1));
        for (float c : d) raw(c);
      } else {
        std::snprintf(line, sizeof line, " -1%10u%12.5E%12.5E%12.5E\n", v + 1, d[0], d[1], d[2]);
        s += line;
      }
    }
    if (!binary) s += " -3\n";
  }
  s += " 9999\n";
  std::ofstream(path, std::ios::binary) << s;
}

// Opening a whole result and reading every step and field, as `dynpm info` does.
void bench_result(const std::string& path, int runs) {
  const double mb = double(std::filesystem::file_size(path)) / 1e6;
  size_t steps = 0, faces = 0;
  const double open = median_seconds(runs, [&] {
    const std::string paths[] = {path};
    if (auto s = dynpm::open_input(paths); !s.ok())
      std::exit((std::fprintf(stderr, "%s\n", s.message().c_str()), 1));
  });
  const double read = median_seconds(runs, [&] {
    const std::string paths[] = {path};
    auto s = dynpm::open_input(paths);
    if (!s) std::exit((std::fprintf(stderr, "%s\n", s.message().c_str()), 1));
    const dynpm::FrameSource& frames = *s->frames;
    std::vector<float> xyz(size_t{frames.vertex_count()} * 3), values(frames.vertex_count());
    for (size_t t = 0; t < frames.step_count(); ++t) {
      if (!frames.read_step(t, xyz).ok()) std::exit(1);
      for (size_t f = 0; f < frames.field_names().size(); ++f)
        if (!frames.read_field(f, t, values).ok()) std::exit(1);
    }
    steps = frames.step_count();
    faces = s->topology.faces.size();
  });
  std::printf("%-40s %9zu faces %7.1f MB  open %6.3f s  open + %zu steps %6.3f s (%5.0f MB/s)\n",
              std::filesystem::path(path).filename().c_str(), faces, mb, open, steps, read,
              mb / read);
}

bool whole_result(const std::string& path) {
  auto format = dynpm::detect_format(path);
  return format.ok() &&
         (*format == dynpm::FileFormat::kFrd || *format == dynpm::FileFormat::kPvd ||
          *format == dynpm::FileFormat::kExodus || *format == dynpm::FileFormat::kD3plot);
}

void bench_file(const std::string& path, int runs) {
  if (whole_result(path)) return bench_result(path, runs);
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
    const auto small = bumpy_grid(400);
    for (bool binary : {false, true}) {
      const std::string path =
          (dir / (binary ? "grid_160k_10steps_binary.frd" : "grid_160k_10steps_ascii.frd"))
              .string();
      write_frd(path, small, 10, binary);
      files.push_back(path);
    }
  }
  for (const std::string& f : files) bench_file(f, runs);
  return 0;
}
