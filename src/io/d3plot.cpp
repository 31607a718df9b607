// LS-DYNA d3plot reader.
#include "formats.h"

namespace dynpm::io {

Result<AnimationStream> open_d3plot(const std::string& path, const ReadOptions& /*options*/) {
  return Status::error(path + ": reading LS-DYNA d3plot files is not implemented yet");
}

}  // namespace dynpm::io
