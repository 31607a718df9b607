// LS-DYNA d3plot reader: the shared LS-DYNA results (qd-cae's and lasso-python's test files),
// cut copies of them, and small families written here from the format description in single and
// double precision, both byte orders, with a state that runs on into the next file.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "dynpm/io.h"
#include "fixtures.h"
#include "reading.h"

namespace dynpm {
namespace {

using test::field;
using test::open;
using test::Opened;
using test::step;

namespace fs = std::filesystem;

std::string d3plot_dir() { return test::shared_data() + "/external/d3plot"; }

void copy_cut(const std::string& from, const std::string& to, size_t bytes) {
  std::ifstream in(from, std::ios::binary);
  std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  data.resize(std::min(bytes, data.size()));
  std::ofstream(to, std::ios::binary).write(data.data(), std::streamsize(data.size()));
}

// qd-cae's test result: a flat tensile specimen ("Zugprobe"), 4,915 nodes, 4,696 four-node
// shells in one part, and a single state (time 0) in the continuation file qd_d3plot01.
TEST(D3plotTest, QdCountsIdsAndGeometry) {
  const std::string path = d3plot_dir() + "/qd_d3plot";
  auto format = detect_format(path);  // by its control block: the name does not start "d3plot"
  ASSERT_TRUE(format.ok()) << format.message();
  EXPECT_EQ(*format, FileFormat::kD3plot);
  Opened r = open(path);
  ASSERT_TRUE(r.stream.ok()) << r.stream.message();
  const Topology& top = r.stream->topology;
  EXPECT_EQ(top.vertex_count, 4915u);
  EXPECT_EQ(top.faces.size(), 4696u);
  EXPECT_EQ(top.quad_count(), 4696u);
  EXPECT_EQ(top.parts(), std::vector<int32_t>{1});
  // User numbers from the NARBS section: nodes 1, 2, 246, … 5321; shells 1 … 4696.
  EXPECT_EQ(top.node_ids[0], 1);
  EXPECT_EQ(top.node_ids[2], 246);
  EXPECT_EQ(top.node_ids.back(), 5321);
  EXPECT_EQ(top.element_ids.front(), 1);
  EXPECT_EQ(top.element_ids.back(), 4696);
  EXPECT_TRUE(validate(top, r.stream->frames.get()).ok());

  ASSERT_EQ(r.stream->frames->step_count(), 1u);
  EXPECT_EQ(r.stream->frames->step_time(0), 0.0);
  const auto xyz = step(*r.stream, 0);
  BoundingBox box;
  box.extend(xyz);
  for (float x : xyz) ASSERT_TRUE(std::isfinite(x));
  // The specimen lies in the x-z plane: 34 wide, 66.7 long.
  EXPECT_NEAR(box.min[0], -17.0, 1e-3);
  EXPECT_NEAR(box.max[0], 17.0, 1e-3);
  EXPECT_NEAR(box.max[1] - box.min[1], 0.0, 1e-3);
  EXPECT_NEAR(box.max[2], 33.3606, 1e-3);
  // IV is set: the velocity magnitude is a node field (the shell results follow it).
  const auto names = r.stream->frames->field_names();
  ASSERT_EQ(names.front(), "|V|");
  std::vector<float> speed(top.vertex_count);
  ASSERT_TRUE(r.stream->frames->read_field(0, 0, speed).ok());
  EXPECT_NEAR(*std::max_element(speed.begin(), speed.end()), 0.25, 1e-4);
}

// The state is in the family's second file: without it, the geometry is the only step.
TEST(D3plotTest, QdFamilyContinuation) {
  test::TempDir dir;
  fs::copy_file(d3plot_dir() + "/qd_d3plot", dir.file("d3plot"));
  Opened alone = open(dir.file("d3plot"));
  ASSERT_TRUE(alone.stream.ok()) << alone.stream.message();
  EXPECT_EQ(alone.stream->frames->step_count(), 1u);
  ASSERT_FALSE(alone.warnings.empty());
  EXPECT_NE(alone.warnings.back().find("holds no state"), std::string::npos);

  fs::copy_file(d3plot_dir() + "/qd_d3plot01", dir.file("d3plot01"));
  Opened both = open(dir.file("d3plot"));
  ASSERT_TRUE(both.stream.ok()) << both.stream.message();
  EXPECT_TRUE(both.warnings.empty());
  std::vector<float> speed(both.stream->topology.vertex_count);
  ASSERT_TRUE(both.stream->frames->read_field(0, 0, speed).ok());
  EXPECT_GT(*std::max_element(speed.begin(), speed.end()), 0.2f);  // read from d3plot01
}

// A family with a hole: d3plot02 without d3plot01 is a lost file, not the family's end. Read on
// from d3plot alone, the run would silently lose every state.
TEST(D3plotTest, MissingMiddleFileOfAFamilyIsAnError) {
  test::TempDir dir;
  fs::copy_file(d3plot_dir() + "/qd_d3plot", dir.file("d3plot"));
  fs::copy_file(d3plot_dir() + "/qd_d3plot01", dir.file("d3plot02"));
  Opened r = open(dir.file("d3plot"));
  ASSERT_FALSE(r.stream.ok()) << "read with " << r.stream->frames->step_count() << " steps";
  EXPECT_EQ(r.stream.message(), dir.file("d3plot01") + ": missing from the d3plot family (" +
                                    dir.file("d3plot02") +
                                    " follows it): a family must be complete, or its states from "
                                    "there on are lost");
  // Names that only look like members do not count: d3plot2 (one digit), d3plot_old.
  fs::rename(dir.file("d3plot02"), dir.file("d3plot2"));
  std::ofstream(dir.file("d3plot_old")) << "x";
  Opened alone = open(dir.file("d3plot"));
  EXPECT_TRUE(alone.stream.ok()) << alone.stream.message();
}

// lasso-python's thermal test result: 2,185 nodes, 2,075 shells (12 of them triangles: a
// repeated 4th node), 23 states over 20 s, no coordinates in the states (IU = 0).
TEST(D3plotTest, LassoNodeTemperature) {
  Opened r = open(d3plot_dir() + "/lasso_d3plot_node_temperature_d3plot");
  ASSERT_TRUE(r.stream.ok()) << r.stream.message();
  const Topology& top = r.stream->topology;
  EXPECT_EQ(top.vertex_count, 2185u);
  EXPECT_EQ(top.faces.size(), 2075u);
  EXPECT_EQ(top.triangle_count(), 12u);
  EXPECT_EQ(top.parts(), std::vector<int32_t>{1000000});  // NORDER: the part's user id
  EXPECT_EQ(top.node_ids.front(), 100001);
  const FrameSource& frames = *r.stream->frames;
  ASSERT_EQ(frames.step_count(), 23u);
  EXPECT_EQ(frames.step_time(0), 0.0);
  EXPECT_NEAR(frames.step_time(1), 0.2, 1e-6);
  EXPECT_NEAR(frames.step_time(22), 20.0, 1e-5);
  EXPECT_EQ(step(*r.stream, 22), step(*r.stream, 0));

  const auto names = frames.field_names();
  ASSERT_GE(names.size(), 1u);
  EXPECT_EQ(names[0], "temperature");
  std::vector<float> first(top.vertex_count), last(top.vertex_count);
  ASSERT_TRUE(frames.read_field(0, 0, first).ok());
  ASSERT_TRUE(frames.read_field(0, 22, last).ok());
  for (float t : first) EXPECT_NEAR(t, 1423.15, 0.01);  // uniform start temperature
  EXPECT_NEAR(*std::min_element(last.begin(), last.end()), 1297.08, 0.05);  // cooled
  EXPECT_NEAR(*std::max_element(last.begin(), last.end()), 1423.15, 0.05);
  test::expect_parallel_reads_agree(*r.stream);  // 23 states across two files, on 4 threads
}

TEST(D3plotTest, BeamsOnlyIsAClearError) {
  Opened r = open(d3plot_dir() + "/lasso_d3plot_beamip_d3plot");
  ASSERT_FALSE(r.stream.ok());
  EXPECT_NE(r.stream.message().find("no shell faces"), std::string::npos) << r.stream.message();
  EXPECT_NE(r.stream.message().find("1 beams"), std::string::npos) << r.stream.message();
}

// 16 solids and 16 shells in 4 parts, geometry only: the solids give their outer faces.
TEST(D3plotTest, SolidsGiveTheirOuterFaces) {
  Opened r = open(d3plot_dir() + "/lasso_d3plot_solid_int_d3plot");
  ASSERT_TRUE(r.stream.ok()) << r.stream.message();
  const Topology& top = r.stream->topology;
  EXPECT_EQ(top.faces.size(), 16u + 56u);
  EXPECT_EQ(top.parts(), (std::vector<int32_t>{1000, 2000, 3000, 4000}));
  EXPECT_EQ(r.stream->frames->step_count(), 1u);  // no state: the geometry
  bool told = false;
  for (const auto& w : r.warnings) told |= w.find("outer faces") != std::string::npos;
  EXPECT_TRUE(told);
}

TEST(D3plotTest, TruncatedFilesAreErrors) {
  const std::string first = d3plot_dir() + "/qd_d3plot", second = d3plot_dir() + "/qd_d3plot01";
  // Cuts in the control block, the coordinates, the shells and the user numbers.
  for (size_t cut :
       {size_t{0}, size_t{10}, size_t{200}, size_t{30000}, size_t{100000}, size_t{191000}}) {
    test::TempDir dir;
    copy_cut(first, dir.file("d3plot"), cut);
    fs::copy_file(second, dir.file("d3plot01"));
    Opened r = open(dir.file("d3plot"));
    ASSERT_FALSE(r.stream.ok()) << "cut at " << cut;
    EXPECT_NE(r.stream.message().find("byte"), std::string::npos) << r.stream.message();
  }
  // Cuts inside the state.
  for (size_t cut : {size_t{3}, size_t{1000000}, size_t{2111000}, size_t{2111001}}) {
    test::TempDir dir;
    fs::copy_file(first, dir.file("d3plot"));
    copy_cut(second, dir.file("d3plot01"), cut);
    Opened r = open(dir.file("d3plot"));
    ASSERT_FALSE(r.stream.ok()) << "cut at " << cut;
    EXPECT_NE(r.stream.message().find("cut short"), std::string::npos) << r.stream.message();
  }
  // Cut right after the state (the end marker and padding gone): still complete.
  test::TempDir dir;
  fs::copy_file(first, dir.file("d3plot"));
  copy_cut(second, dir.file("d3plot01"), 527937 * 4);
  Opened r = open(dir.file("d3plot"));
  ASSERT_TRUE(r.stream.ok()) << r.stream.message();
  EXPECT_EQ(r.stream->frames->step_count(), 1u);
}

// ---------------------------------------------------------------------------------------------
// Families written from the format description.

// A word of a d3plot: an integer, a real, or raw text (part titles are 72 bytes in any
// precision).
struct Word {
  enum Kind { kInteger, kReal, kText } kind;
  int64_t integer = 0;
  double real = 0;
  const char* text = nullptr;                      // a string that outlives the word
  Word(int64_t i) : kind(kInteger), integer(i) {}  // NOLINT: implicit on purpose
  Word(double r) : kind(kReal), real(r) {}         // NOLINT: implicit on purpose
  Word(const char* t) : kind(kText), text(t) {}    // NOLINT: implicit on purpose
};

struct Encoding {
  int size;  // 4 or 8
  bool big_endian;
};

std::string encode(const std::vector<Word>& words, Encoding e) {
  std::string out;
  auto put = [&](uint64_t bits) {
    char b[8];
    for (int i = 0; i < e.size; ++i) {
      const int shift = 8 * (e.big_endian ? e.size - 1 - i : i);
      b[i] = static_cast<char>((bits >> shift) & 0xff);
    }
    out.append(b, size_t(e.size));
  };
  for (const Word& w : words) {
    if (w.kind == Word::kInteger)
      put(e.size == 4 ? uint64_t(uint32_t(int32_t(w.integer))) : uint64_t(w.integer));
    else if (w.kind == Word::kReal)
      put(e.size == 4 ? uint64_t(std::bit_cast<uint32_t>(float(w.real)))
                      : std::bit_cast<uint64_t>(w.real));
    else
      out += w.text;
  }
  return out;
}

// Two quads and a triangle (stored as a quad with a repeated 4th node) over 6 nodes:
//   3---4---5
//   |   |   |      shells 11 (0 1 4 3) and 12 (1 2 5 4), and 13 (1 2 5 5): a triangle on top
//   0---1---2      of shell 12, enough for the reader (faces are not validated here)
// with node ids 101…106, part id 42, and `states` states in which the nodes move by +t·0.5 in
// z and the temperature is 20 + node index + t. Each shell writes 3 integration points (mid,
// bottom, top) of 6 stresses and the plastic strain, then thickness and 3 more words (IOSHL
// 1000 1000 999 1000: NV2D = 3 × 7 + 4 = 25); see shell_value().
struct Synthetic {
  std::vector<Word> geometry;  // control block, geometry, titles
  std::vector<std::vector<Word>> states;
};

// Word `word` of integration point `point` (0 mid, 1 bottom, 2 top) of shell e at state t:
// σxx = 100·(point + 1) + 10·e + t, σxy = 5, the rest 0 (von Mises √(σxx² + 75)); plastic
// strain 0.01·t·(point + 1) + 0.001·e, growing with t.
double shell_value(int t, int e, int point, int word) {
  if (word == 0) return 100.0 * (point + 1) + 10.0 * e + t;
  if (word == 3) return 5.0;
  if (word == 6) return 0.01 * t * (point + 1) + 0.001 * e;
  return 0.0;
}

Synthetic synthetic(int states) {
  Synthetic s;
  auto& g = s.geometry;
  const int64_t numnp = 6, nel4 = 3, nv2d = 25;
  for (int i = 0; i < 10; ++i) g.push_back(int64_t{0x20202020});  // title: blanks
  const int64_t narbs = 10 + numnp + nel4 + 3;
  const std::vector<int64_t> control = {0,
                                        1,
                                        0,
                                        0,
                                        -1 /* version: real, set below */,
                                        4,
                                        numnp,
                                        6,
                                        1 /* nglbv */,
                                        1 /* it */,
                                        1 /* iu */,
                                        0,
                                        0,
                                        0 /* nel8 */,
                                        0,
                                        0,
                                        0,
                                        0,
                                        0 /* nel2 */,
                                        0,
                                        0,
                                        nel4,
                                        1,
                                        nv2d,
                                        0,
                                        0,
                                        -10000 - 3 /* maxint: element deletion */,
                                        0,
                                        0,
                                        narbs,
                                        0,
                                        0,
                                        0,
                                        1000 /* IOSHL(1): stresses */,
                                        1000 /* IOSHL(2): plastic strain */,
                                        999 /* IOSHL(3): no resultants */,
                                        1000 /* IOSHL(4): thickness, energy */,
                                        0,
                                        0,
                                        0,
                                        0,
                                        1 /* nmmat */,
                                        0,
                                        0,
                                        0,
                                        0,
                                        0,
                                        0 /* extra */};
  for (int64_t v : control) g.push_back(v);
  g[14] = 960.0;
  while (g.size() < 64) g.push_back(int64_t{0});
  const double xy[6][2] = {{0, 0}, {1, 0}, {2, 0}, {0, 1}, {1, 1}, {2, 1}};
  for (auto& p : xy) g.insert(g.end(), {p[0], p[1], 0.0});
  // Four nodes and a material number each, 1-based; the third repeats its last node.
  const int64_t shells[3][5] = {{1, 2, 5, 4, 1}, {2, 3, 6, 5, 1}, {2, 3, 6, 6, 1}};
  for (auto& sh : shells)
    for (int64_t v : sh) g.push_back(v);
  // User numbers: NSORT > 0 and a 10-word header, nodes, shells, then NORDER NSRMU NSRMP.
  g.insert(g.end(), {int64_t{1}, int64_t{7}, int64_t{7}, int64_t{7}, int64_t{10}, numnp, int64_t{0},
                     int64_t{0}, nel4, int64_t{0}});
  for (int64_t i = 0; i < numnp; ++i) g.push_back(101 + i);
  for (int64_t i = 0; i < nel4; ++i) g.push_back(11 + i);
  g.insert(g.end(), {int64_t{42}, int64_t{42}, int64_t{1}});
  // Part titles behind an end marker.
  g.push_back(-999999.0);
  g.insert(g.end(), {int64_t{90001}, int64_t{1}, int64_t{42}});
  static const std::string title = "synthetic part" + std::string(58, ' ');  // 72 bytes
  g.push_back(title.c_str());
  g.push_back(-999999.0);

  for (int t = 0; t < states; ++t) {
    std::vector<Word> st{double(t) * 0.25, 1.5 /* kinetic energy */};
    for (auto& p : xy) st.insert(st.end(), {p[0], p[1], 0.5 * t});
    for (int i = 0; i < numnp; ++i) st.push_back(20.0 + i + t);
    for (int e = 0; e < nel4; ++e) {
      for (int point = 0; point < 3; ++point)
        for (int word = 0; word < 7; ++word) st.push_back(shell_value(t, e, point, word));
      st.insert(st.end(), {2.0 - 0.1 * t /* thickness */, 0.0, 0.0, 0.0});
    }
    for (int i = 0; i < nel4; ++i) st.push_back(1.0);  // deletion flags: element alive
    s.states.push_back(std::move(st));
  }
  return s;
}

// Writes the family: the geometry file padded to 512 words as LS-DYNA does, then the states
// split into two files at a word in the middle of state 1 (a state running into the next file).
void write_family(const Synthetic& s, Encoding e, const test::TempDir& dir) {
  std::string geometry = encode(s.geometry, e);
  geometry.resize((geometry.size() + 512 * e.size - 1) / (512 * e.size) * (512 * e.size), '\0');
  std::string states;
  for (const auto& st : s.states) states += encode(st, e);
  states += encode({-999999.0}, e);
  const size_t split = (s.states[0].size() + 7) * e.size;
  std::ofstream(dir.file("d3plot"), std::ios::binary) << geometry;
  std::ofstream(dir.file("d3plot01"), std::ios::binary) << states.substr(0, split);
  std::ofstream(dir.file("d3plot02"), std::ios::binary) << states.substr(split);
}

TEST(D3plotTest, SyntheticFamiliesInEveryEncoding) {
  for (Encoding e :
       {Encoding{4, false}, Encoding{4, true}, Encoding{8, false}, Encoding{8, true}}) {
    SCOPED_TRACE(std::to_string(e.size) + "-byte words, " + (e.big_endian ? "big" : "little") +
                 " endian");
    test::TempDir dir;
    write_family(synthetic(3), e, dir);
    Opened r = open(dir.file("d3plot"));
    ASSERT_TRUE(r.stream.ok()) << r.stream.message();
    const Topology& top = r.stream->topology;
    EXPECT_EQ(top.vertex_count, 6u);
    ASSERT_EQ(top.faces.size(), 3u);
    EXPECT_EQ(top.quad_count(), 2u);
    EXPECT_EQ(top.faces[2], (Face{{1, 2, 5, kNoVertex}}));
    EXPECT_EQ(top.node_ids, (std::vector<int64_t>{101, 102, 103, 104, 105, 106}));
    EXPECT_EQ(top.element_ids, (std::vector<int64_t>{11, 12, 13}));
    EXPECT_EQ(top.parts(), std::vector<int32_t>{42});
    const FrameSource& frames = *r.stream->frames;
    ASSERT_EQ(frames.step_count(), 3u);
    EXPECT_EQ(frames.step_time(2), 0.5);
    const auto last = step(*r.stream, 2);
    EXPECT_FLOAT_EQ(last[3 * 4 + 0], 1.0f);
    EXPECT_FLOAT_EQ(last[3 * 4 + 1], 1.0f);
    EXPECT_FLOAT_EQ(last[3 * 4 + 2], 1.0f);  // displaced by 2 · 0.5
    const auto middle = step(*r.stream, 1);  // the state split over d3plot01 and d3plot02
    EXPECT_FLOAT_EQ(middle[3 * 5 + 2], 0.5f);
    ASSERT_EQ(frames.field_names(), (std::vector<std::string>{"temperature", "von Mises",
                                                              "plastic strain", "thickness"}));
    std::vector<float> temperature(6);
    ASSERT_TRUE(frames.read_field(0, 1, temperature).ok());
    EXPECT_EQ(temperature, (std::vector<float>{21, 22, 23, 24, 25, 26}));
    // The default point is the mid-surface: the first one written when MAXINT = 3.
    const auto mises = field(*r.stream, 1, 2), strain = field(*r.stream, 2, 2);
    for (int shell = 0; shell < 3; ++shell) {
      EXPECT_FLOAT_EQ(mises[size_t(shell)],
                      float(std::hypot(shell_value(2, shell, 0, 0), std::sqrt(75.0))));
      EXPECT_FLOAT_EQ(strain[size_t(shell)], float(shell_value(2, shell, 0, 6)));
    }
    EXPECT_EQ(field(*r.stream, 3, 1), (std::vector<float>{1.9f, 1.9f, 1.9f}));
    // Its states, one split over two files, and its node and element fields read on several
    // threads at once (for_each_step() does) are what one thread reads.
    test::expect_parallel_reads_agree(*r.stream);
  }
}

// The integration point the caller picks: MAXINT = 3 writes mid, bottom, top; max takes the
// largest of them. Plastic strain grows from state to state.
TEST(D3plotTest, SyntheticShellResultsAtEachIntegrationPoint) {
  test::TempDir dir;
  write_family(synthetic(3), {4, false}, dir);
  const std::pair<IntegrationPoint, int> cases[] = {{IntegrationPoint::kMid, 0},
                                                    {IntegrationPoint::kBottom, 1},
                                                    {IntegrationPoint::kTop, 2},
                                                    {IntegrationPoint::kMax, 2}};
  for (auto [point, written] : cases) {
    SCOPED_TRACE(to_string(point));
    ReadOptions options;
    options.integration_point = point;
    Opened r = open(std::vector<std::string>{dir.file("d3plot")}, options);
    ASSERT_TRUE(r.stream.ok()) << r.stream.message();
    std::vector<float> before(3, 0.0f);
    for (size_t t = 0; t < 3; ++t) {
      const auto mises = field(*r.stream, 1, t), strain = field(*r.stream, 2, t);
      for (int e = 0; e < 3; ++e) {
        EXPECT_FLOAT_EQ(mises[size_t(e)],
                        float(std::hypot(shell_value(int(t), e, written, 0), std::sqrt(75.0))));
        EXPECT_FLOAT_EQ(strain[size_t(e)], float(shell_value(int(t), e, written, 6)));
        EXPECT_GE(strain[size_t(e)], before[size_t(e)]);
      }
      before = strain;
    }
  }
}

TEST(D3plotTest, SyntheticCutInTheLastStateIsAnError) {
  test::TempDir dir;
  write_family(synthetic(3), {8, true}, dir);
  fs::resize_file(dir.file("d3plot02"), fs::file_size(dir.file("d3plot02")) - 8 * 10);
  Opened r = open(dir.file("d3plot"));
  ASSERT_FALSE(r.stream.ok());
  EXPECT_NE(r.stream.message().find("d3plot02: byte"), std::string::npos) << r.stream.message();
}

}  // namespace
}  // namespace dynpm
