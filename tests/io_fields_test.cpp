// Result fields as the readers deliver them, per node or per element, on real solver output:
// LS-DYNA shell stresses and plastic strain at each integration point (qd-cae's d3plot), the
// CalculiX crash box written with S and PEEQ, Exodus element variables (VTK's test files and a
// netCDF-4 file meshio writes), and VTK cell data.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
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

// The index of the field called name, or -1.
int field_index(const FrameSource& frames, const std::string& name) {
  const auto fields = frames.fields();
  for (size_t f = 0; f < fields.size(); ++f)
    if (fields[f].name == name) return static_cast<int>(f);
  return -1;
}

std::string qd_d3plot() { return test::shared_data() + "/external/d3plot/qd_d3plot"; }

Opened open_at(const std::string& path, IntegrationPoint point) {
  ReadOptions options;
  options.integration_point = point;
  return open(std::vector<std::string>{path}, options);
}

// qd_d3plot writes 3 integration points of 6 stresses, the plastic strain and 19 history values,
// the resultants, thickness and energy, and the strains: NV2D = 3 × 26 + 8 + 4 + 12 = 102. Its
// one state is the initial one (time 0): no stress yet, and the sheet's 2.93 mm at word 86 of
// every shell, which only a layout that adds up finds. (Stress values at each integration point
// are checked on the synthetic families of io_d3plot_test.cpp.)
TEST(D3plotFields, QdShellStressPlasticStrainAndThickness) {
  if (!std::filesystem::exists(qd_d3plot())) GTEST_SKIP() << qd_d3plot() << " is missing";
  for (IntegrationPoint point : {IntegrationPoint::kMid, IntegrationPoint::kTop,
                                 IntegrationPoint::kBottom, IntegrationPoint::kMax}) {
    SCOPED_TRACE(to_string(point));
    Opened r = open_at(qd_d3plot(), point);
    ASSERT_TRUE(r.stream.ok()) << r.stream.message();
    EXPECT_TRUE(r.warnings.empty());
    const FrameSource& frames = *r.stream->frames;
    // The node fields stay first, the element fields follow; d3plot names no units.
    const std::vector<FieldInfo> expected = {{"|V|", FieldLocation::kNode, ""},
                                             {"von Mises", FieldLocation::kElement, ""},
                                             {"plastic strain", FieldLocation::kElement, ""},
                                             {"thickness", FieldLocation::kElement, ""}};
    ASSERT_EQ(frames.fields(), expected);
    for (size_t f = 1; f < expected.size(); ++f) {
      const auto values = field(*r.stream, f, 0);
      ASSERT_EQ(values.size(), r.stream->topology.face_count());
      for (float v : values) ASSERT_EQ(v, f == 3 ? 2.93f : 0.0f) << expected[f].name;
    }
  }
}

// NV2D patched to 101: the words no longer add up, and the file is refused saying so.
TEST(D3plotFields, RefusesAShellLayoutThatDoesNotAddUp) {
  if (!std::filesystem::exists(qd_d3plot())) GTEST_SKIP() << qd_d3plot() << " is missing";
  test::TempDir dir;
  const std::string copy = dir.file("qd_d3plot");
  std::filesystem::copy_file(qd_d3plot(), copy);
  std::filesystem::copy_file(qd_d3plot() + "01", copy + "01");
  {
    std::fstream f(copy, std::ios::in | std::ios::out | std::ios::binary);
    const int32_t nv2d = 101;
    f.seekp(33 * 4);
    f.write(reinterpret_cast<const char*>(&nv2d), 4);
  }
  Opened r = open(copy);
  ASSERT_FALSE(r.stream.ok());
  const std::string& m = r.stream.message();
  EXPECT_NE(m.find(copy + ": byte 132: NV2D = 101 words per shell does not add up"),
            std::string::npos)
      << m;
  EXPECT_NE(m.find("= 90, or 102 with strains"), std::string::npos) << m;
}

std::string gunzip(const std::string& gz, const test::TempDir& dir, const std::string& name) {
  const std::string out = dir.file(name);
  const auto run = test::run_command("gzip -dc '" + gz + "' > '" + out + "'");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  return out;
}

