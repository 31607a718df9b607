// Exodus II reader.
#include "formats.h"

namespace dynpm::io {

Result<AnimationStream> open_exodus(const std::string& path, const ReadOptions& /*options*/) {
  return Status::error(path + ": reading Exodus II files is not implemented yet");
}

}  // namespace dynpm::io
