// CalculiX FRD reader.
#include "formats.h"

namespace dynpm::io {

Result<AnimationStream> open_frd(const std::string& path, const ReadOptions& /*options*/) {
  return Status::error(path + ": reading CalculiX FRD files is not implemented yet");
}

}  // namespace dynpm::io
