// Reading the result fields of a .dpm file: the FDEF and FLDS chunks (docs/FORMAT.md, "Fields:
// FDEF and FLDS"), with every check that section lists. dpm_read.cpp finds the chunks and calls
// these on their payloads. Internal to dynpm_progressive.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "dynpm/progressive.h"
#include "field_coding.h"

namespace dynpm::progressive {

// What is wrong inside a payload, and at which byte of it.
struct PayloadError {
  std::string what;
  size_t offset = 0;
};

// FDEF: fills mesh.fields (definitions; no values yet). Needs HEAD's step count.
std::optional<PayloadError> parse_field_definitions(std::string_view payload,
                                                    ProgressiveMesh& mesh);

// The FLDS after BASE: the base vertices' and faces' values.
std::optional<PayloadError> parse_base_field_values(std::string_view payload,
                                                    ProgressiveMesh& mesh);

// The FLDS after the SPLT of `chunk`'s splits: the heirs of the faces they created, each field's
// errors and its values of steps [0, steps) (the later steps' sections are skipped, as the
// positions' are). `stencils` are the SPLT's, `models` continue from the FLDS before.
std::optional<PayloadError> parse_split_field_values(std::string_view payload,
                                                     ProgressiveMesh& mesh, const FieldChunk& chunk,
                                                     const ChunkStencils& stencils,
                                                     SplitFieldModels& models, size_t steps);

// The most bytes the FLDS after BASE (n = 0) or after a SPLT of n splits that created faces
// [face_begin, face_end) can take, each value at its longest encoding.
double field_values_limit(const ProgressiveMesh& mesh, uint32_t n, uint32_t face_begin,
                          uint32_t face_end);

}  // namespace dynpm::progressive
