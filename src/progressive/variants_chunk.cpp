// The VARI chunk (docs/FORMAT.md, "Variants: VARI") and the choice of one variant; the browser's
// decoder (viewer/src/dpm/variants.js) makes the same checks in the same order.
#include "variants_chunk.h"

#include <charconv>
#include <cmath>

#include "bytes.h"
#include "dynpm/text.h"

namespace dynpm::progressive {
namespace {

// The smallest variant: a name and a source of one byte, one step (time and stored step).
constexpr size_t kMinVariant = 2 + 1 + 2 + 1 + 4 + 8 + 4;

}  // namespace

std::string variants_payload(const ProgressiveMesh& mesh) {
  if (mesh.variants.empty()) return {};
  ByteWriter w;
  w.put<uint32_t>(static_cast<uint32_t>(mesh.variants.size()));
  for (const MeshVariant& v : mesh.variants) {
    w.text(v.name);
    w.text(v.source);
    w.put<uint32_t>(static_cast<uint32_t>(v.steps.size()));
    for (double t : v.times) w.put<double>(t);
    for (uint32_t s : v.steps) w.put<uint32_t>(s);
  }
  return std::move(w.bytes);
}

std::optional<PayloadError> parse_variants(std::string_view payload, ProgressiveMesh& mesh) {
  ByteReader r(payload);
  const uint32_t count = r.get<uint32_t>();
  if (!r.ok() || count == 0 || !r.can_hold(count, kMinVariant))
    return PayloadError{"the variant count is not valid", r.offset()};
  const size_t stored = mesh.times.size();
  std::vector<bool> used(stored, false);
  mesh.variants.resize(count);
  for (uint32_t k = 0; k < count; ++k) {
    const size_t at = r.offset();
    MeshVariant& v = mesh.variants[k];
    v.name = r.text();
    v.source = r.text();
    const uint32_t steps = r.get<uint32_t>();
    if (!r.ok()) return PayloadError{"the variants are cut short", at};
    const std::string which = "variant " + std::to_string(k);
    if (!is_clean_part_name(v.name) || !is_clean_part_name(v.source))
      return PayloadError{which +
                              ": its name and source are not 1 to 255 bytes of UTF-8 without "
                              "control characters or blanks at their ends",
                          at};
    for (uint32_t j = 0; j < k; ++j)
      if (mesh.variants[j].name == v.name)
        return PayloadError{which + ": the name is variant " + std::to_string(j) + "'s", at};
    if (steps == 0 || !r.can_hold(steps, 12))
      return PayloadError{which + ": the step count is not valid", r.offset()};
    v.times.resize(steps);
    for (double& t : v.times) t = r.get<double>();
    for (double t : v.times)
      if (!std::isfinite(t)) return PayloadError{which + ": a step's time is not finite", at};
    v.steps.resize(steps);
    for (uint32_t& s : v.steps) {
      const size_t step_at = r.offset();
      s = r.get<uint32_t>();
      if (s >= stored)
        return PayloadError{which + ": stored step " + std::to_string(s) + " is past the file's " +
                                std::to_string(stored) + " steps",
                            step_at};
      used[s] = true;
    }
  }
  if (r.remaining() != 0) return PayloadError{"unexpected bytes after the variants", r.offset()};
  for (size_t s = 0; s < stored; ++s)
    if (!used[s])
      return PayloadError{"stored step " + std::to_string(s) + " belongs to no variant", 0};
  return std::nullopt;
}

}  // namespace dynpm::progressive

namespace dynpm {

Result<size_t> find_variant(const ProgressiveMesh& mesh, std::string_view which) {
  std::string list;
  for (size_t k = 0; k < mesh.variants.size(); ++k) {
    if (mesh.variants[k].name == which) return k;
    list += (k ? ", " : "") + std::to_string(k) + " " + mesh.variants[k].name;
  }
  if (mesh.variants.empty())
    return Status::error("the model is not a family file: it has no variants");
  size_t index = 0;
  const auto [end, ec] = std::from_chars(which.data(), which.data() + which.size(), index);
  if (ec == std::errc() && end == which.data() + which.size() && index < mesh.variants.size())
    return index;
  return Status::error("no variant '" + printable(which) + "' (the variants: " + list + ")");
}

void select_variant(ProgressiveMesh& mesh, size_t index) {
  MeshVariant variant = std::move(mesh.variants.at(index));
  mesh.variants.clear();
  const auto pick = [&](std::vector<std::vector<float>>& per_stored_step) {
    std::vector<std::vector<float>> per_step;
    per_step.reserve(variant.steps.size());
    for (uint32_t s : variant.steps)
      per_step.push_back(s < per_stored_step.size() ? per_stored_step[s] : std::vector<float>{});
    per_stored_step = std::move(per_step);
  };
  pick(mesh.positions);
  for (ProgressiveField& f : mesh.fields) pick(f.values);
  std::vector<size_t> key_steps;
  for (size_t t = 0; t < variant.steps.size(); ++t)
    for (size_t k : mesh.key_steps)
      if (k == variant.steps[t]) {
        key_steps.push_back(t);
        break;
      }
  mesh.key_steps = std::move(key_steps);
  size_t read = 0;  // the variant's leading steps that were decoded
  while (read < variant.steps.size() && variant.steps[read] < mesh.steps_read) ++read;
  mesh.steps_read = read;
  mesh.times = std::move(variant.times);
}

}  // namespace dynpm
