// The FDEF and FLDS chunks, read (docs/FORMAT.md, "Fields: FDEF and FLDS"; the writer is
// dpm_write.cpp). The browser's decoder makes the same checks in the same order.
#include "dpm_read_fields.h"

#include <cmath>

#include "bytes.h"
#include "dpm_format.h"

namespace dynpm::progressive {
namespace {

// The smallest FDEF entry: two empty texts, location, flags, reserved, four f64 and an f32.
constexpr size_t kMinFieldDefinition = 2 + 2 + 1 + 1 + 2 + 4 * 8 + 4;

PayloadError at(const ByteReader& r, std::string what) { return {std::move(what), r.offset()}; }

std::string field_name(const ProgressiveField& f) { return "field '" + f.info.name + "': "; }

std::optional<PayloadError> check_definition(const ByteReader& r, const ProgressiveField& f,
                                             uint8_t location, uint8_t flags, uint16_t reserved) {
  const std::string who = field_name(f);
  if (f.info.name.empty()) return at(r, "a field has no name");
  if (f.info.name.size() > 255 || f.info.unit.size() > 255)
    return at(r, who + "its name or unit is longer than 255 bytes");
  if (location > 1) return at(r, who + "unknown location " + std::to_string(location));
  if (flags > 1) return at(r, who + "unknown flags " + std::to_string(flags));
  if (reserved != 0) return at(r, who + "the reserved field is not 0");
  if (!(std::isfinite(f.min) && std::isfinite(f.max) && f.min <= f.max))
    return at(r, who + "min and max are not finite numbers with min ≤ max");
  if (f.lossless) {
    if (f.quant_step != 0 || f.max_error != 0)
      return at(r, who + "a lossless field has a quantization step");
  } else {
    // As for positions: a grid float32 holds at the field's largest magnitude.
    const double largest = std::max(std::abs(f.min), std::abs(f.max));
    if (!(f.quant_step > 0 && std::isfinite(f.quant_step)))
      return at(r, who + "the quantization step is not valid");
    if (f.quant_step < 4 * largest * std::ldexp(1.0, -23))
      return at(r, who + "the quantization step is finer than float32 holds in its range");
    if (!(std::isfinite(f.max_error) && f.max_error >= 0))
      return at(r, who + "the error bound is not a finite number ≥ 0");
  }
  if (!(f.base_error >= 0 && f.base_error <= 1))
    return at(r, who + "the base mesh's field error is not in [0, 1]");
  return std::nullopt;
}

}  // namespace

std::optional<PayloadError> parse_field_definitions(std::string_view payload,
                                                    ProgressiveMesh& mesh) {
  ByteReader r(payload);
  const uint32_t count = r.get<uint32_t>();
  if (!r.ok() || count == 0 || !r.can_hold(count, kMinFieldDefinition))
    return at(r, "the field count is not valid");
  mesh.fields.resize(count);
  for (ProgressiveField& f : mesh.fields) {
    f.info.name = r.text();
    f.info.unit = r.text();
    const uint8_t location = r.get<uint8_t>();
    const uint8_t flags = r.get<uint8_t>();
    const uint16_t reserved = r.get<uint16_t>();
    f.info.location = location == 1 ? FieldLocation::kElement : FieldLocation::kNode;
    f.lossless = flags == 1;
    f.min = r.get<double>();
    f.max = r.get<double>();
    f.quant_step = r.get<double>();
    f.max_error = r.get<double>();
    f.base_error = r.get<float>();
    if (!r.ok()) return at(r, "the field definitions are cut short");
    if (auto e = check_definition(r, f, location, flags, reserved)) return e;
    f.values.resize(mesh.step_count());
  }
  if (r.remaining() != 0) return at(r, "unexpected bytes after the field definitions");
  return std::nullopt;
}

double field_values_limit(const ProgressiveMesh& mesh, uint32_t n, uint32_t face_begin,
                          uint32_t face_end) {
  const double steps = double(mesh.step_count());
  const double faces = double(face_end) - double(face_begin);
  double limit = 8 + (n > 0 && has_element_field(mesh) ? faces * kMaxVarint : 0);
  for (const ProgressiveField& f : mesh.fields) {
    const bool per_face = f.info.location == FieldLocation::kElement;
    const double items = per_face ? faces : (n > 0 ? double(n) : double(mesh.base_vertex_count));
    // After a SPLT: a predictor, a size and a range-coded section a step (5 bytes flushed).
    limit += n > 0 ? 4.0 * n + steps * (1 + 4 + 5 + items * kMaxCodedInteger)
                   : steps * items * kMaxVarint;
  }
  return limit;
}

std::optional<PayloadError> parse_base_field_values(std::string_view payload,
                                                    ProgressiveMesh& mesh) {
  ByteReader r(payload);
  const uint32_t got_first = r.get<uint32_t>();
  const uint32_t got_n = r.get<uint32_t>();
  if (!r.ok() || got_first != 0 || got_n != 0)
    return at(r, "the field values are not those of the chunk before (splits 0 to 0)");
  if (has_element_field(mesh)) mesh.face_heir.assign(mesh.base_face_count, kNoIndex);
  for (ProgressiveField& f : mesh.fields) {
    const std::string who = field_name(f);
    const uint32_t end =
        f.info.location == FieldLocation::kElement ? mesh.base_face_count : mesh.base_vertex_count;
    if (!r.can_hold(uint64_t{end} * mesh.step_count(), 1))
      return at(r, who + "the values are cut short");
    const FieldGrid g(f);
    // A quantized value lies in [min, max], give or take two grid steps.
    const double top = g.lossless ? 0 : (f.max - f.min) / g.step + 2;
    for (auto& values : f.values) values.resize(end);
    const auto value = [&](uint32_t u, size_t s) { return g.q(f.values[s][u]); };
    for (size_t t = 0; t < mesh.step_count(); ++t)
      for (uint32_t item = 0; item < end; ++item) {
        const int64_t residual = r.svarint(), q = g.add(predict_base(item, t, value), residual);
        if (!residual_fits(residual, g.lossless)) return at(r, who + kLosslessResidual);
        const float x = g.value(q);
        if (g.lossless ? !(x >= f.min && x <= f.max) : (q < -2 || double(q) > top))
          return at(r, who + "a value is far outside the field's range");
        f.values[t][item] = x;
      }
    if (!r.ok()) return at(r, who + "the values are cut short");
  }
  if (r.remaining() != 0) return at(r, "unexpected bytes after the field values");
  return std::nullopt;
}

std::optional<PayloadError> parse_split_field_values(std::string_view payload,
                                                     ProgressiveMesh& mesh, const FieldChunk& chunk,
                                                     const ChunkStencils& stencils,
                                                     SplitFieldModels& models, size_t steps) {
  ByteReader r(payload);
  const uint32_t first = chunk.first, n = chunk.last - chunk.first;
  const uint32_t got_first = r.get<uint32_t>();
  const uint32_t got_n = r.get<uint32_t>();
  if (!r.ok() || got_first != first || got_n != n)
    return at(r, "the field values are not those of the chunk before (splits " +
                     std::to_string(first) + " to " + std::to_string(first + n) + ")");
  // Heirs of the faces these splits create: each < F, the faces before its split.
  if (has_element_field(mesh)) {
    mesh.face_heir.resize(chunk.face_begin, kNoIndex);
    if (!r.can_hold(chunk.face_end - chunk.face_begin, 1)) return at(r, "the heirs are cut short");
    uint32_t g = chunk.face_begin;
    for (uint32_t i = first; i < first + n; ++i) {
      const uint32_t before = g;
      for (uint32_t k = mesh.wing_start[i]; k < mesh.wing_start[i + 1]; ++k) {
        if (!mesh.wings[k].was_triangle()) continue;
        const uint64_t dh = r.varint();
        if (!r.ok()) return at(r, "the heirs are cut short");
        if (dh >= before) return at(r, "split " + std::to_string(i) + ": heir out of range");
        mesh.face_heir.push_back(static_cast<uint32_t>(before - 1 - dh));
        ++g;
      }
    }
  }
  for (size_t index = 0; index < mesh.fields.size(); ++index) {
    ProgressiveField& f = mesh.fields[index];
    const std::string who = field_name(f);
    if (!r.can_hold(n, 4)) return at(r, who + "the field errors are cut short");
    for (uint32_t i = first; i < first + n; ++i) {
      const float e = r.get<float>();
      const float before = f.error.empty() ? f.base_error : f.error.back();
      if (!(e >= 0 && e <= before))
        return at(r, who + "split " + std::to_string(i) +
                         ": the field error is not in [0, 1] or increases");
      f.error.push_back(e);
    }
    const size_t start = r.offset();
    std::vector<FieldSectionView> sections;
    for (size_t t = 0; t < mesh.step_count(); ++t) {
      const auto predictor = static_cast<FieldPredictor>(r.get<uint8_t>());
      sections.push_back({predictor, r.bytes(r.get<uint32_t>())});
      if (!r.ok()) return at(r, who + "the values of step " + std::to_string(t) + " are cut short");
    }
    sections.resize(steps);
    if (std::string e = decode_split_field(mesh, f, chunk, stencils, models.field(index), sections);
        !e.empty())
      return PayloadError{who + e, start};
  }
  if (r.remaining() != 0) return at(r, "unexpected bytes after the field values");
  return std::nullopt;
}

}  // namespace dynpm::progressive
