// VTK unstructured grid / VTU / PVD reader.
#include "formats.h"

namespace dynpm::io {

Result<AnimationStream> open_vtk_series(const std::string& path, const ReadOptions& /*options*/) {
  return Status::error(path + ": reading VTK unstructured grid / VTU / PVD files is not implemented yet");
}

}  // namespace dynpm::io
