// A PNG writer for the thumbnails (thumbnail.cpp): 8-bit RGB, or 8-bit palette indices when its
// 256 most common colours hold the picture (the rest, blended edge pixels, mapped to the nearest
// within a small tolerance) and that is smaller; one IDAT of a zlib stream made here (deflate:
// one block with its own Huffman codes, LZ77 with one step of lazy evaluation). A thumbnail is
// mostly background and flat-shaded facets, runs that LZ77 takes at distance 3 (a pixel) or one
// row; this keeps the pipeline free of zlib, within a few % of its level 9.
#pragma once

#include <cstdint>
#include <span>
#include <string>

namespace dynpm::pipeline {

// rgb: width × height × 3 bytes, rows top to bottom.
std::string encode_png(std::span<const uint8_t> rgb, uint32_t width, uint32_t height);

// The zlib stream (RFC 1950) of `bytes`: exposed for its test.
std::string zlib_compress(std::span<const uint8_t> bytes);

}  // namespace dynpm::pipeline
