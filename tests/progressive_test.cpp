// The progressive mesh: build → file → navigator gives the input back on every dataset; every
// level is a valid mesh and equals what the simplifier makes for that vertex count; prefixes of
// a file are coarser animations; damaged files are refused with the place named.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <random>

#include "dpm_chunks.h"
#include "dynpm/io.h"
#include "dynpm/lod.h"
#include "dynpm/pipeline.h"
#include "fixtures.h"
#include "round_trip.h"

namespace dynpm {
namespace {

Animation load(const std::string& pattern) {
  auto paths = expand_inputs(std::vector<std::string>{pattern});
  EXPECT_TRUE(paths.ok()) << paths.message();
  auto a = read_animation(*paths);
  EXPECT_TRUE(a.ok()) << a.message();
  return std::move(a).value();
}

ProgressiveMesh build(const Animation& a, bool lossless,
                      KeyStepRule::Kind rule = KeyStepRule::Kind::kAll) {
  BuildOptions options;
  options.lossless = lossless;
  KeyStepRule r;
  r.kind = rule;
  auto keys = choose_key_steps(a.frames, r);
  EXPECT_TRUE(keys.ok());
  options.simplify.key_steps = keys->steps;
  auto pm = build_progressive_mesh(a.topology, a.frames, options);
  EXPECT_TRUE(pm.ok()) << pm.message();
  return std::move(pm).value();
}

using test::chunk;
using test::chunks_of;
using test::expect_input_back;
using test::face_sets;
using test::through_file;

TEST(Progressive, HatRailRoundTripLosslessAndQuantized) {
  const Animation a = load(test::sample_dir() + "/frame_*.obj");
  for (bool lossless : {true, false}) {
    const ProgressiveMesh built = build(a, lossless);
    EXPECT_LT(built.base_vertex_count, a.topology.vertex_count / 20);
    expect_input_back(a, built);
    expect_input_back(a, through_file(built));
  }
}

TEST(Progressive, EverySharedDatasetComesBack) {
  const std::string data = test::shared_data();
  if (!std::filesystem::exists(data)) GTEST_SKIP() << "../shared/data is not beside the project";
  for (const char* pattern : {"/crashbox-s/obj/frame_*.obj", "/crashbox-mixed-5k/obj/frame_*.obj",
                              "/meshes/bunny.obj", "/meshes/fandisk.obj"}) {
    SCOPED_TRACE(pattern);
    const Animation a = load(data + pattern);
    const ProgressiveMesh built = build(a, false, KeyStepRule::Kind::kPaper);
    expect_input_back(a, through_file(built));
    if (a.step_count() > 1)
      expect_input_back(a, through_file(build(a, true, KeyStepRule::Kind::kPaper)));
  }
}

TEST(Progressive, EveryLevelIsValidAndIsTheSimplifiersMesh) {
  const Animation a = load(test::sample_dir() + "/frame_*.obj");
  const ProgressiveMesh pm = through_file(build(a, false));
  Navigator nav(pm);
  for (uint32_t k = 0; k <= pm.split_count(); ++k) {
    nav.set_level(k);
    const Topology t = nav.topology();
    const ValidationReport report = validate(t);
    ASSERT_TRUE(report.ok()) << "level " << k << ": " << report.problems.front().message;
    ASSERT_EQ(report.count(ProblemKind::kUnreferencedVertex), 0u) << "level " << k;
    ASSERT_EQ(t.vertex_count, pm.base_vertex_count + k);
    ASSERT_EQ(nav.face_count(), pm.face_count_after(k));
  }
  // The same level reached by other paths gives the same faces.
  std::mt19937 random(7);
  nav.set_level(pm.split_count());
  for (int jump = 0; jump < 50; ++jump) {
    const uint32_t k = random() % (pm.split_count() + 1);
    nav.set_level(k);
    Navigator fresh(pm);
    fresh.set_level(k);
    ASSERT_TRUE(std::equal(nav.faces().begin(), nav.faces().end(), fresh.faces().begin(),
                           fresh.faces().end()))
        << "level " << k;
  }
  nav.set_level(0);
  EXPECT_TRUE(std::equal(nav.faces().begin(), nav.faces().end(), pm.base_faces.begin(),
                         pm.base_faces.end()));

  // A level at the end of an error band is what the simplifier makes when stopped at that many
  // vertices: the build reorders the splits only within a band (src/pipeline/split_order.h),
  // so the levels inside one hold other splits.
  // A level whose stated error differs from the one before ends a band (inside a band they
  // state the error before it).
  auto band_end_from = [&](uint32_t vertices) {
    uint32_t k = vertices - pm.base_vertex_count;
    while (k < pm.split_count() && !(k > 0 && pm.level_error(k) != pm.level_error(k - 1))) ++k;
    return pm.base_vertex_count + k;
  };
  for (uint32_t n :
       {band_end_from(pm.base_vertex_count + 10), band_end_from(a.topology.vertex_count / 10),
        band_end_from(a.topology.vertex_count / 2)}) {
    SimplifyOptions options;
    options.target_vertices = n;
    auto s = simplify(a.topology, a.frames, options);
    ASSERT_TRUE(s.ok());
    nav.set_vertex_count(n);
    EXPECT_EQ(face_sets(nav.topology(), pm.vertex_original_index),
              face_sets(s->topology, s->original_vertex))
        << n << " vertices";
  }
}

TEST(Progressive, ErrorsPositionsAndGeomorphs) {
  const Animation a = load(test::sample_dir() + "/frame_*.obj");
  const ProgressiveMesh pm = through_file(build(a, true));
  for (uint32_t i = 1; i < pm.split_count(); ++i) ASSERT_LE(pm.error[i], pm.error[i - 1]);
  EXPECT_EQ(pm.error.back(), 0.0f);
  EXPECT_GE(pm.base_error, pm.error.front());
  Navigator nav(pm);
  for (double e : {pm.base_error * 2, pm.base_error / 3, pm.base_error / 100, 0.0}) {
    nav.set_error(e);
    EXPECT_LE(nav.error(), e);
    if (nav.level() > 0) {
      EXPECT_GT(pm.level_error(nav.level() - 1), e);
    }
  }

  nav.set_level(pm.split_count() / 2);
  const size_t n = size_t{nav.vertex_count()} * 3;
  std::vector<float> p2(n), p3(n), half(n), morph(n);
  nav.positions(2, p2);
  nav.positions(3, p3);
  nav.positions(2.5, half);
  for (size_t j = 0; j < n; ++j) ASSERT_FLOAT_EQ(half[j], p2[j] + 0.5f * (p3[j] - p2[j]));

  const uint32_t from = pm.split_count() / 4;
  nav.geomorph(from, 1.0, 3, morph);
  EXPECT_EQ(morph, p3);
  nav.geomorph(from, 0.0, 3, morph);
  for (uint32_t v = 0; v < nav.vertex_count(); ++v) {
    const uint32_t u = nav.ancestor(v, from);
    ASSERT_LT(u, pm.base_vertex_count + from);
    for (int c = 0; c < 3; ++c) ASSERT_EQ(morph[size_t{v} * 3 + c], p3[size_t{u} * 3 + c]);
  }
}

TEST(Progressive, EveryPrefixIsACoarserAnimation) {
  const Animation a = load(test::sample_dir() + "/frame_*.obj");
  const ProgressiveMesh full = build(a, false);
  const std::string bytes = encode_dpm(full).value();
  const ProgressiveMesh whole = through_file(full);
  uint32_t previous = 0;
  for (double fraction : {0.1, 0.5, 0.9}) {
    SCOPED_TRACE(fraction);
    auto prefix = decode_dpm(std::string_view(bytes).substr(0, size_t(bytes.size() * fraction)),
                             "prefix.dpm");
    ASSERT_TRUE(prefix.ok()) << prefix.message();
    EXPECT_FALSE(prefix->complete);
    EXPECT_GE(prefix->split_count(), previous);
    EXPECT_LT(prefix->split_count(), full.split_count());
    previous = prefix->split_count();
    Navigator nav(*prefix);
    nav.set_level(prefix->split_count());
    EXPECT_TRUE(validate(nav.topology()).ok());
    for (size_t t = 0; t < prefix->step_count(); ++t)
      ASSERT_TRUE(std::equal(prefix->positions[t].begin(), prefix->positions[t].end(),
                             whole.positions[t].begin()));
  }
  EXPECT_GT(previous, 0u);
  auto too_short = decode_dpm(std::string_view(bytes).substr(0, 40), "short.dpm");
  ASSERT_FALSE(too_short.ok());
  EXPECT_NE(too_short.message().find("short.dpm: byte"), std::string::npos) << too_short.message();
}

TEST(Progressive, DamagedFilesAreRefusedWithThePlace) {
  const Animation a = load(test::sample_dir() + "/frame_00*.obj");
  const std::string bytes = encode_dpm(build(a, false)).value();
  std::string damaged = bytes;
  damaged[bytes.size() / 2] ^= 0x40;
  auto r = decode_dpm(damaged, "damaged.dpm");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("checksum"), std::string::npos) << r.message();
  EXPECT_NE(r.message().find("damaged.dpm: byte "), std::string::npos) << r.message();
  auto wrong = decode_dpm("hello, this is not a dpm file at all", "text.dpm");
  ASSERT_FALSE(wrong.ok());
  EXPECT_NE(wrong.message().find("not a .dpm file"), std::string::npos);
  std::string future = bytes;
  future[8] = 8;
  EXPECT_NE(
      decode_dpm(future, "v8.dpm").message().find("v8.dpm: byte 8: version 8 is not supported"),
      std::string::npos);
  // Versions 1 to 5 coded SPLT differently, version 6 FLDS (docs/FORMAT.md): refused with what
  // to do about it.
  for (char version : {1, 2, 3, 4, 5, 6}) {
    std::string old = bytes;
    old[8] = version;
    const std::string name = "v" + std::to_string(version) + ".dpm";
    EXPECT_EQ(decode_dpm(old, name).message(), name +
                                                   ": byte 8: written by an older dynpm (version " +
                                                   std::to_string(version) + "): build it again");
  }
  std::string trailing = bytes + "x";
  EXPECT_FALSE(decode_dpm(trailing, "trailing.dpm").ok());
  // Every single-byte cut of the header region is an error or a prefix, never a crash.
  for (size_t cut = 0; cut < std::min<size_t>(bytes.size(), 400); ++cut) {
    auto p = decode_dpm(std::string_view(bytes).substr(0, cut), "cut.dpm");
    if (p.ok()) {
      EXPECT_FALSE(p->complete);
    }
  }
}

// Node and element ids lie strictly within ±2^51 (FORMAT.md "BASE payload"), so that dpm.js
// holds them exactly and no reader's sum overflows: ids just inside come back (base and split
// vertices, a created face), the writer refuses one outside, and the reader refuses a BASE whose
// deltas overflowed int64 before (undefined behaviour: fuzz/regressions/dpm/
// base-node-id-overflow.dpm, made by hand).
TEST(Progressive, IdsWithinTwoToThe51ComeBackAndOthersAreRefused) {
  const Animation a = load(test::sample_dir() + "/frame_00*.obj");
  ProgressiveMesh pm = build(a, false);
  const int64_t limit = int64_t{1} << 51;
  pm.node_ids[0] = limit - 1;  // against 0
  pm.node_ids[1] = 1 - limit;  // a delta of 2 − 2^52
  pm.node_ids.back() = 1 - limit;
  pm.element_ids.back() = limit - 1;
  const ProgressiveMesh back = through_file(pm);
  EXPECT_EQ(back.node_ids, pm.node_ids);
  EXPECT_EQ(back.element_ids, pm.element_ids);
  pm.node_ids.back() = limit;
  auto refused = encode_dpm(pm);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.message().find("node id 2251799813685248 is not within ±2^51"),
            std::string::npos)
      << refused.message();
  auto mesh = read_dpm(test::source_dir() + "/fuzz/regressions/dpm/base-node-id-overflow.dpm");
  ASSERT_FALSE(mesh.ok());
  EXPECT_NE(mesh.message().find("byte 220: an id is not within ±2^51"), std::string::npos)
      << mesh.message();
}

