// build's result fields: gathered, heirs chosen, errors measured, quantized (docs/FORMAT.md,
// "Fields: FDEF and FLDS").
#include "build_fields.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dynpm {
namespace {

bool holds(const Face& face, uint32_t v) {
  return std::find(face.v.begin(), face.v.end(), v) != face.v.end();
}

// The heir of the triangle wing of split i whose wing vertex is w, among the faces as they are
// before the split; kNoIndex when no face holds v1.
uint32_t heir_of(const ProgressiveMesh& pm, uint32_t i, uint32_t w, std::span<const Face> faces,
                 uint32_t face_count, size_t& searches) {
  const uint32_t v1 = pm.parent[i];
  const auto moved = std::span(pm.moved_faces)
                         .subspan(pm.moved_start[i], pm.moved_start[i + 1] - pm.moved_start[i]);
  const auto wings =
      std::span(pm.wings).subspan(pm.wing_start[i], pm.wing_start[i + 1] - pm.wing_start[i]);
  // The face across v0–w took over the removed triangle's area: after the collapse it holds v1
  // and w, and it is a moved face or (when it held v1 too) a quad wing.
  for (uint32_t f : moved)
    if (holds(faces[f], w)) return f;
  for (const SplitWing& q : wings)
    if (!q.was_triangle() && holds(faces[q.face], w)) return q.face;
  if (!moved.empty()) return moved.front();
  for (const SplitWing& q : wings)
    if (!q.was_triangle()) return q.face;
  ++searches;
  for (uint32_t f = 0; f < face_count; ++f)
    if (holds(faces[f], v1)) return f;
  return kNoIndex;
}

}  // namespace

Status choose_face_heirs(ProgressiveMesh& pm, size_t* searches) {
  size_t searched = 0;
  std::vector<Face> faces(pm.base_faces);
  faces.resize(pm.full_face_count);
  uint32_t face_count = pm.base_face_count;
  pm.face_heir.assign(pm.base_face_count, kNoIndex);
  pm.face_heir.reserve(pm.full_face_count);
  for (uint32_t i = 0; i < pm.split_count(); ++i) {
    for (uint32_t k = pm.wing_start[i]; k < pm.wing_start[i + 1]; ++k) {
      const SplitWing& wing = pm.wings[k];
      if (!wing.was_triangle()) continue;
      const uint32_t h = heir_of(pm, i, wing.vertex, faces, face_count, searched);
      if (h == kNoIndex)
        return Status::error("internal: split " + std::to_string(i) +
                             ": no face holds its parent to stand for the faces it re-creates");
      pm.face_heir.push_back(h);
    }
    apply_split(pm, i, faces, face_count);
  }
  if (searches) *searches = searched;
  return {};
}

void measure_field_errors(ProgressiveMesh& pm, ProgressiveField& field) {
  const uint32_t splits = pm.split_count();
  const bool per_face = field.info.location == FieldLocation::kElement;
  // level[k]: the largest spread at level k (k splits applied), over every step. Coarsening from
  // the full mesh merges what an undone split's vertex (faces) stands for into its parent
  // (heirs); the sets only grow, so a level's largest spread is a running max.
  std::vector<double> level(splits + 1, 0.0);
  std::vector<float> lo, hi;
  for (const std::vector<float>& values : field.values) {
    lo = values;
    hi = values;
    double spread = 0;
    auto merge = [&](uint32_t into, uint32_t from) {
      lo[into] = std::min(lo[into], lo[from]);
      hi[into] = std::max(hi[into], hi[from]);
      spread = std::max(spread, double(hi[into]) - double(lo[into]));
    };
    uint32_t face_end = pm.full_face_count;
    for (uint32_t i = splits; i-- > 0;) {
      face_end = merge_undone_split(pm, i, per_face, face_end, merge);
      level[i] = std::max(level[i], spread);
    }
  }
  // As fractions of the range, rounded to float32 once each: the rounding keeps the order.
  const double range = field.max - field.min;
  auto fraction = [range](double spread) {
    return range > 0 ? static_cast<float>(std::min(1.0, spread / range)) : 0.0f;
  };
  field.base_error = fraction(level[0]);
  field.error.resize(splits);
  for (uint32_t i = 0; i < splits; ++i) field.error[i] = fraction(level[i + 1]);
}

Status build_fields(const FrameSource& frames, const std::vector<uint32_t>& new_vertex,
                    const std::vector<uint32_t>& new_face, double bound, bool lossless,
                    ProgressiveMesh& pm) {
  const size_t steps = frames.step_count();
  for (size_t f = 0; const FieldInfo& info : frames.fields()) {
    const bool per_face = info.location == FieldLocation::kElement;
    const std::vector<uint32_t>& renumber = per_face ? new_face : new_vertex;
    ProgressiveField field;
    field.info = info;
    field.values.resize(steps);
    std::vector<float> values(renumber.size());
    field.min = std::numeric_limits<double>::infinity();
    field.max = -field.min;
    for (size_t t = 0; t < steps; ++t) {
      DYNPM_RETURN_IF_ERROR(frames.read_field(f, t, values));
      field.values[t].resize(values.size());
      for (size_t i = 0; i < values.size(); ++i) {
        if (!std::isfinite(values[i]))
          return Status::error("field '" + info.name + "', step " + std::to_string(t) + ", " +
                               (per_face ? "face " : "vertex ") + std::to_string(i) +
                               ": the value is not finite");
        field.values[t][renumber[i]] = values[i];
        field.min = std::min<double>(field.min, values[i]);
        field.max = std::max<double>(field.max, values[i]);
      }
    }
    if (values.empty()) field.min = field.max = 0;
    pm.fields.push_back(std::move(field));
    ++f;
  }
  const bool per_face = std::any_of(pm.fields.begin(), pm.fields.end(), [](const auto& f) {
    return f.info.location == FieldLocation::kElement;
  });
  if (per_face) DYNPM_RETURN_IF_ERROR(choose_face_heirs(pm));
  // Errors from the values read (within [min, max], so at most 1), then the values quantized.
  for (ProgressiveField& field : pm.fields) measure_field_errors(pm, field);
  quantize_fields(pm, bound, lossless);
  return {};
}

}  // namespace dynpm
