// LS-DYNA d3plot: recognising a family's first file by its control block.
#pragma once

#include <string_view>

namespace dynpm::io {

// Bytes a caller should read from the start of a file for looks_like_d3plot().
inline constexpr size_t kD3plotHeadBytes = 64 * 8;

// True if head (the first bytes of a file) holds a plausible d3plot control block in single or
// double precision, either byte order.
bool looks_like_d3plot(std::string_view head);

}  // namespace dynpm::io
