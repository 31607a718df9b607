// build's result fields (docs/FORMAT.md, "Fields: FDEF and FLDS"): values gathered into the
// progressive numbering, heirs of the faces the splits re-create, each level's field error, and
// the values quantized. Internal to dynpm_pipeline (build.cpp calls it).
#pragma once

#include <cstdint>
#include <vector>

#include "dynpm/progressive.h"

namespace dynpm {

// Reads every field of `frames` at every step into pm.fields (values renumbered by new_vertex or
// new_face, min and max over every step); sets the heirs when a field is per element, each
// level's field error, and quantizes the values to `bound` (a fraction of each field's range)
// unless lossless. pm's splits and faces must be complete.
Status build_fields(const FrameSource& frames, const std::vector<uint32_t>& new_vertex,
                    const std::vector<uint32_t>& new_face, double bound, bool lossless,
                    ProgressiveMesh& pm);

// For every face a split re-creates, a face that exists before that split and holds its parent v1
// (docs/FORMAT.md, "Shown values"): the moved face or quad wing that holds the wing vertex w, else
// the first moved face, else the first quad wing, else any face holding v1 (a search of every
// face: `searches` counts them). An error names a split where no face holds v1.
Status choose_face_heirs(ProgressiveMesh& pm, size_t* searches = nullptr);

// Each level's field error (the largest spread, over present items and every step, of the values
// one item stands for, as a fraction of the range) from the values as they are.
void measure_field_errors(ProgressiveMesh& pm, ProgressiveField& field);

}  // namespace dynpm
