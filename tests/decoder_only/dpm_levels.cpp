// dpm_levels FILE.dpm: a .dpm read and walked through every tenth of its levels with the
// decoder alone (core + progressive + lod): vertices, faces and error at each, one line each.
// It exists to prove that the decoder links without the readers or the simplifier.
#include <cstdio>
#include <vector>

#include "dynpm/lod.h"
#include "dynpm/progressive.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: dpm_levels FILE.dpm\n");
    return 2;
  }
  auto mesh = dynpm::read_dpm(argv[1]);
  if (!mesh) {
    std::fprintf(stderr, "%s\n", mesh.status().message().c_str());
    return 1;
  }
  dynpm::Navigator navigator(*mesh);
  const uint32_t splits = static_cast<uint32_t>(mesh->parent.size());
  std::vector<float> xyz;
  for (int tenth = 0; tenth <= 10; ++tenth) {
    navigator.set_level(static_cast<uint32_t>(uint64_t{splits} * tenth / 10));
    xyz.resize(3 * size_t{navigator.vertex_count()});
    navigator.positions(static_cast<double>(mesh->times.size() - 1), xyz);
    std::printf("level %u: %u vertices, %u faces, error %g\n", navigator.level(),
                navigator.vertex_count(), navigator.face_count(), navigator.error());
  }
  return 0;
}