// CalculiX wrote S and PEEQ at the shell nodes (OUTPUT=2D): von Mises from the stress tensor and
// the equivalent plastic strain, per node; plastic strain only grows under this loading, though
// CalculiX's extrapolation from the integration points to the nodes can move a node's value a
// little either way (the file's PEEQ ranges from -0.0013 to 1.96).
TEST(FrdFields, CrashboxStressAndPlasticStrain) {
  const std::string gz = test::shared_data() + "/crashbox-fields/crashbox-fields.frd.gz";
  if (!std::filesystem::exists(gz)) GTEST_SKIP() << gz << " is missing";
  test::TempDir dir;
  Opened r = open(gunzip(gz, dir, "crashbox-fields.frd"));
  ASSERT_TRUE(r.stream.ok()) << r.stream.message();
  const FrameSource& frames = *r.stream->frames;
  ASSERT_EQ(frames.step_count(), 15u);
  const int mises = field_index(frames, "S_MISES"), peeq = field_index(frames, "PEEQ");
  ASSERT_GE(mises, 0);
  ASSERT_GE(peeq, 0);
  for (const FieldInfo& f : frames.fields()) {
    EXPECT_EQ(f.location, FieldLocation::kNode) << f.name;
    EXPECT_EQ(f.unit, "") << f.name;  // FRD names no units
  }
  std::vector<float> before = field(*r.stream, size_t(peeq), 0);
  for (float v : before) ASSERT_EQ(v, 0.0f);  // step 0: the undeformed mesh
  size_t decreases = 0, values = 0;
  for (size_t t = 1; t < frames.step_count(); ++t) {
    const auto s = field(*r.stream, size_t(mises), t);
    for (float v : s) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f) << "step " << t;
    const auto p = field(*r.stream, size_t(peeq), t);
    for (size_t v = 0; v < p.size(); ++v) {
      ASSERT_GE(p[v], -0.01f) << "step " << t;  // extrapolated to the nodes: may dip below 0
      decreases += p[v] < before[v] - 1e-6f;
      ++values;
    }
    before = p;
  }
  // 1.6 % of the node values fall a little from one step to the next in this file.
  EXPECT_LT(decreases, values / 20) << "PEEQ fell at " << decreases << " of " << values;
  const auto last = field(*r.stream, size_t(peeq), frames.step_count() - 1);
  EXPECT_GT(*std::max_element(last.begin(), last.end()), 0.01f);  // the tube has yielded
}

std::string exodus_file(const std::string& name) {
  return test::shared_data() + "/external/exodus/" + name;
}

// mug.e: two blocks of bricks, the element variable aux_elem over 21 steps. Each outer face
// shows its brick's value: faces of one element agree, and values stay in the file's range.
TEST(ExodusFields, ElementVariableOnTheOuterFacesOfSolids) {
  if (!std::filesystem::exists(exodus_file("vtkdata_mug.e"))) GTEST_SKIP() << "no mug.e";
  Opened r = open(exodus_file("vtkdata_mug.e"));
  ASSERT_TRUE(r.stream.ok()) << r.stream.message();
  const int aux = field_index(*r.stream->frames, "aux_elem");
  ASSERT_GE(aux, 0);
  EXPECT_EQ(r.stream->frames->fields()[size_t(aux)].location, FieldLocation::kElement);
  const Topology& top = r.stream->topology;
  for (size_t t : {size_t{0}, size_t{20}}) {
    const auto values = field(*r.stream, size_t(aux), t);
    std::map<int64_t, float> of_element;
    for (size_t f = 0; f < values.size(); ++f) {
      ASSERT_GE(values[f], 0.009f) << f;  // vals_elem_var1eb1/eb2 lie in 0.0090 … 9.9917
      ASSERT_LE(values[f], 9.992f) << f;
      const auto [it, added] = of_element.emplace(top.element_ids[f], values[f]);
      if (!added) {
        ASSERT_EQ(it->second, values[f]) << "element " << top.element_ids[f];
      }
    }
  }
}

// edgeFaceElem.exii: EPSTRN is written for the hex block only (no truth table, no
// vals_elem_var1eb2): the tet block's faces get 0, with a warning naming the block.
TEST(ExodusFields, BlockWithoutTheVariableGetsZeroAndAWarning) {
  const std::string path = exodus_file("vtkdata_edgeFaceElem.exii");
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is missing";
  Opened r = open(path);
  ASSERT_TRUE(r.stream.ok()) << r.stream.message();
  const int eps = field_index(*r.stream->frames, "EPSTRN");
  ASSERT_GE(eps, 0);
  bool warned = false;
  for (const std::string& w : r.warnings)
    warned |= w.find("EPSTRN is 0 on the faces of block 2") != std::string::npos;
  EXPECT_TRUE(warned);
  const auto values = field(*r.stream, size_t(eps), 1);
  size_t zero = 0, nonzero = 0;
  for (float v : values) (v == 0.0f ? zero : nonzero)++;
  EXPECT_GT(zero, 0u);
  EXPECT_GT(nonzero, 0u);
}

