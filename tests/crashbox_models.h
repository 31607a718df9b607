// The CalculiX crash boxes of ../shared/data built lossless by the command line, once per test
// run, and read back: the real data the selective refinement tests run on.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>

#include "dynpm/io.h"
#include "dynpm/lod.h"
#include "dynpm/pipeline.h"
#include "dynpm/progressive.h"
#include "fixtures.h"
#include "third_party.h"

namespace dynpm::test {

// The build's independent rounds (SimplifyOptions::independent_rounds): 0 unless
// DYNPM_TEST_ROUNDS gives a fraction, to measure the refinement of both hierarchies
// (docs/selective.md "Independent rounds").
inline double test_rounds() {
  const char* r = std::getenv("DYNPM_TEST_ROUNDS");
  return r ? std::atof(r) : 0.0;
}

struct CrashboxModel {
  std::string dpm;  // the built file
  ProgressiveMesh mesh;
};

// `name`: a folder of ../shared/data holding NAME.frd.gz (crashbox-s, crashbox-mixed-5k,
// crashbox-fields), built with independent rounds of `rounds` (DYNPM_TEST_ROUNDS's when
// negative). nullptr when the data is missing; a failed build fails the test.
inline const CrashboxModel* crashbox_model(const std::string& name, double rounds = -1) {
  static TempDir dir;
  static std::map<std::string, std::unique_ptr<CrashboxModel>> built;
  const std::string fraction = std::to_string(rounds < 0 ? test_rounds() : rounds);
  const std::string key = name + "-" + fraction;
  if (auto it = built.find(key); it != built.end()) return it->second.get();
  const std::string gz = shared_data() + "/" + name + "/" + name + ".frd.gz";
  const std::string frd = dir.file(name + ".frd"), dpm = dir.file(key + ".dpm");
  if (std::system(("zcat '" + gz + "' > '" + frd + "' 2>/dev/null").c_str()) != 0) return nullptr;
  const CommandResult r = run_command(std::string(DYNPM_CLI) + " build --lossless --rounds " +
                                      fraction + " '" + frd + "' -o '" + dpm + "'");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  auto mesh = read_dpm(dpm);
  EXPECT_TRUE(mesh.ok()) << mesh.message();
  if (r.exit_code != 0 || !mesh.ok()) return nullptr;
  auto model = std::make_unique<CrashboxModel>(CrashboxModel{dpm, std::move(mesh).value()});
  return (built[key] = std::move(model)).get();
}

// The crash box `name` cut into `bands` parts across its longest axis (by face centre at step
// 0), built lossless in memory: a multi-part model whose part boundaries the build must keep.
inline const ProgressiveMesh* crashbox_in_parts(const std::string& name, int bands) {
  static TempDir dir;
  static std::map<std::string, std::unique_ptr<ProgressiveMesh>> built;
  const std::string key = name + "/" + std::to_string(bands);
  if (auto it = built.find(key); it != built.end()) return it->second.get();
  const std::string gz = shared_data() + "/" + name + "/" + name + ".frd.gz";
  const std::string frd = dir.file(name + ".frd");
  if (std::system(("zcat '" + gz + "' > '" + frd + "' 2>/dev/null").c_str()) != 0) return nullptr;
  auto stream = open_input(std::vector<std::string>{frd});
  EXPECT_TRUE(stream.ok()) << stream.message();
  if (!stream.ok()) return nullptr;
  auto all = load_all_steps(std::move(stream).value());
  EXPECT_TRUE(all.ok()) << all.message();
  if (!all.ok()) return nullptr;
  Animation& a = *all;
  const auto xyz = a.frames.step(0);
  std::array<float, 3> lo{1e30f, 1e30f, 1e30f}, hi{-1e30f, -1e30f, -1e30f};
  for (size_t j = 0; j < xyz.size(); ++j) {
    lo[j % 3] = std::min(lo[j % 3], xyz[j]);
    hi[j % 3] = std::max(hi[j % 3], xyz[j]);
  }
  int axis = 0;
  for (int c = 1; c < 3; ++c)
    if (hi[c] - lo[c] > hi[axis] - lo[axis]) axis = c;
  for (size_t f = 0; f < a.topology.faces.size(); ++f) {
    const Face& face = a.topology.faces[f];
    double centre = 0;
    for (int k = 0; k < face.degree(); ++k) centre += xyz[size_t{face.v[k]} * 3 + axis];
    centre /= face.degree();
    const int band = static_cast<int>((centre - lo[axis]) / (hi[axis] - lo[axis]) * bands);
    a.topology.part_ids[f] = 1 + std::clamp(band, 0, bands - 1);
  }
  BuildOptions options;
  options.lossless = true;
  options.simplify.independent_rounds = test_rounds();
  auto pm = build_progressive_mesh(a.topology, a.frames, options);
  EXPECT_TRUE(pm.ok()) << pm.message();
  if (!pm.ok()) return nullptr;
  auto back = decode_dpm(encode_dpm(*pm).value(), key + ".dpm");
  EXPECT_TRUE(back.ok()) << back.message();
  if (!back.ok()) return nullptr;
  return (built[key] = std::make_unique<ProgressiveMesh>(std::move(back).value())).get();
}

// The read set under test: the default (the face creators) unless DYNPM_SPLIT_READS names
// another (fan, wing, written), to compare them (docs/selective.md "Which faces a split reads").
inline SplitReads test_reads() {
  const char* r = std::getenv("DYNPM_SPLIT_READS");
  const std::string name = r ? r : "creators";
  return name == "wing"      ? SplitReads::kWingEdges
         : name == "written" ? SplitReads::kWritten
         : name == "fan"     ? SplitReads::kFan
                             : SplitReads::kFaceCreators;
}

// The original's boundary loops, components and parts, which a refined mesh keeps.
struct PartsShape {
  size_t boundary_loops = 0, components = 0, parts = 0;
  bool operator==(const PartsShape&) const = default;
};
inline PartsShape parts_shape(const Topology& t) {
  const TopologyStats s = topology_stats(t, Adjacency::build(t));
  return {s.boundary_loops, s.components, s.parts};
}

}  // namespace dynpm::test

// Skips a test without the shared data.
#define DYNPM_CRASHBOX_OR_SKIP(var, name, ...)                        \
  const ::dynpm::test::CrashboxModel* var =                           \
      ::dynpm::test::crashbox_model(name __VA_OPT__(, ) __VA_ARGS__); \
  if (!var) GTEST_SKIP() << "../shared/data/" << name << " is missing"
