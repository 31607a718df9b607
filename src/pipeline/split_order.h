// The splits' order in the file (docs/FORMAT.md "Split records", version 5): within each band of
// errors a quarter octave wide, the splits are reordered so that their parents ascend wherever
// the dependencies allow, and the record codes a parent as a step from the one before it
// instead of as one of all the vertices (issue 19: ~log2(n) bits a split in error order).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "dynpm/progressive.h"

namespace dynpm {

// Bands per octave of error: a band holds the splits whose undone collapses' errors (the level
// error before each split) share ⌊4 log2 e⌋; the levels' sequence changes within a band only.
// The levels inside a band state the error before it (any of its splits may be missing), the
// band's end its own, so the stated error of every level stays an upper bound.
inline constexpr int kSplitOrderBandsPerOctave = 4;

// Reorders pm's splits (errors absolute and non-increasing; the splits, the base and the
// attributes set, no positions or fields yet) in a topological order of their dependencies
// (SplitReads::kFan: every split sees its parent's fan as the error order left it, so each
// record stays valid as it is), band after band, the smallest parent first; renumbers the
// vertices and faces the splits create and maps new_vertex / new_face (input → progressive) to
// the new numbering. `progress`, if set, hears the share of the work done (0 … 1) now and then.
// The dependencies are derived on up to `threads` threads (derive_split_dependencies()).
void order_splits_by_parent(ProgressiveMesh& pm, std::vector<uint32_t>& new_vertex,
                            std::vector<uint32_t>& new_face,
                            const std::function<void(double)>& progress = {}, unsigned threads = 1);

}  // namespace dynpm
