// VTK inputs: legacy .vtk (polydata and unstructured grids, ascii and binary, file versions 4.2
// and 5.1), .vtu (ascii, base64, appended raw/base64, zlib, UInt32/UInt64 headers) and .pvd
// collections. Third-party files come from meshio and from VTK's own writers, converted from the
// shipped sample's first frame, and must read as that OBJ does.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <map>

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

std::string write(const test::TempDir& dir, const std::string& name, const std::string& bytes) {
  const std::string path = dir.file(name);
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// Faces as a multiset of corner cycles starting at the smallest corner (writers such as meshio
// group faces by type, so the order may change, the cycles may not).
std::map<std::array<uint32_t, 4>, int> cycles(const Topology& t) {
  std::map<std::array<uint32_t, 4>, int> m;
  for (Face f : t.faces) {
    const int n = f.degree();
    std::rotate(f.v.begin(), std::min_element(f.v.begin(), f.v.begin() + n), f.v.begin() + n);
    ++m[f.v];
  }
  return m;
}

// ---------------------------------------------------------------------------------------------
// dynpm's own legacy VTK writer, read back

// The T-joint with its own element and node numbers and a per-vertex field.
test::Mesh numbered_t_joint() {
  test::Mesh m = test::t_joint();
  m.topology.element_ids = {101, 205, 3000000000};  // the last needs 64 bits
  for (size_t v = 0; v < m.topology.vertex_count; ++v) m.topology.node_ids[v] = 10 + 7 * v;
  return m;
}

TEST(VtkSeriesLegacy, OwnWriterRoundTrips) {
  const test::Mesh m = numbered_t_joint();
  std::vector<float> heat(m.topology.vertex_count);
  for (size_t v = 0; v < heat.size(); ++v) heat[v] = 0.25f * float(v);
  const NamedValues fields[] = {{"heat flux", heat}};
  for (bool binary : {true, false}) {
    test::TempDir dir;
    WriteOptions options;
    options.binary = binary;
    options.comment = "dynpm test: time 2.5";
    const std::string path = dir.file("t.vtk");
    ASSERT_TRUE(write_mesh(path, m.topology, m.positions, options, fields).ok());
    auto a = read_mesh(path);
    ASSERT_TRUE(a.ok()) << a.message();
    EXPECT_EQ(a->topology.faces, m.topology.faces);
    EXPECT_EQ(a->topology.part_ids, m.topology.part_ids);
    EXPECT_EQ(a->topology.element_ids, m.topology.element_ids);
    EXPECT_EQ(a->topology.node_ids, m.topology.node_ids);
    EXPECT_EQ(std::vector<float>(a->frames.step(0).begin(), a->frames.step(0).end()), m.positions);
    EXPECT_EQ(a->frames.step_time(0), 2.5);  // from the title line
    ASSERT_EQ(a->fields.size(), 1u);
    EXPECT_EQ(a->fields[0].name, "heat_flux");  // VTK names hold no blanks
    EXPECT_EQ(a->fields[0].steps[0], heat);
  }
}

// A sequence of .vtk files through open_input(): times from the titles, fields per step.
TEST(VtkSeriesLegacy, SequenceStreamsStepsAndFields) {
  const test::Mesh m = numbered_t_joint();
  test::TempDir dir;
  std::vector<std::string> paths;
  for (int t = 0; t < 3; ++t) {
    std::vector<float> xyz = m.positions, heat(m.topology.vertex_count, float(t));
    for (size_t i = 2; i < xyz.size(); i += 3) xyz[i] += 0.5f * float(t);
    const NamedValues fields[] = {{"heat", heat}};
    WriteOptions options;
    options.binary = t != 1;
    options.comment = "frame " + std::to_string(t) + ": time " + std::to_string(0.1 * t);
    paths.push_back(dir.file("frame_" + std::to_string(t) + ".vtk"));
    ASSERT_TRUE(write_mesh(paths.back(), m.topology, xyz, options, fields).ok());
  }
  Opened r = open(paths);
  ASSERT_TRUE(r.stream.ok()) << r.stream.message();
  const FrameSource& frames = *r.stream->frames;
  ASSERT_EQ(frames.step_count(), 3u);
  ASSERT_EQ(frames.field_names(), std::vector<std::string>{"heat"});
  for (size_t t = 0; t < 3; ++t) {
    EXPECT_NEAR(frames.step_time(t), 0.1 * double(t), 1e-9);
    const auto xyz = step(*r.stream, t);
    EXPECT_FLOAT_EQ(xyz[2], m.positions[2] + 0.5f * float(t));
    for (float h : field(*r.stream, 0, t)) EXPECT_EQ(h, float(t));
  }
  auto all = load_all_steps(std::move(r.stream).value());
  ASSERT_TRUE(all.ok()) << all.message();
  ASSERT_EQ(all->fields.size(), 1u);
  EXPECT_EQ(all->fields[0].steps.size(), 3u);
}

// Hand-made unstructured grid: every cell kind dynpm reads, skips or reduces.
//   points 0-3 a unit square, 4-5 beyond it, 6-13 a cube above it, 14-16 a far triangle's mid-
//   side points, 17-20 a pixel, 21-24 a strip.
std::string grid_file(const std::string& polygon_cell) {
  return "# vtk DataFile Version 4.2\nhand made\nASCII\nDATASET UNSTRUCTURED_GRID\n"
         "POINTS 25 float\n"
         "0 0 0 1 0 0 1 1 0 0 1 0 2 0 0 2 1 0\n"
         "0 0 1 1 0 1 1 1 1 0 1 1 0 0 2 1 0 2 1 1 2 0 1 2\n"
         "1.5 0 0 1.5 0.5 0 1 0.5 0\n"
         "5 0 0 6 0 0 5 1 0 6 1 0\n"
         "8 0 0 8 1 0 9 0 0 9 1 0\n"
         "CELLS 8 44\n"
         "4 0 1 2 3\n" +
         polygon_cell +
         "\n"
         "8 6 7 8 9 10 11 12 13\n"
         "6 1 4 5 14 15 16\n"
         "2 0 1\n"
         "3 1 4 5\n"
         "4 17 18 19 20\n"
         "4 21 22 23 24\n"
         "CELL_TYPES 8\n9 7 12 22 3 5 8 6\n"
         "CELL_DATA 8\nSCALARS PartId int\nLOOKUP_TABLE default\n1 2 3 4 5 6 7 8\n"
         "POINT_DATA 25\nFIELD attributes 2\npressure 1 25 double\n" +
         [] {
           std::string s;
           for (int i = 0; i < 25; ++i) s += std::to_string(i) + ".5 ";
           return s;
         }() +
         "\nvelocity 3 25 float\n" + std::string(75 * 2, ' ') +
         [] {
           std::string s;
           for (int i = 0; i < 75; ++i) s += "1 ";
           return s;
         }() +
         "\n";
}

TEST(VtkSeriesLegacy, UnstructuredGridCellKinds) {
  test::TempDir dir;
  // A pentagon: an error unless polygons may be split.
  const std::string path = write(dir, "grid.vtk", grid_file("5 1 4 5 2 16"));
  Opened strict = open(std::vector<std::string>{path});
  ASSERT_FALSE(strict.stream.ok());
  EXPECT_NE(strict.stream.message().find("grid.vtk: cell 1"), std::string::npos)
      << strict.stream.message();
  EXPECT_NE(strict.stream.message().find("--split-polygons"), std::string::npos);

  Opened r = open(std::vector<std::string>{path}, /*split_polygons=*/true);
  ASSERT_TRUE(r.stream.ok()) << r.stream.message();
  const Topology& t = r.stream->topology;
  // quad, pentagon → 3 triangles, (hex skipped), quadratic triangle → corners, (line skipped),
  // triangle, pixel → quad 17 18 20 19, strip of 4 → 2 triangles.
  ASSERT_EQ(t.faces.size(), 1u + 3 + 1 + 1 + 1 + 2);
  EXPECT_EQ(t.faces[0], (Face{{0, 1, 2, 3}}));
  EXPECT_EQ(t.faces[4], (Face{{1, 4, 5, kNoVertex}}));  // from the quadratic triangle
  EXPECT_EQ(t.faces[6], (Face{{17, 18, 20, 19}}));
  EXPECT_EQ(t.faces[7], (Face{{21, 22, 23, kNoVertex}}));
  EXPECT_EQ(t.faces[8], (Face{{22, 24, 23, kNoVertex}}));  // flipped to keep the orientation
  EXPECT_EQ(t.part_ids, (std::vector<int32_t>{1, 2, 2, 2, 4, 6, 7, 8, 8}));
  EXPECT_EQ(t.element_ids[0], 1);  // cell number + 1 where the file has no element ids
  EXPECT_EQ(t.element_ids[4], 4);
  ASSERT_EQ(r.stream->frames->field_names(), std::vector<std::string>{"pressure"});
  EXPECT_EQ(field(*r.stream, 0, 0)[3], 3.5f);
  std::string all;
  for (const std::string& w : r.warnings) all += w + "\n";
  EXPECT_NE(all.find("1 quadratic"), std::string::npos) << all;
  EXPECT_NE(all.find("skipped 1 solid"), std::string::npos) << all;
  EXPECT_NE(all.find("skipped 1 vertex and line"), std::string::npos) << all;
  EXPECT_NE(all.find("velocity"), std::string::npos) << all;  // 3 components: not a field
  EXPECT_NE(all.find("split into triangle fans"), std::string::npos) << all;
}

TEST(VtkSeriesLegacy, BrokenFilesFailWithTheirPlace) {
  test::TempDir dir;
  const test::Mesh m = numbered_t_joint();
  const std::string good = dir.file("good.vtk");
  ASSERT_TRUE(write_mesh(good, m.topology, m.positions).ok());
  const std::string bytes = slurp(good);
  for (size_t cut = 60; cut < bytes.size(); cut += 11) {
    const std::string path = write(dir, "cut.vtk", bytes.substr(0, cut));
    Opened r = open(std::vector<std::string>{path});
    if (r.stream.ok()) continue;  // cut right after a complete section
    EXPECT_NE(r.stream.message().find("cut.vtk"), std::string::npos) << r.stream.message();
  }
  struct Case {
    std::string text, expected;
  };
  const std::string head = "# vtk DataFile Version 3.0\nx\nASCII\nDATASET POLYDATA\n";
  const Case cases[] = {
      {head + "POINTS 2000000000 float\n0 0 0\n", "broken.vtk:5: 6000000000 values announced"},
      {head + "POINTS 3 float\n0 0 0 1 0 0 0 1 x\n",
       "broken.vtk:6: value 9 of 9, 'x', is not a number"},
      // One number rule (text.h): whole tokens; integers within their type; counts too.
      {head + "POINTS 3 float\n0 0 0 1 0 0 0 1 0\nPOLYGONS 1 4\n3 0 1 2e0\n",
       "broken.vtk:8: value 4 of 4, '2e0', is not a whole number"},
      {head + "POINTS 3 float\n0 0 0 1 0 0 0 1 0\nPOLYGONS 1 4\n3 0 1 4294967296\n",
       "value 4 of 4, '4294967296', is out of the range of its type"},
      {head + "POINTS 3x float\n",
       "broken.vtk:5: expected a point count after 'POINTS', found '3x'"},
      {"# vtk DataFile Version 3.0\ntime 1e999\nASCII\nDATASET POLYDATA\n",
       "broken.vtk:2: the time note '1e999' is not a finite number"},
      {head + "POINTS 3 float\n0 0 0 1 0 0 0 1 0\nBAN\x1b[2JANAS 3\n",
       "broken.vtk:7: unexpected keyword 'BAN\\x1b[2JANAS'"},
      {head + "POINTS 3 float\n0 0 0 1 0 0 0 1 0\nPOLYGONS 1 4\n3 0 1 7\n",
       "broken.vtk: cell 0 refers to point 7"},
      {head + "POINTS 3 float\n0 0 0 1 0 0 0 1 0\nPOLYGONS 1 4\n9 0 1 2\n", "announces 9 points"},
      {head + "POINTS 3 float\n0 0 0 1 0 0 0 1 0\nBANANAS 3\n", "unexpected keyword 'BANANAS'"},
      {"# vtk DataFile Version 3.0\nx\nASCII\nDATASET STRUCTURED_POINTS\n",
       "is not a surface mesh"},
      {"# vtk DataFile Version 3.0\nx\nBINARY\nDATASET POLYDATA\nPOINTS 3 float\n" +
           std::string(20, '\0'),
       "broken.vtk: byte 68: 9 values announced, but only 20 bytes left"},
  };
  for (const Case& c : cases) {
    Opened r = open(std::vector<std::string>{write(dir, "broken.vtk", c.text)});
    ASSERT_FALSE(r.stream.ok()) << c.expected;
    EXPECT_NE(r.stream.message().find(c.expected), std::string::npos)
        << r.stream.message() << "\nexpected: " << c.expected;
  }
}

// ---------------------------------------------------------------------------------------------
// .vtu details in hand-made files

TEST(VtkSeriesVtu, BrokenFilesFailWithTheirPlace) {
  const std::string head =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" "
      "byte_order=\"LittleEndian\">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\"3\" "
      "NumberOfCells=\"1\">\n";
  const std::string cells =
      "<Cells>\n<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">0 1 2"
      "</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">3</DataArray>\n"
      "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">5</DataArray>\n</Cells>\n";
  const std::string tail = "</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
  auto points = [](const std::string& format, const std::string& data) {
    return "<Points>\n<DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"" + format +
           "\">" + data + "</DataArray>\n</Points>\n";
  };
  test::TempDir dir;
  // The good one: 36 bytes of floats after a 4-byte size, base64.
  Opened good = open(std::vector<std::string>{
      write(dir, "good.vtu", head + points("ascii", "0 0 0 1 0 0 0 1 0") + cells + tail)});
  ASSERT_TRUE(good.stream.ok()) << good.stream.message();
  EXPECT_EQ(good.stream->topology.faces[0], (Face{{0, 1, 2, kNoVertex}}));

  std::string real_index = cells;  // a real number where an Int32 is expected
  real_index.replace(real_index.find("0 1 2<"), 5, "0 1 2.0");
  struct Case {
    std::string text, expected;
  };
  const Case cases[] = {
      {head + points("ascii", "0.0 0 0 1 0 0 0 1") + cells + tail, "8 values, expected 9"},
      {head + points("binary", "JAAAAA!!") + cells + tail, "not base64 text"},
      {head + points("binary", "/////wAAAAAAAAAAAAAAAA==") + cells + tail,
       "holds 4294967295 bytes, expected 36"},
      {head + points("ascii", "0 0 0 1 0 0 0 1 0") + tail, "needs the DataArrays connectivity"},
      {head + points("ascii", "0 0 0 1 0 0 0 1 0") + cells, ""},  // no closing tags: still read
      {"<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\">\n", "dynpm reads UnstructuredGrid"},
      {head.substr(0, 60), "a tag never ends"},
      // One number rule (text.h): beyond the double range is inf (as 1e39 beyond float), not 0;
      // integer types take whole integers within their range; counts are whole tokens.
      {head + points("ascii", "0 0 0 1 0 0 0 1 0") + real_index + tail,
       "DataArray 'connectivity': value 3, '2.0', is not a whole number"},
      {"<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\">\n<UnstructuredGrid>\n"
       "<Piece NumberOfPoints=\"3x\" NumberOfCells=\"1\">\n",
       "Piece NumberOfPoints='3x' is not a whole number"},
      {head + points("ascii", "0 0 0 1 0 0 0 1 0") + cells +
           "<FieldData><DataArray type=\"Float64\" Name=\"TimeValue\" format=\"ascii\">nan"
           "</DataArray></FieldData>\n" +
           tail,
       "FieldData TimeValue holds the time nan, not a finite number"},
  };
  for (const Case& c : cases) {
    Opened r = open(std::vector<std::string>{write(dir, "broken.vtu", c.text)});
    if (c.expected.empty()) {
      EXPECT_TRUE(r.stream.ok()) << r.stream.message();
      continue;
    }
    ASSERT_FALSE(r.stream.ok()) << c.expected;
    EXPECT_NE(r.stream.message().find("broken.vtu"), std::string::npos) << r.stream.message();
    EXPECT_NE(r.stream.message().find(c.expected), std::string::npos)
        << r.stream.message() << "\nexpected: " << c.expected;
  }
}

// ---------------------------------------------------------------------------------------------
// Third-party writers: meshio and VTK, from the shipped sample's first frame

// Writes `name` variants of frame_000.obj with the given Python program (argv: obj, folder).
void run_python(const std::string& python, const std::string& program, const test::TempDir& dir) {
  const std::string script = dir.file("write.py");
  std::ofstream(script) << program;
  const auto run = test::run_command(python + " " + script + " " + test::sample_dir() +
                                     "/frame_000.obj " + dir.path().string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
}

// Every variant must read as the OBJ does: same points, same faces (as cycles), one part per
// meshio cell block (so never triangles and quads in one part), the scalar point field.
void expect_like_obj(const std::string& path, const Animation& obj) {
  SCOPED_TRACE(path);
  Opened r = open(std::vector<std::string>{path});
  ASSERT_TRUE(r.stream.ok()) << r.stream.message();
  const Topology& t = r.stream->topology;
  ASSERT_EQ(t.vertex_count, obj.topology.vertex_count);
  EXPECT_EQ(cycles(t), cycles(obj.topology));
  const auto xyz = step(*r.stream, 0);
  const auto base = obj.frames.step(0);
  for (size_t i = 0; i < xyz.size(); ++i) ASSERT_NEAR(xyz[i], base[i], 1e-4) << i;
  std::map<int32_t, std::pair<size_t, size_t>> kinds;  // part → (triangles, quads)
  for (size_t f = 0; f < t.faces.size(); ++f)
    (t.faces[f].is_triangle() ? kinds[t.part_ids[f]].first : kinds[t.part_ids[f]].second)++;
  for (const auto& [part, count] : kinds) {
    EXPECT_GE(part, 7);
    EXPECT_TRUE(count.first == 0 || count.second == 0) << "part " << part;
  }
  ASSERT_EQ(r.stream->frames->field_names(), std::vector<std::string>{"temperature"});
  const auto temperature = field(*r.stream, 0, 0);
  for (size_t v = 0; v < temperature.size(); ++v) ASSERT_EQ(temperature[v], float(v));
}

const char* kMeshioProgram = R"(import sys, numpy as np, meshio
m = meshio.read(sys.argv[1])
out = sys.argv[2] + "/"
n = len(m.points)
mm = meshio.Mesh(m.points, m.cells,
                 point_data={"temperature": np.arange(n, dtype=float), "velocity": np.ones((n, 3))},
                 cell_data={"part_id": [np.full(len(c.data), 7 + k) for k, c in enumerate(m.cells)]})
meshio.vtk.write(out + "legacy42_ascii.vtk", mm, fmt_version="4.2", binary=False)
meshio.vtk.write(out + "legacy42_binary.vtk", mm, fmt_version="4.2", binary=True)
meshio.vtk.write(out + "legacy51_ascii.vtk", mm, fmt_version="5.1", binary=False)
meshio.vtk.write(out + "legacy51_binary.vtk", mm, fmt_version="5.1", binary=True)
meshio.vtu.write(out + "ascii.vtu", mm, binary=False)
meshio.vtu.write(out + "base64.vtu", mm, binary=True, compression=None)
meshio.vtu.write(out + "base64_uint64.vtu", mm, binary=True, compression=None, header_type="UInt64")
meshio.vtu.write(out + "zlib.vtu", mm, binary=True, compression="zlib")
meshio.vtu.write(out + "zlib_uint64.vtu", mm, binary=True, compression="zlib", header_type="UInt64")
)";

TEST(VtkSeriesMeshio, WrittenFilesReadLikeTheObj) {
  DYNPM_REQUIRE_MESHIO();
  auto obj = read_mesh(test::sample_dir() + "/frame_000.obj");
  ASSERT_TRUE(obj.ok()) << obj.message();
  test::TempDir dir;
  run_python(test::meshio_python(), kMeshioProgram, dir);
  for (const char* name :
       {"legacy42_ascii.vtk", "legacy42_binary.vtk", "legacy51_ascii.vtk", "legacy51_binary.vtk",
        "ascii.vtu", "base64.vtu", "base64_uint64.vtu", "zlib.vtu", "zlib_uint64.vtu"})
    expect_like_obj(dir.file(name), *obj);
}

// VTK's own XML and legacy writers: appended raw and base64 data, inline base64, zlib or none,
// UInt32 and UInt64 headers, legacy 4.2 and 5.1 binary.
const char* kVtkProgram = R"(import sys, numpy as np, meshio, vtk
m = meshio.read(sys.argv[1])
out = sys.argv[2] + "/"
n = len(m.points)
meshio.vtu.write(out + "meshio.vtu", meshio.Mesh(m.points, m.cells,
    point_data={"temperature": np.arange(n, dtype=float)},
    cell_data={"part_id": [np.full(len(c.data), 7 + k) for k, c in enumerate(m.cells)]}),
    binary=False)
r = vtk.vtkXMLUnstructuredGridReader(); r.SetFileName(out + "meshio.vtu"); r.Update()
grid = r.GetOutput()
def xml(name, mode, encode, zlib, uint64):
    w = vtk.vtkXMLUnstructuredGridWriter(); w.SetFileName(out + name); w.SetInputData(grid)
    getattr(w, "SetDataModeTo" + mode)()
    w.SetEncodeAppendedData(encode)
    w.SetCompressorTypeToZLib() if zlib else w.SetCompressorTypeToNone()
    w.SetHeaderTypeToUInt64() if uint64 else w.SetHeaderTypeToUInt32()
    w.Write()
xml("appended_raw.vtu", "Appended", False, False, False)
xml("appended_raw_zlib.vtu", "Appended", False, True, True)
xml("appended_base64.vtu", "Appended", True, False, True)
xml("appended_base64_zlib.vtu", "Appended", True, True, False)
xml("inline_base64.vtu", "Binary", True, False, False)
xml("inline_base64_zlib.vtu", "Binary", True, True, True)
for name, version in (("legacy42.vtk", 42), ("legacy51.vtk", 51)):
    w = vtk.vtkUnstructuredGridWriter(); w.SetFileName(out + name); w.SetInputData(grid)
    w.SetFileTypeToBinary(); w.SetFileVersion(version); w.Write()
)";