// A SPLT is sections (docs/FORMAT.md "SPLT payload"): 2 + m of them, their sizes adding up to the
// payload, each range-coded one decoded to its last byte.
TEST(Progressive, SplitSectionsAreReadToTheirLastByte) {
  const Animation a = load(test::sample_dir() + "/frame_00*.obj");
  const std::string bytes = encode_dpm(build(a, false)).value();
  const auto chunks = chunks_of(bytes);
  ASSERT_EQ(chunks[2].first, "SPLT");
  const size_t at = chunks[2].second, next = chunks[3].second;
  std::string payload = bytes.substr(at + 24, next - at - 24);
  uint32_t count, last_size;
  std::memcpy(&count, payload.data() + 8, 4);
  EXPECT_EQ(count, 2 + a.step_count());
  std::memcpy(&last_size, payload.data() + 12 + 4 * (count - 1), 4);
  // The SPLT with its payload changed, and what the reader must say about it.
  const auto refused = [&](std::string changed, const std::string& why) {
    const std::string file = bytes.substr(0, at) +
                             chunk("SPLT", 0, uint32_t(changed.size()), changed) +
                             bytes.substr(next);
    auto r = decode_dpm(file, "s.dpm");
    ASSERT_FALSE(r.ok()) << why;
    EXPECT_NE(r.message().find("s.dpm: byte " + std::to_string(at + 24) + ": " + why),
              std::string::npos)
        << r.message();
  };
  std::string p = payload;
  p[8] = char(count + 1);
  refused(p, "the SPLT does not have 2 + " + std::to_string(a.step_count()) + " sections");
  refused(payload + "x", "the SPLT's section sizes do not add up to its payload");
  // The last step's positions with a byte more, and with a byte less.
  const auto resized = [&](int delta) {
    std::string q = payload;
    const uint32_t size = last_size + uint32_t(delta);
    std::memcpy(q.data() + 12 + 4 * (count - 1), &size, 4);
    return delta > 0 ? q + std::string(size_t(delta), '\0') : q.substr(0, q.size() - 1);
  };
  refused(resized(1), "the positions of step " + std::to_string(count - 3) + " leave bytes unread");
  refused(resized(-1), "the positions of step " + std::to_string(count - 3) + " are cut short");
}

