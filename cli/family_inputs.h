// 'dynpm build --family': each input one variant of one mesh (docs/family.md), opened and
// checked before any work; and the --variant flag of the verbs that read a family file.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "args.h"
#include "dynpm/pipeline.h"

namespace dynpm::cli {

inline const FlagSpec kFamilyFlag{"--family", "", false, "",
                                  "each INPUT is one variant of one mesh: one hierarchy for all"};
inline const FlagSpec kVariantFlag{"--variant", "", true, "NAME|INDEX",
                                   "a family file's variant (INDEX from 0; default 0)"};

struct FamilyInputs {
  // One per input, in the order given; once compared, all but the first without their faces
  // (Topology::release_faces()): they are the first one's.
  std::vector<AnimationStream> members;
  std::unique_ptr<FamilySteps> steps;      // their distinct steps, the build's FrameSource
  std::optional<ValidationProof> checked;  // of the first member's faces (the build's mesh)
};

// The output's folder first, then each input opened as 'build' opens one (a d3plot family's
// first file stands for the family), each named by variant_name() (batch_list.h), the meshes
// compared (the first difference refused), and the steps compared (each distinct step stored once,
// read on up to `threads` threads).
Result<FamilyInputs> open_family(const Args& args, const std::string& output,
                                 const ProgressCallback& progress, unsigned threads);

// Makes a family file `mesh` one variant's animation: --variant's, else variant 0 with a note
// naming it (`verb` prints it). A model that is not a family with --variant is an error.
Status choose_variant(const Args& args, const std::string& verb, const std::string& path,
                      ProgressiveMesh& mesh);

// read_dpm() with `limits` for the variant choose_variant() will pick (--variant's, else 0):
// a family file's variant steps up to limits.last_step are not the stored steps up to it
// (variant 0's are stored reversed, docs/family.md "How it is built"), so the reader maps them
// through the file's VARI and decodes what they need, in one pass (DpmReadLimits::variant).
Result<ProgressiveMesh> read_dpm_of_variant(const Args& args, const std::string& path,
                                            DpmReadLimits limits);

class Json;
// A family's variants as 'info --json' and the catalogue list them: "variants": [{"index",
// "name", "source", "steps", "first_time", "last_time", "shared_steps"}] (shared: steps stored
// with an earlier variant).
void json_variants(Json& j, const std::vector<MeshVariant>& variants);
// One line a variant, for 'dynpm info' (the chosen one marked).
void print_variants(const std::vector<MeshVariant>& variants, std::optional<size_t> chosen);

}  // namespace dynpm::cli
