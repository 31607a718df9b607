// dynpm/pipeline.h — build(): animation → simplifier → collapse record → progressive mesh.
//
// The simplifier runs to the end (until no legal collapse remains) with a listener that keeps
// every collapse. Reversed, the collapses are the vertex splits; vertices are renumbered so the
// base mesh holds 0…b−1 and split i creates vertex b+i, faces so the base holds the first ones
// and each split's re-created triangles take the next numbers (docs/FORMAT.md). Every step's
// positions are then read once through the FrameSource and stored in that order.
#pragma once

#include <functional>
#include <string>

#include "dynpm/progressive.h"
#include "dynpm/simplify.h"

namespace dynpm {

struct BuildOptions {
  // Key steps, placement limits, features and threads as for simplify(). Placement must be
  // kHalfEdge (positions stay original, one per vertex per step serves every level); stop
  // conditions are ignored: the build collapses until no legal collapse remains.
  SimplifyOptions simplify;
  bool lossless = false;
  // Bound on a stored position's error, in bounding-box diagonals (docs/FORMAT.md).
  double max_position_error = 1.0 / (1 << 18);
  std::string note;
  // Called with (steps read, steps) while positions are gathered. May be empty.
  std::function<void(size_t, size_t)> progress;
};

// Simplifies the animation to the end and records the progressive mesh, with every step's
// positions (read once each, through the FrameSource) and the source's scalar fields.
Result<ProgressiveMesh> build_progressive_mesh(const Topology& topology, const FrameSource& frames,
                                               const BuildOptions& options);

}  // namespace dynpm
