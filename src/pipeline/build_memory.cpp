// The build's memory estimate: what `dynpm build` prints before the work and refuses on.
#include <algorithm>
#include <thread>

#include "dynpm/pipeline.h"

namespace dynpm {

// The build peaks in one of two phases. Simplifying: per vertex the mesh, the queue, the vertex
// classes and the collapse record, plus each key step's positions and quadric; fitted to the
// peak resident memory (/usr/bin/time -v, 2026-12-02, with RSS sampled per phase) of `dynpm
// build` on the 251,001-vertex plate of `eval_bench --write-plate` with 50 steps, auto:3 (129 MB
// collapsing) and all 50 key steps (758 MB collapsing), checked on the 1,002,001-vertex plate
// (all 25: 1,647 MB, estimate 1,645). The last pass (build_dpm) streams the steps: per vertex
// the input, the record in the progressive numbering and each split's position stencil (about
// 300 B), plus for each step coded at once (min(threads, 4)) its grid integers and residuals
// (24 B), plus the coded positions of every step (about 1 B per vertex and step at the default
// bound); counted from the arrays and checked on the tiled 1 M × 25 crash box (auto:3, two
// threads: 371 MB in "encoding positions", estimate 389 MB). Result fields hold every value
// (4 B per vertex or face per step and field) from "recording the splits" to the end.
uint64_t build_memory_estimate(uint64_t vertices, uint64_t steps, uint64_t key_steps,
                               unsigned threads, uint64_t field_values_per_step) {
  constexpr uint64_t kProcess = 16ull << 20;  // the program, its libraries, a small input
  constexpr uint64_t kSimplifyPerVertex = 305, kPerVertexKeyStep = 56;
  constexpr uint64_t kLastPassPerVertex = 300, kPerVertexBatchStep = 24, kPerVertexStep = 1;
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const uint64_t batch = std::min<uint64_t>(threads == 0 ? cores : threads, 4);
  const uint64_t simplifying = vertices * (kSimplifyPerVertex + kPerVertexKeyStep * key_steps);
  const uint64_t last_pass =
      vertices * (kLastPassPerVertex + kPerVertexBatchStep * batch + kPerVertexStep * steps);
  const uint64_t fields = 4 * steps * field_values_per_step;
  return kProcess + std::max(simplifying, last_pass + fields);
}

}  // namespace dynpm
