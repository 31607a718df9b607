// The positions of a SPLT's new vertices (docs/FORMAT.md "Positions"): one range-coded section
// per time step, predicted from the split's quad wings (a parallelogram) at step 0 and from the
// vertex's own previous position moved by its neighbours' mean motion later. The browser's
// decoder is viewer/src/dpm/positions.js; both follow FORMAT.md.
//
//   for each SPLT, for t = 0 … m−1, for each new vertex v0 (in split order), for c = x, y, z:
//     guess  = round(mean over v0's quad wings (w, v0, v1, x) of w + v1 − x)   (v1 if none)  t = 0
//            = q_{t−1}(v0) + round(mean over v0's ring R of q_t(u) − q_{t−1}(u))          t > 0
//     (lossless: v1, and q_{t−1}(v0) + v1's motion, modulo 2^32)
//     residual = q_t(v0) − guess, coded with model[t][c][bucket of v0's residual at t − 1]
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "dpm_format.h"
#include "dynpm/progressive.h"
#include "range_coder.h"

namespace dynpm::progressive {

// What predicts split vertex v0, as the faces are right after its split: its parent v1, for
// each quad wing (w, v0, v1, x) w and x, and its ring (the vertices sharing an edge with it).
struct SplitStencil {
  uint32_t parent = 0;
  int quads = 0;
  std::array<uint32_t, 4> w{}, x{};
  uint32_t ring_begin = 0, ring_end = 0;  // in ChunkStencils::ring
};

struct ChunkStencils {
  std::vector<SplitStencil> splits;
  std::vector<uint32_t> ring;
  // Split i's stencil, from `faces` as they are right after apply_split(i).
  void add(const ProgressiveMesh& mesh, uint32_t i, std::span<const Face> faces);
};

inline constexpr int kPositionContexts = 5;

// The adaptive models of the position sections, one set per step, continued from SPLT to SPLT.
class SplitPositionModels {
 public:
  explicit SplitPositionModels(size_t steps) : steps_(steps) {}
  std::array<std::array<SignedModel, kPositionContexts>, 3>& step(size_t t) { return steps_[t]; }

 private:
  std::vector<std::array<std::array<SignedModel, kPositionContexts>, 3>> steps_;
};

// Every vertex's q-values so far, per step: the predictions read a vertex's ring at every step,
// and converting floats back to grid integers there cost more than the decoding itself.
// Quantized q-values fit 32 bits signed, lossless ones are the float32 bits.
class GridValues {
 public:
  GridValues(const Grid& g, size_t steps) : lossless_(g.lossless), q_(steps) {}
  int64_t at(uint32_t v, size_t t, int c) const {
    const uint32_t u = q_[t][size_t{v} * 3 + c];
    return lossless_ ? int64_t{u} : int64_t{static_cast<int32_t>(u)};
  }
  void set(uint32_t v, size_t t, int c, int64_t q) {
    q_[t][size_t{v} * 3 + c] = static_cast<uint32_t>(q);
  }
  // Step t's values for `values` (of the same size): the encoder turns q-values into residuals.
  void swap_step(size_t t, std::vector<uint32_t>& values) { q_[t].swap(values); }
  size_t step_size(size_t t) const { return q_[t].size(); }
  // Room for `vertices` vertices at steps [0, steps).
  void resize(size_t steps, uint32_t vertices) {
    for (size_t t = 0; t < steps; ++t) q_[t].resize(size_t{vertices} * 3);
  }
  // Vertices [begin, end) of steps [0, steps) from mesh.positions.
  void take(const ProgressiveMesh& mesh, size_t steps, uint32_t begin, uint32_t end);
  // Step t's vertices from `begin` on into mesh.positions (its first `begin` already there), and
  // this step's values freed: the decoder keeps one copy of the positions at a time.
  void move_to_positions(ProgressiveMesh& mesh, size_t t, uint32_t begin);

 private:
  bool lossless_;
  std::vector<std::vector<uint32_t>> q_;
};

// The encoder's side, in passes that each keep every thread busy and give exactly the bytes of
// the decoder's walk (the specification): the residuals do not depend on the models, and each
// step's models see only that step's residuals, so steps are coded apart.
//
// Every split vertex's residual at every step, in place of its q-values in `q` (which holds the
// whole mesh: GridValues::take). `all` holds every split's stencil, in split order. Steps go
// from the last down, so a step's q-values are replaced once no later step reads them; the
// 3/8 correction (a residual's own recurrence over the steps) is applied last.
void turn_into_residuals(const ProgressiveMesh& mesh, const ChunkStencils& all, GridValues& q,
                         unsigned threads);

// The position section of step t for splits [first, last), from turn_into_residuals()'s
// values, continuing step t's models.
std::string encode_step_positions(const ProgressiveMesh& mesh, uint32_t first, uint32_t last,
                                  const GridValues& residuals, size_t t,
                                  SplitPositionModels& models);

// Decodes the sections given (steps 0 … sections.size() − 1) into `q` (sized for the new
// vertices), which holds the earlier vertices' values. Empty, or what is wrong.
std::string decode_split_positions(ProgressiveMesh& mesh, uint32_t first,
                                   const ChunkStencils& stencils, SplitPositionModels& models,
                                   std::span<const std::string_view> sections, GridValues& q);

}  // namespace dynpm::progressive
