// The thumbnail drawn during the build (build_dpm() with BuildOptions::thumbnail): from the
// build's own records and positions, the picture a reader of the written file draws
// (render_thumbnail() of the file read with thumbnail_read_limits()), without decoding the file.
#pragma once

#include <span>

#include "dynpm/pipeline.h"

namespace dynpm {

// The level the thumbnail draws, copied from a complete `mesh` before its records are released:
// what a reader with thumbnail_read_limits(options) holds but the positions (empty).
ProgressiveMesh thumbnail_level(const ProgressiveMesh& mesh, const ThumbnailOptions& options);

// The steps the level keeps: the first and the last, which are all render_thumbnail() reads.
inline bool thumbnail_keeps_step(size_t t, size_t steps) { return t == 0 || t + 1 == steps; }

// Step t of `steps` (quantized as the file stores it, in the progressive numbering), if the level
// keeps it.
void keep_thumbnail_step(ProgressiveMesh& level, size_t t, size_t steps,
                         std::span<const float> xyz);

}  // namespace dynpm
