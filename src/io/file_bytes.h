// Whole-file reads with clear errors, and atomic writes (temporary name, then rename).
#pragma once

#include <string>
#include <string_view>

#include "dynpm/result.h"

namespace dynpm::io {

// The bytes of a regular file; errors name the file and the cause (missing, a directory, …).
Result<std::string> read_file(const std::string& path);
// The first up-to-n bytes of a file (for format signatures and header comments).
Result<std::string> read_file_head(const std::string& path, size_t n);

// Writes bytes to "<path>.tmp-<pid>-<n>" beside path, flushes, and renames it over path. On any
// failure the temporary file is removed and path is left as it was.
Status write_file_atomically(const std::string& path, std::string_view bytes);

}  // namespace dynpm::io
