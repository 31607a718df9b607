// The build's memory estimate: what `dynpm build` prints before the work and refuses on.
#include <algorithm>
#include <thread>

#include "dynpm/pipeline.h"

namespace dynpm {

// The build peaks in one of two phases. Simplifying: per vertex the mesh, the queue, the vertex
// classes and the collapse record, plus each key step's positions and quadric (56 B: a 12 B
// position and an 11-float quadric). The last pass (build_dpm) streams the steps: per vertex the
// input, the record in the progressive numbering and each split's position stencil, plus for
// each step coded at once (min(threads, 4)) its grid integers and residuals (24 B), plus the
// coded positions of every step (about 1 B per vertex and step at the default bound). Refitted
// after the simplifier's memory cuts (2026-12-03) to the peak resident memory (/usr/bin/time and
// VmRSS sampled per phase, Release, two threads) of the tiled 1 M × 25 crash box (1,003,002
// vertices): auto:3 358 MB collapsing (estimate 365), the last pass 320 MB in "encoding
// positions" (its term 325), all 25 key steps 1,591 MB (estimate 1,601); and of the real crash
// boxes (crashbox-s, crashbox-mixed-5k: 19.6–28.6 MB, mostly the program itself; estimates
// 22.0–34.0). Result fields hold every value (4 B per vertex or face per step and field) from
// "recording the splits" to the end.
uint64_t build_memory_estimate(uint64_t vertices, uint64_t steps, uint64_t key_steps,
                               unsigned threads, uint64_t field_values_per_step) {
  constexpr uint64_t kProcess = 20ull << 20;  // the program, its libraries, a small input
  constexpr uint64_t kSimplifyPerVertex = 175, kPerVertexKeyStep = 56;
  constexpr uint64_t kLastPassPerVertex = 230, kPerVertexBatchStep = 24, kPerVertexStep = 1;
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const uint64_t batch = std::min<uint64_t>(threads == 0 ? cores : threads, 4);
  const uint64_t simplifying = vertices * (kSimplifyPerVertex + kPerVertexKeyStep * key_steps);
  const uint64_t last_pass =
      vertices * (kLastPassPerVertex + kPerVertexBatchStep * batch + kPerVertexStep * steps);
  const uint64_t fields = 4 * steps * field_values_per_step;
  return kProcess + std::max(simplifying, last_pass + fields);
}

}  // namespace dynpm
