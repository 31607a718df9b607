// CalculiX .frd results: the real crash-box and hat-rail runs against the OBJ sequences of the
// same runs, ASCII against binary output of ccx itself (fields included), hand-made files for
// the format's corners, and broken files that must fail with a message, never crash.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>

#include "dynpm/io.h"
#include "fixtures.h"
#include "reading.h"
#include "third_party.h"

namespace dynpm {
namespace {

using test::field;
using test::open;
using test::Opened;
using test::step;

std::string gunzip(const std::string& gz, const test::TempDir& dir, const std::string& name) {
  const std::string out = dir.file(name);
  const auto run = test::run_command("gzip -dc '" + gz + "' > '" + out + "'");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  return out;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// ---------------------------------------------------------------------------------------------
// Real results against the OBJ sequences written from them (../shared/data, data/hat-rail)

struct RealRun {
  const char* name;
  std::string frd_gz, obj_folder;
  uint32_t vertices;
  size_t quads, triangles, steps;
  std::vector<std::string> fields = {};  // in block order (ccx writes ERROR with S)
};

class FrdRealData : public ::testing::TestWithParam<RealRun> {};

// The "time" column of times.csv (frame,frd_block,time,max_disp or frame,time,ccx_step,…).
std::vector<double> csv_times(const std::string& path) {
  std::ifstream in(path);
  std::string line, cell;
  std::getline(in, line);
  std::stringstream header(line);
  int column = 0;
  while (std::getline(header, cell, ',') && cell != "time") ++column;
  std::vector<double> times;
  while (std::getline(in, line)) {
    std::stringstream row(line);
    for (int c = 0; c <= column; ++c) std::getline(row, cell, ',');
    times.push_back(std::stod(cell));
  }
  return times;
}

TEST_P(FrdRealData, AgreesWithTheObjSequenceOfTheSameRun) {
  const RealRun& run = GetParam();
  if (!std::filesystem::exists(run.frd_gz) || !std::filesystem::exists(run.obj_folder))
    GTEST_SKIP() << run.frd_gz << " or " << run.obj_folder << " is missing";
  test::TempDir dir;
  const std::string frd = gunzip(run.frd_gz, dir, std::string(run.name) + ".frd");
  Opened r = open(frd);
  ASSERT_TRUE(r.stream.ok()) << r.stream.message();
  EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
  const Topology& a = r.stream->topology;
  const FrameSource& frames = *r.stream->frames;

  auto objs = expand_inputs(std::vector<std::string>{run.obj_folder + "/frame_*.obj"});
  ASSERT_TRUE(objs.ok()) << objs.message();
  auto obj = open_animation(*objs);
  ASSERT_TRUE(obj.ok()) << obj.message();
  const Topology& b = obj->topology;

  EXPECT_EQ(a.vertex_count, run.vertices);
  EXPECT_EQ(a.quad_count(), run.quads);
  EXPECT_EQ(a.triangle_count(), run.triangles);
  ASSERT_EQ(a.vertex_count, b.vertex_count);
  // Faces in ascending element number, vertices in ascending node number: the same lists.
  ASSERT_EQ(a.faces.size(), b.faces.size());
  for (size_t f = 0; f < a.faces.size(); ++f) ASSERT_EQ(a.faces[f], b.faces[f]) << "face " << f;
  EXPECT_TRUE(std::is_sorted(a.element_ids.begin(), a.element_ids.end()));
  ASSERT_EQ(a.node_ids.size(), a.vertex_count);
  EXPECT_TRUE(std::adjacent_find(a.node_ids.begin(), a.node_ids.end(),
                                 [](int64_t x, int64_t y) { return x >= y; }) == a.node_ids.end());
  EXPECT_EQ(a.parts(), std::vector<int32_t>{1});  // one material
  EXPECT_TRUE(validate(a, &frames).ok());

  // Every step: positions within the OBJ text's rounding, times as in times.csv.
  ASSERT_EQ(frames.step_count(), run.steps);
  ASSERT_EQ(obj->frames->step_count(), run.steps);
  const std::vector<double> times = csv_times(run.obj_folder + "/times.csv");
  ASSERT_EQ(times.size(), run.steps);
  BoundingBox box;
  box.extend(step(*r.stream, 0));
  const double tolerance = 1e-4 * box.diagonal();
  for (size_t t = 0; t < run.steps; ++t) {
    EXPECT_NEAR(frames.step_time(t), times[t], 1e-9 + 1e-6 * std::abs(times[t])) << "step " << t;
    const auto p = step(*r.stream, t), q = step(*obj, t);
    double worst = 0;
    for (size_t i = 0; i < p.size(); ++i) worst = std::max(worst, double(std::abs(p[i] - q[i])));
    EXPECT_LT(worst, tolerance) << "step " << t;
  }
  // Fields: zero in the undeformed frame, von Mises >= 0; the steel (yield 200 MPa) flows.
  ASSERT_EQ(frames.field_names(), run.fields);
  for (size_t f = 0; f < run.fields.size(); ++f) {
    float peak = 0;
    for (size_t t = 0; t < run.steps; ++t)
      for (float x : field(*r.stream, f, t)) {
        ASSERT_TRUE(std::isfinite(x) && (t > 0 || x == 0) && (x >= 0 || run.fields[f] != "S_MISES"))
            << run.fields[f] << " = " << x << " at step " << t;
        peak = std::max(peak, x);
      }
    EXPECT_GE(peak, run.fields[f] == "PEEQ" ? 0.01f : run.fields[f] == "ERROR" ? 0 : 200) << f;
  }
}

INSTANTIATE_TEST_SUITE_P(
    FrdRuns, FrdRealData,
    ::testing::Values(RealRun{"crashbox_s", test::shared_data() + "/crashbox-s/crashbox-s.frd.gz",
                              test::shared_data() + "/crashbox-s/obj", 3003, 2937, 0, 26},
                      RealRun{"crashbox_mixed_5k",
                              test::shared_data() + "/crashbox-mixed-5k/crashbox-mixed-5k.frd.gz",
                              test::shared_data() + "/crashbox-mixed-5k/obj", 4929, 4827, 16, 41},
                      RealRun{"hat_rail", test::source_dir() + "/data/hat-rail/rail.frd.gz",
                              test::sample_dir(), 2608, 2435, 123, 31,
                              std::vector<std::string>{"S_MISES", "PEEQ", "ERROR"}}),
    [](const auto& run_info) { return std::string(run_info.param.name); });

// Cutting or scribbling over a real file gives an error naming it, never a crash.
TEST(FrdBroken, CutAndScribbledRealFileFailsCleanly) {
  const std::string gz = test::source_dir() + "/data/hat-rail/rail.frd.gz";
  test::TempDir dir;
  const std::string bytes = slurp(gunzip(gz, dir, "rail.frd"));
  ASSERT_GT(bytes.size(), 100000u);
  for (size_t cut : {size_t{10}, size_t{900}, size_t{5000}, bytes.size() / 10, bytes.size() / 2,
                     bytes.size() - 20}) {
    const std::string path = dir.file("cut.frd");
    std::ofstream(path, std::ios::binary) << bytes.substr(0, cut);
    Opened r = open(path);
    ASSERT_FALSE(r.stream.ok()) << "cut at " << cut;
    EXPECT_NE(r.stream.message().find(path), std::string::npos) << r.stream.message();
  }
  // Scribbles: whatever happens, every step either reads or fails with a message.
  for (size_t at = 1000; at < bytes.size(); at += bytes.size() / 23) {
    std::string broken = bytes;
    for (size_t k = 0; k < 40 && at + k < broken.size(); ++k) broken[at + k] = char('A' + k % 7);
    const std::string path = dir.file("scribbled.frd");
    std::ofstream(path, std::ios::binary) << broken;
    Opened r = open(path);
    if (!r.stream.ok()) {
      EXPECT_NE(r.stream.message().find(path), std::string::npos) << r.stream.message();
      continue;
    }
    std::vector<float> xyz(size_t{r.stream->frames->vertex_count()} * 3);
    for (size_t t = 0; t < r.stream->frames->step_count(); ++t)
      (void)r.stream->frames->read_step(t, xyz);
  }
}

TEST(FrdBroken, GzipFileSaysGunzipIt) {
  Opened r = open(test::source_dir() + "/data/hat-rail/rail.frd.gz");
  ASSERT_FALSE(r.stream.ok());
  EXPECT_NE(r.stream.message().find("gzip-compressed; gunzip it first"), std::string::npos)
      << r.stream.message();
  // Also when the name says .frd.
  test::TempDir dir;
  std::ofstream(dir.file("rail.frd"), std::ios::binary)
      << slurp(test::source_dir() + "/data/hat-rail/rail.frd.gz");
  r = open(dir.file("rail.frd"));
  ASSERT_FALSE(r.stream.ok());
  EXPECT_NE(r.stream.message().find("gunzip it first"), std::string::npos) << r.stream.message();
}

// ---------------------------------------------------------------------------------------------
// Hand-made files: the record layouts of the cgx manual's "Result Format"

// Fixed-column helpers for writing .frd records.
std::string pad_left(const std::string& s, size_t width) {
  return s.size() >= width ? s : std::string(width - s.size(), ' ') + s;
}
std::string e12(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%12.5E", v);
  return b;
}
std::string i(int64_t v, size_t width) { return pad_left(std::to_string(v), width); }

// A little model: nodes 10, 20, 30, 40 (a unit square) and 7 (a triangle's tip), written in
// descending node order on purpose; quad 5 (material 2) and triangle 3 (material 1).
struct Model {
  std::vector<std::pair<int64_t, std::array<double, 3>>> nodes = {
      {40, {0, 1, 0}}, {30, {1, 1, 0}}, {20, {1, 0, 0}}, {10, {0, 0, 0}}, {7, {2, 0.5, 0}}};
  struct Element {
    int64_t id, type, material;
    std::vector<int64_t> nodes;
  };
  std::vector<Element> elements = {{5, 9, 2, {10, 20, 30, 40}}, {3, 7, 1, {20, 7, 30}}};
};

std::string header_1c() { return "    1C\n    1UUSER\n    1UMAT    1STEEL\n    1UMAT    2ALU\n"; }

std::string ascii_mesh(const Model& m, bool long_format) {
  const size_t w = long_format ? 10 : 5;
  std::string s = header_1c();
  s += "    2C" + std::string(18, ' ') + i(int64_t(m.nodes.size()), 12) + std::string(37, ' ') +
       (long_format ? "1" : "0") + "\n";
  for (const auto& [id, xyz] : m.nodes)
    s += " -1" + i(id, w) + e12(xyz[0]) + e12(xyz[1]) + e12(xyz[2]) + "\n";
  s += " -3\n";
  s += "    3C" + std::string(18, ' ') + i(int64_t(m.elements.size()), 12) + std::string(37, ' ') +
       (long_format ? "1" : "0") + "\n";
  for (const auto& e : m.elements) {
    s += " -1" + i(e.id, w) + i(e.type, 5) + i(0, 5) + i(e.material, 5) + "\n -2";
    for (int64_t n : e.nodes) s += i(n, w);
    s += "\n";
  }
  s += " -3\n";
  return s;
}

// A 100C block of `values` per node for every node of m (ASCII).
std::string ascii_result(const Model& m, const std::string& name, double time, int step,
                         const std::vector<std::string>& components, bool with_all,
                         const std::function<std::vector<double>(int64_t)>& values,
                         bool long_format) {
  const size_t w = long_format ? 10 : 5;
  std::string s = "  100CL  1" + i(step, 2) + e12(time) + i(int64_t(m.nodes.size()), 12) +
                  std::string(20, ' ') + i(0, 2) + i(step, 5) + std::string(10, ' ') +
                  (long_format ? " 1" : " 0") + "\n";
  const size_t n = components.size() + (with_all ? 1 : 0);
  s += " -4  " + name + std::string(8 - name.size(), ' ') + i(int64_t(n), 5) + i(1, 5) + "\n";
  for (size_t c = 0; c < components.size(); ++c)
    s += " -5  " + components[c] + std::string(8 - components[c].size(), ' ') + i(1, 5) + i(2, 5) +
         i(int64_t(c + 1), 5) + i(0, 5) + "\n";
  if (with_all) s += " -5  ALL         1    2    0    0    1ALL\n";
  for (const auto& [id, xyz] : m.nodes) {
    s += " -1" + i(id, w);
    for (double v : values(id)) s += e12(v);
    s += "\n";
  }
  return s + " -3\n";
}

std::vector<double> disp(int64_t node, double scale) { return {scale * node, -scale, 2 * scale}; }

std::string write(const test::TempDir& dir, const std::string& name, const std::string& bytes) {
  const std::string path = dir.file(name);
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

TEST(FrdHandMade, AsciiShortAndLongFormatsReadAlike) {
  const Model m;
  for (bool long_format : {false, true}) {
    std::string s = ascii_mesh(m, long_format);
    // Step 1 writes STRESS before DISP: blocks pair by step number and time, not by order.
    s += ascii_result(
        m, "STRESS", 0.5, 1, {"SXX", "SYY", "SZZ", "SXY", "SYZ", "SZX"}, false,
        [](int64_t n) { return std::vector<double>{double(n), 0, 0, 0, 0, 0}; }, long_format);
    s += ascii_result(
        m, "DISP", 0.5, 1, {"D1", "D2", "D3"}, true, [](int64_t n) { return disp(n, 0.5); },
        long_format);
    s += ascii_result(
        m, "DISP", 1.0, 2, {"D1", "D2", "D3"}, true, [](int64_t n) { return disp(n, 1.0); },
        long_format);
    s += ascii_result(
        m, "PE", 1.0, 2, {"PE"}, false, [](int64_t n) { return std::vector<double>{0.01 * n}; },
        long_format);
    s += ascii_result(
        m, "FORC", 1.0, 2, {"F1", "F2", "F3"}, true,
        [](int64_t) {
          return std::vector<double>{1, 2, 3};
        },
        long_format);
    s += " 9999\n";
    test::TempDir dir;
    Opened r = open(write(dir, "model.frd", s));
    ASSERT_TRUE(r.stream.ok()) << r.stream.message();
    const Topology& t = r.stream->topology;
    // Vertices in ascending node number; faces in ascending element number.
    EXPECT_EQ(t.node_ids, (std::vector<int64_t>{7, 10, 20, 30, 40}));
    ASSERT_EQ(t.faces.size(), 2u);
    EXPECT_EQ(t.element_ids, (std::vector<int64_t>{3, 5}));
    EXPECT_EQ(t.faces[0], (Face{{2, 0, 3, kNoVertex}}));  // nodes 20 7 30
    EXPECT_EQ(t.faces[1], (Face{{1, 2, 3, 4}}));          // nodes 10 20 30 40
    EXPECT_EQ(t.part_ids, (std::vector<int32_t>{1, 2}));  // the material numbers
    ASSERT_EQ(r.warnings.size(), 1u);
    EXPECT_NE(r.warnings[0].find("FORC"), std::string::npos) << r.warnings[0];

    const FrameSource& frames = *r.stream->frames;
    ASSERT_EQ(frames.step_count(), 3u);
    EXPECT_EQ(frames.step_time(0), 0.0);
    EXPECT_EQ(frames.step_time(1), 0.5);
    EXPECT_EQ(frames.step_time(2), 1.0);
    const auto p0 = step(*r.stream, 0), p2 = step(*r.stream, 2);
    for (size_t v = 0; v < 5; ++v) {
      const auto d = disp(t.node_ids[v], 1.0);
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(p2[3 * v + k], p0[3 * v + k] + d[k], 1e-4);
    }
    EXPECT_EQ(p0[3 * 0], 2.0f);  // node 7 at (2, 0.5, 0)
    ASSERT_EQ(frames.field_names(), (std::vector<std::string>{"S_MISES", "PEEQ"}));
    // Uniaxial stress: von Mises = |SXX|; no STRESS block at step 2, no PE at step 1: zeros.
    const auto mises = field(*r.stream, 0, 1);
    for (size_t v = 0; v < 5; ++v) EXPECT_NEAR(mises[v], double(t.node_ids[v]), 1e-4);
    for (float x : field(*r.stream, 0, 2)) EXPECT_EQ(x, 0.0f);
    for (float x : field(*r.stream, 1, 0)) EXPECT_EQ(x, 0.0f);
    const auto peeq = field(*r.stream, 1, 2);
    for (size_t v = 0; v < 5; ++v) EXPECT_NEAR(peeq[v], 0.01 * double(t.node_ids[v]), 1e-6);

    auto all = load_all_steps(std::move(r.stream).value());
    ASSERT_TRUE(all.ok()) << all.message();
    EXPECT_EQ(all->fields.size(), 2u);
  }
}

// Native-endian binary records: coordinates as float (2C format 2), elements (3C format 2),
// DISP as float (100C format 2); the same model as ASCII must read alike.
TEST(FrdHandMade, BinaryRecordsReadLikeAscii) {
  const Model m;
  auto raw = [](auto v) { return std::string(reinterpret_cast<const char*>(&v), sizeof v); };
  std::string s = header_1c();
  s += "    2C" + std::string(18, ' ') + i(5, 12) + std::string(37, ' ') + "2\n";
  for (const auto& [id, xyz] : m.nodes) {
    s += raw(int32_t(id));
    for (double c : xyz) s += raw(float(c));
  }
  s += "    3C" + std::string(18, ' ') + i(2, 12) + std::string(37, ' ') + "2\n";
  for (const auto& e : m.elements) {
    s += raw(int32_t(e.id)) + raw(int32_t(e.type)) + raw(int32_t(0)) + raw(int32_t(e.material));
    for (int64_t n : e.nodes) s += raw(int32_t(n));
  }
  for (int stepno : {1, 2}) {
    s += "  100CL  10" + std::to_string(stepno) + e12(0.5 * stepno) + i(5, 12) +
         std::string(20, ' ') + " 0" + i(stepno, 5) + std::string(10, ' ') + " 2\n";
    s += " -4  DISP        4    1\n -5  D1          1    2    1    0\n"
         " -5  D2          1    2    2    0\n -5  D3          1    2    3    0\n"
         " -5  ALL         1    2    0    0    1ALL\n";
    for (const auto& [id, xyz] : m.nodes) {
      s += raw(int32_t(id));
      for (double d : disp(id, 0.5 * stepno)) s += raw(float(d));
    }
  }
  s += " 9999\n";
  test::TempDir dir;
  Opened b = open(write(dir, "binary.frd", s));
  ASSERT_TRUE(b.stream.ok()) << b.stream.message();

  std::string text = ascii_mesh(m, true);
  for (int stepno : {1, 2})
    text += ascii_result(
        m, "DISP", 0.5 * stepno, stepno, {"D1", "D2", "D3"}, true,
        [&](int64_t n) { return disp(n, 0.5 * stepno); }, true);
  Opened a = open(write(dir, "ascii.frd", text));
  ASSERT_TRUE(a.stream.ok()) << a.stream.message();

  EXPECT_EQ(a.stream->topology.faces, b.stream->topology.faces);
  EXPECT_EQ(a.stream->topology.node_ids, b.stream->topology.node_ids);
  EXPECT_EQ(a.stream->topology.part_ids, b.stream->topology.part_ids);
  ASSERT_EQ(b.stream->frames->step_count(), 3u);
  for (size_t t = 0; t < 3; ++t) {
    EXPECT_EQ(a.stream->frames->step_time(t), b.stream->frames->step_time(t));
    const auto pa = step(*a.stream, t), pb = step(*b.stream, t);
    for (size_t k = 0; k < pa.size(); ++k) EXPECT_NEAR(pa[k], pb[k], 1e-4) << t << " " << k;
  }

  // A binary block announcing more records than the file holds is refused before allocating.
  std::string huge = s;
  const size_t at = huge.find("    2C");
  huge.replace(at + 24, 12, i(2000000000, 12));
  Opened h = open(write(dir, "huge.frd", huge));
  ASSERT_FALSE(h.stream.ok());
  EXPECT_NE(h.stream.message().find("bytes left"), std::string::npos) << h.stream.message();
  // Cut inside binary data: an error with a byte offset or "ends inside".
  for (size_t cut = 80; cut < s.size(); cut += 37) {
    Opened c = open(write(dir, "cut.frd", s.substr(0, cut)));
    if (c.stream.ok()) continue;  // a cut right after a complete block can still be a file
    EXPECT_NE(c.stream.message().find("cut.frd"), std::string::npos) << c.stream.message();
  }
}

TEST(FrdHandMade, ErrorsNameTheFileAndLine) {
  const Model m;
  test::TempDir dir;
  struct Case {
    std::string bytes, expected;
  };
  std::string missing_node = ascii_mesh(m, false);
  missing_node.replace(missing_node.rfind("   40\n"), 5, "   99");  // in quad 5's node list
  std::string unknown_type = ascii_mesh(m, false);
  unknown_type.replace(unknown_type.find("    5    9"), 10, "    5   42");
  const Case cases[] = {
      {"hello\n", "model.frd:1: not a CalculiX .frd record"},
      {header_1c() + "    2C                           1                                     0\n"
                     " -1    1 1.00000E+00 xx          0.00000E+00\n",
       "model.frd:6: cannot read coordinate 2 of node 1"},
      {missing_node, "uses node 99, which the node block does not define"},
      {unknown_type, "model.frd:13: element 5 has the unknown frd type 42"},
      {ascii_mesh(m, false) + "  100CL  101 1.00000E+00           5                     0    1"
                              "           0\n -4  DISP        4    1\n -1   10 1.0\n",
       "model.frd:20: expected 4 ' -5' component records"},
      {header_1c(), "no node block (2C)"},
      // One number rule (text.h): a header number is blank or a whole number; times are finite.
      {ascii_mesh(m, false) + "  100CL  101 1.00000E+00          5x                     0    1"
                              "           0\n",
       "model.frd:18: the node count of the 100C line, '5x', is not a whole number"},
      {ascii_mesh(m, false) + "  100CL  101         inf           5                     0    1"
                              "           0\n",
       "model.frd:18: the step time 'inf' (columns 13-24 of the 100C line) is not a finite number"},
      {header_1c() + "    2C                          1x                                     0\n",
       "model.frd:5: the record count of the node block (2C) header, '1x', is not a whole number"},
  };
  for (const Case& c : cases) {
    Opened r = open(write(dir, "model.frd", c.bytes));
    ASSERT_FALSE(r.stream.ok()) << c.expected;
    EXPECT_NE(r.stream.message().find(c.expected), std::string::npos)
        << r.stream.message() << "\nexpected: " << c.expected;
  }
}

TEST(FrdHandMade, SolidsOnlyAsksForOutput2D) {
  Model m;
  m.nodes.push_back({50, {0, 0, 1}});
  m.nodes.push_back({60, {1, 0, 1}});
  m.nodes.push_back({70, {1, 1, 1}});
  m.nodes.push_back({80, {0, 1, 1}});
  m.elements = {{1, 1, 1, {10, 20, 30, 40, 50, 60, 70, 80}}};
  test::TempDir dir;
  Opened r = open(write(dir, "solid.frd", ascii_mesh(m, true)));
  ASSERT_FALSE(r.stream.ok());
  EXPECT_NE(r.stream.message().find("OUTPUT=2D"), std::string::npos) << r.stream.message();
}

// ---------------------------------------------------------------------------------------------
// ccx itself: the same deck written as ASCII (*NODE FILE / *EL FILE) and as binary
// (*NODE OUTPUT / *ELEMENT OUTPUT) frd, with shells S4, S3, S8R, S6, a C3D8 brick and fields.

std::string ccx() {
  static const std::string path = [] {
    auto r = test::run_command("command -v ccx");
    return r.exit_code == 0 ? std::string("ccx") : std::string();
  }();
  return path;
}

const char* kDeck = R"(*NODE
1, 0, 0, 0
2, 1, 0, 0
3, 2, 0, 0
4, 0, 1, 0
5, 1, 1, 0
6, 2, 1, 0
7, 3, 0.5, 0
101, 0, 3, 0
102, 1, 3, 0
103, 1, 4, 0
104, 0, 4, 0
105, 0.5, 3, 0
106, 1, 3.5, 0
107, 0.5, 4, 0
108, 0, 3.5, 0
109, 2, 3, 0
110, 1.5, 3, 0
111, 1.5, 3.5, 0
201, 5, 0, 0
202, 6, 0, 0
203, 6, 1, 0
204, 5, 1, 0
205, 5, 0, 1
206, 6, 0, 1
207, 6, 1, 1
208, 5, 1, 1
*ELEMENT, TYPE=S4, ELSET=PLATE
1, 1, 2, 5, 4
2, 2, 3, 6, 5
*ELEMENT, TYPE=S3, ELSET=PLATE
3, 3, 7, 6
*ELEMENT, TYPE=S8R, ELSET=PLATE2
10, 101, 102, 103, 104, 105, 106, 107, 108
*ELEMENT, TYPE=S6, ELSET=PLATE2
11, 102, 109, 103, 110, 111, 106
*ELEMENT, TYPE=C3D8, ELSET=BRICK
20, 201, 202, 203, 204, 205, 206, 207, 208
*MATERIAL, NAME=STEEL
*ELASTIC
210000, 0.3
*PLASTIC
200, 0
400, 0.5
*MATERIAL, NAME=ALU
*ELASTIC
70000, 0.3
*SHELL SECTION, ELSET=PLATE, MATERIAL=STEEL
0.1
*SHELL SECTION, ELSET=PLATE2, MATERIAL=ALU
0.1
*SOLID SECTION, ELSET=BRICK, MATERIAL=ALU
*BOUNDARY
1, 1, 6
4, 1, 6
101, 1, 6
104, 1, 6
108, 1, 6
201, 1, 3
202, 1, 3
203, 1, 3
204, 1, 3
*STEP, NLGEOM, INC=100
*STATIC
0.25, 1.0
*CLOAD
7, 3, 0.2
109, 3, 0.1
205, 3, 1000.0
*NODE FILE, OUTPUT=2D
U
*EL FILE
S, PE
*END STEP
)";

TEST(FrdCcx, AsciiAndBinaryOutputOfOneRunAgree) {
  if (ccx().empty()) {
    if (test::third_party_required()) FAIL() << "calculix-ccx is not installed";
    GTEST_SKIP() << "calculix-ccx is not installed";
  }
  test::TempDir dir;
  std::filesystem::create_directories(dir.path() / "ascii");
  std::filesystem::create_directories(dir.path() / "binary");
  std::string binary_deck = kDeck;
  binary_deck.replace(binary_deck.find("*NODE FILE"), 10, "*NODE OUTPUT");
  binary_deck.replace(binary_deck.find("*EL FILE"), 8, "*ELEMENT OUTPUT");
  std::ofstream(dir.file("ascii/mix.inp")) << kDeck;
  std::ofstream(dir.file("binary/mix.inp")) << binary_deck;
  for (const char* sub : {"ascii", "binary"}) {
    const auto run =
        test::run_command("cd '" + dir.file(sub) + "' && " + ccx() + " -i mix > ccx.log 2>&1");
    ASSERT_EQ(run.exit_code, 0) << slurp(dir.file(std::string(sub) + "/ccx.log"));
  }
  Opened a = open(dir.file("ascii/mix.frd"));
  Opened b = open(dir.file("binary/mix.frd"));
  ASSERT_TRUE(a.stream.ok()) << a.stream.message();
  ASSERT_TRUE(b.stream.ok()) << b.stream.message();
  // ccx wrote binary blocks indeed: format 3 (doubles) on the 2C line, no " -3" block ends.
  const std::string bytes = slurp(dir.file("binary/mix.frd"));
  const size_t nodes = bytes.find("    2C");
  ASSERT_NE(nodes, std::string::npos);
  EXPECT_EQ(bytes[bytes.find('\n', nodes) - 1], '3');
  EXPECT_EQ(bytes.find("\n -3\n"), std::string::npos);

  for (const Opened* r : {&a, &b}) {
    const Topology& t = r->stream->topology;
    // Corner nodes of the shells only: 7 + 5; the brick and the mid-side nodes are not vertices.
    EXPECT_EQ(t.vertex_count, 12u);
    EXPECT_EQ(t.quad_count(), 3u);
    EXPECT_EQ(t.triangle_count(), 2u);
    EXPECT_EQ(t.element_ids, (std::vector<int64_t>{1, 2, 3, 10, 11}));
    EXPECT_EQ(t.part_ids, (std::vector<int32_t>{1, 1, 1, 2, 2}));  // STEEL, ALU
    EXPECT_EQ(t.node_ids, (std::vector<int64_t>{1, 2, 3, 4, 5, 6, 7, 101, 102, 103, 104, 109}));
    ASSERT_GE(r->warnings.size(), 2u);  // quadratic shells, the brick
    EXPECT_NE(r->warnings[0].find("2 quadratic shells"), std::string::npos) << r->warnings[0];
    EXPECT_NE(r->warnings[1].find("skipped 1 solid"), std::string::npos) << r->warnings[1];
  }
  const FrameSource& fa = *a.stream->frames;
  const FrameSource& fb = *b.stream->frames;
  ASSERT_GE(fa.step_count(), 2u);
  ASSERT_EQ(fa.step_count(), fb.step_count());
  ASSERT_EQ(fa.field_names(), fb.field_names());
  EXPECT_EQ(fa.field_names()[0], "S_MISES");
  EXPECT_EQ(fa.field_names()[1], "PEEQ");
  for (size_t t = 0; t < fa.step_count(); ++t) {
    EXPECT_NEAR(fa.step_time(t), fb.step_time(t), 1e-5);
    const auto pa = step(*a.stream, t), pb = step(*b.stream, t);
    for (size_t k = 0; k < pa.size(); ++k)
      ASSERT_NEAR(pa[k], pb[k], 1e-5 * (1 + std::abs(pb[k]))) << "step " << t << " " << k;
    for (size_t f = 0; f < fa.field_names().size(); ++f) {
      const auto va = field(*a.stream, f, t), vb = field(*b.stream, f, t);
      for (size_t v = 0; v < va.size(); ++v)
        ASSERT_NEAR(va[v], vb[v], 1e-4 * (1 + std::abs(vb[v]))) << fa.field_names()[f] << " " << t;
    }
  }
  // The load bends the plates: the last step moved, and the stress is not zero.
  const auto last = step(*b.stream, fb.step_count() - 1), first = step(*b.stream, 0);
  EXPECT_GT(std::abs(last[3 * 6 + 2] - first[3 * 6 + 2]), 1e-3);  // node 7 lifts
  const auto mises = field(*b.stream, 0, fb.step_count() - 1);
  EXPECT_GT(*std::max_element(mises.begin(), mises.end()), 1.0f);
}

}  // namespace
}  // namespace dynpm
