// Reading the result fields of a .dpm file: the FDEF and FLDS chunks (docs/FORMAT.md, "Fields:
// FDEF and FLDS"), with every check that section lists. dpm_read.cpp finds the chunks and calls
// these on their payloads. Internal to dynpm_progressive.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "dynpm/progressive.h"

namespace dynpm::progressive {

// What is wrong inside a payload, and at which byte of it.
struct PayloadError {
  std::string what;
  size_t offset = 0;
};

// FDEF: fills mesh.fields (definitions; no values yet). Needs HEAD's step count.
std::optional<PayloadError> parse_field_definitions(std::string_view payload,
                                                    ProgressiveMesh& mesh);

// The FLDS after BASE (n = 0) or after the SPLT of splits [first, first + n), which created faces
// [face_begin, face_end): the heirs of those faces, each field's errors and values.
std::optional<PayloadError> parse_field_values(std::string_view payload, ProgressiveMesh& mesh,
                                               uint32_t first, uint32_t n, uint32_t face_begin,
                                               uint32_t face_end);

// The most bytes that FLDS can take, each value at its longest encoding.
double field_values_limit(const ProgressiveMesh& mesh, uint32_t n, uint32_t face_begin,
                          uint32_t face_end);

}  // namespace dynpm::progressive
