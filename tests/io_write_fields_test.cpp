// Result fields written by dynpm, read by third-party tools: VTK's own readers for .vtk and .vtu
// (point and cell data), meshio for .ply (vertex and face properties); and dynpm's VTU reader
// reads its own .vtu back.
#include <gtest/gtest.h>

#include "dynpm/io.h"
#include "fixtures.h"
#include "third_party.h"

namespace dynpm {
namespace {

struct Written {
  test::Mesh mesh = test::tri_quad_strip();
  std::vector<float> strain = {0, 0.5f, 1, 0, 0, 0, 0, 2};  // per vertex
  std::vector<float> mises = {10, 20.5f, -3, 400};          // per face
  test::TempDir dir;

  std::string write(const std::string& name, bool binary) {
    if (mesh.topology.faces.size() == 4) mesh.topology.part_ids = {4, 4, 9, 9};
    const NamedValues points[] = {{"plastic strain", strain}};
    const NamedValues cells[] = {{"von Mises", mises}};
    WriteOptions options;
    options.binary = binary;
    options.comment = "fields -- test";
    const std::string path = dir.file(name);
    const Status s = write_mesh(path, mesh.topology, mesh.positions, options, points, cells);
    EXPECT_TRUE(s.ok()) << s.message();
    return path;
  }
};

// What VTK's reader for the file's kind finds: cells by size, part ids and both fields.
std::string vtk_summary(const std::string& path) {
  const std::string script =
      "import sys, vtk\n"
      "p = sys.argv[1]\n"
      "r = vtk.vtkXMLUnstructuredGridReader() if p.endswith('.vtu') else vtk.vtkPolyDataReader()\n"
      "r.SetFileName(p)\n"
      "if not p.endswith('.vtu'): r.ReadAllScalarsOn()\n"
      "r.Update()\n"
      "g = r.GetOutput()\n"
      "sizes = [g.GetCell(i).GetNumberOfPoints() for i in range(g.GetNumberOfCells())]\n"
      "print('points', g.GetNumberOfPoints(), 'quads', sizes.count(4), 'triangles', "
      "sizes.count(3))\n"
      "def show(kind, data, name):\n"
      "  a = data.GetArray(name)\n"
      "  print(kind, name, *[round(a.GetValue(i), 3) for i in range(a.GetNumberOfTuples())])\n"
      "show('cell', g.GetCellData(), 'part_id')\n"
      "show('cell', g.GetCellData(), 'von_Mises')\n"
      "show('point', g.GetPointData(), 'plastic_strain')\n"
      "show('point', g.GetPointData(), 'node_id')\n";
  auto r = test::run_command(test::vtk_python() + " -c \"" + script + "\" " + path);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return r.output;
}

class FieldsWrite : public ::testing::TestWithParam<std::tuple<std::string, bool>> {};

TEST_P(FieldsWrite, VtkReadsPointAndCellData) {
  DYNPM_REQUIRE_VTK();
  const auto& [extension, binary] = GetParam();
  Written w;
  const std::string summary = vtk_summary(w.write("m" + extension, binary));
  for (const char* expected :
       {"points 8 quads 2 triangles 2", "cell part_id 4 4 9 9",
        "cell von_Mises 10.0 20.5 -3.0 400.0",
        "point plastic_strain 0.0 0.5 1.0 0.0 0.0 0.0 0.0 2.0", "point node_id 1 2 3 4 5 6 7 8"})
    EXPECT_NE(summary.find(expected), std::string::npos) << expected << "\n" << summary;
}

INSTANTIATE_TEST_SUITE_P(VtkAndVtu, FieldsWrite,
                         ::testing::Combine(::testing::Values(".vtk", ".vtu"), ::testing::Bool()));

TEST(FieldsWrite, MeshioReadsPlyVertexAndFaceProperties) {
  DYNPM_REQUIRE_MESHIO();
  Written w;
  const std::string path = w.write("m.ply", false);
  const std::string script =
      "import sys, meshio\n"
      "m = meshio.read(sys.argv[1])\n"
      "print('points', len(m.points))\n"
      "print('strain', *[round(float(x), 3) for x in m.point_data['plastic_strain']])\n"
      "mises = [round(float(x), 3) for block in m.cell_data['von_Mises'] for x in block]\n"
      "print('mises', *sorted(mises))\n";
  auto r = test::run_command(test::meshio_python() + " -c \"" + script + "\" " + path);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("points 8"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("strain 0.0 0.5 1.0 0.0 0.0 0.0 0.0 2.0"), std::string::npos) << r.output;
  // meshio groups faces by type (quads, then triangles): compare as a set.
  EXPECT_NE(r.output.find("mises -3.0 10.0 20.5 400.0"), std::string::npos) << r.output;
}

// meshio's binary PLY reader fails on any face property ("object of type 'numpy.int32' has no
// len()", its own limitation); a binary file's layout is checked by reading it back: a property
// written with the wrong size would shift every face after it.
TEST(FieldsWrite, BinaryPlyWithFieldsReadsBack) {
  Written w;
  auto back = read_mesh(w.write("m.ply", true));
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_EQ(back->topology.faces, w.mesh.topology.faces);
  EXPECT_EQ(back->topology.part_ids, (std::vector<int32_t>{4, 4, 9, 9}));
  EXPECT_EQ(back->topology.node_ids, w.mesh.topology.node_ids);
  EXPECT_EQ(back->frames.step(0)[7 * 3], 3.0f);
}

TEST(FieldsWrite, DynpmReadsItsOwnVtuBack) {
  for (const bool binary : {false, true}) {
    Written w;
    auto back = read_mesh(w.write("m.vtu", binary));
    ASSERT_TRUE(back.ok()) << back.message();
    EXPECT_EQ(back->topology.faces, w.mesh.topology.faces);
    EXPECT_EQ(back->topology.part_ids, (std::vector<int32_t>{4, 4, 9, 9}));
    EXPECT_EQ(back->topology.node_ids, w.mesh.topology.node_ids);
    EXPECT_EQ(back->frames.step(0)[7 * 3], 3.0f);
    bool found = false;
    for (const ScalarField& field : back->fields)
      if (field.name == "plastic_strain") {
        found = true;
        EXPECT_EQ(field.steps.at(0), w.strain);
      }
    EXPECT_TRUE(found) << "the point field was not read back";
  }
}

TEST(FieldsWrite, OnlyMeshFormatsAreWritten) {
  Written w;
  const Status s = write_mesh(w.dir.file("m.frd"), w.mesh.topology, w.mesh.positions);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find(".obj, .ply, .vtk or .vtu"), std::string::npos) << s.message();
}

}  // namespace
}  // namespace dynpm