// A zstd frame (RFC 8878) declaring `declared` bytes and holding `held` zero bytes in RLE blocks.
std::string zstd_zeros(uint64_t declared, uint64_t held) {
  std::string f = "\x28\xb5\x2f\xfd\xc0\x38";  // magic; 8-byte content size; 128 KiB window
  f.append(reinterpret_cast<const char*>(&declared), 8);
  while (held > 0) {
    const uint32_t size = uint32_t(std::min<uint64_t>(held, 1 << 17));
    held -= size;
    const uint32_t header = (size << 3) | (1 << 1) | (held == 0 ? 1 : 0);  // an RLE block
    f.append(reinterpret_cast<const char*>(&header), 3);
    f.push_back('\0');
  }
  return f;
}

// Chunk sizes are checked against HEAD's counts and against what the frame holds before any
// memory is taken for them (a 64 KiB BASE of 2^31 zero bytes took 2.1 GB: tests/bad/bomb-base.dpm).
TEST(Progressive, ChunkSizesAreBoundedBeforeAllocating) {
  const Animation a = load(test::sample_dir() + "/frame_00*.obj");
  const std::string bytes = encode_dpm(build(a, false)).value();
  const auto chunks = chunks_of(bytes);
  ASSERT_GE(chunks.size(), 4u);
  ASSERT_EQ(chunks[2].first, "SPLT");
  const size_t splt = chunks[2].second, end = chunks.back().second;
  // A SPLT chunk of 2^31 zero bytes in 64 KiB.
  const std::string bomb =
      bytes.substr(0, splt) + chunk("SPLT", 1, 1u << 31, zstd_zeros(1u << 31, 1u << 31));
  auto r = decode_dpm(bomb, "bomb.dpm");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("bomb.dpm: byte " + std::to_string(splt + 12) +
                             ": the SPLT chunk claims 2147483648 bytes; the header's counts "
                             "allow at most"),
            std::string::npos)
      << r.message();
  // A frame that declares 256 KiB and holds 128 KiB: refused once it runs dry.
  const std::string liar =
      bytes.substr(0, splt) + chunk("SPLT", 1, 1u << 18, zstd_zeros(1u << 18, 1u << 17));
  r = decode_dpm(liar, "liar.dpm");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("cannot decompress the SPLT chunk"), std::string::npos) << r.message();
  // HEAD and END are never compressed.
  const std::string packed_end = bytes.substr(0, end) + chunk("END ", 1, 1u << 30, "");
  r = decode_dpm(packed_end, "end.dpm");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("a compressed END  chunk"), std::string::npos) << r.message();
}

