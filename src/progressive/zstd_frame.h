// One zstd frame of a .dpm chunk, decompressed with its size checked as it grows (dpm_read.cpp).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace dynpm::progressive {

// Decompresses `frame`, which must hold exactly `raw` bytes, into `out`: the buffer grows with
// what the frame really produces, so a frame that claims more than it holds costs only what it
// holds. Empty on success, else what is wrong.
std::string inflate(std::string_view frame, uint64_t raw, std::string& out);

}  // namespace dynpm::progressive
