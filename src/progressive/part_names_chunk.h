// The PART chunk of a .dpm file: the parts' names (docs/FORMAT.md, "Part names: PART"), written
// and read in one place. Internal to dynpm_progressive.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "dpm_read_fields.h"
#include "dynpm/progressive.h"

namespace dynpm::progressive {

// The payload of mesh.part_names; empty when no part has a name (then no chunk is written).
std::string part_names_payload(const ProgressiveMesh& mesh);

// PART: fills mesh.part_names, with every check FORMAT.md lists (names are untrusted text a
// viewer shows).
std::optional<PayloadError> parse_part_names(std::string_view payload, ProgressiveMesh& mesh);

}  // namespace dynpm::progressive
