// Exodus II files in netCDF's classic formats: recognised, and their header checked before
// netCDF's reader sees them (exodus.cpp reads them; exodus_classic.cpp says why and how).
#pragma once

#include <cstdint>
#include <string>

#include "dynpm/core.h"

namespace dynpm::io {

// The classic format's version byte (1, 2 or 5) if the file starts like one, else 0.
char classic_version(const std::string& path);

// Every count and length of the classic header checked against the bytes left in the file, and
// every byte of data the header describes present; an error naming the byte otherwise.
Status check_classic_header(const std::string& path, uint64_t file_size, char version);

}  // namespace dynpm::io
