// Reading speed of the LS-DYNA d3plot reader. Writes a crash-sized family from the format
// description (single precision, a 600 × 600 shell grid: 361,201 nodes, 360,000 shells, with
// displacements, velocities, accelerations, stress and plastic strain at 3 points per shell
// (IOSHL 1000, 1000, 999, 999: NV2D = 21) and deletion flags;
// 24 states over d3plot, d3plot01, …), then times opening it (control block, geometry and the
// index of every state) and reading every state's coordinates, median of several runs. Files
// given on the command line are timed the same way.
//
//   d3plot_bench [--runs N] [--states N] [D3PLOT...]
//   d3plot_bench [--states N] --write DIR      (only writes the family, for timing other tools)
//
// Two rates are printed: the family's bytes over the time to open and read every step (how fast
// a d3plot result is consumed: element data is skipped, not read), and the coordinate bytes
// actually read over the time of the reads alone.
#include <algorithm>
#include <bit>
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
namespace fs = std::filesystem;

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

// Little-endian single-precision words.
struct Writer {
  std::vector<uint32_t> words;
  void i(int64_t v) { words.push_back(static_cast<uint32_t>(static_cast<int32_t>(v))); }
  void r(double v) { words.push_back(std::bit_cast<uint32_t>(static_cast<float>(v))); }
};

// The family under dir/d3plot: geometry in the first file, states in files of at most
// `file_words` words (LS-DYNA starts a new file when a state does not fit, and pads each file to
// a multiple of 512 words).
void write_family(const fs::path& dir, int n, int states) {
  const int64_t numnp = int64_t(n + 1) * (n + 1), nel4 = int64_t(n) * n, nv2d = 21;
  Writer g;
  for (int k = 0; k < 10; ++k) g.i(0x20202020);
  const int64_t narbs = 10 + numnp + nel4 + 3;
  const int64_t control[] = {0, 1, 0, 0, 0, 4,    numnp, 6,    1, 0, 1,      1, 1, 0,     0, 0,
                             0, 0, 0, 0, 0, nel4, 1,     nv2d, 0, 0, -10003, 0, 0, narbs, 0, 0,
                             0, 0, 0, 0, 0, 0,    0,     0,    0, 1, 0,      0, 0, 0,     0, 0};
  for (int64_t v : control) g.i(v);
  g.words[14] = std::bit_cast<uint32_t>(960.0f);
  for (int k = 0; k < 4; ++k) g.words[43 + k] = k < 2 ? 1000 : 999;  // IOSHL: stress, strain
  while (g.words.size() < 64) g.i(0);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) g.r(i), g.r(j), g.r(0);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int64_t v = int64_t(j) * (n + 1) + i + 1;
      g.i(v), g.i(v + 1), g.i(v + n + 2), g.i(v + n + 1), g.i(1);
    }
  g.i(1), g.i(0), g.i(0), g.i(0), g.i(0), g.i(numnp), g.i(0), g.i(0), g.i(nel4), g.i(0);
  for (int64_t k = 0; k < numnp; ++k) g.i(k + 1);
  for (int64_t k = 0; k < nel4; ++k) g.i(k + 1);
  g.i(1), g.i(1), g.i(1);
  auto flush = [&](Writer& w, const fs::path& path) {
    w.words.resize((w.words.size() + 511) / 512 * 512, 0);
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(w.words.data()), std::streamsize(w.words.size() * 4));
    w.words.clear();
  };
  flush(g, dir / "d3plot");

  const size_t file_words = size_t{1} << 26;  // 256 MB files
  Writer s;
  int file = 1;
  for (int t = 0; t < states; ++t) {
    const size_t state_words = 2 + 9 * size_t(numnp) + size_t(nel4) * (nv2d + 1);
    if (!s.words.empty() && s.words.size() + state_words > file_words) {
      char name[32];
      std::snprintf(name, sizeof name, "d3plot%02d", file++);
      flush(s, dir / name);
    }
    s.r(0.001 * t);
    s.r(1.0);
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i)
        s.r(i), s.r(j), s.r(0.01 * t * std::sin(0.05 * i) * std::cos(0.07 * j));
    for (int64_t k = 0; k < 6 * numnp; ++k) s.r(0.5);
    for (int64_t k = 0; k < nel4 * nv2d; ++k) s.r(0.25);
    for (int64_t k = 0; k < nel4; ++k) s.r(1.0);
  }
  s.r(-999999.0);
  char name[32];
  std::snprintf(name, sizeof name, "d3plot%02d", file);
  flush(s, dir / name);
}

void bench(const std::string& path, int runs) {
  double family_bytes = 0;
  for (int k = 0;; ++k) {
    std::string member = path;
    if (k > 0) member += (k < 10 ? "0" : "") + std::to_string(k);
    if (!fs::exists(member)) break;
    family_bytes += double(fs::file_size(member));
  }
  size_t steps = 0, vertices = 0;
  double read_seconds = 0;
  const double total = median_seconds(runs, [&] {
    const std::vector<std::string> paths{path};
    auto stream = dynpm::open_input(paths);
    if (!stream) {
      std::fprintf(stderr, "%s\n", stream.message().c_str());
      std::exit(1);
    }
    steps = stream->frames->step_count();
    vertices = stream->topology.vertex_count;
    std::vector<float> xyz(vertices * 3);
    const auto start = Clock::now();
    for (size_t t = 0; t < steps; ++t)
      if (auto s = stream->frames->read_step(t, xyz); !s.ok()) {
        std::fprintf(stderr, "%s\n", s.message().c_str());
        std::exit(1);
      }
    read_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  });
  const double coordinate_mb = double(steps) * double(vertices) * 12 / 1e6;
  std::printf("%s: %.1f MB in %zu steps, %zu vertices\n", path.c_str(), family_bytes / 1e6, steps,
              vertices);
  std::printf("  open + read every step  %8.3f s  %8.0f MB/s of d3plot\n", total,
              family_bytes / 1e6 / total);
  std::printf("  read_step alone         %8.3f s  %8.0f MB/s of coordinates\n", read_seconds,
              coordinate_mb / read_seconds);
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 5, states = 24;
  std::vector<std::string> files;
  std::string write_only;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--runs" && i + 1 < argc)
      runs = std::max(1, std::atoi(argv[++i]));
    else if (arg == "--states" && i + 1 < argc)
      states = std::max(1, std::atoi(argv[++i]));
    else if (arg == "--write" && i + 1 < argc)
      write_only = argv[++i];
    else
      files.push_back(arg);
  }
  if (!write_only.empty()) {
    fs::create_directories(write_only);
    write_family(write_only, 600, states);
    std::printf("wrote %s/d3plot …\n", write_only.c_str());
    return 0;
  }
  if (files.empty()) {
    const fs::path dir = fs::temp_directory_path() / "dynpm-d3plot-bench";
    fs::create_directories(dir);
    for (const auto& entry : fs::directory_iterator(dir)) fs::remove(entry.path());
    std::printf("writing a synthetic d3plot family under %s …\n", dir.c_str());
    write_family(dir, 600, states);
    bench((dir / "d3plot").string(), runs);
    fs::remove_all(dir);
    return 0;
  }
  for (const auto& f : files) bench(f, runs);
}
