// The result fields' values of a SPLT's vertices and faces (docs/FORMAT.md "Fields: FDEF and
// FLDS", version 7): one range-coded section per field and step in the FLDS after the SPLT. The
// browser's decoder is viewer/src/dpm/fields.js; both follow FORMAT.md.
//
//   for each field, for t = 0 … m−1: the section's predictor, then for each item of the chunk
//   (its split vertices, or the faces its splits create), in order:
//     guess  = q_0(P)                                       t = 0 (P: the parent, or the heir)
//            = q_{t−1}(v) + q_t(P) − q_{t−1}(P)             t > 0, predictor "parent"
//            = q_{t−1}(v) + median over v's ring R of q_t(u) − q_{t−1}(u)     "ring median"
//     residual = q_t − guess, coded with model[field][t][bucket of the item's residual at t − 1]
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "dynpm/progressive.h"
#include "position_coding.h"
#include "range_coder.h"

namespace dynpm::progressive {

// The adaptive models of the field sections: per field and step, one per residual bucket;
// continued from one SPLT's FLDS to the next.
class SplitFieldModels {
 public:
  using StepModels = std::array<SignedModel, kResidualBuckets>;
  SplitFieldModels(size_t fields, size_t steps) : models_(fields, std::vector<StepModels>(steps)) {}
  // Field f's models, one set per step.
  std::span<StepModels> field(size_t f) { return models_[f]; }

 private:
  std::vector<std::vector<StepModels>> models_;
};

// What a field section's values at t > 0 are guessed from (FORMAT.md): the parent's (heir's)
// change, or the median change of the vertex's ring.
enum class FieldPredictor : uint8_t { kParent = 0, kRingMedian = 1 };
// The ring vertices a median reads, at most (the first in ascending order).
inline constexpr uint32_t kMaxMedianRing = 16;

struct FieldSection {
  FieldPredictor predictor = FieldPredictor::kParent;
  std::string bytes;  // range-coded
};
struct FieldSectionView {
  FieldPredictor predictor = FieldPredictor::kParent;
  std::string_view bytes;
};

// A SPLT's share of the fields: splits [first, last), which create faces [face_begin, face_end).
struct FieldChunk {
  uint32_t first = 0, last = 0, face_begin = 0, face_end = 0;
};

// Every chunk's sections: sections[field][t][chunk]. `all` holds every split's stencil, in split
// order (the positions' rings). On `threads` threads, one field and step a task.
std::vector<std::vector<std::vector<FieldSection>>> encode_split_fields(
    const ProgressiveMesh& mesh, const ChunkStencils& all, std::span<const FieldChunk> chunks,
    unsigned threads);

// Decodes field f's sections of one chunk (steps 0 … sections.size() − 1) into f.values, whose
// earlier items are there; `stencils` are the chunk's (split `chunk.first` first). Empty, or what
// is wrong.
std::string decode_split_field(const ProgressiveMesh& mesh, ProgressiveField& f,
                               const FieldChunk& chunk, const ChunkStencils& stencils,
                               std::span<SplitFieldModels::StepModels> models,
                               std::span<const FieldSectionView> sections);

}  // namespace dynpm::progressive
