// Result fields in the .dpm file (docs/FORMAT.md, "Fields: FDEF and FLDS"): node and element
// fields come back within their stated bound (bit-exact lossless) and equal what the built mesh
// holds in memory; damaged FDEF and FLDS chunks are refused at their byte; unknown optional chunks
// are skipped and other unknown tags refused; a prefix that ends inside an FLDS holds the levels
// before its SPLT.
#include <gtest/gtest.h>
#include <zstd.h>

#include <cmath>
#include <cstring>

#include "dpm_chunks.h"
#include "dynpm/io.h"
#include "dynpm/lod.h"
#include "dynpm/pipeline.h"
#include "field_sources.h"
#include "fixtures.h"
#include "round_trip.h"

namespace dynpm {
namespace {

using test::chunk;
using test::chunks_of;
using test::expect_refused_at;
using test::put;
using test::through_file;
using test::with_payload;

struct Built {
  Animation animation;
  ProgressiveMesh mesh;
};

// The hat rail's first steps with a node field from the positions and an element field, the
// mean of it over each face.
Built hat_rail_with_fields(bool lossless, double bound = 0.001) {
  auto paths = expand_inputs(std::vector<std::string>{test::sample_dir() + "/frame_00*.obj"});
  EXPECT_TRUE(paths.ok()) << paths.message();
  auto a = read_animation(*paths);
  EXPECT_TRUE(a.ok()) << a.message();
  Built out{std::move(a).value(), {}};
  test::WithFields source(out.animation.frames, out.animation.topology);
  source.add_node_field("PEEQ", [](const float* p, size_t t) {
    return std::max(0.0f, std::sin(0.05f * p[0]) * std::cos(0.03f * p[1]) * float(t) * 0.1f);
  });
  source.add_element_mean("S_MISES_elem", 0);
  BuildOptions options;
  options.lossless = lossless;
  options.field_bound = bound;
  auto pm = build_progressive_mesh(out.animation.topology, source, options);
  EXPECT_TRUE(pm.ok()) << pm.message();
  out.mesh = std::move(pm).value();
  // The input's values, to compare with (read again through the source, in the input's order).
  return out;
}

// Values of field f at step t in the input's order, read from a fresh source like the build's.
std::vector<float> input_values(const Built& b, size_t f, size_t t) {
  test::WithFields source(b.animation.frames, b.animation.topology);
  source.add_node_field("PEEQ", [](const float* p, size_t s) {
    return std::max(0.0f, std::sin(0.05f * p[0]) * std::cos(0.03f * p[1]) * float(s) * 0.1f);
  });
  source.add_element_mean("S_MISES_elem", 0);
  const bool per_face = f == 1;
  std::vector<float> out(per_face ? b.animation.topology.faces.size()
                                  : b.animation.topology.vertex_count);
  EXPECT_TRUE(source.read_field(f, t, out).ok());
  return out;
}

TEST(ProgressiveFields, NodeAndElementFieldsComeBackWithinTheirBound) {
  const Built b = hat_rail_with_fields(false);
  const ProgressiveMesh back = through_file(b.mesh);
  ASSERT_EQ(back.fields.size(), 2u);
  EXPECT_EQ(back.fields[0].info, (FieldInfo{"PEEQ", FieldLocation::kNode, "1"}));
  EXPECT_EQ(back.fields[1].info, (FieldInfo{"S_MISES_elem", FieldLocation::kElement, "MPa"}));
  EXPECT_EQ(back.face_heir, b.mesh.face_heir);
  for (size_t f = 0; f < 2; ++f) {
    const ProgressiveField& field = back.fields[f];
    SCOPED_TRACE(field.info.name);
    // The file holds what the built mesh holds in memory, bit for bit.
    EXPECT_TRUE(field.values == b.mesh.fields[f].values);
    EXPECT_EQ(field.error, b.mesh.fields[f].error);
    EXPECT_EQ(field.base_error, b.mesh.fields[f].base_error);
    EXPECT_EQ(field.min, b.mesh.fields[f].min);
    // The stated bound: 0.1 % of the range, and every value within it of the input's.
    ASSERT_GT(field.max, field.min);
    EXPECT_NEAR(field.max_error, 0.001 * (field.max - field.min), 1e-9 * field.max);
    const bool per_face = field.info.location == FieldLocation::kElement;
    double worst = 0;
    for (size_t t = 0; t < back.step_count(); ++t) {
      const std::vector<float> input = input_values(b, f, t);
      for (size_t i = 0; i < field.values[t].size(); ++i) {
        const uint32_t o = per_face ? back.face_original_index[i] : back.vertex_original_index[i];
        worst = std::max(worst, std::abs(double(field.values[t][i]) - input[o]));
      }
    }
    EXPECT_LE(worst, field.max_error * (1 + 1e-6));
    EXPECT_GT(worst, 0.1 * field.max_error);  // quantized, not stored exactly
  }
}

TEST(ProgressiveFields, LosslessFieldsAreExact) {
  const Built b = hat_rail_with_fields(true);
  const ProgressiveMesh back = through_file(b.mesh);
  for (size_t f = 0; f < 2; ++f) {
    const ProgressiveField& field = back.fields[f];
    EXPECT_TRUE(field.lossless);
    EXPECT_EQ(field.quant_step, 0);
    const bool per_face = field.info.location == FieldLocation::kElement;
    for (size_t t = 0; t < back.step_count(); ++t) {
      const std::vector<float> input = input_values(b, f, t);
      for (size_t i = 0; i < field.values[t].size(); ++i) {
        const uint32_t o = per_face ? back.face_original_index[i] : back.vertex_original_index[i];
        ASSERT_EQ(std::memcmp(&field.values[t][i], &input[o], 4), 0)
            << field.info.name << " step " << t << " item " << i;
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Damage, chunk by chunk: the payload changed, stored uncompressed (flags 0) with a right
// checksum, so that the reader's checks of the payload itself are what refuse it.

std::string raw_payload(const std::string& bytes, size_t at) {
  uint32_t flags, stored, raw;
  std::memcpy(&flags, bytes.data() + at + 4, 4);
  std::memcpy(&stored, bytes.data() + at + 8, 4);
  std::memcpy(&raw, bytes.data() + at + 12, 4);
  const std::string body = bytes.substr(at + 24, stored);
  if (flags == 0) return body;
  std::string out(raw, '\0');
  EXPECT_EQ(ZSTD_decompress(out.data(), raw, body.data(), body.size()), raw);
  return out;
}

std::string varint(uint64_t v) {
  std::string s;
  for (; v >= 0x80; v >>= 7) s.push_back(char((v & 0x7f) | 0x80));
  s.push_back(char(v));
  return s;
}

size_t varint_length(const std::string& s, size_t at) {
  size_t n = 1;
  while (uint8_t(s[at + n - 1]) & 0x80) ++n;
  return n;
}

// The encoder codes each step's positions and each chunk's fields on its own thread: the bytes
// must not depend on how many there are (quantized and lossless, several SPLT chunks).
TEST(ProgressiveFields, TheFileIsTheSameOnAnyThreadCount) {
  for (bool lossless : {false, true}) {
    const Built b = hat_rail_with_fields(lossless);
    ASSERT_GT(b.mesh.split_count(), 256u * 3);  // at least three SPLT chunks
    const std::string one = encode_dpm(b.mesh, 1).value();
    for (unsigned threads : {2u, 3u, 8u})
      EXPECT_TRUE(encode_dpm(b.mesh, threads).value() == one)
          << threads << " threads, lossless " << lossless;
    auto back = decode_dpm(one, "one.dpm");
    ASSERT_TRUE(back.ok()) << back.message();
    EXPECT_EQ(back->positions.size(), b.mesh.positions.size());
  }
}

TEST(ProgressiveFields, DamagedFieldChunksAreRefusedAtTheirByte) {
  const Built b = hat_rail_with_fields(false);
  const std::string bytes = encode_dpm(b.mesh).value();
  const auto chunks = chunks_of(bytes);
  ASSERT_EQ(chunks[1].first, "FDEF");
  ASSERT_EQ(chunks[2].first, "BASE");
  ASSERT_EQ(chunks[3].first, "FLDS");
  ASSERT_EQ(chunks[4].first, "SPLT");
  ASSERT_EQ(chunks[5].first, "FLDS");
  // FDEF: u32 count, then "PEEQ" (2 + 4), unit "1" (2 + 1), location, flags, reserved, min, max,
  // quant_step, max_error, base_error.
  const size_t fdef = chunks[1].second;
  const std::string def = raw_payload(bytes, fdef);
  const size_t location = 4 + 6 + 3, min = location + 4;
  auto refuse_def = [&](const std::string& changed, const std::string& what) {
    expect_refused_at(with_payload(bytes, fdef, changed), fdef + 24, what);
  };
  refuse_def(put<uint32_t>(def, 0, 0), "field count is not valid");
  refuse_def(put<uint32_t>(def, 0, 1u << 30), "field count is not valid");
  refuse_def(put<uint8_t>(def, location, 2), "unknown location 2");
  refuse_def(put<uint8_t>(def, location + 1, 4), "unknown flags 4");
  refuse_def(put<uint16_t>(def, location + 2, 1), "reserved field is not 0");
  refuse_def(put<double>(def, min, 1e30), "min ≤ max");
  refuse_def(put<double>(def, min + 8, std::nan("")), "min ≤ max");
  refuse_def(put<double>(def, min + 16, 0.0), "quantization step is not valid");
  refuse_def(put<double>(def, min + 16, 1e-30), "finer than float32");
  refuse_def(put<float>(def, min + 32, 1.5f), "field error is not in [0, 1]");
  refuse_def(def.substr(0, 4) + std::string(2, '\0') + def.substr(10), "a field has no name");
  refuse_def(def + "x", "unexpected bytes after the field definitions");
  refuse_def(def.substr(0, def.size() - 1), "cut short");

  // The base mesh's FLDS: first_split, count, then PEEQ's values (no errors, no heirs there).
  const size_t base = chunks[3].second;
  const std::string values = raw_payload(bytes, base);
  auto refuse_base = [&](const std::string& changed, const std::string& what) {
    expect_refused_at(with_payload(bytes, base, changed), base + 24, what);
  };
  refuse_base(put<uint32_t>(values, 4, 256), "not those of the chunk before");
  refuse_base(
      values.substr(0, 8) + varint(uint64_t{1} << 40) + values.substr(8 + varint_length(values, 8)),
      "far outside the field's range");
  refuse_base(values + "\x01", "unexpected bytes after the field values");
  refuse_base(values.substr(0, values.size() - 1), "cut short");

  // The first SPLT's FLDS: heirs first (there is an element field), then each field's errors.
  const size_t first = chunks[5].second;
  const std::string split_values = raw_payload(bytes, first);
  auto refuse_split = [&](const std::string& changed, const std::string& what) {
    expect_refused_at(with_payload(bytes, first, changed), first + 24, what);
  };
  refuse_split(put<uint32_t>(split_values, 0, 1), "not those of the chunk before");
  const size_t heir = varint_length(split_values, 8);
  refuse_split(
      split_values.substr(0, 8) + varint(b.mesh.base_face_count) + split_values.substr(8 + heir),
      "heir out of range");
  uint32_t created = 0;
  for (uint32_t k = 0; k < b.mesh.wing_start[256]; ++k) created += b.mesh.wings[k].was_triangle();
  size_t errors = 8;
  for (uint32_t g = 0; g < created; ++g) errors += varint_length(split_values, errors);
  refuse_split(put<float>(split_values, errors, 2.0f), "the field error is not in [0, 1]");
  refuse_split(put<float>(split_values, errors + 4, -1.0f), "the field error is not in [0, 1]");
  refuse_split(put<float>(split_values, errors + 4, std::nanf("")),
               "the field error is not in [0, 1]");
  // Then each step's section (version 7): a predictor, a size, the range-coded values. PEEQ's
  // first; the ring's median is no guess at step 0, nor for an element field.
  const size_t peeq = errors + 4 * 256;
  refuse_split(put<uint8_t>(split_values, peeq, 2), "step 0: predictor 2 is not valid here");
  refuse_split(put<uint8_t>(split_values, peeq, 1), "step 0: predictor 1 is not valid here");
  refuse_split(put<uint32_t>(split_values, peeq + 1, 1u << 30), "values of step 0 are cut short");
  uint32_t size = 0;
  std::memcpy(&size, split_values.data() + peeq + 1, 4);
  refuse_split(put<uint32_t>(split_values, peeq + 1, size - 1).erase(peeq + 5 + size - 1, 1),
               "step 0: the values are cut short");
  refuse_split(put<uint32_t>(split_values, peeq + 1, size + 1).insert(peeq + 5 + size, 1, '\0'),
               "step 0: the values leave bytes unread");
  size_t element = peeq;  // S_MISES_elem's step 1, past PEEQ's sections and its own errors
  for (size_t t = 0; t < b.mesh.step_count(); ++t) {
    std::memcpy(&size, split_values.data() + element + 1, 4);
    element += 5 + size;
  }
  element += 4 * 256;
  std::memcpy(&size, split_values.data() + element + 1, 4);
  element += 5 + size;
  refuse_split(put<uint8_t>(split_values, element, 1), "step 1: predictor 1 is not valid here");
  // A SPLT's FLDS that claims more than its counts allow: refused from its header.
  const std::string huge = bytes.substr(0, first) + chunk("FLDS", 1, 1u << 30, "xxxx");
  expect_refused_at(huge, first + 12, "the header's counts allow at most");
  // An FLDS where none may be, and FDEF's order kept.
  const size_t splt = chunks[4].second;
  expect_refused_at(bytes.substr(0, splt) + bytes.substr(first), splt, "unexpected chunk 'FLDS'");
  expect_refused_at(bytes.substr(0, first) + bytes.substr(splt), first,
                    "expected the FLDS chunk, found 'SPLT'");
}

// A lossless residual is a signed 32-bit value (FORMAT.md "Positions"): one beyond is refused
// where it is read, as dpm.js does, which could not add it exactly beyond 2^53 (a decoder
// disagreement found by differential fuzzing, docs/RELIABILITY.md finding 6).
TEST(ProgressiveFields, ALosslessResidualBeyond32BitsIsRefused) {
  const Built b = hat_rail_with_fields(true);
  const std::string bytes = encode_dpm(b.mesh).value();
  const auto chunks = chunks_of(bytes);
  ASSERT_EQ(chunks[3].first, "FLDS");
  const size_t base = chunks[3].second;
  const std::string values = raw_payload(bytes, base);
  const std::string rest = values.substr(8 + varint_length(values, 8));
  for (uint64_t zigzag : {uint64_t{1} << 32, uint64_t{1} << 60, ~uint64_t{0}})
    expect_refused_at(with_payload(bytes, base, values.substr(0, 8) + varint(zigzag) + rest),
                      base + 24, "a lossless residual outside 32 bits");
  // The base positions: the fuzzer's input, a residual above 2^53 in a lossless grid's BASE.
  auto mesh =
      read_dpm(test::source_dir() + "/fuzz/regressions/dpm/lossless-residual-beyond-2-53.dpm");
  ASSERT_FALSE(mesh.ok());
  EXPECT_NE(mesh.message().find("byte 220: a lossless residual outside 32 bits"), std::string::npos)
      << mesh.message();
}

TEST(ProgressiveFields, UnknownOptionalChunksAreSkipped) {
  const Built b = hat_rail_with_fields(false);
  const std::string bytes = encode_dpm(b.mesh).value();
  const auto chunks = chunks_of(bytes);
  const ProgressiveMesh plain = through_file(b.mesh);
  const std::string zzzz = chunk("ZZZZ", 0, 5, "hello");
  const std::string packed = chunk("NOT1", 1, 100, "not a zstd frame, never decompressed");
  // After HEAD, between a SPLT and its FLDS, and before END.
  for (size_t k : {size_t{1}, size_t{5}, chunks.size() - 1}) {
    SCOPED_TRACE(chunks[k].first + " after the insert");
    const size_t at = chunks[k].second;
    for (const std::string& extra : {zzzz, packed}) {
      auto r = decode_dpm(bytes.substr(0, at) + extra + bytes.substr(at), "optional.dpm");
      ASSERT_TRUE(r.ok()) << r.message();
      EXPECT_TRUE(r->complete);
      EXPECT_EQ(r->split_count(), plain.split_count());
      EXPECT_TRUE(r->fields[0].values == plain.fields[0].values);
      EXPECT_TRUE(r->fields[1].values == plain.fields[1].values);
    }
  }
  const size_t at = chunks[4].second;  // before the first SPLT
  auto insert = [&](const std::string& extra) {
    return bytes.substr(0, at) + extra + bytes.substr(at);
  };
  expect_refused_at(insert(chunk("ZZ\x01Z", 0, 5, "hello")), at, "unknown chunk tag");
  expect_refused_at(insert(chunk("zzzz", 0, 5, "hello")), at, "unknown chunk tag");
  std::string bad_sum = zzzz;
  bad_sum.back() = 'O';
  expect_refused_at(insert(bad_sum), at, "ZZZZ chunk checksum mismatch");
  expect_refused_at(insert(put<uint32_t>(zzzz, 20, 1)), at + 20, "reserved field is not 0");
  expect_refused_at(insert(put<uint32_t>(zzzz, 12, 6)), at + 12, "sizes differ");
  // Before HEAD it is not skipped, nor after END.
  expect_refused_at(bytes.substr(0, 12) + zzzz + bytes.substr(12), 12,
                    "expected the HEAD chunk, found 'ZZZZ'");
  expect_refused_at(bytes + zzzz, bytes.size(), "bytes after the END chunk");
}

TEST(ProgressiveFields, APrefixEndingInsideAnFldsHoldsTheLevelsBeforeItsSplt) {
  const Built b = hat_rail_with_fields(false);
  const std::string bytes = encode_dpm(b.mesh).value();
  const auto chunks = chunks_of(bytes);
  const ProgressiveMesh full = through_file(b.mesh);
  uint32_t splits_before = 0;
  for (size_t k = 4; chunks[k].first == "SPLT"; k += 2) {
    ASSERT_EQ(chunks[k + 1].first, "FLDS");
    // Cut inside the FLDS, and right after its SPLT.
    for (size_t cut : {chunks[k + 1].second + 30, chunks[k + 1].second}) {
      auto r = decode_dpm(bytes.substr(0, cut), "prefix.dpm");
      ASSERT_TRUE(r.ok()) << r.message();
      const ProgressiveMesh& m = *r;
      EXPECT_FALSE(m.complete);
      ASSERT_EQ(m.split_count(), splits_before);
      const uint32_t faces = m.face_count_after(m.split_count());
      EXPECT_EQ(m.vertex_original_index.size(), m.vertex_count());
      EXPECT_EQ(m.face_original_index.size(), faces);
      EXPECT_EQ(m.positions[0].size(), size_t{m.vertex_count()} * 3);
      EXPECT_EQ(m.fields[0].values[0].size(), m.vertex_count());
      EXPECT_EQ(m.fields[1].values[0].size(), faces);
      EXPECT_EQ(m.fields[0].error.size(), m.split_count());
      EXPECT_EQ(m.wing_start.size(), m.split_count() + 1);
      // What it holds is the complete file's.
      for (size_t t = 0; t < m.step_count(); ++t)
        for (uint32_t v = 0; v < m.vertex_count(); ++v)
          ASSERT_EQ(m.fields[0].values[t][v], full.fields[0].values[t][v]);
      Navigator nav(m);
      nav.set_level(m.split_count());
      std::vector<float> shown(faces);
      nav.field_values(1, m.step_count() - 1, shown);
      EXPECT_EQ(nav.field_error(1), m.split_count() == 0
                                        ? full.fields[1].base_error
                                        : full.fields[1].error[m.split_count() - 1]);
    }
    uint32_t count;
    std::memcpy(&count, raw_payload(bytes, chunks[k].second).data() + 4, 4);
    splits_before += count;
    if (k >= 8) break;  // three SPLTs are enough
  }
}

}  // namespace
}  // namespace dynpm
