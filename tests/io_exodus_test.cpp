// Exodus II reader: VTK's test files (netCDF classic, 64-bit offset and netCDF-4/HDF5; quads,
// hexahedra, tetrahedra, wedges, shells and beams), a file meshio writes from the shipped sample,
// and cut copies.
//
// The counts below were checked with Debian's python3-netcdf4 (dimensions num_nodes, num_elem,
// num_el_in_blk<b>, time_step; connect<b>:elem_type; time_whole) and, for the outer surfaces,
// against the closed-surface invariants tested here (no boundary edge, positive enclosed volume).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>

#include <csignal>

#include "dynpm/io.h"
#include "fixtures.h"
#include "io/contained_read.h"
#include "reading.h"
#include "third_party.h"

namespace dynpm {
namespace {

using test::field;
using test::open;
using test::Opened;
using test::step;

namespace fs = std::filesystem;

std::string exodus_file(const std::string& name) {
  return test::shared_data() + "/external/exodus/" + name;
}

// Volume enclosed by the faces (divergence theorem; quads split into two triangles): positive
// when the faces point outward.
double enclosed_volume(const Topology& top, std::span<const float> xyz) {
  auto p = [&](uint32_t v) {
    return std::array<double, 3>{xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]};
  };
  auto tet = [&](uint32_t a, uint32_t b, uint32_t c) {
    const auto A = p(a), B = p(b), C = p(c);
    return (A[0] * (B[1] * C[2] - B[2] * C[1]) - A[1] * (B[0] * C[2] - B[2] * C[0]) +
            A[2] * (B[0] * C[1] - B[1] * C[0])) /
           6.0;
  };
  double volume = 0;
  for (const Face& f : top.faces) {
    volume += tet(f.v[0], f.v[1], f.v[2]);
    if (!f.is_triangle()) volume += tet(f.v[0], f.v[2], f.v[3]);
  }
  return volume;
}

TopologyStats stats(const Topology& top) { return topology_stats(top, Adjacency::build(top)); }

// 10 × 10 QUAD4 in the plane (num_dim 2), one nodal variable "u" and one element variable
// "box" (1 or 2 per quad).
TEST(ExodusTest, CoarseGridQuads) {
  Opened r = open(exodus_file("vtkdata_coarseGrid.e"));
  ASSERT_TRUE(r.stream.ok()) << r.stream.message();
  const Topology& top = r.stream->topology;
  EXPECT_EQ(top.vertex_count, 121u);
  EXPECT_EQ(top.faces.size(), 100u);
  EXPECT_EQ(top.quad_count(), 100u);
  EXPECT_EQ(top.parts(), std::vector<int32_t>{0});  // eb_prop1 = 0
  EXPECT_EQ(r.stream->frames->step_count(), 1u);
  EXPECT_EQ(r.stream->frames->fields(),
            (std::vector<FieldInfo>{{"u", FieldLocation::kNode, ""},
                                    {"box", FieldLocation::kElement, ""}}));
  std::vector<float> box_values(top.faces.size());
  ASSERT_TRUE(r.stream->frames->read_field(1, 0, box_values).ok());
  for (float v : box_values) EXPECT_TRUE(v == 1.0f || v == 2.0f) << v;
  EXPECT_NE(std::count(box_values.begin(), box_values.end(), 2.0f), 0);
  const auto xyz = step(*r.stream, 0);
  BoundingBox box;
  box.extend(xyz);
  EXPECT_EQ(box.min, (std::array<float, 3>{0, 0, 0}));
  EXPECT_EQ(box.max, (std::array<float, 3>{1, 1, 0}));
  EXPECT_TRUE(validate(top, r.stream->frames.get()).ok());
}

// 2,476 HEX8 in two blocks (ids 1 and 76), 3,774 nodes, 21 steps t = 0, 0.1, … 2; nodal
// variables "convected" and "diffused", element variable "aux_elem".
TEST(ExodusTest, MugHexesOverTwentyOneSteps) {
  Opened r = open(exodus_file("vtkdata_mug.e"));
  ASSERT_TRUE(r.stream.ok()) << r.stream.message();
  const Topology& top = r.stream->topology;
  EXPECT_EQ(top.faces.size(), 2552u);  // the outer faces of the hexes
  EXPECT_EQ(top.quad_count(), 2552u);
  EXPECT_EQ(top.vertex_count, 2554u);  // nodes on the surface, of 3,774
  EXPECT_EQ(top.parts(), (std::vector<int32_t>{1, 76}));
  EXPECT_EQ(top.node_ids.back(), 3774);
  const FrameSource& frames = *r.stream->frames;
  ASSERT_EQ(frames.step_count(), 21u);
  for (size_t t = 0; t < 21; ++t) EXPECT_NEAR(frames.step_time(t), 0.1 * t, 1e-9);
  EXPECT_EQ(frames.field_names(), (std::vector<std::string>{"convected", "diffused", "aux_elem"}));
  std::vector<float> diffused(top.vertex_count);
  ASSERT_TRUE(frames.read_field(1, 20, diffused).ok());
  EXPECT_NEAR(*std::max_element(diffused.begin(), diffused.end()), 2.0, 1e-6);

  const TopologyStats s = stats(top);
  EXPECT_EQ(s.boundary_edges, 0u);  // a closed surface
  EXPECT_EQ(s.non_manifold_edges, 0u);
  EXPECT_GT(enclosed_volume(top, step(*r.stream, 20)), 0.0);  // faces point outward
  EXPECT_TRUE(validate(top, &frames).ok());
}

// 40 TETRA on a 3 × 3 × 3 grid of nodes: the outer surface is 6 sides × 8 triangles over the
// 26 nodes that are not the centre.
TEST(ExodusTest, TetrahedraGiveAClosedOutwardSurface) {
  Opened r = open(exodus_file("vtkdata_box-noglom.ex2"));
  ASSERT_TRUE(r.stream.ok()) << r.stream.message();
  const Topology& top = r.stream->topology;
  EXPECT_EQ(top.faces.size(), 48u);
  EXPECT_EQ(top.triangle_count(), 48u);
  EXPECT_EQ(top.vertex_count, 26u);
  EXPECT_EQ(stats(top).boundary_edges, 0u);
  EXPECT_NEAR(enclosed_volume(top, step(*r.stream, 0)), 1000.0, 1e-3);  // the 10³ box
  EXPECT_EQ(r.stream->frames->field_names().size(), 3u + 6u);  // nodal, then element variables
}

// 1,344 WEDGE in three blocks and no time step: the mesh is the one step.
TEST(ExodusTest, WedgesWithoutTimeSteps) {
  Opened r = open(exodus_file("vtkdata_mesh_fs8.exo"));
  ASSERT_TRUE(r.stream.ok()) << r.stream.message();
  const Topology& top = r.stream->topology;
  EXPECT_EQ(top.faces.size(), 920u);
  EXPECT_EQ(top.triangle_count(), 672u);
  EXPECT_EQ(top.parts(), (std::vector<int32_t>{1, 2, 3}));
  EXPECT_EQ(r.stream->frames->step_count(), 1u);
  EXPECT_EQ(stats(top).boundary_edges, 0u);
  EXPECT_GT(enclosed_volume(top, step(*r.stream, 0)), 0.0);
}

// netCDF-4/HDF5 with 46 blocks: HEX, HEX20, TETRA10, TETRA, SHELL8, SHELL, TRI3, TRI6, TRI,
// BEAM and BAR2. Beams and bars (172 elements) are ignored with a warning.
TEST(ExodusTest, Hdf5MixedBlocks) {
  Opened r = open(exodus_file("vtkdata_biplane_rms_pressure_bs.exo"));
  ASSERT_TRUE(r.stream.ok()) << r.stream.message();
  const Topology& top = r.stream->topology;
  EXPECT_EQ(top.faces.size(), 648u);
  EXPECT_EQ(top.triangle_count(), 530u);
  EXPECT_EQ(top.vertex_count, 467u);
  bool told = false;
  for (const auto& w : r.warnings) told |= w.find("172 elements ignored") != std::string::npos;
  EXPECT_TRUE(told);
}

// Old-style files with one coord and one vals_nod_var array.
TEST(ExodusTest, CombinedCoordinateAndVariableArrays) {
  Opened r = open(exodus_file("vtkdata_disk_out_ref.ex2"));
  ASSERT_TRUE(r.stream.ok()) << r.stream.message();
  EXPECT_EQ(r.stream->topology.faces.size(), 1988u);
  const auto names = r.stream->frames->field_names();
  ASSERT_EQ(names.size(), 9u);
  EXPECT_EQ(names[0], "Temp");
  std::vector<float> temp(r.stream->topology.vertex_count);
  ASSERT_TRUE(r.stream->frames->read_field(0, 0, temp).ok());
  EXPECT_NEAR(*std::min_element(temp.begin(), temp.end()), 293.15, 1e-3);
  EXPECT_NEAR(*std::max_element(temp.begin(), temp.end()), 913.15, 1e-3);
}

TEST(ExodusTest, TruncatedFilesAreErrors) {
  const std::string mug = exodus_file("vtkdata_mug.e");
  std::ifstream in(mug, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (size_t cut : {size_t{0}, size_t{100}, size_t{5000}, size_t{1000000}, bytes.size() - 1}) {
    test::TempDir dir;
    std::ofstream(dir.file("mug.e"), std::ios::binary) << bytes.substr(0, cut);
    Opened r = open(dir.file("mug.e"));
    EXPECT_FALSE(r.stream.ok()) << "cut at " << cut;
    EXPECT_NE(r.stream.message().find("mug.e"), std::string::npos) << r.stream.message();
  }
  // HDF5 (netCDF-4) cut short.
  const std::string hdf5 = exodus_file("vtkdata_biplane_rms_pressure_bs.exo");
  std::ifstream in5(hdf5, std::ios::binary);
  const std::string bytes5((std::istreambuf_iterator<char>(in5)), std::istreambuf_iterator<char>());
  for (size_t cut : {size_t{1000}, bytes5.size() / 2}) {
    test::TempDir dir;
    std::ofstream(dir.file("b.exo"), std::ios::binary) << bytes5.substr(0, cut);
    EXPECT_FALSE(open(dir.file("b.exo")).stream.ok()) << "cut at " << cut;
  }
}

// A classic header that declares more than the file holds is refused before netCDF allocates
// it (fuzzing finding 4, docs/RELIABILITY.md): the error names the file, the byte and the
// declared size, not netCDF's NC_ENOMEM (and under ASan no 4 GB calloc aborts the test).
TEST(ExodusTest, ForgedClassicHeaderCountsAreErrors) {
  Opened forged =
      open(test::source_dir() + "/fuzz/regressions/exodus/netcdf-header-4gb-string-oom.ex2");
  ASSERT_FALSE(forged.stream.ok());
  EXPECT_NE(forged.stream.message().find("netcdf-header-4gb-string-oom.ex2: byte 756: the netCDF "
                                         "header declares a name of 4294967295 bytes"),
            std::string::npos)
      << forged.stream.message();

  // The same in a valid CDF-2 file, patched: the dimension count (byte 12), then the first
  // dimension's name length (byte 16).
  std::ifstream in(exodus_file("vtkdata_box-noglom.ex2"), std::ios::binary);
  const std::string box((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_EQ(box.substr(0, 4), std::string("CDF\x02", 4));
  const struct {
    size_t at;
    const char* expected;
  } patches[] = {{12, "byte 12: the netCDF header declares 2147483647 dimensions, more than"},
                 {16, "byte 16: the netCDF header declares a name of 2147483647 bytes"}};
  for (const auto& patch : patches) {
    std::string bytes = box;
    bytes.replace(patch.at, 4, "\x7f\xff\xff\xff");
    test::TempDir dir;
    std::ofstream(dir.file("box.ex2"), std::ios::binary) << bytes;
    Opened r = open(dir.file("box.ex2"));
    ASSERT_FALSE(r.stream.ok()) << "patched at " << patch.at;
    EXPECT_NE(r.stream.message().find(patch.expected), std::string::npos) << r.stream.message();
    EXPECT_NE(r.stream.message().find("box.ex2"), std::string::npos) << r.stream.message();
  }
}

// meshio writes the shipped sample's first frame as Exodus II (netCDF-4) with a nodal
// displacement DISPL_X/Y/Z = (0.5·i, −1, 2) at node i: dynpm must read the same faces and the
// displaced positions.
TEST(ExodusTest, MeshioWrittenFileRoundTrips) {
  DYNPM_REQUIRE_MESHIO_EXODUS();
  const std::string obj = test::sample_dir() + "/frame_000.obj";
  auto original = read_mesh(obj);
  ASSERT_TRUE(original.ok()) << original.message();
  test::TempDir dir;
  const std::string script = dir.file("write.py"), out = dir.file("rail.e");
  std::ofstream(script) << "import sys, meshio, numpy as np\n"
                           "m = meshio.read(sys.argv[1])\n"
                           "n = len(m.points)\n"
                           "i = np.arange(n, dtype=float)\n"
                           "pd = {'DISPL_X': 0.5 * i, 'DISPL_Y': -np.ones(n), "
                           "'DISPL_Z': 2 * np.ones(n), 'temperature': i}\n"
                           "meshio.write(sys.argv[2], meshio.Mesh(m.points, m.cells, "
                           "point_data=pd), file_format='exodus')\n";
  const auto run =
      test::run_command(test::meshio_exodus_python() + " " + script + " " + obj + " " + out);
  ASSERT_EQ(run.exit_code, 0) << run.output;

  Opened r = open(out);
  ASSERT_TRUE(r.stream.ok()) << r.stream.message();
  const Topology& a = original->topology;
  const Topology& b = r.stream->topology;
  ASSERT_EQ(b.vertex_count, a.vertex_count);
  // Same faces, as multisets of corner cycles (meshio groups faces by type).
  auto cycles = [](const Topology& t) {
    std::map<std::array<uint32_t, 4>, int> m;
    for (Face f : t.faces) {
      const int n = f.degree();
      std::rotate(f.v.begin(), std::min_element(f.v.begin(), f.v.begin() + n), f.v.begin() + n);
      ++m[f.v];
    }
    return m;
  };
  EXPECT_EQ(cycles(a), cycles(b));
  ASSERT_EQ(r.stream->frames->step_count(), 1u);
  const auto xyz = step(*r.stream, 0);
  const auto base = original->frames.step(0);
  for (size_t v = 0; v < a.vertex_count; ++v) {
    ASSERT_NEAR(xyz[3 * v], base[3 * v] + 0.5f * v, 1e-3) << v;
    ASSERT_NEAR(xyz[3 * v + 1], base[3 * v + 1] - 1.0f, 1e-4) << v;
    ASSERT_NEAR(xyz[3 * v + 2], base[3 * v + 2] + 2.0f, 1e-4) << v;
  }
  EXPECT_EQ(r.stream->frames->field_names(), std::vector<std::string>{"temperature"});
}

// Steps and nodal fields are read a slab of 65,536 nodes at a time (issue 20): a grid of 75,250
// nodes (three slabs) whose last column no face uses, so that the kept vertices skip a node in
// every row and slab boundaries fall between them; every vertex gets its own node's values.
TEST(ExodusTest, StepsReadInSlabsGiveEveryVertexItsNode) {
  const std::string python = test::python_with("numpy, netCDF4");
  DYNPM_REQUIRE_PYTHON(python, "python3-netcdf4");
  test::TempDir dir;
  const std::string script = dir.file("write.py"), out = dir.file("slabs.e");
  constexpr int kWidth = 301, kRows = 250;  // column 300 is in no face
  std::ofstream(script) <<                  // a classic file: the slabs are for uncompressed files
      "import sys, netCDF4, numpy as np\n"
      "w, rows = 301, 250\n"
      "n = w * rows\n"
      "i = np.arange(n)\n"
      "q = np.array([[y * w + x, y * w + x + 1, (y + 1) * w + x + 1, (y + 1) * w + x]\n"
      "              for y in range(rows - 1) for x in range(w - 2)]) + 1\n"
      "names = ['DISPL_X', 'DISPL_Y', 'DISPL_Z', 'temperature']\n"
      "f = i.astype(float)\n"
      "values = [1e-3 * f, -5e-4 * f, np.ones(n), f]\n"
      "nc = netCDF4.Dataset(sys.argv[1], 'w', format='NETCDF3_64BIT_OFFSET')\n"
      "dims = [('len_name', 33), ('time_step', None), ('num_dim', 3), ('num_nodes', n),\n"
      "        ('num_elem', len(q)), ('num_el_blk', 1), ('num_el_in_blk1', len(q)),\n"
      "        ('num_nod_per_el1', 4), ('num_nod_var', len(names))]\n"
      "for name, size in dims:\n"
      "    nc.createDimension(name, size)\n"
      "for axis, column in zip('xyz', [i % w, i // w, np.zeros(n)]):\n"
      "    nc.createVariable('coord' + axis, 'f8', ('num_nodes',))[:] = column\n"
      "nc.createVariable('eb_prop1', 'i4', ('num_el_blk',))[:] = [1]\n"
      "connect = nc.createVariable('connect1', 'i4', ('num_el_in_blk1', 'num_nod_per_el1'))\n"
      "connect.elem_type = 'SHELL4'\n"
      "connect[:] = q\n"
      "nc.createVariable('time_whole', 'f8', ('time_step',))[:] = [0.0]\n"
      "text = nc.createVariable('name_nod_var', 'S1', ('num_nod_var', 'len_name'))\n"
      "text[:] = netCDF4.stringtochar(np.array(names, dtype='S33'))\n"
      "for k, v in enumerate(values):\n"
      "    name = 'vals_nod_var%d' % (k + 1)\n"
      "    nc.createVariable(name, 'f8', ('time_step', 'num_nodes'))[0, :] = v\n"
      "nc.close()\n";
  const auto run = test::run_command(python + " " + script + " " + out);
  ASSERT_EQ(run.exit_code, 0) << run.output;

  Opened r = open(out);
  ASSERT_TRUE(r.stream.ok()) << r.stream.message();
  const Topology& top = r.stream->topology;
  ASSERT_EQ(top.vertex_count, uint32_t{(kWidth - 1) * kRows});
  const auto xyz = step(*r.stream, 0);
  ASSERT_EQ(r.stream->frames->field_names(), std::vector<std::string>{"temperature"});
  const auto temperature = field(*r.stream, 0, 0);
  ASSERT_EQ(temperature.size(), top.vertex_count);
  for (uint32_t v = 0; v < top.vertex_count; ++v) {
    const int64_t node = top.node_ids[v] - 1;
    ASSERT_NE(node % kWidth, kWidth - 1) << v;  // the unused column is dropped
    ASSERT_NEAR(xyz[3 * v], double(node % kWidth) + 1e-3 * double(node), 1e-3) << v;
    ASSERT_NEAR(xyz[3 * v + 1], double(node / kWidth) - 5e-4 * double(node), 1e-3) << v;
    ASSERT_NEAR(xyz[3 * v + 2], 1.0, 1e-6) << v;
    ASSERT_EQ(temperature[v], float(node)) << v;
  }
}

// Issue 16: single-word corruptions of this netCDF-4 file made libhdf5 SIGSEGV inside nc_open
// (fuzz/exodus_word_flips.py: 171 of 1,020 between bytes 7,780 and 11,860). HDF5 files are read
// in a child process: dynpm must exit 1 with "damaged HDF5 file" naming the file, never crash.
// The same for the files in fuzz/regressions/exodus/ made from the meshio seed the same way.
TEST(ExodusTest, DamagedHdf5FilesAreErrorsNotCrashes) {
  std::ifstream in(exodus_file("vtkdata_biplane_rms_pressure_bs.exo"), std::ios::binary);
  const std::string biplane((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  test::TempDir dir;
  std::vector<std::string> files;
  const struct {
    size_t at;
    bool invert;  // the word's bytes inverted, else all ones
  } patches[] = {{7780, false}, {9652, true}, {11812, false}};
  for (const auto& patch : patches) {
    std::string bytes = biplane;
    for (size_t i = patch.at; i < patch.at + 4; ++i)
      bytes[i] = patch.invert ? static_cast<char>(~bytes[i]) : '\xff';
    files.push_back(dir.file("biplane-" + std::to_string(patch.at) + ".exo"));
    std::ofstream(files.back(), std::ios::binary) << bytes;
  }
  for (const auto& entry : fs::directory_iterator(test::source_dir() + "/fuzz/regressions/exodus"))
    if (entry.path().filename().string().starts_with("hdf5-"))
      files.push_back(entry.path().string());
  ASSERT_GE(files.size(), 5u);
  for (const std::string& file : files) {
    const auto run = test::run_command(std::string(DYNPM_CLI) + " info '" + file + "'");
    EXPECT_EQ(run.exit_code, 1) << file << "\n" << run.output;
    EXPECT_NE(run.output.find(file + ": damaged HDF5 file (the HDF5 library crashed reading it"),
              std::string::npos)
        << run.output;
  }
}

// A 40 KB netCDF-4 file the fuzzer made (fuzz/regressions/exodus/): libhdf5 never returns from
// it. The child is called hung after 10 s plus the file at 8 MiB/s (it was a flat 120 s).
TEST(ExodusTest, AnHdf5FileThatHangsTheLibraryIsRefusedWithinSeconds) {
  const std::string file = test::source_dir() + "/fuzz/regressions/exodus/netcdf4-libhdf5-hangs.e";
  const auto start = std::chrono::steady_clock::now();
  auto read = open_input(std::vector<std::string>{file});
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_FALSE(read.ok());
  EXPECT_EQ(read.message(), file + ": damaged HDF5 file (the HDF5 library gave no answer in 10 s)");
  EXPECT_LT(seconds, 60.0);
}

// open_in_child on stand-in readers: what the child reads arrives whole, its errors arrive as
// they are, and its death, at open or at a later step, becomes the "damaged file" error.
class CrashingSteps final : public FrameSource {
 public:
  uint32_t vertex_count() const override { return 3; }
  size_t step_count() const override { return 3; }
  double step_time(size_t t) const override { return 0.5 * double(t); }
  Status read_step(size_t t, std::span<float> out) const override {
    if (t == 2) std::raise(SIGSEGV);
    for (size_t i = 0; i < out.size(); ++i) out[i] = float(10 * t + i);
    return t == 1 ? Status::error("step 1: no data") : Status();
  }
  std::vector<FieldInfo> fields() const override { return {{"T", FieldLocation::kNode, {}}}; }
  Status read_field(size_t, size_t t, std::span<float> out) const override {
    std::fill(out.begin(), out.end(), float(t) + 0.25f);
    return {};
  }
};

TEST(ContainedReadTest, ChildReadsErrorsAndCrashes) {
  std::vector<std::string> warnings;
  ReadOptions options;
  options.warn = [&](const std::string& w) { warnings.push_back(w); };
  auto stream = io::open_in_child("a.exo", options, "HDF5", [](const ReadOptions& o) {
    o.warn("a note");
    AnimationStream s;
    s.topology = Topology::with_vertices(3);
    s.topology.add_triangle(0, 1, 2, 7, 42);
    s.frames = std::make_unique<CrashingSteps>();
    return Result<AnimationStream>(std::move(s));
  });
  ASSERT_TRUE(stream.ok()) << stream.message();
  EXPECT_EQ(warnings, std::vector<std::string>{"a note"});
  EXPECT_EQ(stream->topology.faces, (std::vector<Face>{Face{{0, 1, 2, kNoVertex}}}));
  EXPECT_EQ(stream->topology.part_ids, std::vector<int32_t>{7});
  EXPECT_EQ(stream->topology.element_ids, std::vector<int64_t>{42});
  const FrameSource& frames = *stream->frames;
  ASSERT_EQ(frames.step_count(), 3u);
  EXPECT_EQ(frames.step_time(2), 1.0);
  EXPECT_EQ(frames.field_names(), std::vector<std::string>{"T"});
  std::vector<float> xyz(9), values(3);
  ASSERT_TRUE(frames.read_step(0, xyz).ok());
  EXPECT_EQ(xyz[8], 8.0f);
  ASSERT_TRUE(frames.read_field(0, 2, values).ok());
  EXPECT_EQ(values[0], 2.25f);
  EXPECT_EQ(frames.read_step(1, xyz).message(), "step 1: no data");
  const std::string died = "a.exo: damaged HDF5 file (the HDF5 library crashed reading it: ";
  EXPECT_TRUE(frames.read_step(2, xyz).message().starts_with(died))
      << frames.read_step(2, xyz).message();
  EXPECT_TRUE(frames.read_step(0, xyz).message().starts_with(died));  // and stays dead

  auto refused = io::open_in_child("b.exo", options, "HDF5", [](const ReadOptions&) {
    return Result<AnimationStream>(Status::error("b.exo: no num_nodes"));
  });
  EXPECT_EQ(refused.message(), "b.exo: no num_nodes");
  auto crashed = io::open_in_child("c.exo", options, "HDF5", [](const ReadOptions&) {
    std::raise(SIGSEGV);
    return Result<AnimationStream>(Status::error("not reached"));
  });
  EXPECT_TRUE(
      crashed.message().starts_with("c.exo: damaged HDF5 file (the HDF5 library crashed "
                                    "reading it: "))
      << crashed.message();
}

}  // namespace
}  // namespace dynpm
