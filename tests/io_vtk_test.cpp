// Files checked by third-party tools: VTK's own reader reads what dynpm writes, dynpm reads
// what meshio writes.
#include <gtest/gtest.h>

#include "dynpm/io.h"
#include "fixtures.h"
#include "third_party.h"

namespace dynpm {
namespace {

// What VTK's own legacy reader (vtkPolyDataReader) finds in a file.
std::string vtk_summary(const std::string& path) {
  const std::string script =
      "import sys, vtk\n"
      "r = vtk.vtkPolyDataReader(); r.SetFileName(sys.argv[1]); r.ReadAllScalarsOn(); r.Update()\n"
      "if r.GetErrorCode() != 0 or not r.IsFilePolyData(): sys.exit('not read')\n"
      "p = r.GetOutput()\n"
      "print('points', p.GetNumberOfPoints())\n"
      "sizes = [p.GetCell(i).GetNumberOfPoints() for i in range(p.GetNumberOfCells())]\n"
      "print('quad', sizes.count(4)); print('triangle', sizes.count(3))\n"
      "print('point3', *[round(c, 4) for c in p.GetPoint(3)])\n"
      "a = p.GetCellData().GetArray('part_id')\n"
      "print('cell part_id', *[int(a.GetValue(i)) for i in range(a.GetNumberOfTuples())])\n"
      "a = p.GetPointData().GetArray('plastic_strain')\n"
      "print('point plastic_strain', *[round(a.GetValue(i), 3) for i in "
      "range(a.GetNumberOfTuples())])\n";
  auto r = test::run_command(test::vtk_python() + " -c \"" + script + "\" " + path);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return r.output;
}

class VtkWrite : public ::testing::TestWithParam<bool> {};

TEST_P(VtkWrite, VtkReadsQuadsTrianglesPartsAndFields) {
  DYNPM_REQUIRE_VTK();
  test::TempDir dir;
  auto m = test::tri_quad_strip();
  m.topology.part_ids = {4, 4, 9, 9};
  std::vector<float> strain = {0, 0.5f, 1, 0, 0, 0, 0, 2};
  const NamedValues fields[] = {{"plastic strain", strain}};
  WriteOptions options;
  options.binary = GetParam();
  ASSERT_TRUE(write_mesh(dir.file("m.vtk"), m.topology, m.positions, options, fields).ok());
  const std::string summary = vtk_summary(dir.file("m.vtk"));
  EXPECT_NE(summary.find("points 8"), std::string::npos) << summary;
  EXPECT_NE(summary.find("quad 2"), std::string::npos) << summary;
  EXPECT_NE(summary.find("triangle 2"), std::string::npos) << summary;
  EXPECT_NE(summary.find("point3 0.0 1.0 0.0"), std::string::npos) << summary;
  EXPECT_NE(summary.find("cell part_id 4 4 9 9"), std::string::npos) << summary;
  EXPECT_NE(summary.find("point plastic_strain 0.0 0.5 1.0 0.0 0.0 0.0 0.0 2.0"), std::string::npos)
      << summary;
}

INSTANTIATE_TEST_SUITE_P(AsciiAndBinary, VtkWrite, ::testing::Bool());

TEST(ThirdPartyFiles, DynpmReadsMeshioPlyAndObjWithQuads) {
  DYNPM_REQUIRE_MESHIO();
  test::TempDir dir;
  const std::string script =
      "import meshio, sys\n"
      "points = [[0,0,0],[1,0,0],[2,0,0],[0,1,0],[1,1,0],[2,1,0],[3,0.5,0]]\n"
      "cells = [('quad', [[0,1,4,3],[1,2,5,4]]), ('triangle', [[2,6,5]])]\n"
      "m = meshio.Mesh(points, cells)\n"
      "d = sys.argv[1]\n"
      "meshio.write(d + '/b.ply', m, binary=True)\n"
      "meshio.write(d + '/a.ply', m, binary=False)\n"
      "meshio.write(d + '/m.obj', m)\n";
  auto r =
      test::run_command(test::meshio_python() + " -c \"" + script + "\" " + dir.path().string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* name : {"b.ply", "a.ply", "m.obj"}) {
    auto a = read_mesh(dir.file(name));
    ASSERT_TRUE(a.ok()) << name << ": " << a.message();
    EXPECT_EQ(a->topology.vertex_count, 7u) << name;
    EXPECT_EQ(a->topology.quad_count(), 2u) << name;
    EXPECT_EQ(a->topology.triangle_count(), 1u) << name;
    EXPECT_EQ(a->frames.step(0)[6 * 3], 3.0f) << name;
    EXPECT_TRUE(validate(*a).ok()) << name;
  }
}

}  // namespace
}  // namespace dynpm
