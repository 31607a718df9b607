// The mesh as a reader has it before the first SPLT: HEAD's counts, the base mesh and its
// attributes, no split. For the split records' test and split_records_dump.
#pragma once

#include "dynpm/progressive.h"

namespace dynpm::test {

inline ProgressiveMesh base_level_of(const ProgressiveMesh& pm) {
  ProgressiveMesh m = pm;
  m.parent.clear();
  m.error.clear();
  m.wing_start = {0};
  m.wings.clear();
  m.moved_start = {0};
  m.moved_faces.clear();
  m.vertex_original_index.resize(pm.base_vertex_count);
  m.node_ids.resize(pm.base_vertex_count);
  m.face_original_index.resize(pm.base_face_count);
  m.part_ids.resize(pm.base_face_count);
  m.element_ids.resize(pm.base_face_count);
  return m;
}

}  // namespace dynpm::test
