// 'dynpm build --family' and --variant (docs/family.md).
#include "family_inputs.h"

#include <cstdio>
#include <filesystem>

#include "batch_list.h"
#include "dynpm/text.h"
#include "inputs.h"
#include "json.h"
#include "outputs.h"
#include "report.h"

namespace dynpm::cli {

namespace {

// A variant's name: variant_name() of its file, or of its folder when the input is a glob of
// per-step files ("runs/b/frame_*.obj" → "b").
std::string member_name(const std::string& input) {
  if (input.find_first_of("*?[") == std::string::npos) return variant_name(input);
  return std::filesystem::path(input).parent_path().filename().string();
}

}  // namespace

Result<FamilyInputs> open_family(const Args& args, const std::string& output,
                                 const ProgressCallback& progress, unsigned threads) {
  DYNPM_RETURN_IF_ERROR(check_output_folder(output));
  FamilyInputs family;
  std::vector<FamilyMember> members;
  const auto member = [&](size_t k, bool mesh_checked) {
    return FamilyMember{member_name(args.positional[k]),
                        std::filesystem::path(args.positional[k]).filename().string(),
                        &family.members[k].topology, family.members[k].frames.get(), mesh_checked};
  };
  {
    Phase phase("reading the inputs");
    for (const std::string& input : args.positional) {
      const std::string one[] = {input};
      // The first mesh is checked; each later one is compared with it as it is opened (the same
      // faces are as sound) and its faces freed: only the first is built, and a family holds
      // one more mesh at a time, not one per variant.
      const bool first = family.members.empty();
      auto stream =
          open_inputs(one, args, first ? InputChecks::kSimplifiable : InputChecks::kFinite,
                      first ? &family.checked : nullptr);
      if (!stream) return stream.status();
      family.members.push_back(std::move(*stream));
      if (first) continue;
      const FamilyMember pair[] = {member(0, false), member(family.members.size() - 1, false)};
      DYNPM_RETURN_IF_ERROR(check_same_mesh(pair));
      family.members.back().topology.release_faces();
    }
  }
  for (size_t k = 0; k < family.members.size(); ++k) members.push_back(member(k, k > 0));
  Phase phase("comparing the variants");
  auto steps = FamilySteps::make(members, progress, threads);
  if (!steps) return steps.status();
  family.steps = std::move(*steps);
  return family;
}

Status choose_variant(const Args& args, const std::string& verb, const std::string& path,
                      ProgressiveMesh& mesh) {
  const auto which = args.value("--variant");
  if (mesh.variants.empty()) {
    if (which) return Status::error(path + ": --variant: the model is not a family file");
    return {};
  }
  size_t index = 0;
  if (which) {
    auto found = find_variant(mesh, *which);
    if (!found) return Status::error(path + ": --variant: " + found.message());
    index = *found;
  } else {
    note(verb, path + " is a family of " + std::to_string(mesh.variants.size()) +
                   " variants: showing variant 0, " + printable(mesh.variants[0].name) +
                   " (--variant NAME|INDEX picks another; 'dynpm info' lists them)");
  }
  select_variant(mesh, index);
  return {};
}

Result<ProgressiveMesh> read_dpm_of_variant(const Args& args, const std::string& path,
                                            DpmReadLimits limits) {
  limits.variant = args.value("--variant").value_or("0");
  return read_dpm(path, limits);
}

namespace {

// Per variant: how many of its steps an earlier variant stored.
std::vector<size_t> shared_steps(const std::vector<MeshVariant>& variants) {
  std::vector<size_t> shared;
  std::vector<bool> seen;
  for (const MeshVariant& v : variants) {
    size_t count = 0;
    for (uint32_t s : v.steps) count += s < seen.size() && seen[s];
    for (uint32_t s : v.steps) {
      if (s >= seen.size()) seen.resize(s + 1, false);
      seen[s] = true;
    }
    shared.push_back(count);
  }
  return shared;
}

}  // namespace

void json_variants(Json& j, const std::vector<MeshVariant>& variants) {
  const std::vector<size_t> shared = shared_steps(variants);
  j.begin_array("variants");
  for (size_t k = 0; k < variants.size(); ++k) {
    const MeshVariant& v = variants[k];
    j.begin_object();
    j.value("index", uint64_t{k});
    j.value("name", v.name);
    j.value("source", v.source);
    j.value("steps", uint64_t{v.steps.size()});
    j.value("first_time", v.times.front());
    j.value("last_time", v.times.back());
    j.value("shared_steps", uint64_t{shared[k]});
    j.end_object();
  }
  j.end_array();
}

void print_variants(const std::vector<MeshVariant>& variants, std::optional<size_t> chosen) {
  const std::vector<size_t> shared = shared_steps(variants);
  for (size_t k = 0; k < variants.size(); ++k) {
    const MeshVariant& v = variants[k];
    std::printf("variant %c %zu %s (%s): %zu steps, time %g to %g", chosen == k ? '*' : ' ', k,
                printable(v.name).c_str(), printable(v.source).c_str(), v.steps.size(),
                v.times.front(), v.times.back());
    if (shared[k] > 0) std::printf("; %zu stored with an earlier variant", shared[k]);
    std::printf("\n");
  }
}

}  // namespace dynpm::cli
