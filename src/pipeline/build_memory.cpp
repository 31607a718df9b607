// The build's memory estimate: what `dynpm build` prints before the work and refuses on.
#include <algorithm>
#include <thread>

#include "dynpm/pipeline.h"

namespace dynpm {

// The build peaks in one of two phases. Simplifying: per vertex and per face the mesh, the
// queue, the vertex classes and the collapse record, plus each key step's positions (12 B per
// vertex) and quadrics (44 B, 11 floats, per vertex whose island is at work; without islands
// every vertex). After it (the record, the split records' coding, the last pass of build_dpm,
// which streams the steps): per vertex and per face the record in the progressive numbering, the
// coding's mesh and each split's position stencil, plus for each step coded at once (min(threads,
// 4)) its grid integers and residuals (24 B per vertex), plus the coded positions of every step
// (about 1 B per vertex and step at the default bound). Fitted to the peak resident memory
// (/usr/bin/time and VmRSS sampled per phase, Release, two threads; MB = 10^6 B) of a quad and
// a triangle mesh, which set the per-vertex and per-face bytes apart, last on 2026-12-05 when
// islands began to hold their quadrics only while at work: the tiled 1 M × 25 crash box
// (1,003,002 vertices, 980,958 quads, 56 islands): auto:3 330–340 MB, in "coding the splits"
// (estimate 360; 351–359 MB on huge pages, 314–320 MB since `dynpm build` frees the input's faces
// before the coding, both 2026-12-05), all 25 key steps 569 MB collapsing (584; 555 MB since
// islands run without rounds); the dragon of ../shared/data/meshes (437,645 vertices, 871,414
// triangles, one step, one component): 208–223 MB in four runs, "recording the splits" (226); the
// real crash boxes (crashbox-s, crashbox-mixed-5k, one component: 19.6–28.6 MB, mostly the program
// itself; estimates 21.6–33.2). Result fields hold every value (4 B per vertex or face per step and
// field) from "recording the splits" to the end. Since 2026-12-08 the collapse also holds each
// face's place in its island (4 B per face, counted) and an opening island's face shapes (about
// 2 MB a thread): all 25 key steps 563–571 MB (estimate 587).
uint64_t build_memory_estimate(uint64_t vertices, uint64_t faces, uint64_t steps,
                               uint64_t key_steps, unsigned threads, uint64_t field_values_per_step,
                               uint64_t quadric_vertices) {
  constexpr uint64_t kProcess = 20ull << 20;  // the program, its libraries, a small input
  constexpr uint64_t kSimplifyPerVertex = 40, kSimplifyPerFace = 149;
  constexpr uint64_t kPositionPerKeyStep = 12, kQuadricPerKeyStep = 44;
  constexpr uint64_t kAfterPerVertex = 116, kAfterPerFace = 152;
  constexpr uint64_t kPerVertexBatchStep = 24, kPerVertexStep = 1;
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const uint64_t batch = std::min<uint64_t>(threads == 0 ? cores : threads, 4);
  const uint64_t simplifying =
      vertices * (kSimplifyPerVertex + kPositionPerKeyStep * key_steps) +
      std::min(vertices, quadric_vertices) * kQuadricPerKeyStep * key_steps +
      faces * kSimplifyPerFace;
  const uint64_t after =
      vertices * (kAfterPerVertex + kPerVertexBatchStep * batch + kPerVertexStep * steps) +
      faces * kAfterPerFace;
  const uint64_t fields = 4 * steps * field_values_per_step;
  return kProcess + std::max(simplifying, after + fields);
}

}  // namespace dynpm
