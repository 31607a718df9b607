// The PART chunk (docs/FORMAT.md, "Part names: PART"); the browser's decoder
// (viewer/src/dpm/parts.js) makes the same checks in the same order.
#include "part_names_chunk.h"

#include "bytes.h"

namespace dynpm::progressive {
namespace {

// The smallest entry: an id and a name of one byte.
constexpr size_t kMinPartEntry = 4 + 2 + 1;

}  // namespace

std::string part_names_payload(const ProgressiveMesh& mesh) {
  if (mesh.part_names.empty()) return {};
  ByteWriter w;
  w.put<uint32_t>(static_cast<uint32_t>(mesh.part_names.size()));
  for (const PartName& p : mesh.part_names) {
    w.put<int32_t>(p.id);
    w.text(p.name);
  }
  return std::move(w.bytes);
}

std::optional<PayloadError> parse_part_names(std::string_view payload, ProgressiveMesh& mesh) {
  ByteReader r(payload);
  const uint32_t count = r.get<uint32_t>();
  if (!r.ok() || count == 0 || !r.can_hold(count, kMinPartEntry))
    return PayloadError{"the part count is not valid", r.offset()};
  mesh.part_names.reserve(count);
  for (uint32_t k = 0; k < count; ++k) {
    const size_t at = r.offset();
    const int32_t id = r.get<int32_t>();
    std::string name = r.text();
    if (!r.ok()) return PayloadError{"the part names are cut short", at};
    if (!mesh.part_names.empty() && id <= mesh.part_names.back().id)
      return PayloadError{"part " + std::to_string(id) + " is not after part " +
                              std::to_string(mesh.part_names.back().id) + " (ascending ids)",
                          at};
    if (!is_clean_part_name(name))
      return PayloadError{"the name of part " + std::to_string(id) +
                              " is not 1 to 255 bytes of UTF-8 without control characters or "
                              "blanks at its ends",
                          at};
    mesh.part_names.push_back({id, std::move(name)});
  }
  if (r.remaining() != 0) return PayloadError{"unexpected bytes after the part names", r.offset()};
  return std::nullopt;
}

}  // namespace dynpm::progressive
