// The catalogue of a folder of .dpm files: DIR/index.json, one entry per file below DIR with what
// its header and metadata hold (docs/batch.md "The catalogue index"). 'dynpm catalogue' writes
// it; so does 'dynpm batch' when its builds end (or its last Slurm job).
#pragma once

#include <string>
#include <vector>

#include "dynpm/result.h"

namespace dynpm::cli {

struct CatalogueResult {
  size_t entries = 0;
  std::vector<std::string> problems;  // "path: message" of each .dpm that could not be read
};

// Writes DIR/index.json atomically (a reader never sees half of it). Files that cannot be read
// are listed in the index's "problems" and returned, and do not stop the others.
Result<CatalogueResult> write_catalogue_index(const std::string& dir);

}  // namespace dynpm::cli
