// The VARI chunk of a family file (docs/FORMAT.md, "Variants: VARI"), written and read in one
// place. Internal to dynpm_progressive.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "dpm_read_fields.h"
#include "dynpm/progressive.h"

namespace dynpm::progressive {

// The payload of mesh.variants; empty when the mesh is not a family (then no chunk is written).
std::string variants_payload(const ProgressiveMesh& mesh);

// VARI: fills mesh.variants after HEAD (its step count bounds the stored steps), with every check
// FORMAT.md lists (names are untrusted text a viewer shows).
std::optional<PayloadError> parse_variants(std::string_view payload, ProgressiveMesh& mesh);

}  // namespace dynpm::progressive