// HEAD's numbers are finite: a NaN error bound or time would reach every report as "nan".
TEST(Progressive, HeaderNumbersAreFinite) {
  const Animation a = load(test::sample_dir() + "/frame_00*.obj");
  const std::string bytes = encode_dpm(build(a, false)).value();
  const auto chunks = chunks_of(bytes);
  ASSERT_EQ(chunks[0].first, "HEAD");
  const size_t head = chunks[0].second, payload = head + 24;
  uint32_t stored;
  std::memcpy(&stored, bytes.data() + head + 8, 4);
  // max_error after 8 counts, two corners and the grid step; the first time after base_error.
  for (const size_t field : {size_t{8 * 4 + 7 * 8}, size_t{8 * 4 + 9 * 8}}) {
    std::string head_bytes = bytes.substr(payload, stored);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::memcpy(head_bytes.data() + field, &nan, 8);
    const std::string damaged = bytes.substr(0, head) + chunk("HEAD", 0, stored, head_bytes) +
                                bytes.substr(payload + stored);
    auto r = decode_dpm(damaged, "nan.dpm");
    ASSERT_FALSE(r.ok()) << "field at " << field;
    EXPECT_NE(r.message().find("not finite"), std::string::npos) << r.message();
  }
}

// A source with one per-vertex field, to check fields travel through the file.
class WithField final : public FrameSource {
 public:
  explicit WithField(const Frames& frames) : frames_(frames) {}
  uint32_t vertex_count() const override { return frames_.vertex_count(); }
  size_t step_count() const override { return frames_.step_count(); }
  double step_time(size_t t) const override { return frames_.step_time(t); }
  Status read_step(size_t t, std::span<float> out) const override {
    return frames_.read_step(t, out);
  }
  std::vector<FieldInfo> fields() const override { return {{"PEEQ", FieldLocation::kNode, {}}}; }
  Status read_field(size_t, size_t t, std::span<float> out) const override {
    for (size_t v = 0; v < out.size(); ++v) out[v] = float(v) * 0.001f + float(t);
    return {};
  }

