// The io module's names for the whole-file helpers that live in core (core.h, "Files").
#pragma once

#include "dynpm/core.h"

namespace dynpm::io {

using dynpm::read_file;
using dynpm::read_file_head;
using dynpm::write_file_atomically;

}  // namespace dynpm::io
