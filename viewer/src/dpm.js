// The .dpm decoder and navigator (docs/FORMAT.md, docs/viewer.md), as plain ES modules that run
// in the browser and in Node (tests, benchmarks). This entry re-exports the pieces, which mirror
// the C++ ones:
//   dpm/file.js              the file and its chunks (src/progressive/dpm_read.cpp)
//   dpm/progressive_mesh.js  the mesh's arrays and the split record; applySplit()/undoSplit()
//                            (include/dynpm/progressive.h, src/progressive/progressive_mesh.cpp)
//   dpm/fields.js            the result fields: FDEF and FLDS (dpm_read.cpp)
//   dpm/parts.js             the parts' names: PART (part_names_chunk.cpp)
//   dpm/navigator.js         the mesh at one level (src/lod/navigator.cpp)
//   dpm/shown_values.js      a field's values at one level (Navigator::field_values())
//   dpm/draw_indices.js      index buffers of a level for WebGL (the viewer's own)
//   dpm/bytes.js             CRC-32, varints, the bounds-checked payload reader
//                            (src/progressive/bytes.h)
export { DpmError } from './dpm/bytes.js';
export { decodeDpm, DpmDecoder, MAGIC, readDpm, streamDpm, withChunkMargin, zstdFrameProblem } from './dpm/file.js';
export {
  applySplit,
  checkSplit,
  ProgressiveMesh,
  touchedFacesValid,
  undoSplit,
  WING_SLOT_SHIFT,
  WING_V1_FOLLOWS_V0,
  WING_WAS_TRIANGLE,
} from './dpm/progressive_mesh.js';
export { DpmField, FIELD_ELEMENT, FIELD_NODE } from './dpm/fields.js';
export { cleanPartName } from './dpm/parts.js';
export { findVariant, variantView } from './dpm/variants.js';
export { Navigator } from './dpm/navigator.js';
export { AGGREGATES, largerMagnitude, ShownValues } from './dpm/shown_values.js';
export { updateIndices, writeFaceIndices } from './dpm/draw_indices.js';