 private:
  const Frames& frames_;
};

TEST(Progressive, FieldsTravelWithTheirVertices) {
  const Animation a = load(test::sample_dir() + "/frame_00*.obj");
  WithField source(a.frames);
  auto pm = build_progressive_mesh(a.topology, source, BuildOptions{});
  ASSERT_TRUE(pm.ok()) << pm.message();
  const ProgressiveMesh back = through_file(*pm);
  ASSERT_EQ(back.fields.size(), 1u);
  ASSERT_EQ(back.fields[0].info.name, "PEEQ");
  const double bound = back.fields[0].max_error;
  ASSERT_GT(bound, 0);
  for (size_t t = 0; t < back.step_count(); ++t)
    for (uint32_t v = 0; v < back.vertex_count(); ++v)
      ASSERT_NEAR(back.fields[0].values[t][v],
                  float(back.vertex_original_index[v]) * 0.001f + float(t), bound * 1.0001);
}

TEST(Progressive, OptimalPlacementIsRefused) {
  const Animation a = load(test::sample_dir() + "/frame_000.obj");
  BuildOptions options;
  options.simplify.placement = Placement::kOptimal;
  auto pm = build_progressive_mesh(a.topology, a.frames, options);
  ASSERT_FALSE(pm.ok());
  EXPECT_NE(pm.message().find("half-edge"), std::string::npos);
}

}  // namespace
}  // namespace dynpm