// A netCDF-4 (HDF5) Exodus file written here with python3-netcdf4 (meshio writes no element
// variables), read in the child process: a 5 × 5 quad grid whose element variable is each
// quad's centroid x at step 0 and twice that at step 1, so every face must show its own.
TEST(ExodusFields, ElementVariableThroughTheHdf5Child) {
  DYNPM_REQUIRE_MESHIO_EXODUS();
  test::TempDir dir;
  const std::string script = dir.file("write.py"), out = dir.file("grid.e");
  std::ofstream(script)
      << "import sys, netCDF4, numpy as np\n"
         "n = 6\n"
         "pts = np.array([[i, j, 0.1 * i * j] for j in range(n) for i in range(n)], dtype=float)\n"
         "q = np.array([[j*n+i, j*n+i+1, (j+1)*n+i+1, (j+1)*n+i] for j in range(n-1) for i in "
         "range(n-1)])\n"
         "cx = pts[q][:, :, 0].mean(axis=1)\n"
         "d = netCDF4.Dataset(sys.argv[1], 'w', format='NETCDF4')\n"
         "for name, size in [('num_nodes', len(pts)), ('num_dim', 3), ('num_elem', len(q)), "
         "('num_el_blk', 1),\n"
         "                   ('num_el_in_blk1', len(q)), ('num_nod_per_el1', 4), ('len_string', "
         "33),\n"
         "                   ('num_elem_var', 1), ('time_step', None)]:\n"
         "    d.createDimension(name, size)\n"
         "for a, axis in enumerate('xyz'):\n"
         "    d.createVariable('coord' + axis, 'f8', ('num_nodes',))[:] = pts[:, a]\n"
         "c = d.createVariable('connect1', 'i4', ('num_el_in_blk1', 'num_nod_per_el1'))\n"
         "c.elem_type = 'QUAD4'\n"
         "c[:] = q + 1\n"
         "d.createVariable('eb_prop1', 'i4', ('num_el_blk',))[:] = [7]\n"
         "t = d.createVariable('time_whole', 'f8', ('time_step',))\n"
         "t[0:2] = [0.0, 1.0]\n"
         "names = d.createVariable('name_elem_var', 'S1', ('num_elem_var', 'len_string'))\n"
         "names[0, :] = netCDF4.stringtochar(np.array(['cx'], dtype='S33'))\n"
         "d.createVariable('elem_var_tab', 'i4', ('num_el_blk', 'num_elem_var'))[:] = [[1]]\n"
         "v = d.createVariable('vals_elem_var1eb1', 'f8', ('time_step', 'num_el_in_blk1'))\n"
         "v[0, :] = cx\n"
         "v[1, :] = 2 * cx\n"
         "d.close()\n";
  const auto run = test::run_command(test::meshio_exodus_python() + " " + script + " " + out);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  Opened r = open(out);
  ASSERT_TRUE(r.stream.ok()) << r.stream.message();
  const int cx = field_index(*r.stream->frames, "cx");
  ASSERT_GE(cx, 0);
  EXPECT_EQ(r.stream->frames->fields()[size_t(cx)].location, FieldLocation::kElement);
  const auto xyz = test::step(*r.stream, 0);
  const Topology& top = r.stream->topology;
  ASSERT_EQ(top.face_count(), 25u);
  for (size_t t = 0; t < 2; ++t) {
    const auto values = field(*r.stream, size_t(cx), t);
    for (size_t f = 0; f < top.face_count(); ++f) {
      double x = 0;
      for (uint32_t v : top.faces[f].v) x += xyz[3 * v];
      EXPECT_NEAR(values[f], double(t + 1) * x / 4, 1e-6) << "face " << f << ", step " << t;
    }
  }
}

