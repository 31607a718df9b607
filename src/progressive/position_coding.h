// The positions of a SPLT's new vertices (docs/FORMAT.md "Positions"): one range-coded section
// per time step, predicted from the split's quad wings (a parallelogram) at step 0 and later from
// the vertex's own previous position moved as its ring moved (the ring fit). The browser's
// decoder is viewer/src/dpm/positions.js; both follow FORMAT.md.
//
//   for each SPLT, for t = 0 … m−1, for each new vertex v0 (in split order), for c = x, y, z:
//     guess  = round(mean over v0's quad wings (w, v0, v1, x) of w + v1 − x)   (v1 if none)  t = 0
//            = c_t + M (q_{t−1}(v0) − c_{t−1}), rounded (c: the ring R's centre, M the      t > 0
//              least-squares map of R's offsets from t − 1 to t; with |R| < 3 or M unsound
//              q_{t−1}(v0) + round(mean over R of q_t(u) − q_{t−1}(u))), + 3/8 of the last miss
//     (lossless: v1, and q_{t−1}(v0) + v1's motion, modulo 2^32)
//     residual = q_t(v0) − guess, coded with model[t][c][bucket of v0's residual at t − 1]
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/prefetch.h"
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

// The adaptive models of the position sections, one set per step, continued from SPLT to SPLT.
class SplitPositionModels {
 public:
  explicit SplitPositionModels(size_t steps) : steps_(steps) {}
  std::array<std::array<SignedModel, kResidualBuckets>, 3>& step(size_t t) { return steps_[t]; }

 private:
  std::vector<std::array<std::array<SignedModel, kResidualBuckets>, 3>> steps_;
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
  // Asks for vertex v's values at step t ahead of at() (core/prefetch.h).
  void prefetch(uint32_t v, size_t t) const { dynpm::prefetch(&q_[t][size_t{v} * 3]); }
  void set(uint32_t v, size_t t, int c, int64_t q) {
    q_[t][size_t{v} * 3 + c] = static_cast<uint32_t>(q);
  }
  // Room for `vertices` vertices at steps [0, steps), taken before the chunks come when the
  // reader knows how far it will read: grown chunk by chunk, each step's array was copied into
  // fresh memory at every doubling (at 1 M vertices 31 MB a step mapped, faulted in and copied).
  void reserve(size_t steps, uint32_t vertices) {
    for (size_t t = 0; t < steps; ++t) q_[t].reserve(size_t{vertices} * 3);
  }
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

// The encoder's side, one step after the other, so that only a few steps' values are held at
// once and every thread is busy: the residuals do not depend on the models, and each step's
// models see only that step's residuals, so a batch of steps is coded in parallel (one step a
// thread) and gives exactly the bytes of the decoder's walk (the specification).
class StepPositionEncoder {
 public:
  // `all` holds every split's stencil, in split order; `chunks` the SPLTs' split ranges
  // [first, last), in order. Both must outlive the encoder.
  StepPositionEncoder(const ProgressiveMesh& mesh, const ChunkStencils& all,
                      std::span<const std::pair<uint32_t, uint32_t>> chunks, unsigned threads);
  // Steps coded at once, at most: each holds 24 B per vertex (its q-values and residuals).
  static constexpr unsigned kMaxBatchSteps = 4;
  // A vector for the next step's q-values, of any content: one the encoder no longer needs when
  // it has one (a fresh 12 MB vector a step, zeroed and faulted in, cost a third of the pass).
  std::vector<uint32_t> spare_step();
  // The next step's q-values (every vertex, xyz, in the progressive numbering): steps 0, 1, …
  // in order. Batches of min(threads, kMaxBatchSteps) steps are coded as they fill.
  void add_step(std::vector<uint32_t> q);
  // Every step's position section of every chunk: sections[t][k].
  std::vector<std::vector<std::string>> finish();

 private:
  void code_batch();

  const ProgressiveMesh& mesh_;
  const ChunkStencils& all_;
  std::span<const std::pair<uint32_t, uint32_t>> chunks_;
  unsigned threads_, batch_steps_;
  size_t steps_done_ = 0;
  std::vector<uint32_t> last_q_;  // the step before the batch, every vertex
  std::vector<int32_t> last_r_;   // its residuals, split vertices (v − b), xyz
  std::vector<std::vector<uint32_t>> batch_;
  std::vector<std::vector<uint32_t>> spare_q_;   // steps coded and no longer read, to reuse
  std::vector<std::vector<int32_t>> residuals_;  // the batch's, kept for their memory
  std::vector<std::vector<std::string>> sections_;
};

// Decodes the sections given (steps 0 … sections.size() − 1) into `q` (sized for the new
// vertices), which holds the earlier vertices' values. Empty, or what is wrong.
std::string decode_split_positions(const ProgressiveMesh& mesh, uint32_t first,
                                   const ChunkStencils& stencils, SplitPositionModels& models,
                                   std::span<const std::string_view> sections, GridValues& q);

// A SPLT's positions kept for later: the reader decodes them while it decodes the next SPLT's
// records, on a second thread (dpm_read.cpp). Holds the chunk's payload.
struct DeferredPositions {
  std::string payload;
  std::vector<std::pair<size_t, size_t>> sections;  // each step's: offset in payload, size
  ChunkStencils stencils;
  uint32_t first = 0;        // the chunk's first split
  size_t payload_start = 0;  // the payload's place in the file, for a message
  // decode_split_positions() of them; it reads of `mesh` only its header's values.
  std::string decode(const ProgressiveMesh& mesh, SplitPositionModels& models,
                     GridValues& q) const {
    std::vector<std::string_view> views;
    for (const auto& [at, size] : sections)
      views.push_back(std::string_view(payload).substr(at, size));
    return decode_split_positions(mesh, first, stencils, models, views, q);
  }
};

}  // namespace dynpm::progressive
