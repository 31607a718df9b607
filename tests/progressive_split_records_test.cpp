// The compact split records (src/progressive/split_records_coding.h): on real crash data every
// array comes back exactly through the records and attributes sections, chunk after chunk with
// the models continued; prepared errors are never below the true ones and never increase; and
// damaged sections are refused with a message, never a crash.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>

#include "dynpm/io.h"
#include "dynpm/pipeline.h"
#include "fixtures.h"
#include "progressive/index_sets.h"
#include "progressive/split_records_coding.h"
#include "round_trip.h"
#include "split_records_base.h"

namespace dynpm {
namespace {

using namespace progressive;

ProgressiveMesh build(const std::string& pattern) {
  auto paths = expand_inputs(std::vector<std::string>{pattern});
  EXPECT_TRUE(paths.ok()) << paths.message();
  auto a = read_animation(*paths);
  EXPECT_TRUE(a.ok()) << a.message();
  BuildOptions options;
  KeyStepRule rule;
  rule.kind = KeyStepRule::Kind::kPaper;
  auto keys = choose_key_steps(a->frames, rule);
  EXPECT_TRUE(keys.ok());
  options.simplify.key_steps = keys->steps;
  auto pm = build_progressive_mesh(a->topology, a->frames, options);
  EXPECT_TRUE(pm.ok()) << pm.message();
  return std::move(pm).value();
}

struct Section {
  uint32_t first, count;
  std::string records, attributes;
};

// The writer's chunks: 256 splits, then 512, … (docs/FORMAT.md "Layout").
std::vector<Section> encode(const ProgressiveMesh& pm) {
  std::vector<Section> out;
  RecordModels models(pm);
  for (uint32_t first = 0, n = 256; first < pm.split_count();
       first += n, n = std::min(2 * n, 16384u)) {
    const uint32_t last = std::min(pm.split_count(), first + n);
    auto s = encode_split_records(pm, first, last, models, {});
    EXPECT_TRUE(s.ok()) << s.message();
    if (!s.ok()) return {};
    out.push_back({first, last - first, s->first, s->second});
  }
  return out;
}

// Decodes sections in order; the first problem, or empty.
std::string decode(const std::vector<Section>& sections, ProgressiveMesh& m) {
  RecordModels models(m);
  for (const Section& s : sections)
    if (auto e = decode_split_records(s.records, s.attributes, s.first, s.count, m, models, {}))
      return e->what;
  return {};
}

TEST(SplitRecords, ErrorsOnTheGridAreNeverBelowTheTrueOnesAndNeverIncrease) {
  const ProgressiveMesh built = build(test::sample_dir() + "/frame_*.obj");
  ProgressiveMesh pm = built;
  prepare_split_records(pm);
  ASSERT_GE(pm.base_error, built.base_error);
  const double p = error_reference(pm.base_error);
  EXPECT_LE(pm.base_error, p);
  EXPECT_GT(pm.base_error, p / 2);
  double before = pm.base_error;
  for (uint32_t i = 0; i < pm.split_count(); ++i) {
    ASSERT_GE(pm.error[i], built.error[i]) << "split " << i;
    // At most one grid step (1/16 of an octave) above, unless below 2^-40 of P.
    if (built.error[i] > p * std::ldexp(1.0, -40)) {
      ASSERT_LE(pm.error[i], built.error[i] * (1 + 1.0 / 16)) << "split " << i;
    }
    ASSERT_LE(pm.error[i], before) << "split " << i;
    before = pm.error[i];
  }
  EXPECT_EQ(pm.error.back(), 0.0f);
  // Prepared once is prepared: the grid is the same and the values stay.
  ProgressiveMesh again = pm;
  prepare_split_records(again);
  EXPECT_EQ(again.error, pm.error);
  EXPECT_EQ(again.base_error, pm.base_error);
}

TEST(SplitRecords, EveryArrayComesBackOnRealCrashData) {
  const std::string data = test::shared_data();
  std::vector<std::string> patterns = {test::sample_dir() + "/frame_*.obj"};
  if (std::filesystem::exists(data))
    for (const char* p : {"/crashbox-s/obj/frame_*.obj", "/crashbox-mixed-5k/obj/frame_*.obj",
                          "/crashbox-fields/obj/frame_*.obj"})
      patterns.push_back(data + p);
  for (const std::string& pattern : patterns) {
    SCOPED_TRACE(pattern);
    ProgressiveMesh pm = build(pattern);
    prepare_split_records(pm);
    const auto sections = encode(pm);
    ASSERT_FALSE(sections.empty());
    ProgressiveMesh back = test::base_level_of(pm);
    ASSERT_EQ(decode(sections, back), "");
    test::expect_same_split_records(pm, back);
    // Version 1 took 19–21 B per vertex on these (zstd-compressed); this coding under 6.
    size_t bytes = 0;
    for (const Section& s : sections) bytes += s.records.size() + s.attributes.size();
    EXPECT_LT(double(bytes) / pm.full_vertex_count, 6.0);
  }
}

TEST(SplitRecords, DamagedSectionsAreRefusedWithAMessage) {
  ProgressiveMesh pm = build(test::sample_dir() + "/frame_*.obj");
  prepare_split_records(pm);
  const auto sections = encode(pm);
  ASSERT_GE(sections.size(), 2u);
  auto verdict = [&](auto damage) {
    auto s = sections;
    damage(s);
    ProgressiveMesh m = test::base_level_of(pm);
    return decode(s, m);
  };
  EXPECT_EQ(verdict([](auto& s) { s[0].records.pop_back(); }),
            "the split records section is cut short or damaged");
  EXPECT_EQ(verdict([](auto& s) { s[1].attributes.resize(s[1].attributes.size() / 2); }),
            "the split attributes section is cut short or damaged");
  EXPECT_EQ(verdict([](auto& s) { s[0].records.push_back('\0'); }),
            "bytes left over after the split records");
  EXPECT_EQ(verdict([](auto& s) { s[0].attributes.push_back('\0'); }),
            "bytes left over after the split attributes");
  EXPECT_EQ(verdict([](auto& s) { s.pop_back(); }), "");  // a prefix of the stream is valid
  // A chunk alone, without the models of the one before it, is not the same stream.
  EXPECT_NE(verdict([](auto& s) {
              s.erase(s.begin());
              s[0].first = 0;
            }),
            "");
  // Every byte of the first records section flipped: refused, or (rarely) another valid
  // stream; never a crash. Most are refused.
  size_t refused = 0, tried = 0;
  for (size_t k = 0; k < sections[0].records.size(); ++k, ++tried)
    refused += !verdict([k](auto& s) { s[0].records[k] ^= 0x5a; }).empty();
  EXPECT_GT(refused, tried * 9 / 10) << refused << " of " << tried;
}

// The free original indices against a plain list of flags: ranks both ways after every take, on
// sizes that end inside a word, inside a block and on a block's edge, with takes spread and
// clustered; and a set of 3 billion indices whose blocks with nothing taken cost no memory.
TEST(SplitRecords, FreeIndicesAnswerAsAListOfFlags) {
  std::mt19937 random(7);
  for (uint32_t n : {1u, 63u, 64u, 65u, 65535u, 65536u, 65537u, 200000u}) {
    SCOPED_TRACE(n);
    progressive::FreeIndices set(n);
    std::vector<uint8_t> free(n, 1);
    const auto check = [&] {
      uint32_t below = 0;
      for (uint32_t v = 0; v <= n; ++v) {
        if (v % 97 == 0 || v + 70 > n) {
          ASSERT_EQ(set.below(v), below) << "below " << v;
        }
        if (v < n && free[v]) {
          ASSERT_TRUE(set.is_free(v));
          if (below % 13 == 0 || below + 5 > set.count()) {
            ASSERT_EQ(set.nth(below), v);
          }
          ++below;
        } else if (v < n) {
          ASSERT_FALSE(set.is_free(v));
        }
      }
      ASSERT_EQ(set.count(), below);
      ASSERT_FALSE(set.is_free(n));
    };
    check();
    const uint32_t takes = std::min(n, 3000u);
    for (uint32_t k = 0; k < takes; ++k) {
      // Half at random, half next to the last one taken.
      uint32_t v = k % 2 ? random() % n : set.nth(std::min(k, set.count() - 1));
      if (!free[v]) v = set.nth(random() % set.count());
      set.take(v);
      free[v] = 0;
      if (k % 500 == 0) check();
    }
    check();
  }
  progressive::FreeIndices huge(3'000'000'000u);
  huge.take(2'999'999'999u);
  huge.take(5);
  EXPECT_EQ(huge.count(), 2'999'999'998u);
  EXPECT_EQ(huge.below(3'000'000'000u), 2'999'999'998u);
  EXPECT_EQ(huge.nth(5), 6u);
  EXPECT_EQ(huge.nth(2'999'999'997u), 2'999'999'998u);
  EXPECT_FALSE(huge.is_free(2'999'999'999u));
}

}  // namespace
}  // namespace dynpm