// A VTU with two quads, a pentagon (split into three triangles), a hexahedron (skipped) and a
// line (skipped), with cell data: part_id gives parts, "pressure" becomes an element field, the
// two-component "shear" is left out with a warning, and point data stays a node field.
TEST(VtkFields, CellDataBecomesElementFields) {
  test::TempDir dir;
  const std::string vtu = dir.file("cells.vtu");
  std::ofstream(vtu)
      << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
         "<UnstructuredGrid><Piece NumberOfPoints=\"16\" NumberOfCells=\"5\">\n"
         "<Points><DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"ascii\">\n"
         "0 0 0 1 0 0 2 0 0 0 1 0 1 1 0 2 1 0 3 0 0 3 1 0\n"
         "0 0 5 1 0 5 1 1 5 0 1 5 0 0 6 1 0 6 1 1 6 0 1 6\n"
         "</DataArray></Points>\n"
         "<Cells><DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n"
         "0 1 4 3  1 2 5 4  2 6 7 5 4  8 9 10 11 12 13 14 15  0 8\n"
         "</DataArray><DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n"
         "4 8 13 21 23</DataArray>\n"
         "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">9 9 7 12 3</DataArray>\n"
         "</Cells>\n"
         "<CellData><DataArray type=\"Int32\" Name=\"part_id\" format=\"ascii\">7 7 8 9 9"
         "</DataArray>\n"
         "<DataArray type=\"Float64\" Name=\"pressure\" format=\"ascii\">1.5 2.5 3.5 4.5 5.5"
         "</DataArray>\n"
         "<DataArray type=\"Float64\" Name=\"shear\" NumberOfComponents=\"2\" format=\"ascii\">"
         "0 0 0 0 0 0 0 0 0 0</DataArray></CellData>\n"
         "<PointData><DataArray type=\"Float32\" Name=\"temperature\" format=\"ascii\">\n"
         "0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15</DataArray></PointData>\n"
         "</Piece></UnstructuredGrid></VTKFile>\n";
  Opened r = open(std::vector<std::string>{vtu}, /*split_polygons=*/true);
  ASSERT_TRUE(r.stream.ok()) << r.stream.message();
  const std::vector<FieldInfo> expected = {{"temperature", FieldLocation::kNode, ""},
                                           {"pressure", FieldLocation::kElement, ""}};
  ASSERT_EQ(r.stream->frames->fields(), expected);
  EXPECT_EQ(field(*r.stream, 1, 0), (std::vector<float>{1.5f, 2.5f, 3.5f, 3.5f, 3.5f}));
  EXPECT_EQ(r.stream->topology.part_ids, (std::vector<int32_t>{7, 7, 8, 8, 8}));
  bool warned = false;
  for (const std::string& w : r.warnings)
    warned |= w.find("cell data with several components not read") != std::string::npos &&
              w.find("shear") != std::string::npos;
  EXPECT_TRUE(warned);

  // The same through read_mesh(): one step, the field per face.
  ReadOptions split;
  split.split_polygons = true;
  auto mesh = read_mesh(vtu, split);
  ASSERT_TRUE(mesh.ok()) << mesh.message();
  ASSERT_EQ(mesh->fields.size(), 2u);
  EXPECT_EQ(mesh->fields[1].location, FieldLocation::kElement);
  EXPECT_EQ(mesh->fields[1].steps[0].size(), 5u);
}

// Legacy VTK: CELL_DATA scalars other than the ids are element fields, and a sequence of files
// reads each step's cell values by name.
TEST(VtkFields, LegacyCellDataOverASequence) {
  test::TempDir dir;
  std::vector<std::string> paths;
  for (int t = 0; t < 2; ++t) {
    paths.push_back(dir.file("step" + std::to_string(t) + ".vtk"));
    std::ofstream(paths.back()) << "# vtk DataFile Version 3.0\ntime " << t
                                << "\nASCII\nDATASET POLYDATA\nPOINTS 5 float\n"
                                   "0 0 0 1 0 0 1 1 0 0 1 0 2 0 0\n"
                                   "POLYGONS 2 9\n4 0 1 2 3\n3 1 4 2\n"
                                   "CELL_DATA 2\nSCALARS element_id int 1\nLOOKUP_TABLE default\n"
                                   "11 12\nSCALARS plastic_strain float 1\nLOOKUP_TABLE default\n"
                                << 0.1 * t << " " << 0.2 * t << "\n";
  }
  Opened r = open(paths);
  ASSERT_TRUE(r.stream.ok()) << r.stream.message();
  const std::vector<FieldInfo> expected = {{"plastic_strain", FieldLocation::kElement, ""}};
  ASSERT_EQ(r.stream->frames->fields(), expected);
  EXPECT_EQ(r.stream->topology.element_ids, (std::vector<int64_t>{11, 12}));
  EXPECT_EQ(field(*r.stream, 0, 0), (std::vector<float>{0.0f, 0.0f}));
  EXPECT_EQ(field(*r.stream, 0, 1), (std::vector<float>{0.1f, 0.2f}));
}

}  // namespace
}  // namespace dynpm