TEST(VtkSeriesVtk, WrittenFilesReadLikeTheObj) {
  DYNPM_REQUIRE_MESHIO();
  DYNPM_REQUIRE_VTK();
  auto obj = read_mesh(test::sample_dir() + "/frame_000.obj");
  ASSERT_TRUE(obj.ok()) << obj.message();
  test::TempDir dir;
  run_python(test::vtk_python(), kVtkProgram, dir);
  for (const char* name : {"appended_raw.vtu", "appended_raw_zlib.vtu", "appended_base64.vtu",
                           "appended_base64_zlib.vtu", "inline_base64.vtu",
                           "inline_base64_zlib.vtu", "legacy42.vtk", "legacy51.vtk"})
    expect_like_obj(dir.file(name), *obj);
}

// A .pvd collection of meshio-written steps, listed out of time order, files in a subfolder.
TEST(VtkSeriesPvd, CollectionOpensAsASequenceWithItsTimes) {
  DYNPM_REQUIRE_MESHIO();
  auto obj = read_mesh(test::sample_dir() + "/frame_000.obj");
  ASSERT_TRUE(obj.ok()) << obj.message();
  test::TempDir dir;
  run_python(test::meshio_python(), R"(import sys, os, numpy as np, meshio
m = meshio.read(sys.argv[1])
os.makedirs(sys.argv[2] + "/steps")
for k in range(3):
    p = m.points.copy(); p[:, 2] += k
    meshio.vtu.write(sys.argv[2] + "/steps/s%d.vtu" % k, meshio.Mesh(p, m.cells,
        point_data={"temperature": np.arange(len(p), dtype=float) + k}), binary=True)
)",
             dir);
  const std::string pvd = write(dir, "run.pvd",
                                "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" "
                                "version=\"0.1\">\n<Collection>\n"
                                "  <DataSet timestep=\"0.5\" group=\"\" part=\"0\" "
                                "file=\"steps/s1.vtu\"/>\n"
                                "  <DataSet timestep=\"0\" group=\"\" part=\"0\" "
                                "file=\"steps/s0.vtu\"/>\n"
                                "  <DataSet timestep=\"1.25\" part=\"0\" file=\"steps/s2.vtu\"/>\n"
                                "</Collection>\n</VTKFile>\n");
  Opened r = open(std::vector<std::string>{pvd});
  ASSERT_TRUE(r.stream.ok()) << r.stream.message();
  const FrameSource& frames = *r.stream->frames;
  ASSERT_EQ(frames.step_count(), 3u);
  EXPECT_EQ(frames.step_time(0), 0.0);
  EXPECT_EQ(frames.step_time(1), 0.5);
  EXPECT_EQ(frames.step_time(2), 1.25);
  EXPECT_EQ(cycles(r.stream->topology), cycles(obj->topology));
  const auto base = obj->frames.step(0);
  for (size_t t = 0; t < 3; ++t) {
    const auto xyz = step(*r.stream, t);
    for (size_t v = 0; v < xyz.size() / 3; ++v)
      ASSERT_NEAR(xyz[3 * v + 2], base[3 * v + 2] + float(t), 1e-4) << t << " " << v;
    EXPECT_EQ(field(*r.stream, 0, t)[10], 10.0f + float(t));
  }
  // The pvd alone: another file beside it is a usage error.
  Opened twice = open(std::vector<std::string>{pvd, pvd});
  EXPECT_FALSE(twice.stream.ok());
  // A DataSet whose file is missing names it.
  const std::string broken = write(dir, "broken.pvd",
                                   "<VTKFile type=\"Collection\"><Collection><DataSet "
                                   "timestep=\"0\" file=\"nope.vtu\"/></Collection></VTKFile>");
  Opened missing = open(std::vector<std::string>{broken});
  ASSERT_FALSE(missing.stream.ok());
  EXPECT_NE(missing.stream.message().find("nope.vtu"), std::string::npos)
      << missing.stream.message();
}

}  // namespace
}  // namespace dynpm
