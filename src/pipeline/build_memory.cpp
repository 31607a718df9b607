// The build's memory estimate: what `dynpm build` prints before the work and refuses on.
#include <algorithm>

#include "dynpm/pipeline.h"

namespace dynpm {

// The build peaks in one of two phases. Simplifying: per vertex the mesh, the queue, the vertex
// classes and the collapse record, plus each key step's positions and quadric. Gathering and
// encoding: per vertex the record and the model's arrays, plus every step's positions as floats
// and as grid integers (turned into residuals in place), plus each split's position stencil,
// kept for the parallel coding of the steps (about 64 B: measured +15 MB at 252 k vertices). Fitted
// to the peak resident memory (/usr/bin/time -v, 2026-12-02, with RSS sampled per phase) of `dynpm
// build` on the 251,001-vertex plate of `eval_bench --write-plate` with 50 steps, auto:3 (129 MB
// collapsing, 374 MB encoding) and all 50 key steps (758 MB collapsing); checked on the
// 1,002,001-vertex, 25-step plate (auto:3 842 MB, all 1,647 MB: estimates 852 and 1,645) and the
// crash boxes (docs/build.md).
uint64_t build_memory_estimate(uint64_t vertices, uint64_t steps, uint64_t key_steps) {
  constexpr uint64_t kProcess = 16ull << 20;  // the program, its libraries, a small input
  constexpr uint64_t kSimplifyPerVertex = 305, kPerVertexKeyStep = 56;
  constexpr uint64_t kGatherPerVertex = 250 + 64, kPerVertexStep = 25;
  const uint64_t simplifying = vertices * (kSimplifyPerVertex + kPerVertexKeyStep * key_steps);
  const uint64_t gathering = vertices * (kGatherPerVertex + kPerVertexStep * steps);
  return kProcess + std::max(simplifying, gathering);
}

}  // namespace dynpm
