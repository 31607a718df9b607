// Connected components of a mesh, as the simplifier's (P3) rule and its islands count them.
// Internal: modules include it as "core/components.h".
#pragma once

#include <cstdint>
#include <vector>

#include "dynpm/core.h"

namespace dynpm {

// Each vertex's connected component (vertices joined through faces; a vertex in no face is one of
// its own), numbered 0, 1, … in the order of their first vertex; `count` gets how many.
std::vector<uint32_t> connected_components(const Topology& topology, size_t& count);

}  // namespace dynpm
