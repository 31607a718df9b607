// The catalogue of a folder of .dpm files: DIR/index.json, one entry per file below DIR with what
// its header and metadata hold (docs/batch.md "The catalogue index"). 'dynpm catalogue' writes
// it; so does 'dynpm batch' when its builds end (or its last Slurm job).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "dynpm/result.h"

namespace dynpm::cli {

struct CatalogueResult {
  size_t entries = 0;
  std::vector<std::string> problems;  // "path: message" of each .dpm that could not be read
};

// The .dpm files below dir, relative to it ('/'-separated), sorted: not through symbolic links,
// and not the temporaries of a build ("x.dpm.tmp-123-0"), so never a file half-written.
std::vector<std::string> catalogue_files(const std::string& dir);

// One entry of the index, a JSON object, for the file dir/relative; an error (naming the file)
// when it cannot be read.
Result<std::string> catalogue_entry(const std::string& dir, const std::string& relative);

// The index of `files` (below dir) with each entry as `entry` makes it: catalogue_entry(), or a
// cache of it ('dynpm serve'). The files that fail are added to result.problems.
using CatalogueEntryMaker = std::function<Result<std::string>(const std::string& relative)>;
std::string catalogue_index(const std::vector<std::string>& files, const CatalogueEntryMaker& entry,
                            CatalogueResult& result);

// Writes DIR/index.json atomically (a reader never sees half of it). Files that cannot be read
// are listed in the index's "problems" and returned, and do not stop the others.
Result<CatalogueResult> write_catalogue_index(const std::string& dir);

}  // namespace dynpm::cli
