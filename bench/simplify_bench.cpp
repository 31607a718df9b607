// Simplification speed on given meshes: median seconds of several runs per target ratio,
// simplification only (the file is read once). The side-by-side comparison with the peers is
// bench/simplify_bench.py; this one is for quick, repeatable measurements while tuning.
//
//   simplify_bench [--runs N] [--ratios 0.25,0.05] [--placement half|optimal] FILE...
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "dynpm/io.h"
#include "dynpm/simplify.h"

int main(int argc, char** argv) {
  int runs = 3;
  std::vector<double> ratios = {0.25, 0.05, 0.01};
  dynpm::Placement placement = dynpm::Placement::kHalfEdge;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--runs") && i + 1 < argc) {
      runs = std::atoi(argv[++i]);
    } else if (!std::strcmp(argv[i], "--ratios") && i + 1 < argc) {
      ratios.clear();
      for (char* p = std::strtok(argv[++i], ","); p; p = std::strtok(nullptr, ","))
        ratios.push_back(std::atof(p));
    } else if (!std::strcmp(argv[i], "--placement") && i + 1 < argc) {
      placement = std::strcmp(argv[++i], "optimal") == 0 ? dynpm::Placement::kOptimal
                                                         : dynpm::Placement::kHalfEdge;
    } else {
      files.push_back(argv[i]);
    }
  }
  std::printf("%-24s %8s %9s %9s %8s %10s\n", "input", "ratio", "vertices", "faces", "seconds",
              "collapses/s");
  for (const std::string& path : files) {
    auto mesh = dynpm::read_mesh(path);
    if (!mesh) {
      std::fprintf(stderr, "%s\n", mesh.message().c_str());
      return 1;
    }
    for (double ratio : ratios) {
      dynpm::SimplifyOptions options;
      options.target_ratio = ratio;
      options.placement = placement;
      std::vector<double> seconds;
      dynpm::SimplifyResult last;
      for (int r = 0; r < runs; ++r) {
        const auto start = std::chrono::steady_clock::now();
        auto result = dynpm::simplify(mesh->topology, mesh->frames, options);
        seconds.push_back(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        if (!result) {
          std::fprintf(stderr, "%s\n", result.message().c_str());
          return 1;
        }
        last = std::move(result).value();
      }
      std::sort(seconds.begin(), seconds.end());
      const double median = seconds[seconds.size() / 2];
      std::printf("%-24s %8.3f %9u %9zu %8.3f %10.0f\n",
                  std::filesystem::path(path).filename().c_str(), ratio, last.topology.vertex_count,
                  last.topology.faces.size(), median, double(last.collapses) / median);
    }
  }
  return 0;
}
